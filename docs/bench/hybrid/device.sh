#!/usr/bin/env bash
# The H100 runs behind docs/bench/hybrid/README.md, through the device tool, from the
# repository root, with the release binary in .devbin/relief and the Vulkan loader's .debs in
# .gl/ carried (see the tool's README). It times one 1080p frame of the endless world's default
# view with each mesh method (twice), the hybrid at coarser knobs, and runs
# `relief bench --world endless` (the hybrid at every knob). Everything lands in
# $OUT/hybrid.tar.gz.
set -uo pipefail
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
R=.devbin/relief
export RELIEF_FONT=.devbin/DejaVuSans.ttf
out=/tmp/hybrid
mkdir -p "$out"
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv >"$out/gpu.txt" 2>&1
for i in 1 2; do
    for m in mesh visibility hybrid; do
        echo "== endless $m, 1 px ($i)"
        $R render --world endless --out "$out/world-$m.png" --width 1920 --height 1080 --method "$m" --timings --stats
    done
    for k in 4 8 16; do
        echo "== endless hybrid, $k px ($i)"
        $R render --world endless --pixel-error "$k" --out "$out/world-hybrid-$k.png" --width 1920 --height 1080 --method hybrid --timings --stats
    done
done 2>&1 | tee "$out/render-timings.txt"
time timeout 480 $R bench --world endless --out-dir "$out/landscape" >"$out/landscape-stdout.txt" 2>"$out/landscape-stderr.txt"
tail -n 5 "$out/landscape-stdout.txt"
tar -czf "$OUT/hybrid.tar.gz" -C /tmp hybrid
