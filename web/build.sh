#!/usr/bin/env bash
# Builds the thread planner page: the threadcut-web crate for wasm32, then its JS glue with
# wasm-bindgen-cli into web/www/pkg/. Installs the wasm32 target and wasm-bindgen-cli when missing.
#
#   web/build.sh          build into web/www/pkg/
#   web/build.sh --serve  build, then serve web/www on http://127.0.0.1:8000/ (PORT=… to change)
#
# No wasm-pack and no wasm-opt: Debian's binaryen (108) writes a broken module
# (docs: ../shared/reference/rust-ecosystem.md §3 in the project's notes).
set -euo pipefail
cd "$(dirname "$0")/.."

# Must equal the `wasm-bindgen = "=…"` pin in web/Cargo.toml.
WASM_BINDGEN_VERSION=0.2.130

if ! rustup target list --installed | grep -qx wasm32-unknown-unknown; then
  rustup target add wasm32-unknown-unknown
fi
if ! command -v wasm-bindgen >/dev/null 2>&1 \
    || [ "$(wasm-bindgen --version | awk '{print $2}')" != "$WASM_BINDGEN_VERSION" ]; then
  # Not --locked: the registry mirror may lag behind the lock file's versions.
  cargo install wasm-bindgen-cli --version "$WASM_BINDGEN_VERSION"
fi

# No debug info in the module (the workspace's release profile keeps some for profiling).
CARGO_PROFILE_RELEASE_DEBUG=0 cargo build --release -p threadcut-web --target wasm32-unknown-unknown
wasm-bindgen --target web --no-typescript --out-dir web/www/pkg \
  target/wasm32-unknown-unknown/release/threadcut_web.wasm
echo "built web/www/pkg/ ($(du -k web/www/pkg/threadcut_web_bg.wasm | cut -f1) KB of wasm)"

if [ "${1:-}" = "--serve" ]; then
  port="${PORT:-8000}"
  echo "threadcut planner: http://127.0.0.1:$port/"
  exec python3 -m http.server "$port" --bind 127.0.0.1 --directory web/www
fi
