#!/usr/bin/env bash
# The H100 run of the scroll axis (docs/stability/README.md, "The scroll axis"), through the
# device tool, from the repository root, with the release binary in .devbin/relief, a font in
# .devbin/ and the Vulkan loader's .debs in .gl/ carried (see the tool's README). Everything
# lands in $OUT/scroll.tar.gz.
set -uo pipefail
for f in .gl/*.deb; do dpkg -x "$f" /; done
ldconfig
R=.devbin/relief
export RELIEF_FONT=.devbin/DejaVuSans.ttf
out=/tmp/scroll
mkdir -p "$out"
nvidia-smi --query-gpu=name,driver_version --format=csv >"$out/gpu.txt" 2>&1
/usr/bin/time -f "wall %e s" $R stability --axis scroll --out-dir "$out/stability" 2>&1 | tee "$out/stability-stdout.txt"
tar -czf "$OUT/scroll.tar.gz" -C /tmp scroll
