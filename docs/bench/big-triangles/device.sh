#!/usr/bin/env bash
# The H100 run behind docs/bench/big-triangles/README.md, through the device tool, from the
# repository root, with the release binaries from before (.devbin/relief-old) and after
# (.devbin/relief) the big triangles' dispatch and the Vulkan loader's .debs in .gl/ carried.
# Each view twice with each binary; whether their PNGs are the same; the default (auto) in
# both worlds. Everything lands in $OUT/big-triangles.tar.gz.
set -uo pipefail
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
export RELIEF_FONT=.devbin/DejaVuSans.ttf
out=/tmp/big-triangles
mkdir -p "$out"
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv >"$out/gpu.txt" 2>&1
views=(
    "default"
    "horizon --eye 0,1202,0 --look-at 1,1201.99,0.2"
    "ridge --eye 5730,1198.7011293135074,1000 --look-at 5730.3,1198.6811293135074,1001"
    "oblique --eye -5000,4195.8573366294322,2000 --look-at -4999.2,4195.3573366294322,2000.33"
)
for i in 1 2; do
    for bin in old new; do
        R=.devbin/relief; [ $bin = old ] && R=.devbin/relief-old
        for v in "${views[@]}"; do
            set -- $v
            name=$1
            shift
            for m in "visibility --samples 1 --raster compute" "hybrid --samples 1 --raster compute"; do
                echo "== $bin $name, --method $m ($i)"
                $R render --world endless --width 1920 --height 1080 --timings --out "$out/$bin-$name-${m%% *}.png" "$@" --method $m
            done
        done
        for t in "default" "low --eye 0.1,0.31,0.2 --look-at 0.5,0.2,0.6"; do
            set -- $t
            name=$1
            shift
            echo "== $bin tile $name, --method visibility --samples 1 --raster compute ($i)"
            $R render --width 1920 --height 1080 --timings --out "$out/$bin-tile-$name.png" "$@" --method visibility --samples 1 --raster compute
        done
    done
done 2>&1 | tee "$out/render-timings.txt"
for f in "$out"/new-*.png; do
    o="$out/old-${f##*/new-}"
    cmp -s "$f" "$o" && echo "same: ${f##*/new-}" || echo "DIFFER: ${f##*/new-}"
done | tee "$out/png-same.txt"
for v in default tile; do
    w=""; [ $v = default ] && w="--world endless"
    echo "== auto $v"
    .devbin/relief render $w --width 1920 --height 1080 --timings --out "$out/auto-$v.png"
done 2>&1 | tee "$out/render-auto.txt"
mkdir -p "$out/png"; cp "$out/new-horizon-visibility.png" "$out/png/"
rm -f "$out"/*.png
tar -czf "$OUT/big-triangles.tar.gz" -C /tmp big-triangles
