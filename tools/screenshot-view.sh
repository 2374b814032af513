#!/usr/bin/env bash
# Regenerate docs/view.png: `printwatt view` with the default robot and path, rendered by
# headless Chromium (software WebGL). Run from the repository root after `cargo build --release`.
set -euo pipefail
bin=${PRINTWATT_BIN:-target/release/printwatt}
out=${1:-docs/view.png}
log=$(mktemp)
"$bin" view --port 0 >"$log" 2>/dev/null &
pid=$!
trap 'kill $pid 2>/dev/null; rm -f "$log"' EXIT
for _ in $(seq 100); do grep -q http "$log" && break; sleep 0.1; done
url=$(grep -o 'http://[^ ]*' "$log")
profile=$(mktemp -d)
chromium --headless --no-sandbox --enable-unsafe-swiftshader --use-angle=swiftshader \
  --user-data-dir="$profile" --hide-scrollbars --window-size=1400,850 \
  --virtual-time-budget=10000 --screenshot="$out" "$url" 2>/dev/null
rm -rf "$profile"
echo "wrote $out"
