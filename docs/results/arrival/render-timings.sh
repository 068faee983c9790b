#!/usr/bin/env bash
# The default frame on five views: old (dbde83c), new (light borrowed in a second read), new2
# (one read, its level chosen first), interleaved three times.
set -uo pipefail
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
chmod +x .bin/relief-*
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv >"$OUT/gpu2.txt" 2>&1
views=(
    "horizon --world endless --eye 0,1202,0 --look-at 1,1201.99,0.2"
    "ridge --world endless --eye 5730,1198.7011293135074,1000 --look-at 5730.3,1198.6811293135074,1001"
    "oblique --world endless --eye -5000,4195.8573366294322,2000 --look-at -4999.2,4195.3573366294322,2000.33"
    "default --world endless"
    "tile"
)
for i in 1 2 3; do
    for v in "${views[@]}"; do
        set -- $v
        name=$1
        shift
        for b in old new3 new4; do
            echo "== $name $b ($i)"
            timeout 60 .bin/relief-$b render --width 1920 --height 1080 --timings --out "/tmp/$name-$b.png" "$@" 2>&1 | grep -v "^relief: --pixel-error"
        done
    done
done >"$OUT/render-timings2.txt" 2>&1
for v in horizon ridge oblique default tile; do
    cmp -s "/tmp/$v-old.png" "/tmp/$v-new4.png" && echo "$v: same bytes" || echo "$v: DIFFERENT"
done
