#!/bin/bash
# The terrain's shadows in the light shafts on the device: the clouds' benchmark's costs (25
# views; cut short after them), pictures by this build (.devbin/relief) and the one before it
# (.devbin/relief-old: the clouds' shafts only), and the reference's time with the shafts.
for f in .gl/*.deb; do dpkg -x $f /; done; ldconfig
export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
export XDG_RUNTIME_DIR=$(mktemp -d)
mkdir -p /usr/share/fonts/truetype/dejavu; cp .devbin/DejaVuSans.ttf /usr/share/fonts/truetype/dejavu/
nvidia-smi --query-gpu=name,driver_version --format=csv > $OUT/gpu.txt 2>&1
B=.devbin
timeout 100 $B/relief bench --world endless --only clouds --quick --out-dir /tmp/warm > /tmp/warm.txt 2>&1
echo "warm rc $?" >> $OUT/gpu.txt
mkdir -p /tmp/p
M="--method visibility --samples 1 --raster compute"
R="render --world endless --frames 32 --width 1920 --height 1080 --timings --stats $M"
A="--cloud-coverage 0.2 --fog 0.2 --sun-azimuth 150 --sun-elevation 5 --fov 60 --eye -4500,1450,1500 --look-at -2778,1420,3957"
V="--cloud-coverage 0.3 --fog 0.2 --sun-azimuth 150 --sun-elevation 13 --fov 60 --eye -4500,1160,1500 --look-at -2778,1390,3957 --no-grass"
T="--cloud-coverage 0.5 --fog 0.2 --sun-azimuth 145 --sun-elevation 8 --eye 0,1900,0 --look-at 1720,2200,2457"
for b in relief relief-old; do
  for v in A V T; do
    timeout 60 $B/$b $R ${!v} --out /tmp/p/$b-$v.png > /tmp/p/$b-$v.txt 2>&1
  done
  timeout 60 $B/$b render --world endless --method reference --width 960 --height 540 --timings $A --out /tmp/p/$b-A-ref.png > /tmp/p/$b-A-ref.txt 2>&1
done
grep -H timings /tmp/p/*.txt > $OUT/timings.txt
grep -H "shafts_mib\|method_texture" /tmp/p/*.txt >> $OUT/timings.txt
(cd /tmp/p && tar cf $OUT/pictures.tar *.png)
echo "pictures done $SECONDS" >> $OUT/gpu.txt
timeout 330 $B/relief bench --world endless --only clouds --out-dir $OUT/clouds > $OUT/bench-clouds.txt 2>&1
echo "bench rc $? $SECONDS" >> $OUT/gpu.txt
