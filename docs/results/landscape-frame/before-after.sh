#!/usr/bin/env bash
# The frame before (relief-new4, the last measured binary) and after this restructuring
# (relief-new), interleaved three times on five views; then byte comparisons of pinned methods.
set -uo pipefail
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
chmod +x .bin/relief-*
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv >"$OUT/gpu.txt" 2>&1
views=(
    "horizon --world endless --eye 0,1202,0 --look-at 1,1201.99,0.2"
    "ridge --world endless --eye 5730,1198.7011293135074,1000 --look-at 5730.3,1198.6811293135074,1001"
    "oblique --world endless --eye -5000,4195.8573366294322,2000 --look-at -4999.2,4195.3573366294322,2000.33"
    "default --world endless"
    "tile"
)
# Warm the GPU's clocks.
timeout 60 .bin/relief-new render --world endless --width 1920 --height 1080 --out /tmp/warm.png >/dev/null 2>&1
for i in 1 2 3; do
    for v in "${views[@]}"; do
        set -- $v
        name=$1
        shift
        for b in new4 new; do
            echo "== $name $b ($i)"
            timeout 60 .bin/relief-$b render --width 1920 --height 1080 --timings --out "/tmp/$name-$b.png" "$@" 2>&1 | grep -v "^relief: --pixel-error"
        done
    done
done >"$OUT/render-timings.txt" 2>&1
for v in horizon ridge oblique default tile; do
    cmp -s "/tmp/$v-new4.png" "/tmp/$v-new.png" && echo "$v auto: same bytes" || echo "$v auto: DIFFERENT"
done >"$OUT/same.txt"
for m in "mesh" "visibility --samples 1 --raster compute" "visibility" "hybrid --samples 1 --raster compute" "raymarch" "reference"; do
    for v in "${views[@]:0:3}"; do
        set -- $v
        name=$1
        shift
        for b in new4 new; do
            timeout 60 .bin/relief-$b render --width 1920 --height 1080 --out "/tmp/p-$b.png" --method $m "$@" >/dev/null 2>&1
        done
        cmp -s /tmp/p-new4.png /tmp/p-new.png && echo "$name --method $m: same bytes" || echo "$name --method $m: DIFFERENT"
    done
done >>"$OUT/same.txt" 2>&1
cat "$OUT/same.txt"
grep -h "timings on\|the fastest draw" "$OUT/render-timings.txt" | head -4
