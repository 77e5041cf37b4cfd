#!/usr/bin/env bash
# Periodic errors in motor angle end to end (issue 19, docs/method/03-error-model.md §9): the IRB
# 120 robot file with a gear ratio for joint 6 (`gear_ratio: [~, ~, ~, ~, ~, 101]`), a truth file
# whose joint-6 motor adds 0.01° at the motor angle (`motor_periodic_deg`), simulated and
# calibrated with `--identify joint6.motor_periodic`: the four terms within 3σ of the truth's,
# the group significant in the JSON and the model file (which keeps the gear ratio); a request
# for joint 5 (no ratio) refused naming the joint.
# Usage: motor_periodic_cli.sh path/to/robcal (cwd: repo root).
set -u
ROBCAL=${1:?usage: motor_periodic_cli.sh path/to/robcal}
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
source "$(dirname "$0")/lib/checks.sh"

sed 's/^joint_limits_deg:/gear_ratio: [~, ~, ~, ~, ~, 101]\njoint_limits_deg:/' \
  data/robots/abb-irb120.yaml >"$TMP/robot.yaml"
"$ROBCAL" simulate --robot "$TMP/robot.yaml" --truth published --random 5 --seed 1 \
  --out "$TMP/plain" >/dev/null || fail "simulate with the geared robot file failed"
# A·sin(r·q6 + 40°), A = 0.01°: cos term A·sin 40°, sin term A·cos 40°.
sed "s|^robot: .*|robot: $TMP/robot.yaml|" "$TMP/plain/truth/truth.yaml" >"$TMP/truth.yaml"
printf 'motor_periodic_deg:\n  6: [0.0064279, 0.0076604, 0, 0]\n' >>"$TMP/truth.yaml"
"$ROBCAL" simulate --robot "$TMP/robot.yaml" --truth "$TMP/truth.yaml" --random 100 --seed 19 \
  --noise-mm 0.01 --out "$TMP/motor" >/dev/null || fail "simulate with motor errors failed"
"$ROBCAL" calibrate --robot "$TMP/robot.yaml" --tool "$TMP/motor/tool.yaml" \
  --measurements "$TMP/motor/measurements.csv" --level full --identify joint6.motor_periodic \
  --json --out "$TMP/motor.yaml" >"$TMP/motor.json" || fail "calibrate with the group failed"
/usr/bin/python3 - "$TMP" <<'PY' || FAILED=1
import json, sys
tmp = sys.argv[1]
errors = []
d = json.load(open(f"{tmp}/motor.json"))
groups = {g["name"]: g for g in d.get("groups", [])}
if list(groups) != ["joint6.motor_periodic"] or not groups["joint6.motor_periodic"]["significant"]:
    errors.append(f"groups {groups}")
rows = {p["name"]: p for p in d["parameters"]}
truth = {"1.cos": 0.0064279, "1.sin": 0.0076604, "2.cos": 0.0, "2.sin": 0.0}
for term, value in truth.items():
    p = rows[f"joint6.motor_periodic{term}"]
    if p["status"] != "identified" or p["unit"] != "deg" or abs(p["value"] - value) > 3 * p["std"]:
        errors.append(f"{p} (expected {value} deg)")
text = open(f"{tmp}/motor.yaml").read()
for key in ("joint6.motor_periodic1.sin", "name: joint6.motor_periodic", "gear_ratio: [~, ~, ~, ~, ~, 101]"):
    if key not in text: errors.append(f"model file lacks {key}")
for e in errors: print("FAIL:", e)
sys.exit(1 if errors else 0)
PY
expect_error "joint without a gear ratio" "joint 5, whose gear ratio the robot file does not give" \
  calibrate --robot "$TMP/robot.yaml" --tool "$TMP/motor/tool.yaml" \
  --measurements "$TMP/motor/measurements.csv" --identify 'joint5.motor_periodic*' \
  --out "$TMP/bad.yaml"
finish motor_periodic_cli.sh
