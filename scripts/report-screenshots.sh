#!/usr/bin/env bash
# Refreshes the report screenshots in docs/ from the binary: builds the demo, reports it again
# with a simulated ballbar file (so that every section the demo can fill is shown), and takes
# three screenshots with headless Chromium (`make browser-deps` installs it):
#   docs/report-screenshot.png          the top: provenance, summary, shared axes
#   docs/report-screenshot-classes.png  errors by class, residuals per configuration
#   docs/report-screenshot-groups.png   ballbar, parameters and parameter groups
# Usage: scripts/report-screenshots.sh [build]   (seeds fixed: the pages are reproducible)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
robcal="$root/${1:-build}/robcal"
chromium=$(command -v chromium || command -v chromium-browser || true)
[ -n "$chromium" ] || { echo "chromium is not installed: make browser-deps" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
"$robcal" demo --out demo --seed 1 >/dev/null
"$robcal" simulate --instrument ballbar --truth published --random 60 --seed 5 --out bar >/dev/null
"$robcal" report --model demo/models/full.yaml --before demo/models/nominal.yaml \
  --between demo/models/base.yaml --between demo/models/kinematic.yaml \
  --measurements demo/validation/measurements.csv \
  --calibration demo/calibration/measurements.csv \
  --instrument demo/calibration/instrument.yaml --seed 1 \
  --ballbar bar/measurements.csv --ballbar-length 150 \
  --title "robcal demo: virtual IRB 120, laser tracker" --out report.html >/dev/null
shoot() {  # PNG, then the ids of the sections to show (none: the page from its top)
  local png=$1 page=report.html
  shift
  if [ $# -gt 0 ]; then
    # A copy of the page showing only these sections (a headless screenshot shows the top).
    local keep=""
    for id in "$@"; do keep="$keep:not(#$id)"; done
    page="part-$png.html"
    sed "s|</style>|body > section$keep, body > h1, body > p.sub { display: none; }\n</style>|" \
      report.html > "$page"
  fi
  "$chromium" --headless --no-sandbox --disable-gpu --no-first-run --hide-scrollbars \
    --user-data-dir="$work/profile" --window-size=1200,1500 --virtual-time-budget=5000 \
    --screenshot="$root/docs/$png" "file://$work/$page" 2>/dev/null
  echo "wrote docs/$png"
}
shoot report-screenshot.png
shoot report-screenshot-classes.png classes-section residuals-section
shoot report-screenshot-groups.png ballbar-section groups-section
