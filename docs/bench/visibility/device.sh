#!/usr/bin/env bash
# The H100 runs behind docs/bench/visibility/README.md, through the device tool, from the
# repository root: the release binary in .devbin/relief and the Vulkan loader's .debs in .gl/
# carried (see the tool's README). `device.sh render` times one frame of each mesh method in
# both worlds at 1080p (twice) and runs `relief bench`; `device.sh world` runs
# `relief bench --world endless`; `device.sh stability` runs `relief stability` (the detail
# axis draws the visibility method beside the mesh). Everything lands in
# $OUT/visibility.tar.gz.
set -uo pipefail
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
R=.devbin/relief
export RELIEF_FONT=.devbin/DejaVuSans.ttf
out=/tmp/visibility
mkdir -p "$out"
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv >"$out/gpu.txt" 2>&1
case "${1:-render}" in
render)
    for i in 1 2; do
        for m in mesh visibility; do
            echo "== tile $m ($i)"
            $R render --out "$out/tile-$m.png" --width 1920 --height 1080 --method "$m" --timings --stats
            echo "== endless $m ($i)"
            $R render --world endless --out "$out/world-$m.png" --width 1920 --height 1080 --method "$m" --timings --stats
        done
    done 2>&1 | tee "$out/render-timings.txt"
    rm -f "$out"/tile-mesh.png "$out"/world-mesh.png
    time $R bench --out-dir "$out/bench" >"$out/bench-stdout.txt" 2>"$out/bench-stderr.txt"
    ;;
world)
    $R bench --world endless --out-dir "$out/landscape" >"$out/landscape-stdout.txt" 2>"$out/landscape-stderr.txt"
    ;;
stability)
    $R stability --out-dir "$out/stability" >"$out/stability-stdout.txt" 2>"$out/stability-stderr.txt"
    ;;
esac
for f in "$out"/*stdout.txt; do tail -n 5 "$f"; done
tar -czf "$OUT/visibility.tar.gz" -C /tmp visibility
