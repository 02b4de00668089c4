#!/usr/bin/env bash
# The studio in the browser (docs/web.md).
#
#   scripts/web.sh build [DIR]   builds the static site into DIR (default target/web): index.html,
#                                the JavaScript glue and the WebAssembly module; host it anywhere
#   scripts/web.sh serve [PORT]  builds it into target/web and serves it on http://localhost:PORT
#                                (default 8080) until interrupted
#
# Installs what it needs when missing: the wasm32-unknown-unknown target (rustup), wasm-bindgen-cli
# of the version in Cargo.lock (cargo install), and clang with llvm-ar (apt-get, on Debian), which
# compile meshoptimizer's C++ for WebAssembly. Runs wasm-opt -Os on the module when wasm-opt is
# installed (binaryen); it is optional.
#
# WEB_PROFILE picks the cargo profile (default `web-release`: the release profile, optimised for
# size).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
profile=${WEB_PROFILE:-web-release}

usage() {
  sed -n '2,15p' "$0" | sed 's/^# \{0,1\}//'
  exit 2
}

install_tools() {
  if ! rustup target list --installed | grep -qx wasm32-unknown-unknown; then
    rustup target add wasm32-unknown-unknown
  fi
  # wasm-bindgen's command must be the same version as the wasm-bindgen crate the module uses.
  local version
  version=$(awk '/^name = "wasm-bindgen"$/ { getline; gsub(/[^0-9.]/, ""); print; exit }' Cargo.lock)
  if [ "$(wasm-bindgen --version 2>/dev/null | awk '{print $2}')" != "$version" ]; then
    # --locked first; without it when the lock file names a crate the registry no longer has.
    cargo install wasm-bindgen-cli --version "$version" --locked ||
      cargo install wasm-bindgen-cli --version "$version"
  fi
  if ! command -v clang >/dev/null 2>&1 || ! command -v llvm-ar >/dev/null 2>&1; then
    if command -v apt-get >/dev/null 2>&1 && [ "$(id -u)" = 0 ]; then
      DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends clang llvm
    else
      echo "error: the web build needs clang and llvm-ar (Debian: apt-get install clang llvm)" >&2
      exit 1
    fi
  fi
}

build() {
  local out=$1
  install_tools
  # meshoptimizer (through the meshopt crate) is C++ compiled with clang for wasm32 against
  # stripped-down headers that lack a few math functions; this header supplies them.
  export CFLAGS_wasm32_unknown_unknown="-include $root/scripts/web/meshopt-wasm.h"
  # A cdylib only here: native builds of the workspace keep orbifold-web a plain library.
  cargo rustc -p orbifold-web --lib --locked --target wasm32-unknown-unknown --profile "$profile" \
    --crate-type cdylib
  local target_dir
  target_dir=$(cargo metadata --format-version 1 --no-deps | python3 -c 'import json,sys; print(json.load(sys.stdin)["target_directory"])')
  local wasm="$target_dir/wasm32-unknown-unknown/$profile/orbifold_web.wasm"
  mkdir -p "$out"
  rm -f "$out"/orbifold_studio*
  wasm-bindgen --target web --no-typescript --out-dir "$out" --out-name orbifold_studio "$wasm"
  if command -v wasm-opt >/dev/null 2>&1; then
    wasm-opt -Os --enable-bulk-memory --enable-nontrapping-float-to-int --enable-sign-ext \
      --enable-mutable-globals "$out/orbifold_studio_bg.wasm" -o "$out/orbifold_studio_bg.wasm"
  fi
  cp scripts/web/index.html "$out/index.html"
  local bytes gz
  bytes=$(stat -c %s "$out/orbifold_studio_bg.wasm")
  gz=$(gzip -9 -c "$out/orbifold_studio_bg.wasm" | wc -c)
  echo "web studio: $out (module $((bytes / 1024)) KiB, $((gz / 1024)) KiB gzipped)"
}

case "${1:-build}" in
  build)
    build "${2:-target/web}"
    ;;
  serve)
    port=${2:-8080}
    build target/web
    echo "serving http://localhost:$port/ (Ctrl+C stops)"
    exec python3 -m http.server "$port" --bind 127.0.0.1 --directory target/web
    ;;
  *)
    usage
    ;;
esac
