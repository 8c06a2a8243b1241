#!/usr/bin/env bash
# A picture of report.html as a browser shows it (headless Chromium: apt-get install chromium):
#   tools/screenshot_report.sh runs/dambreak/report.html docs/figures/report_html.png
# Used to check that the self-contained report renders (docs/figures/report_html.png).
set -euo pipefail
page=$(realpath "$1")
out=$2
browser=$(command -v chromium || command -v chromium-browser || true)
[ -n "$browser" ] || { echo "screenshot_report: no chromium (apt-get install chromium)" >&2; exit 1; }
timeout 120 "$browser" --headless --no-sandbox --disable-gpu --hide-scrollbars --window-size=1200,2400 \
  --screenshot="$(realpath -m "$out")" "file://$page" 2>/dev/null
[ -s "$out" ] || { echo "screenshot_report: no picture written" >&2; exit 1; }
echo "screenshot_report: $out"
