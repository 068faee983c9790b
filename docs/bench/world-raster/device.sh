#!/usr/bin/env bash
# The H100 runs behind docs/bench/world-raster/README.md, through the device tool, from the
# repository root, with the release binary in .devbin/relief and the Vulkan loader's .debs in
# .gl/ carried (see the tool's README). `device.sh views`: one 1080p frame of each of the
# landscape benchmark's three views (src/bench_world.rs::views, their cameras written out)
# with the mesh, `visibility` and `hybrid` at one sample a pixel in both rasters, and the
# default (auto), twice. `device.sh bench`: `relief render --world endless`'s default, then the
# full `relief bench --world endless`. Everything lands in $OUT/world-raster.tar.gz.
set -uo pipefail
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
R=.devbin/relief
export RELIEF_FONT=.devbin/DejaVuSans.ttf
out=/tmp/world-raster
mkdir -p "$out"
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv >"$out/gpu.txt" 2>&1
if [ "${1:-views}" = views ]; then
    views=(
        "horizon --eye 0,1202,0 --look-at 1,1201.99,0.2"
        "ridge --eye 5730,1198.7011293135074,1000 --look-at 5730.3,1198.6811293135074,1001"
        "oblique --eye -5000,4195.8573366294322,2000 --look-at -4999.2,4195.3573366294322,2000.33"
    )
    for i in 1 2; do
        for v in "${views[@]}"; do
            set -- $v
            name=$1
            shift
            for m in "mesh" "visibility --samples 1" "visibility --samples 1 --raster compute" \
                "hybrid --samples 1" "hybrid --samples 1 --raster compute"; do
                echo "== $name, --method $m ($i)"
                $R render --world endless --width 1920 --height 1080 --timings \
                    --out "$out/$name.png" "$@" --method $m
            done
            echo "== $name, auto ($i)"
            $R render --world endless --width 1920 --height 1080 --timings --out "$out/$name.png" "$@"
        done
    done 2>&1 | tee "$out/render-views.txt"
else
    echo "== endless, auto" >"$out/render-default.txt"
    /usr/bin/time -f "wall %e s" $R render --world endless --out "$out/endless-auto.png" \
        --width 1920 --height 1080 --timings >>"$out/render-default.txt" 2>&1
    time timeout 575 $R bench --world endless --out-dir "$out/landscape" \
        >"$out/landscape-stdout.txt" 2>"$out/landscape-stderr.txt"
    tail -n 3 "$out/landscape-stdout.txt"
fi
rm -f "$out"/*.png
tar -czf "$OUT/world-raster.tar.gz" -C /tmp world-raster
