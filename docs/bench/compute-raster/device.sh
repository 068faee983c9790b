#!/usr/bin/env bash
# The H100 run behind docs/bench/compute-raster/README.md, through the device tool, from the
# repository root, with the release binary in .devbin/relief and the Vulkan loader's .debs in
# .gl/ carried (see the tool's README). The tile's visibility method at one sample a pixel with
# its raster in hardware and in compute, pinned, three times each at 1920x1080; `relief render`'s
# default (auto) three times; then `relief bench` (the tile: both rasters beside the mesh, the
# ray marches and the blog, in one run). Everything lands in $OUT/compute-raster.tar.gz.
set -uo pipefail
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
R=.devbin/relief
export RELIEF_FONT=.devbin/DejaVuSans.ttf
out=/tmp/compute-raster
mkdir -p "$out"
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv >"$out/gpu.txt" 2>&1
for i in 1 2 3; do
    for r in hardware compute; do
        echo "== tile, --method visibility --samples 1 --raster $r ($i)"
        $R render --out "$out/tile-$r.png" --width 1920 --height 1080 --timings \
            --method visibility --samples 1 --raster $r
    done
    echo "== tile, auto ($i)"
    /usr/bin/time -f "wall %e s" $R render --out "$out/tile-auto.png" --width 1920 --height 1080 --timings
done 2>&1 | tee "$out/render-timings.txt"
if [ "${1:-all}" != render ]; then
    time timeout 480 $R bench --out-dir "$out/bench" >"$out/bench-stdout.txt" 2>"$out/bench-stderr.txt"
    tail -n 30 "$out/bench-stdout.txt"
fi
tar -czf "$OUT/compute-raster.tar.gz" -C /tmp compute-raster
