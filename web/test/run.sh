#!/usr/bin/env bash
# The web page's tests, from a fresh Debian machine: installs Chromium and ChromeDriver if
# missing, builds the page (web/build.sh), then in headless Chromium with WebGPU:
#   - wasm-bindgen-test: the bake's heights match the CPU twin (crates/app/tests/web.rs);
#   - Playwright: the page renders, controls and URL work, no console errors, and the page
#     without WebGPU explains itself (web/test/page.mjs);
#   - FLIP: the page's canvas against `relief render` of the same scene and size.
set -euo pipefail
cd "$(dirname "$0")/../.."

sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
missing=""
[ -x /usr/bin/chromium ] || missing="$missing chromium"
[ -x /usr/bin/chromedriver ] || missing="$missing chromium-driver"
command -v npm >/dev/null || missing="$missing nodejs npm"
if [ -n "$missing" ]; then
    echo "installing:$missing"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq $missing >/dev/null
fi
(cd web && npm install --no-audit --no-fund --silent)

bash web/build.sh
route=$(cat target/wasm-route)

out=web/test-output
mkdir -p "$out"
profile=$(mktemp -d)
cat > "$out/webdriver.json" <<JSON
{"goog:chromeOptions": {"binary": "/usr/bin/chromium", "args": ["--headless", "--no-sandbox",
 "--no-first-run", "--disable-background-networking", "--disable-component-update",
 "--disable-sync", "--disable-quic", "--enable-unsafe-webgpu", "--user-data-dir=$profile"]}}
JSON

echo "== wasm-bindgen-test in Chromium (crates/app/tests/web.rs)"
export CARGO_TARGET_WASM32_UNKNOWN_UNKNOWN_RUNNER=wasm-bindgen-test-runner
export CHROMEDRIVER=/usr/bin/chromedriver
export WASM_BINDGEN_TEST_WEBDRIVER_JSON="$PWD/$out/webdriver.json"
export WASM_BINDGEN_TEST_TIMEOUT=300
if [ "$route" = A ]; then
    cargo test --locked --release -p relief-app --target wasm32-unknown-unknown --test web
else
    RUSTC=/usr/bin/rustc RUSTC_BOOTSTRAP=1 /usr/bin/cargo test --locked --release -p relief-app \
        --target wasm32-unknown-unknown -Zbuild-std=std,panic_abort --target-dir target/wasm-debian --test web
fi

echo "== page tests in Chromium (web/test/page.mjs)"
node web/test/page.mjs

# The program and the FLIP tool, built as `cargo test --workspace` builds them (the workspace's
# features): after the tests, nothing is built twice (`cargo run --bin relief` alone would unify
# other features and rebuild wgpu, twice).
cargo build --locked --quiet --workspace --bin relief --example flip
relief=target/debug/relief
flip=target/debug/examples/flip

echo "== page against relief render (FLIP)"
"$relief" render --out "$out/native.png" --width 256 --height 192 \
    --seed 7 --size 256 --grid 128 --method mesh
# The page draws the mesh unless told: `--method mesh`, as relief render's default (auto)
# measures which method is fastest on this machine's GPU.
# SwiftShader (Chromium's CPU WebGPU) against lavapipe: the same shaders and inputs; what
# differs is rasterisation, MSAA resolve (the canvas is not sRGB, so edges blend in encoded
# space) and rounding. Measured: mean 0.028 for the same scene, 0.25 for seed 8 against seed 7.
# 0.05 accepts the first and rejects the second by a wide margin (checked below).
max_mean=0.05
"$flip" "$out/native.png" "$out/page.png" \
    --max-mean "$max_mean" --diff "$out/page-vs-native.png"
"$flip" "$out/native.png" "$out/page-seed8.png" > "$out/control.txt"
cat "$out/control.txt"
control=$(sed -n 's/.*mean \([0-9.]*\),.*/\1/p' "$out/control.txt")
awk -v c="$control" -v m="$max_mean" 'BEGIN { if (c <= m) { print "the FLIP threshold cannot tell seed 8 from seed 7"; exit 1 } }'

echo "== the page's visibility method against relief render --method visibility (FLIP)"
"$relief" render --out "$out/native-visibility.png" --width 256 \
    --height 192 --seed 7 --size 256 --grid 128 --method visibility
"$flip" "$out/native-visibility.png" "$out/page-visibility.png" \
    --max-mean "$max_mean" --diff "$out/page-vs-native-visibility.png"
"$flip" "$out/native-visibility.png" "$out/page-seed8.png" \
    > "$out/control-visibility.txt"
cat "$out/control-visibility.txt"
control=$(sed -n 's/.*mean \([0-9.]*\),.*/\1/p' "$out/control-visibility.txt")
awk -v c="$control" -v m="$max_mean" 'BEGIN { if (c <= m) { print "the FLIP threshold cannot tell seed 8 from the visibility method'"'"'s seed 7"; exit 1 } }'

echo "== the endless world's page against relief render (FLIP)"
"$relief" render --out "$out/native-endless.png" --width 256 \
    --height 192 --world endless --seed 3 --pixel-error 16 --no-grass --method mesh
# The same tolerance: measured mean 0.021 for the same view; the control (the page after W was
# held for 1.5 s, a view some 300 m on) scored 0.096.
"$flip" "$out/native-endless.png" "$out/page-endless.png" \
    --max-mean "$max_mean" --diff "$out/page-vs-native-endless.png"
"$flip" "$out/native-endless.png" "$out/page-endless-flown.png" > "$out/control-endless.txt"
cat "$out/control-endless.txt"
control=$(sed -n 's/.*mean \([0-9.]*\),.*/\1/p' "$out/control-endless.txt")
awk -v c="$control" -v m="$max_mean" 'BEGIN { if (c <= m) { print "the FLIP threshold cannot tell the flown view from the first"; exit 1 } }'
echo "== the page's ray march against relief render --method raymarch (FLIP)"
"$relief" render --out "$out/native-endless-raymarch.png" --width 256 \
    --height 192 --world endless --seed 3 --pixel-error 16 --no-grass --method raymarch
"$flip" "$out/native-endless-raymarch.png" \
    "$out/page-endless-raymarch.png" --max-mean "$max_mean" --diff "$out/page-vs-native-raymarch.png"
"$flip" "$out/native-endless.png" "$out/page-endless-raymarch.png" \
    > "$out/control-raymarch.txt"
cat "$out/control-raymarch.txt"
echo "== the page's hybrid against relief render --method hybrid (FLIP)"
"$relief" render --out "$out/native-endless-hybrid.png" --width 256 \
    --height 192 --world endless --seed 3 --pixel-error 16 --no-grass --method hybrid
"$flip" "$out/native-endless-hybrid.png" \
    "$out/page-endless-hybrid.png" --max-mean "$max_mean" --diff "$out/page-vs-native-hybrid.png"
echo "web tests passed"
