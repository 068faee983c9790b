#!/usr/bin/env bash
# Stage 2 of issue 28: the landscape benchmark with the new binary, the seeded random views
# beside the named ones, its arrival included.
set -uo pipefail
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
export RELIEF_FONT=.bin/DejaVuSans.ttf
chmod +x .bin/relief-new
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv >"$OUT/gpu.txt" 2>&1
( time timeout 575 .bin/relief-new bench --world endless --out-dir "$OUT/landscape" ) >"$OUT/landscape-stdout.txt" 2>&1
tail -20 "$OUT/landscape-stdout.txt"
