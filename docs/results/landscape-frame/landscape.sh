#!/usr/bin/env bash
# Issue 28, stage 3: the landscape benchmark with the workspace's binary.
set -uo pipefail
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
export RELIEF_FONT=.bin/DejaVuSans.ttf
chmod +x .bin/relief-ws
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv >"$OUT/gpu.txt" 2>&1
( time timeout 570 .bin/relief-ws bench --world endless --out-dir "$OUT/landscape" ) >"$OUT/landscape-stdout.txt" 2>&1
tail -25 "$OUT/landscape-stdout.txt"
