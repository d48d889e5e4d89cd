#!/usr/bin/env bash
# Renders the top of reports/index.html (header, provenance, Table 1, derived
# values) to docs/report-screenshot.png for the README, with headless Chromium
# (Debian package chromium). Builds nothing: run `cargo run --release -- report`
# first if the report is stale.
#
# Usage: scripts/screenshot.sh [HEIGHT]   (default 1800; the width is 1366 px)
# PHALANX_CHROMIUM names the browser; else chromium, chromium-browser or
# google-chrome on PATH.
set -euo pipefail
cd "$(dirname "$0")/.."

width=1366
height=${1:-1800}
report=reports/index.html
out=docs/report-screenshot.png
max_bytes=600000

if [ ! -f "$report" ]; then
    echo "screenshot: $report is missing; run 'cargo run --release -- report' first" >&2
    exit 1
fi

if [ -n "${PHALANX_CHROMIUM:-}" ]; then
    browser=$(command -v "$PHALANX_CHROMIUM" || true)
    if [ -z "$browser" ] || [ ! -x "$browser" ]; then
        echo "screenshot: PHALANX_CHROMIUM=$PHALANX_CHROMIUM is not an executable" >&2
        exit 1
    fi
else
    browser=$(command -v chromium || command -v chromium-browser || command -v google-chrome || true)
fi
if [ -z "$browser" ]; then
    echo "screenshot: no Chromium found; install the Debian package chromium or set PHALANX_CHROMIUM" >&2
    exit 1
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/profile" "$(dirname "$out")"

# The flags keep a root, offline, headless Chromium from reaching for the
# network or a sandbox; timeout stops a hung browser.
timeout --kill-after=10 120 "$browser" \
    --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
    --disable-background-networking --disable-component-update --disable-sync \
    --user-data-dir="$work/profile" --hide-scrollbars \
    --force-device-scale-factor=1 --window-size="$width,$height" \
    --virtual-time-budget=5000 \
    --screenshot="$work/shot.png" "file://$PWD/$report" \
    >"$work/log" 2>&1 || {
    echo "screenshot: $browser failed; its output ends:" >&2
    tail -n 20 "$work/log" >&2
    exit 1
}
if [ ! -s "$work/shot.png" ]; then
    echo "screenshot: $browser wrote no PNG; its output ends:" >&2
    tail -n 20 "$work/log" >&2
    exit 1
fi

# Lossless recompression when the tool is there.
if command -v optipng >/dev/null 2>&1; then
    optipng -quiet -o2 -strip all "$work/shot.png"
fi

mv "$work/shot.png" "$out"
bytes=$(wc -c <"$out")
echo "screenshot: $out, ${width}x${height} px, $bytes bytes"
if [ "$bytes" -gt "$max_bytes" ]; then
    echo "screenshot: larger than $max_bytes bytes; try a smaller height, e.g. scripts/screenshot.sh 1400" >&2
fi
