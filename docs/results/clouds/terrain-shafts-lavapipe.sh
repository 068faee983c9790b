#!/bin/bash
# The fast path against the reference with the terrain's shadows in the shafts, on lavapipe at
# 320x180 (this repository's test machine: 2 cores, Mesa's software Vulkan), for the build with
# them ($NEW, relief at this commit) and the one before them ($OLD, relief at eb7dc1c): the
# default method (visibility, 1 sample, compute raster) converged over 32 frames, against
# `--method reference` (3x3 rays a pixel), on the terrain-shafts picture's view (A) and two of
# the device script's (T, V); FLIP by crates/eval/examples/flip.rs.
A="--cloud-coverage 0.2 --fog 0.2 --sun-azimuth 150 --sun-elevation 5 --fov 60 --eye -4500,1450,1500 --look-at -2778,1420,3957"
T="--cloud-coverage 0.5 --fog 0.2 --sun-azimuth 145 --sun-elevation 8 --eye 0,1900,0 --look-at 1720,2200,2457"
V="--cloud-coverage 0.3 --fog 0.2 --sun-azimuth 150 --sun-elevation 13 --fov 60 --eye -4500,1160,1500 --look-at -2778,1390,3957 --no-grass"
M="--method visibility --samples 1 --raster compute"
FLIP=${FLIP:-target/debug/examples/flip}
mkdir -p /tmp/lp
for v in A T V; do
  for b in NEW OLD; do
    B=${!b}
    $B render --world endless --method reference --width 320 --height 180 ${!v} --out /tmp/lp/$v-ref-$b.png > /dev/null
    $B render --world endless $M --frames 32 --width 320 --height 180 ${!v} --out /tmp/lp/$v-fast-$b.png > /dev/null
    echo "$v $b: $($FLIP /tmp/lp/$v-ref-$b.png /tmp/lp/$v-fast-$b.png)"
  done
done
