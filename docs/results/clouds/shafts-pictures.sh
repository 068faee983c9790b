#!/bin/bash
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export XDG_RUNTIME_DIR=$(mktemp -d)
nvidia-smi --query-gpu=name,driver_version --format=csv > $OUT/gpu.txt 2>&1
M="--method visibility --samples 1 --raster compute"
R="render --world endless --cloud-coverage 0.5 --frames 32 --width 1920 --height 1080 --timings $M"
mkdir -p /tmp/p
for b in relief relief-noshafts; do
  timeout 60 .bin/$b $R --time-of-day 12 --eye 0,1900,0 --look-at 800,3000,-3000 --out /tmp/p/$b-noon.png > /tmp/p/$b-noon.txt 2>&1
  timeout 60 .bin/$b $R --sun-azimuth 145 --sun-elevation -2 --eye 0,1900,0 --look-at 800,2300,-3000 --out /tmp/p/$b-dusk.png > /tmp/p/$b-dusk.txt 2>&1
  for fog in 0.03 0.2; do
    timeout 60 .bin/$b $R --sun-azimuth 145 --sun-elevation 8 --fog $fog --eye 0,1900,0 --look-at 1720,2200,2457 --out /tmp/p/$b-toward-$fog.png > /tmp/p/$b-toward-$fog.txt 2>&1
    timeout 60 .bin/$b $R --sun-azimuth 145 --sun-elevation 8 --fog $fog --eye 0,1900,0 --look-at 2457,2000,-1720 --out /tmp/p/$b-side-$fog.png > /tmp/p/$b-side-$fog.txt 2>&1
  done
done
cd /tmp/p && tar cf $OUT/pictures.tar . 
grep -h timings /tmp/p/*.txt > $OUT/timings.txt
echo done >> $OUT/gpu.txt
