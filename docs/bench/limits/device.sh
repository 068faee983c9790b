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

# The other runs on this page:
# - bake-terms-*.txt (H100): .devbin/relief-old (committed) and .devbin/relief-new (the noise
#   from per-cell terms), each twice: `relief-$b bake --world endless --region 0,0,4096,4096
#   --size 4096 --timings` and the same with `--feature-size 256`; then the oblique view with
#   `--method hybrid --samples 1 --raster compute --timings` and `--method reference --timings`.
# - oblique-lavapipe.txt (lavapipe, 960x540): `relief render --width 960 --height 540 --world
#   endless --eye -5000,4195.8573366294322,2000 --look-at -4999.2,4195.3573366294322,2000.33`
#   with `--method reference`, `--method visibility --samples 1 --raster compute` and `--method
#   hybrid --samples 1 --raster compute`, the last also from a build whose hybrid neither raises
#   its levels nor refines (`t = length(point_at(dir, d))` in wgsl/hybrid.wgsl); FLIP by the
#   flip-evaluator Python package.
# - ridge-worst-pixels.txt (lavapipe, 1920x1080): a temporary example that renders
#   `bench_world::views`' ridge with the default World into an Offscreen keeping its depth and
#   repeats `world_depth_metrics` at every pixel, printing the largest.
