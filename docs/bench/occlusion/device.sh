# The passes' variants on the H100 (h100-passes.txt): blocks = be5d93b, cull = 3 passes [2, 5], p4 = 4 passes [2, 4, 7] (committed)
#!/usr/bin/env bash
set -uo pipefail
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
out=$OUT/cull
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
        for b in blocks cull p4; do
            bin=.devbin/relief
            [ $b = blocks ] && bin=.devbin/relief-blocks
            [ $b = p4 ] && bin=.devbin/relief-p4
            echo "== $name $b ($i)"
            $bin render --width 1920 --height 1080 --timings --out "/tmp/$name-$b.png" "$@" --method visibility --samples 1 --raster compute | grep -E "timings"
        done
    done
done 2>&1 | tee "$out/raster-cull.txt"
for v in horizon ridge oblique default tile; do for b in cull p4; do cmp -s /tmp/$v-blocks.png /tmp/$v-$b.png && echo "$v $b identical" || echo "$v $b differs"; done; done | tee "$out/cull-identical.txt"


# The landscape benchmark and render's choice with the committed binary
export RELIEF_FONT=.devbin/DejaVuSans.ttf
out=$OUT/occlusion
mkdir -p "$out"
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv >"$out/gpu-bench.txt" 2>&1
time timeout 500 .devbin/relief-p4 bench --world endless --out-dir "$out/landscape" \
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
    timeout 30 .devbin/relief-p4 render --width 1920 --height 1080 --timings --out "/tmp/$name-auto.png" "$@"
done 2>&1 | tee "$out/render-auto.txt"

# The depth held at the nearest corner (clamp) against the benchmarked binary (blocks = 6fdced0)
out=$OUT/clamp
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
        for b in blocks clamp; do
            bin=.devbin/relief
            [ $b = blocks ] && bin=.devbin/relief-blocks
            
            echo "== $name $b ($i)"
            $bin render --width 1920 --height 1080 --timings --out "/tmp/$name-$b.png" "$@" --method visibility --samples 1 --raster compute | grep -E "timings"
        done
    done
done 2>&1 | tee "$out/raster-clamp.txt"
for v in horizon ridge oblique default tile; do for b in clamp; do cmp -s /tmp/$v-blocks.png /tmp/$v-$b.png && echo "$v $b identical" || echo "$v $b differs"; done; done | tee "$out/clamp-identical.txt"

for v in horizon ridge; do cp /tmp/$v-blocks.png /tmp/$v-clamp.png "$out/"; done
