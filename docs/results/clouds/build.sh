#!/bin/bash
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export XDG_RUNTIME_DIR=$(mktemp -d)
export __GL_SHADER_DISK_CACHE=0
nvidia-smi --query-gpu=name,driver_version --format=csv > $OUT/gpu.txt 2>&1
R="render --world endless --width 1920 --height 1080 --timings"
run() { # label binary args...
  local l=$1 b=$2; shift 2
  export __GL_SHADER_DISK_CACHE_PATH=$(mktemp -d)
  local t0=$EPOCHREALTIME
  timeout 60 $b $R --out /tmp/x.png "$@" > /tmp/o.txt 2>&1
  local rc=$? t1=$EPOCHREALTIME
  echo "$l rc=$rc wall_s=$(awk "BEGIN{print $t1 - $t0}") $(grep -m1 timings /tmp/o.txt)" >> $OUT/toggle.txt
}
.bin/relief $R --out /tmp/w.png > /dev/null 2>&1
for i in 1 2; do  # .bin/relief-old: the binary of the previous H200 runs (docs/results/clouds.md), every pipeline with the march
  for m in visibility hybrid; do
    run "new $m no-clouds" .bin/relief --method $m
    run "new $m clouds" .bin/relief --method $m --cloud-coverage 0.5
    run "old $m no-clouds" .bin/relief-old --method $m
  done
  run "new raymarch no-clouds" .bin/relief --method raymarch
  run "old raymarch no-clouds" .bin/relief-old --method raymarch
done
for b in relief relief-old; do
  timeout 150 .bin/$b bench --world endless --only look --out-dir $OUT/look-$b > $OUT/look-$b.txt 2>&1
done
echo done >> $OUT/gpu.txt
