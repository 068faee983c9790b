#!/bin/bash
# The running day with clouds (coverage 0.5, the default haze): what the light shafts'
# shadow-height map adds to a moving sun's cost. Run on the device machine that had just run
# ../clouds/terrain-shafts-3.sh (warm).
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export XDG_RUNTIME_DIR=$(mktemp -d)
mkdir -p /usr/share/fonts/truetype/dejavu; cp .devbin/DejaVuSans.ttf /usr/share/fonts/truetype/dejavu/
timeout 200 .devbin/relief bench --world endless --only arrival --cloud-coverage 0.5 --out-dir $OUT/arrival > $OUT/bench-arrival.txt 2>&1
