#!/bin/bash
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export XDG_RUNTIME_DIR=$(mktemp -d)
nvidia-smi --query-gpu=name,driver_version --format=csv > $OUT/gpu.txt 2>&1
B=.bin/relief
mkdir -p /usr/share/fonts/truetype/dejavu; cp .bin/DejaVuSans.ttf /usr/share/fonts/truetype/dejavu/
R="render --world endless --cloud-coverage 0.5 --frames 32"
timeout 60 $B $R --time-of-day 12 --eye 0,1900,0 --look-at 800,3000,-3000 --width 1920 --height 1080 --out $OUT/clouds-noon.png --timings > $OUT/render-noon.txt 2>&1
timeout 60 $B $R --sun-azimuth 145 --sun-elevation -2 --eye 0,1900,0 --look-at 800,2300,-3000 --width 1920 --height 1080 --out $OUT/clouds-dusk.png --timings > $OUT/render-dusk.txt 2>&1
timeout 60 $B $R --time-of-day 15 --width 1920 --height 1080 --out $OUT/clouds-default.png --timings > $OUT/render-default.txt 2>&1
timeout 400 $B bench --world endless --only clouds --out-dir $OUT/clouds > $OUT/bench-clouds.txt 2>&1
mkdir -p $OUT/seq
for h in $(seq 4 0.5 21); do
  timeout 20 $B $R --frames 8 --time-of-day $h --eye 0,1900,0 --look-at 800,2600,-3000 --width 480 --height 270 --out $OUT/seq/$h.png > /dev/null 2>> $OUT/seq-err.txt
done
echo done >> $OUT/gpu.txt
