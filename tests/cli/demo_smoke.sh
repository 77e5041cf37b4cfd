#!/usr/bin/env bash
# robcal demo (reduced sizes) end to end, then robcal report on the files it wrote: the full
# model beats the kinematic one, which beats the nominal one; every file is there.
set -euo pipefail
robcal="$1"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT

"$robcal" demo --out "$out/demo" --seed 2 --count 40 --validation 200 --json > "$out/demo.json"
for f in plan.csv calibration/measurements.csv calibration/tool.yaml calibration/truth/truth.yaml \
         validation/measurements.csv models/base.yaml models/kinematic.yaml models/full.yaml \
         report.html report.json; do
  test -s "$out/demo/$f" || { echo "missing $f"; exit 1; }
done
python3 - "$out/demo.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
m = {k: v["mean_mm"] for k, v in d["vs_measurements"].items()}
assert m["full"] < m["kinematic"] < m["nominal"], m
assert d["vs_truth"]["full"]["mean_mm"] < 0.05, d["vs_truth"]["full"]
assert d["validation_rows"] == 200, d["validation_rows"]
PY
# The demo's own report, built by the report workflow: provenance (inputs with SHA-256, the
# instrument and its σ, the seed), every level, and the classes including the region ones.
python3 - "$out/demo/report.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
p = r["provenance"]
assert p["seed"] == 2 and p["robcal_version"] and p["date_utc"], p
assert p["instrument"] == "laser-tracker" and abs(p["instrument_sigma_mm"] - 0.022) < 1e-12, p
roles = [f["role"] for f in p["files"]]
assert roles.count("model") == 3 and "calibration" in roles and "validation" in roles, roles
assert all(len(f["sha256"]) == 64 for f in p["files"]), p["files"]
assert [m["label"] for m in r["models"]] == [
    "nominal (base fitted on the calibration data)", "base", "kinematic", "full"], r["models"]
tables = [c["table"] for c in r["models"][-1]["classes"]]
assert "front/back" in tables and any("region" in t for t in tables), tables
PY

"$robcal" report --model "$out/demo/models/full.yaml" \
  --measurements "$out/demo/validation/measurements.csv" \
  --calibration "$out/demo/calibration/measurements.csv" --out "$out/report.html" > /dev/null
test -s "$out/report.html" && test -s "$out/report.json"
grep -q 'id="render-status"' "$out/report.html"
python3 - "$out/report.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
assert len(r["models"]) == 2 and r["models"][1]["summary"]["count"] == 200
assert len(r["distance_to_calibration_mm"]) == 200
assert any(p["status"] == "identified" for p in r["parameters"])
PY

# Bad input: exit 2 and no output.
set +e
"$robcal" report --model "$out/demo/models/full.yaml" --measurements /nonexistent.csv \
  --out "$out/bad.html" 2> "$out/err"
code=$?
set -e
test "$code" -eq 2 && grep -q "nonexistent.csv" "$out/err" && test ! -e "$out/bad.html"
echo "demo_smoke: ok"
