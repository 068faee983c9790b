#!/usr/bin/env bash
# The H100 runs behind docs/bench/present/README.md, through the device tool, from the
# repository root, with the release binaries in .devbin/ (relief: this change; relief-old: the
# commit before it, 592d1f9) and the Vulkan loader's .debs in .gl/ carried (see the tool's
# README). `render-timings.txt`: one 1080p frame of each view with each method, both binaries,
# twice. `render-auto.txt`: `relief render`'s default (auto) on each view, twice. Then, in a call
# of its own, `relief bench --world endless` in full (`bench`); in a third, `relief bench` of the
# tile in full and `relief render`'s default on each view again (`tile`); in a fourth, the present
# timed to an empty pass after its copy (`end`). (raster-variants.txt came from a temporary
# switch in src/gpu/raster.rs, not committed: see the README.) (The variants files
# came from calls with temporary switches, not committed: see the README.)
set -uo pipefail
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
export RELIEF_FONT=.devbin/DejaVuSans.ttf
out=$OUT/present
mkdir -p "$out"
nvidia-smi --query-gpu=name,driver_version,clocks.sm,clocks.max.sm --format=csv >"$out/gpu.txt" 2>&1
views=(
    "default --world endless"
    "horizon --world endless --eye 0,1202,0 --look-at 1,1201.99,0.2"
    "ridge --world endless --eye 5730,1198.7011293135074,1000 --look-at 5730.3,1198.6811293135074,1001"
    "oblique --world endless --eye -5000,4195.8573366294322,2000 --look-at -4999.2,4195.3573366294322,2000.33"
    "tile"
)
if [ "${1:-render}" = render ]; then
    for i in 1 2; do
        for bin in old new; do
            R=.devbin/relief; [ $bin = old ] && R=.devbin/relief-old
            for v in "${views[@]}"; do
                set -- $v
                name=$1
                shift
                for m in "visibility --samples 1 --raster compute" "hybrid --samples 1 --raster compute" "visibility --samples 1"; do
                    [ "$name" = tile ] && [ "${m%% *}" = hybrid ] && continue
                    echo "== $bin $name, --method $m ($i)"
                    $R render --width 1920 --height 1080 --timings --out "/tmp/$bin-$name-${m// /_}.png" "$@" --method $m
                done
            done
        done
    done 2>&1 | tee "$out/render-timings.txt"
    for i in 1 2; do
        for v in "${views[@]}"; do
            set -- $v
            name=$1
            shift
            echo "== auto $name ($i)"
            .devbin/relief render --width 1920 --height 1080 --timings --out "/tmp/auto-$name.png" "$@"
        done
    done 2>&1 | tee "$out/render-auto.txt"
elif [ "$1" = tile ]; then
    for v in "${views[@]}"; do
        set -- $v
        name=$1
        shift
        echo "== auto $name"
        .devbin/relief render --width 1920 --height 1080 --timings --out "/tmp/auto-$name.png" "$@"
    done 2>&1 | tee "$out/render-auto-final.txt"
    time timeout 500 .devbin/relief bench --out-dir "$out/tile" >"$out/bench-stdout.txt" 2>"$out/bench-stderr.txt"
    tail -n 40 "$out/bench-stdout.txt"
elif [ "$1" = end ]; then
    # The present timed to an empty pass after its copy (the final binary).
    for i in 1 2; do
        for v in "${views[@]:3:2}"; do
            set -- $v
            name=$1
            shift
            echo "== $name ($i)"
            .devbin/relief render --width 1920 --height 1080 --timings --out "/tmp/$name.png" "$@" \
                --method visibility --samples 1 --raster compute
        done
    done 2>&1 | tee "$out/render-end-pass.txt"
else
    time timeout 575 .devbin/relief bench --world endless --out-dir "$out/landscape" \
        >"$out/landscape-stdout.txt" 2>"$out/landscape-stderr.txt"
fi
