#!/usr/bin/env bash
# Renders the top of reports/index.html to docs/report-screenshot.png with
# headless Chromium (Debian package chromium), for the README.
set -euo pipefail
cd "$(dirname "$0")/.."
browser=${PHALANX_CHROMIUM:-$(command -v chromium || command -v chromium-browser || true)}
if [ -z "$browser" ]; then
    echo "screenshot: no Chromium found; apt-get install chromium" >&2
    exit 1
fi
profile=$(mktemp -d)
trap 'rm -rf "$profile"' EXIT
"$browser" --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
    --disable-background-networking --disable-component-update --disable-sync \
    --user-data-dir="$profile" --hide-scrollbars --window-size=1366,1500 \
    --screenshot="$PWD/docs/report-screenshot.png" "file://$PWD/reports/index.html" 2>/dev/null
ls -l docs/report-screenshot.png
