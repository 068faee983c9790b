#!/usr/bin/env bash
# The frames that must not change when the code is restructured: both worlds, every method,
# a few looks. Renders each with the given `relief` binary into DIR and prints one
# `sha256  name.png` line per frame (sorted). Compare two binaries' lists with diff:
#   bash tools/pixels.sh old/relief /tmp/old > old.txt
#   bash tools/pixels.sh target/debug/relief /tmp/new > new.txt && diff old.txt new.txt
set -euo pipefail
bin=$1
dir=$2
mkdir -p "$dir"
rm -f "$dir"/*.png
size=(--width 192 --height 108)
tile_methods=(mesh visibility raymarch raymarch-fragment blog reference)
world_methods=(mesh visibility hybrid raymarch raymarch-bandlimited reference)
render() {
    local name=$1
    shift
    "$bin" render "${size[@]}" --out "$dir/$name.png" "$@" >/dev/null
}
for m in "${tile_methods[@]}"; do
    render "tile-$m" --method "$m"
done
render tile-visibility-s1-compute --method visibility --samples 1 --raster compute --size 256
render tile-analytic --method mesh --normals analytic --size 256 --offset 0.3,0.1
for m in "${world_methods[@]}"; do
    render "world-$m" --world endless --method "$m"
done
render world-hybrid-s1-compute --world endless --method hybrid --samples 1 --raster compute
render world-visibility-s1 --world endless --method visibility --samples 1
render world-path --world endless --method mesh --camera path --time 20
render world-low-sun --world endless --method mesh --sun-elevation 3 --sun-azimuth 250 --fog 0.2
render world-plain --world endless --method mesh --no-water --no-shadows --palette blog --terrain fbm
render world-water --world endless --method visibility --water-level 1400 --camera path --time 5
(cd "$dir" && sha256sum -- *.png | sort -k2)
