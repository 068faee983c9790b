#!/usr/bin/env bash
# The landscape benchmark with the final binary (the light budget, borrowed light read from
# the nearest texel), its arrival included.
set -uo pipefail
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
export RELIEF_FONT=.bin/DejaVuSans.ttf
chmod +x .bin/relief-new4
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv >"$OUT/gpu.txt" 2>&1
( time timeout 540 .bin/relief-new4 bench --world endless --out-dir /tmp/landscape ) >"$OUT/landscape-stdout.txt" 2>&1
cp /tmp/landscape/landscape.csv /tmp/landscape/landscape.png /tmp/landscape/look.csv /tmp/landscape/arrival.csv "$OUT/"
cat "$OUT/landscape-stdout.txt"
