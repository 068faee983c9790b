#!/usr/bin/env bash
# Builds the web page: relief's window app (crates/app) for wasm32 plus its wasm-bindgen glue, into web/pkg/
# where index.html's web/main.js loads it. Works from a fresh Debian machine:
#   - the wasm32 standard library comes from rustup's target where that works (route A), else
#     from Debian's rustc-web packages with build-std (route B; RELIEF_WASM_ROUTE=B forces it);
#   - wasm-bindgen-cli is installed at exactly the wasm-bindgen version in Cargo.lock.
set -euo pipefail
cd "$(dirname "$0")/.."
start=$SECONDS

wb_version=$(awk '$0 == "name = \"wasm-bindgen\"" { getline; gsub(/version = |"/, ""); print }' Cargo.lock)
[ -n "$wb_version" ] || { echo "wasm-bindgen not found in Cargo.lock" >&2; exit 1; }

sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"

route=${RELIEF_WASM_ROUTE:-A}
if [ "$route" = A ]; then
    sysroot=$(rustc --print sysroot)
    if [ ! -d "$sysroot/lib/rustlib/wasm32-unknown-unknown" ]; then
        if ! rustup target add wasm32-unknown-unknown; then
            echo "rustup could not add wasm32-unknown-unknown: using Debian's rustc-web (route B)"
            route=B
        fi
    fi
fi
if [ "$route" = B ]; then
    packages="rustc-web cargo-web rust-web-src rust-web-llvm lld-22"
    if ! dpkg -s $packages >/dev/null 2>&1; then
        $sudo apt-get update -qq
        DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq $packages >/dev/null
    fi
fi

if ! command -v wasm-bindgen >/dev/null || [ "$(wasm-bindgen --version | awk '{print $2}')" != "$wb_version" ]; then
    echo "installing wasm-bindgen-cli $wb_version (matches Cargo.lock)"
    cargo install wasm-bindgen-cli --version "=$wb_version" --locked \
        || cargo install wasm-bindgen-cli --version "=$wb_version"
fi

if [ "$route" = A ]; then
    cargo build --locked --release -p relief-app --lib --target wasm32-unknown-unknown
    wasm=target/wasm32-unknown-unknown/release/relief_app.wasm
else
    RUSTC=/usr/bin/rustc RUSTC_BOOTSTRAP=1 /usr/bin/cargo build --locked --release -p relief-app --lib \
        --target wasm32-unknown-unknown -Zbuild-std=std,panic_abort --target-dir target/wasm-debian
    wasm=target/wasm-debian/wasm32-unknown-unknown/release/relief_app.wasm
fi

mkdir -p target
echo "$route" > target/wasm-route
rm -rf web/pkg
# The window app (crates/app) is the page's module; its files keep the name relief.js.
wasm-bindgen --target web --no-typescript --out-name relief --out-dir web/pkg "$wasm"
# wasm-opt (binaryen, from npm: web/package.json) shrinks the module by about a third. Without
# it the page works the same, from the larger module; the line below says which was shipped.
opt=web/node_modules/.bin/wasm-opt
if [ ! -x "$opt" ] && command -v npm >/dev/null; then
    (cd web && npm install --no-audit --no-fund --silent) || true
fi
if [ -x "$opt" ]; then
    before=$(stat -c %s web/pkg/relief_bg.wasm)
    if "$opt" -Oz --enable-bulk-memory --enable-nontrapping-float-to-int --enable-sign-ext \
        --enable-mutable-globals --enable-reference-types --enable-multivalue \
        web/pkg/relief_bg.wasm -o web/pkg/relief_bg.opt.wasm; then
        mv web/pkg/relief_bg.opt.wasm web/pkg/relief_bg.wasm
        echo "wasm-opt -Oz: $before -> $(stat -c %s web/pkg/relief_bg.wasm) bytes"
    else
        rm -f web/pkg/relief_bg.opt.wasm
        echo "wasm-opt failed: the page ships the module unoptimised ($before bytes)"
    fi
else
    echo "no wasm-opt (npm install in web/ failed): the page ships the module unoptimised"
fi
echo "web/pkg built by route $route in $((SECONDS - start)) s: $(du -h web/pkg/relief_bg.wasm | cut -f1) wasm"
