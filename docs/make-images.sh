#!/usr/bin/env bash
# Makes the pictures of README.md and docs/ from a build, so none is pasted by hand:
#   docs/images/frame.png   the last frame of the README's main command (the map's street shot)
#   docs/images/report.png  the top of that capture's HTML report, as headless Chromium shows it
# Usage: docs/make-images.sh [BUILD_DIR]   (default: build/). Needs oiiotool and chromium, which
# tests/install-deps.sh installs.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$(cd "${1:-$root/build}" && pwd)"
images="$root/docs/images"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# The README's main command, into a scratch folder.
"$build/nightcap" render -o "$work/map" --force
"$build/nightcap" report "$work/map" -o "$work/map-report" --force

mkdir -p "$images"
# Half size keeps the file small; the full frame is one command away.
oiiotool --nosoftwareattrib "$work/map/final.png" --resize 640x360 -o "$images/frame.png"

# The same flags as the tests' browser (tests/e2e/browser.cpp): headless, no sandbox (root in a
# container), no GPU.
chromium --headless --no-sandbox --disable-gpu --no-first-run --hide-scrollbars \
  --user-data-dir="$work/chromium-profile" --window-size=1280,900 \
  --screenshot="$work/report.png" "file://$work/map-report/index.html" 2>"$work/chromium.log" ||
  { cat "$work/chromium.log" >&2; exit 2; }
oiiotool --nosoftwareattrib "$work/report.png" --resize 960x675 -o "$images/report.png"

ls -l "$images"
