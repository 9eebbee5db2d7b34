#!/usr/bin/env bash
# The browser tests: builds the page (web/build.sh), serves target/web on a local port, and runs
# tests/all/web.rs, which loads it in Chromium headless (SwiftShader's WebGL2) and compares its
# frames with the native headless ones. Installs Debian's chromium when it is missing.
set -euo pipefail
cd "$(dirname "$0")/.."
say() { echo "web/test.sh: $*"; }

if ! command -v "${TUTORIAL13_CHROMIUM:-chromium}" >/dev/null; then
  say "installing chromium (apt)"
  sudo=""; [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends chromium
fi

bash web/build.sh

port=${TUTORIAL13_WEB_PORT:-8613}
say "serving target/web on port $port"
python3 -m http.server --bind 127.0.0.1 -d target/web "$port" >/dev/null 2>&1 &
server=$!
trap 'kill "$server" 2>/dev/null || true' EXIT
for _ in $(seq 50); do
  python3 -c "import urllib.request; urllib.request.urlopen('http://127.0.0.1:$port/index.html')" 2>/dev/null && break
  sleep 0.1
done

say "running the browser tests (cargo test --release -- web::)"
TUTORIAL13_WEB_URL="http://127.0.0.1:$port" TUTORIAL13_WEB_DIR="$PWD/target/web" TUTORIAL13_REQUIRE_WEB=1 \
  cargo test --release --test all -- web:: --test-threads=1 --nocapture
