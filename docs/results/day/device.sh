#!/bin/bash
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export XDG_RUNTIME_DIR=$(mktemp -d)
nvidia-smi --query-gpu=name,driver_version --format=csv > $OUT/gpu.txt 2>&1
B=.bin/relief
mkdir -p /usr/share/fonts/truetype/dejavu; cp .bin/DejaVuSans.ttf /usr/share/fonts/truetype/dejavu/
timeout 300 $B bench --world endless --only arrival --out-dir $OUT/arrival > $OUT/bench-arrival.txt 2>&1
for h in 12 19.3; do
  timeout 60 $B render --world endless --method mesh --time-of-day $h --width 1920 --height 1080 --out $OUT/day-$h.png --timings > $OUT/render-$h.txt 2>&1
done
mkdir -p $OUT/seq
for h in $(seq 4 0.5 21); do
  timeout 30 $B render --world endless --method mesh --time-of-day $h --width 480 --height 270 --out $OUT/seq/$h.png > /dev/null 2>> $OUT/seq-err.txt
done
echo done >> $OUT/gpu.txt
