#!/usr/bin/env bash
# Builds the browser page into target/web/ (index.html, the .wasm and its JS glue, the assets): a
# static folder any file server serves, e.g. `python3 -m http.server -d target/web`.
# Installs what it lacks first: the wasm32 target (rustup) and wasm-bindgen-cli at the version
# web/Cargo.lock has (cargo install). The native build is untouched.
set -euo pipefail
cd "$(dirname "$0")/.."
say() { echo "web/build.sh: $*"; }

if ! rustup target list --installed | grep -qx wasm32-unknown-unknown; then
  say "adding Rust's wasm32-unknown-unknown target (rustup target add)"
  rustup target add wasm32-unknown-unknown
fi
# The CLI must be the very version of the wasm-bindgen crate the module is built with.
version=$(grep -A1 '^name = "wasm-bindgen"$' web/Cargo.lock | sed -n 's/^version = "\(.*\)"$/\1/p')
if ! wasm-bindgen --version 2>/dev/null | grep -qx "wasm-bindgen $version"; then
  say "installing wasm-bindgen-cli $version (cargo install: a few minutes, once)"
  if ! cargo install --locked wasm-bindgen-cli --version "$version"; then
    # A registry mirror may lack one of the CLI's locked dependencies: let cargo pick others.
    say "cargo install --locked failed: trying again without --locked"
    cargo install wasm-bindgen-cli --version "$version"
  fi
fi

# --locked: web/Cargo.lock as committed, which tests/all/web.rs checks against the root Cargo.lock
# (the versions the native tests ran); cargo says so and stops if the manifests need another.
say "building the page's module (web/: cargo build --locked --release --target wasm32-unknown-unknown)"
(cd web && cargo build --locked --release --target wasm32-unknown-unknown)

out=target/web
rm -rf "$out"
mkdir -p "$out/assets"
module=target/wasm32-unknown-unknown/release/tutorial13_web.wasm
# Optional: binaryen's wasm-opt shrinks the module (gzipped -7 %, BENCHMARKS.md), before
# wasm-bindgen: Debian 12's binaryen 108 run on wasm-bindgen's output breaks its externref table
# (the page fails to load), which the browser tests caught. The features are those Rust's wasm32
# target emits.
if command -v wasm-opt >/dev/null; then
  say "shrinking the module with wasm-opt -Os (about a minute)"
  wasm-opt -Os --enable-simd --enable-bulk-memory --enable-sign-ext --enable-nontrapping-float-to-int \
    --enable-mutable-globals --enable-reference-types --enable-multivalue \
    "$module" -o target/wasm32-unknown-unknown/release/tutorial13_web.opt.wasm
  module=target/wasm32-unknown-unknown/release/tutorial13_web.opt.wasm
else
  say "no wasm-opt (Debian: apt-get install binaryen): the module is not shrunk further"
fi
say "writing the JS glue (wasm-bindgen --target web) into $out"
wasm-bindgen --target web --no-typescript --out-dir "$out" --out-name tutorial13 "$module"
cp web/index.html web/bake-worker.js "$out/"
say "copying the crate's assets (the page fetches a scene's files when it first opens it)"
cp -r assets/. "$out/assets/"
say "done: $out ($(du -sh "$out" | cut -f1)); serve it with: python3 -m http.server -d $out"
