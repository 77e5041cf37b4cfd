#!/usr/bin/env bash
# robcal experiments: the published simulation experiments (docs/method/11-published-results.md §2) against the published
# figures: (a) nominal error up to ~5 mm, no noise → model error far below 0.004 mm; (b) noise
# and mass error → the published 0.05–0.10 mm band; (c) compliance visibly matters.
set -euo pipefail
robcal="$1"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT

"$robcal" experiments --seed 1 --out "$out" --json > "$out/stdout.json"
test -s "$out/results.md"
python3 - "$out/results.json" <<'PY'
import json, sys
e = json.load(open(sys.argv[1]))["experiments"]
a, b, c = e["a"]["result"], e["b"]["result"], e["c"]["result"]
assert 4.0 <= a["nominal_vs_truth"]["max_mm"] <= 5.3, a["nominal_vs_truth"]
assert a["full_vs_truth"]["max_mm"] < 0.004, a["full_vs_truth"]
assert b["full_vs_truth"]["mean_mm"] < 0.10 and b["full_vs_truth"]["max_mm"] < 0.15, b
assert c["kinematic_vs_measurements"]["mean_mm"] > 3 * c["full_vs_measurements"]["mean_mm"], c
PY

# A bad seed is refused with exit code 2 and no output.
rc=0
"$robcal" experiments --seed x --out "$out/bad" 2> "$out/err" || rc=$?
test "$rc" -eq 2 || { echo "exit code $rc, expected 2"; exit 1; }
grep -q -- '--seed' "$out/err" || { echo "error does not name --seed: $(cat "$out/err")"; exit 1; }
test ! -e "$out/bad"
