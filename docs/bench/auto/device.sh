#!/usr/bin/env bash
# The H100 run behind docs/bench/auto/README.md, through the device tool, from the repository
# root, with the release binary in .devbin/relief and the Vulkan loader's .debs in .gl/ carried
# (see the tool's README). `relief render --timings` with the default method (auto: the
# fastest candidate measured on the device) in both worlds at 1920x1080, three times each; the
# choices pinned, to compare; then `relief bench` (the tile, whose chart marks the default as
# chosen from its own rows); `device.sh render` leaves the benchmark out. Everything lands in
# $OUT/auto.tar.gz.
set -uo pipefail
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
R=.devbin/relief
export RELIEF_FONT=.devbin/DejaVuSans.ttf
out=/tmp/auto
mkdir -p "$out"
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv >"$out/gpu.txt" 2>&1
for i in 1 2 3; do
    echo "== tile, auto ($i)"
    /usr/bin/time -f "wall %e s" $R render --out "$out/tile-auto.png" --width 1920 --height 1080 --timings
    echo "== endless, auto ($i)"
    /usr/bin/time -f "wall %e s" $R render --world endless --out "$out/endless-auto.png" --width 1920 --height 1080 --timings
done 2>&1 | tee "$out/render-timings.txt"
for m in "mesh" "visibility --samples 1"; do
    echo "== tile, --method $m"
    /usr/bin/time -f "wall %e s" $R render --out "$out/tile-pinned.png" --width 1920 --height 1080 --timings --method $m
done 2>&1 | tee -a "$out/render-timings.txt"
for m in "mesh" "hybrid --samples 1"; do
    echo "== endless, --method $m"
    /usr/bin/time -f "wall %e s" $R render --world endless --out "$out/endless-pinned.png" --width 1920 --height 1080 --timings --method $m
done 2>&1 | tee -a "$out/render-timings.txt"
if [ "${1:-all}" != render ]; then
    time timeout 420 $R bench --out-dir "$out/bench" >"$out/bench-stdout.txt" 2>"$out/bench-stderr.txt"
    tail -n 20 "$out/bench-stdout.txt"
fi
tar -czf "$OUT/auto.tar.gz" -C /tmp auto
