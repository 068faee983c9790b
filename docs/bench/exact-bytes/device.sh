#!/usr/bin/env bash
# Exact bytes (9ca3481, "new") against ad6ea0a ("old"): the default frame's time on five views, the
# ridge's reference and default frame, then the landscape benchmark with the new binary.
set -uo pipefail
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
export RELIEF_FONT=.devbin/DejaVuSans.ttf
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv >"$OUT/gpu.txt" 2>&1
views=(
    "horizon --world endless --eye 0,1202,0 --look-at 1,1201.99,0.2"
    "ridge --world endless --eye 5730,1198.7011293135074,1000 --look-at 5730.3,1198.6811293135074,1001"
    "oblique --world endless --eye -5000,4195.8573366294322,2000 --look-at -4999.2,4195.3573366294322,2000.33"
    "default --world endless"
    "tile"
)
for i in 1 2; do
    for v in "${views[@]}"; do
        set -- $v
        name=$1
        shift
        for b in old new; do
            bin=.devbin/relief
            [ $b = old ] && bin=.devbin/relief-old
            echo "== $name $b ($i)"
            timeout 40 $bin render --width 1920 --height 1080 --timings --out "/tmp/$name-$b.png" "$@"
        done
    done
done 2>&1 | tee "$OUT/render-timings.txt"
a=(--width 1920 --height 1080 --world endless --eye 5730,1198.7011293135074,1000 --look-at 5730.3,1198.6811293135074,1001)
.devbin/relief render "${a[@]}" --method reference --out "$OUT/ridge-ref.png" 2>&1 | tail -2
cp /tmp/ridge-new.png "$OUT/ridge-new.png"
time timeout 450 .devbin/relief bench --world endless --out-dir /tmp/landscape >"$OUT/landscape-stdout.txt" 2>&1
cp /tmp/landscape/landscape.csv /tmp/landscape/landscape.png /tmp/landscape/look.csv "$OUT/"

# Second call: the region bake with one reciprocal, then the tile benchmark
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
export RELIEF_FONT=.devbin/DejaVuSans.ttf
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv >"$OUT/gpu.txt" 2>&1
for i in 1 2; do
    for b in relief relief-recip; do
        echo "== $b region 12 octaves ($i)"
        .devbin/$b bake --world endless --region 0,0,4096,4096 --size 4096 --timings --out-dir /tmp/bake-$b 2>&1 | grep -E 'timings|G/s'
        echo "== $b region feature-size 256 ($i)"
        .devbin/$b bake --world endless --feature-size 256 --region 0,0,4096,4096 --size 4096 --timings --out-dir /tmp/bake256-$b 2>&1 | grep -E 'timings|G/s'
    done
done 2>&1 | tee "$OUT/bake-timings.txt"
time timeout 500 .devbin/relief bench --out-dir /tmp/tile >"$OUT/bench-stdout.txt" 2>&1
cp /tmp/tile/bench.csv /tmp/tile/bench.png "$OUT/"

# Third call: the oblique view with and without sun shadows
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
a=(--width 1920 --height 1080 --world endless --eye -5000,4195.8573366294322,2000 --look-at -4999.2,4195.3573366294322,2000.33)
for s in on off; do
    extra=()
    [ $s = off ] && extra=(--no-shadows)
    .devbin/relief render "${a[@]}" "${extra[@]}" --method reference --out "$OUT/ob-ref-$s.png" 2>&1 | tail -1
    .devbin/relief render "${a[@]}" "${extra[@]}" --method visibility --samples 1 --raster compute --out "$OUT/ob-vis-$s.png" 2>&1 | tail -1
    .devbin/relief render "${a[@]}" "${extra[@]}" --method hybrid --samples 1 --raster compute --out "$OUT/ob-hyb-$s.png" 2>&1 | tail -1
done
