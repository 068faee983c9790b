#!/usr/bin/env bash
# The run behind "The tile's bake by quads" in docs/bench/README.md, through the device tool
# from the repository root: the release binaries before (.devbin/relief) and after
# (.devbin/relief-new) the change and the Vulkan loader's .debs in .gl/ carried. Each bake is
# timed twice per binary; the PNGs of the two binaries are compared byte for byte.
set -uo pipefail
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
out=$OUT/bake; mkdir -p $out
for i in 1 2; do
  for b in relief relief-new; do
    echo "== $b tile 4096, 8 octaves ($i)"; .devbin/$b bake --size 4096 --timings --out-dir /tmp/$b-8 2>&1 | grep timings
    echo "== $b tile 4096, 16 octaves freq 1 ($i)"; .devbin/$b bake --size 4096 --octaves 16 --frequency 1 --timings --out-dir /tmp/$b-16 2>&1 | grep timings
    echo "== $b tile 4096, 10 octaves freq 2 ($i)"; .devbin/$b bake --size 4096 --octaves 10 --frequency 2 --timings --out-dir /tmp/$b-10 2>&1 | grep timings
    echo "== $b region 4096, 12 octaves ($i)"; .devbin/$b bake --world endless --region 0,0,4096,4096 --size 4096 --timings --out-dir /tmp/$b-r 2>&1 | grep timings
  done
done 2>&1 | tee $out/bake-timings.txt
for n in 8 10 16; do for f in height.png color.png normal.png; do cmp -s /tmp/relief-$n/$f /tmp/relief-new-$n/$f && echo "$n $f same" || echo "$n $f differs"; done; done | tee $out/png-same.txt
