#!/usr/bin/env bash
# Thermal drift without a temperature end to end (issue 19, docs/method/03-error-model.md §10): a
# simulated IRB 120 that warms up (`simulate --effects thermal --clock`: each row's time in the
# `time_s` column, no temperature), calibrated with the warm-up group (`--identify warmup`): the
# growths of the links with length in mm at full warm-up with σ, within 3σ of the simulator's
# (23 ppm/K × 3 K × the link's length) or held as barely seen, the links without length dropped
# with their reason, the group in the model file and JSON with the time constant; compensate
# cold and `--warm` differ; a time constant out of range is refused.
# Usage: warmup_cli.sh path/to/robcal (cwd: repo root).
set -u
ROBCAL=${1:?usage: warmup_cli.sh path/to/robcal}
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
source "$(dirname "$0")/lib/checks.sh"

"$ROBCAL" simulate --truth published --effects thermal --clock --random 100 --seed 19 \
  --noise-mm 0.01 --out "$TMP/warm" >/dev/null || fail "simulate --effects thermal --clock failed"
head -3 "$TMP/warm/measurements.csv" | grep -q ",time_s$" ||
  fail "no time_s column: $(head -3 "$TMP/warm/measurements.csv")"
"$ROBCAL" calibrate --robot abb-irb120 --tool "$TMP/warm/tool.yaml" \
  --measurements "$TMP/warm/measurements.csv" --level full --identify warmup --warmup-tau-s 1800 \
  --json --out "$TMP/warm.yaml" >"$TMP/warm.json" || fail "calibrate with times failed"
/usr/bin/python3 - "$TMP" <<'PY' || FAILED=1
import json, math, sys
tmp = sys.argv[1]
errors = []
d = json.load(open(f"{tmp}/warm.json"))
names = [g["name"] for g in d.get("groups", [])]
if names != ["warmup"]: errors.append(f"groups {names}")
rows = {p["name"]: p for p in d["parameters"]}
lengths = {3: 270.0, 4: math.hypot(70, 302), 6: 72.0}  # the IRB 120's nominal links
for link, length in lengths.items():
    p = rows[f"link{link}.warmup_growth"]
    truth = 23e-6 * 3 * length
    held = p["status"] == "dropped" and "barely see it" in p.get("reason", "")
    if not held and (p["status"] != "identified" or p["unit"] != "mm"
                     or abs(p["value"] - truth) > 3 * p["std"]):
        errors.append(f"{p} (expected {truth:.4f} mm)")
for link in (2, 5):
    p = rows[f"link{link}.warmup_growth"]
    if p["status"] != "dropped" or "has no length" not in p.get("reason", ""):
        errors.append(f"link {link}: {p}")
text = open(f"{tmp}/warm.yaml").read()
for key in ("link3.warmup_growth", "groups:", "name: warmup"):
    if key not in text: errors.append(f"model file lacks {key}")
for e in errors: print("FAIL:", e)
sys.exit(1 if errors else 0)
PY

printf 'name,x,y,z,qw,qx,qy,qz\np1,-600,1700,500,0,0,1,0\n' >"$TMP/poses.csv"
"$ROBCAL" compensate --model "$TMP/warm.yaml" --targets "$TMP/poses.csv" \
  --out "$TMP/cold.csv" >/dev/null || fail "compensate cold failed"
"$ROBCAL" compensate --model "$TMP/warm.yaml" --targets "$TMP/poses.csv" --warm \
  --out "$TMP/hot.csv" >/dev/null || fail "compensate --warm failed"
cmp -s "$TMP/cold.csv" "$TMP/hot.csv" && fail "--warm changed nothing"
expect_error "time constant in hours" "--warmup-tau-s" calibrate --robot abb-irb120 \
  --tool "$TMP/warm/tool.yaml" --measurements "$TMP/warm/measurements.csv" --identify warmup \
  --warmup-tau-s 0.5 --out "$TMP/bad.yaml"
finish warmup_cli.sh
