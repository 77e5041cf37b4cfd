#!/usr/bin/env bash
# Periodic joint errors end to end (issue 19): a simulated IRB 120 with the simulator's joint-6
# gear error, calibrated with and without the opt-in group `joint6.periodic*`: the group is
# reported significant on data with the effect (model file and JSON carry its rows, σ and the
# groups section) and NOT significant on data without it; a pattern that matches nothing is
# refused. Usage: periodic_cli.sh path/to/robcal (cwd: repo root).
set -u
ROBCAL=${1:?usage: periodic_cli.sh path/to/robcal}
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
source "$(dirname "$0")/lib/checks.sh"

"$ROBCAL" simulate --truth published --effects j6-periodic --random 100 --seed 19 \
  --noise-mm 0.01 --out "$TMP/gear" >/dev/null || fail "simulate with the effect failed"
"$ROBCAL" simulate --truth published --random 100 --seed 19 --noise-mm 0.01 \
  --out "$TMP/clean" >/dev/null || fail "simulate without the effect failed"
for set in gear clean; do
  "$ROBCAL" calibrate --robot abb-irb120 --tool "$TMP/$set/tool.yaml" \
    --measurements "$TMP/$set/measurements.csv" --level full --identify 'joint6.periodic*' \
    --json --out "$TMP/$set.yaml" >"$TMP/$set.json" || fail "calibrate $set failed"
done
/usr/bin/python3 - "$TMP" <<'PY' || FAILED=1
import json, sys
tmp = sys.argv[1]
errors = []
for name, significant in (("gear", True), ("clean", False)):
    d = json.load(open(f"{tmp}/{name}.json"))
    groups = d.get("groups", [])
    if [g["name"] for g in groups] != ["joint6.periodic"]:
        errors.append(f"{name}: groups {groups}")
        continue
    if groups[0]["significant"] != significant or groups[0]["identified"] != 4:
        errors.append(f"{name}: group {groups[0]} (expected significant={significant})")
    rows = {p["name"]: p for p in d["parameters"]}
    if rows["joint6.periodic2.sin"]["status"] != "identified" or rows["joint6.periodic2.sin"]["std"] <= 0:
        errors.append(f"{name}: {rows['joint6.periodic2.sin']}")
    text = open(f"{tmp}/{name}.yaml").read()
    for key in ("joint6.periodic2.cos", "groups:", "name: joint6.periodic"):
        if key not in text: errors.append(f"{name}: model file lacks {key}")
    if "joint5.periodic" in text: errors.append(f"{name}: model file shows a group not enabled")
# The true error 0.01°·sin(2·q6 + 0°): cos term 0, sin term 0.01° (simulator defaults).
rows = {p["name"]: p for p in json.load(open(f"{tmp}/gear.json"))["parameters"]}
for key, expected in (("joint6.periodic2.cos", 0.0), ("joint6.periodic2.sin", 0.01)):
    p = rows[key]
    if abs(p["value"] - expected) > 3 * p["std"]: errors.append(f"{key} {p} (expected {expected})")
for e in errors: print("FAIL:", e)
sys.exit(1 if errors else 0)
PY

# The text printout says what the significance means.
"$ROBCAL" calibrate --robot abb-irb120 --tool "$TMP/clean/tool.yaml" \
  --measurements "$TMP/clean/measurements.csv" --identify 'joint6.periodic*' \
  --out "$TMP/clean2.yaml" >"$TMP/clean.txt" || fail "calibrate text failed"
grep -q "group joint6.periodic: .*NOT significant" "$TMP/clean.txt" ||
  fail "no significance line: $(grep group "$TMP/clean.txt")"
# A model written with the group reads back (validate uses it).
"$ROBCAL" validate --robot abb-irb120 --tool "$TMP/gear/tool.yaml" --model "$TMP/gear.yaml" \
  --measurements "$TMP/gear/measurements.csv" \
  >"$TMP/validate.txt" || fail "validate with a periodic model failed"

expect_error "pattern matching nothing" "joint7.periodic*" calibrate --robot abb-irb120 \
  --tool "$TMP/gear/tool.yaml" --measurements "$TMP/gear/measurements.csv" \
  --identify 'joint7.periodic*' --out "$TMP/bad.yaml"
finish periodic_cli.sh
