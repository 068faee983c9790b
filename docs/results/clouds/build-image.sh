#!/bin/bash
# The wall time of a whole `relief render` with and without clouds, the temporal service on
# (--frames 2: the clouds' image and its passes are built), the driver's shader cache off.
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export XDG_RUNTIME_DIR=$(mktemp -d)
export __GL_SHADER_DISK_CACHE=0
R="render --world endless --width 1920 --height 1080 --method visibility --samples 1 --raster compute"
run() { # label args...
  local l=$1; shift
  export __GL_SHADER_DISK_CACHE_PATH=$(mktemp -d)
  local t0=$EPOCHREALTIME
  timeout 60 .bin/relief $R --out /tmp/x.png "$@" > /tmp/o.txt 2>&1
  local rc=$? t1=$EPOCHREALTIME
  echo "$l rc=$rc wall_s=$(awk "BEGIN{print $t1 - $t0}")" >> $OUT/build.txt
}
.bin/relief $R --out /tmp/w.png > /dev/null 2>&1
for i in 1 2 3; do
  run "frames=1 no-clouds"
  run "frames=1 clouds" --cloud-coverage 0.5
  run "frames=2 no-clouds" --frames 2
  run "frames=2 clouds (image)" --frames 2 --cloud-coverage 0.5
done
