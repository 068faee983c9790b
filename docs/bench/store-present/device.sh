#!/usr/bin/env bash
# The present stored straight into relief render's image (4ff749b, "new") against the packed
# buffer and copy (87b5f52, "old"): the default frame's time on five views, both binaries, twice;
# the frames' bytes compared; then the landscape benchmark with the new binary.
set -uo pipefail
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
export RELIEF_FONT=.devbin/DejaVuSans.ttf
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv >"$OUT/gpu.txt" 2>&1
views=(
    "horizon --world endless --eye 0,1202,0 --look-at 1,1201.99,0.2"
    "ridge --world endless --eye 5730,1198.7011293135074,1000 --look-at 5730.3,1198.6811293135074,1001"
    "oblique --world endless --eye -5000,4195.8573366294322,2000 --look-at -4999.2,4195.3573366294322,2000.33"
    "default --world endless"
    "tile"
)
for i in 1 2; do
    for v in "${views[@]}"; do
        set -- $v
        name=$1
        shift
        for b in old new; do
            echo "== $name $b ($i)"
            timeout 60 .devbin/relief-$b render --width 1920 --height 1080 --timings --out "/tmp/$name-$b.png" "$@" 2>&1 | grep -v "^relief: --pixel-error"
        done
    done
done >"$OUT/render-timings.txt" 2>&1
python3 - >"$OUT/bytes.txt" 2>&1 <<'PY'
import numpy as np
from PIL import Image
for v in ["horizon", "ridge", "oblique", "default", "tile"]:
    a = np.asarray(Image.open(f"/tmp/{v}-old.png")).astype(int)
    b = np.asarray(Image.open(f"/tmp/{v}-new.png")).astype(int)
    d = b - a
    print(f"{v}: {np.count_nonzero(d)} of {d.size} values differ; +1: {np.count_nonzero(d == 1)}, -1: {np.count_nonzero(d == -1)}, most {np.abs(d).max()}")
PY
( time timeout 480 .devbin/relief-new bench --world endless --out-dir /tmp/landscape ) >"$OUT/landscape-stdout.txt" 2>&1
cp /tmp/landscape/landscape.csv /tmp/landscape/landscape.png /tmp/landscape/look.csv "$OUT/"
