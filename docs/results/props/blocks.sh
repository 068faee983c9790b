#!/bin/bash
# Two builds that marched the props' shadow and occlusion on the surface a 4x4 block at a time
# (blocks-agree.diff: a pixel takes them bilinearly between its four nearest blocks where those
# agree within 1/16, else marches its own; blocks-always.diff: it takes them wherever the four
# blocks' points lie within 10% of its own distance) against the build before (.devbin/relief-base:
# 2x2 blocks, each pixel its own block's). The full benchmark on eight views with props in view,
# NVIDIA H200, 1920x1080; rows in blocks-before.csv, blocks-agree.csv and blocks-always.csv.
# .devbin/relief-new was each of the two builds in turn (the second run in a later call, the
# base not run again there).
# (A first pass with --quick, lavapipe's size, timed too noisily to read: 2-5x between two runs
# of the same build.)
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export XDG_RUNTIME_DIR=$(mktemp -d)
mkdir -p /usr/share/fonts/truetype/dejavu; cp .devbin/DejaVuSans.ttf /usr/share/fonts/truetype/dejavu/
nvidia-smi --query-gpu=name,driver_version --format=csv > $OUT/gpu.txt 2>&1
V=among-2m,meadow,over-200m,random-3,random-7,random-9,random-12,random-15
timeout 30 .devbin/relief-new bench --world endless --only props --quick --view meadow --out-dir /tmp/warm > /dev/null 2>&1
for b in base new; do
  timeout 290 .devbin/relief-$b bench --world endless --only props --view $V --out-dir /tmp/$b > $OUT/$b.txt 2>&1
  cp /tmp/$b/props.csv $OUT/$b.csv
done
