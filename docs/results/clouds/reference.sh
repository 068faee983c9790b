#!/bin/bash
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export XDG_RUNTIME_DIR=$(mktemp -d)
mkdir -p /usr/share/fonts/truetype/dejavu; cp .bin/DejaVuSans.ttf /usr/share/fonts/truetype/dejavu/
nvidia-smi --query-gpu=name,driver_version --format=csv > $OUT/gpu.txt 2>&1
timeout 570 .bin/relief bench --world endless --only clouds --out-dir $OUT/clouds > $OUT/bench-clouds.txt 2>&1
echo "rc $?" >> $OUT/gpu.txt
