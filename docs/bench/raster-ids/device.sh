#!/usr/bin/env bash
set -uo pipefail
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
out=$OUT/ids
mkdir -p "$out"
views=(
    "horizon --world endless --eye 0,1202,0 --look-at 1,1201.99,0.2"
    "ridge --world endless --eye 5730,1198.7011293135074,1000 --look-at 5730.3,1198.6811293135074,1001"
    "oblique --world endless --eye -5000,4195.8573366294322,2000 --look-at -4999.2,4195.3573366294322,2000.33"
    "default --world endless"
)
for i in 1 2; do
    for v in "${views[@]}"; do
        set -- $v
        name=$1
        shift
        for m in visibility hybrid; do
            for b in base ids; do
                bin=.devbin/relief
                [ $b = base ] && bin=.devbin/relief-base
                echo "== $name $m $b ($i)"
                $bin render --width 1920 --height 1080 --timings --out "/tmp/$name-$m-$b.png" "$@" --method $m --samples 1 --raster compute | grep -E "timings"
            done
        done
    done
done 2>&1 | tee "$out/raster-ids.txt"
cp /tmp/*-visibility-*.png "$out/" 2>/dev/null
nvidia-smi --query-gpu=name,driver_version --format=csv > "$out/gpu.txt"
# ---- the landscape benchmark, render's choice, and the resolve's share (a temporary switch, RELIEF_PROF_NORESOLVE, not committed) ----
export RELIEF_FONT=.devbin/DejaVuSans.ttf
out=$OUT/raster-ids
mkdir -p "$out"
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv >"$out/gpu-bench.txt" 2>&1
time timeout 500 .devbin/relief bench --world endless --out-dir "$out/landscape" \
    >"$out/landscape-stdout.txt" 2>"$out/landscape-stderr.txt"
tail -n 3 "$out/landscape-stdout.txt"
views=(
    "horizon --world endless --eye 0,1202,0 --look-at 1,1201.99,0.2"
    "ridge --world endless --eye 5730,1198.7011293135074,1000 --look-at 5730.3,1198.6811293135074,1001"
    "oblique --world endless --eye -5000,4195.8573366294322,2000 --look-at -4999.2,4195.3573366294322,2000.33"
    "default --world endless"
    "tile"
)
for v in "${views[@]}"; do
    set -- $v
    name=$1
    shift
    echo "== $name auto"
    timeout 30 .devbin/relief render --width 1920 --height 1080 --timings --out "/tmp/$name-auto.png" "$@"
done 2>&1 | tee "$out/render-auto.txt"
for i in 1 2; do
for v in "${views[@]:0:3}"; do
    set -- $v
    name=$1
    shift
    for p in shipped noresolve; do
        echo "== $name $p ($i)"
        if [ $p = noresolve ]; then export RELIEF_PROF_NORESOLVE=1; else unset RELIEF_PROF_NORESOLVE; fi
        timeout 30 .devbin/relief-prof render --width 1920 --height 1080 --timings --out "/tmp/$name-p.png" "$@" --method visibility --samples 1 --raster compute | grep timings
    done
done
done 2>&1 | tee "$out/resolve-split.txt"
# ---- a workgroup a block of 8x8 cells (blocks) against a thread a cell (ids) ----
out=$OUT/blocks
mkdir -p "$out"
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
        for b in ids blocks; do
            bin=.devbin/relief
            [ $b = ids ] && bin=.devbin/relief-ids
            echo "== $name $b ($i)"
            $bin render --width 1920 --height 1080 --timings --out "/tmp/$name-$b.png" "$@" --method visibility --samples 1 --raster compute | grep -E "timings"
        done
    done
done 2>&1 | tee "$out/raster-blocks.txt"
for v in horizon ridge oblique default tile; do cmp -s /tmp/$v-ids.png /tmp/$v-blocks.png && echo "$v identical" || echo "$v differs"; done | tee "$out/blocks-identical.txt"
# Here, on the first part's PNGs: python3 compare.py <their folder> > pixels-ids.txt
