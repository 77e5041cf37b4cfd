#!/usr/bin/env bash
# Joint backlash end to end (issue 19): a simulated IRB 120 with the simulator's dead bands,
# measured with each joint approached from a random side (`simulate --approach random`, recorded
# in the `approach` column), calibrated with the opt-in group '*.backlash': every group
# significant, the dead bands within 3σ of the simulator's (model file and JSON carry them with
# σ); the same robot measured from below only: the group dropped with its reason; compensate
# takes the approach. Usage: backlash_cli.sh path/to/robcal (cwd: repo root).
set -u
ROBCAL=${1:?usage: backlash_cli.sh path/to/robcal}
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
source "$(dirname "$0")/lib/checks.sh"

"$ROBCAL" simulate --truth published --effects backlash --approach random --random 100 \
  --seed 19 --noise-mm 0.01 --out "$TMP/both" >/dev/null || fail "simulate --approach random failed"
"$ROBCAL" simulate --truth published --effects backlash --random 100 --seed 19 --noise-mm 0.01 \
  --out "$TMP/below" >/dev/null || fail "simulate from below failed"
head -3 "$TMP/both/measurements.csv" | grep -q ",approach$" ||
  fail "no approach column: $(head -3 "$TMP/both/measurements.csv")"
grep -q "approach" "$TMP/below/measurements.csv" && fail "approach column in data from below"
for set in both below; do
  "$ROBCAL" calibrate --robot abb-irb120 --tool "$TMP/$set/tool.yaml" \
    --measurements "$TMP/$set/measurements.csv" --level full --identify '*.backlash' \
    --json --out "$TMP/$set.yaml" >"$TMP/$set.json" || fail "calibrate $set failed"
done
/usr/bin/python3 - "$TMP" <<'PY' || FAILED=1
import json, sys
tmp = sys.argv[1]
errors = []
d = json.load(open(f"{tmp}/both.json"))
names = [g["name"] for g in d.get("groups", [])]
if names != [f"joint{j}.backlash" for j in range(1, 7)]: errors.append(f"groups {names}")
for g in d.get("groups", []):
    if not g["significant"] or g["identified"] != 1: errors.append(f"group {g}")
rows = {p["name"]: p for p in d["parameters"]}
# The simulator's dead bands: 0.01° on joints 1-3, 0.015° on 4-6.
for j, b in zip(range(1, 7), (0.01, 0.01, 0.01, 0.015, 0.015, 0.015)):
    p = rows[f"joint{j}.backlash"]
    if p["status"] != "identified" or p["unit"] != "deg" or abs(p["value"] - b) > 3 * p["std"]:
        errors.append(f"{p} (expected {b})")
text = open(f"{tmp}/both.yaml").read()
for key in ("joint6.backlash", "groups:", "name: joint1.backlash"):
    if key not in text: errors.append(f"model file lacks {key}")
rows = {p["name"]: p for p in json.load(open(f"{tmp}/below.json"))["parameters"]}
p = rows["joint2.backlash"]
if p["status"] != "dropped" or "every row approaches joint 2 from below" not in p.get("reason", ""):
    errors.append(f"below: {p}")
for e in errors: print("FAIL:", e)
sys.exit(1 if errors else 0)
PY

# The model with the dead bands validates on its own data (rows with their sides) and
# compensates targets reached from above differently from below.
"$ROBCAL" validate --robot abb-irb120 --tool "$TMP/both/tool.yaml" --model "$TMP/both.yaml" \
  --measurements "$TMP/both/measurements.csv" >"$TMP/validate.txt" ||
  fail "validate with a backlash model failed"
printf 'name,x,y,z,qw,qx,qy,qz\np1,-600,1700,500,0,0,1,0\n' >"$TMP/poses.csv"
for side in ++++++ ------; do
  "$ROBCAL" compensate --model "$TMP/both.yaml" --targets "$TMP/poses.csv" --approach "$side" \
    --out "$TMP/comp$side.csv" >/dev/null || fail "compensate --approach $side failed"
done
cmp -s "$TMP/comp++++++.csv" "$TMP/comp------.csv" &&
  fail "the approach changed nothing in the corrected targets"
expect_error "bad approach" "is not an approach" compensate --model "$TMP/both.yaml" \
  --targets "$TMP/poses.csv" --approach '+-' --out "$TMP/bad.csv"
finish backlash_cli.sh
