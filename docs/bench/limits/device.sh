#!/usr/bin/env bash
# B=256 against B=128 (the clipmap's largest patch): the visibility method at 1 sample rasterised
# in compute, knob 1, on the landscape views; a hack binary (XB256 raises the cap, XONLY runs
# that one method at the one knob).
set -uo pipefail
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
export RELIEF_FONT=.devbin/DejaVuSans.ttf
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv >"$OUT/gpu.txt" 2>&1
views=(
    "horizon --eye 0,1202,0 --look-at 1,1201.99,0.2"
    "ridge --eye 5730,1198.7011293135074,1000 --look-at 5730.3,1198.6811293135074,1001"
    "oblique --eye -5000,4195.8573366294322,2000 --look-at -4999.2,4195.3573366294322,2000.33"
)
for b in 128 256; do
    x=()
    [ $b = 256 ] && x=(XB256=1)
    for v in "${views[@]}"; do
        set -- $v
        name=$1
        shift
        echo "== $name B$b"
        env "${x[@]}" timeout 60 .devbin/relief-hack render --world endless --width 1920 --height 1080 --method visibility --samples 1 --raster compute --timings --stats --out /tmp/$name-$b.png "$@" 2>&1
    done
done >"$OUT/render-b256.txt" 2>&1
for b in 128 256; do
    x=()
    [ $b = 256 ] && x=(XB256=1)
    ( time env XONLY=1 "${x[@]}" timeout 250 .devbin/relief-hack bench --world endless --out-dir /tmp/b$b ) >"$OUT/bench-b$b-stdout.txt" 2>&1
    cp /tmp/b$b/landscape.csv "$OUT/landscape-b$b.csv"
done
