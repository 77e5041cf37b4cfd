#!/usr/bin/env bash
# `robcal model import|export` (URDF): a built-in robot through URDF and back gives the same FK,
# a URDF with a tilted mount becomes a model file, a calibrated model's export names what URDF
# cannot hold and its cost, bad URDFs are refused by name. Usage: model_io.sh path/to/robcal
# (cwd: repo root).
set -u
ROBCAL=${1:?usage: model_io.sh path/to/robcal}
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
source "$(dirname "$0")/lib/checks.sh"
REF=tests/data/irb120-published

# 1. Round trip of every built-in robot of one maker per family: the same flange pose.
for robot in abb-irb120 kuka-kr6-r900-sixx universal-robots-ur5e yaskawa-gp7; do
  "$ROBCAL" model export --robot $robot --out "$TMP/$robot.urdf" >/dev/null || fail "export $robot"
  "$ROBCAL" model import --urdf "$TMP/$robot.urdf" --out "$TMP/$robot.yaml" >"$TMP/import.txt" ||
    fail "import $robot"
  grep -q "a robot file: use it with --robot" "$TMP/import.txt" || fail "$robot: not a robot file"
  for joints in 10,20,-30,40,50,60 -60,-30,20,90,-80,150; do
    "$ROBCAL" fk --robot $robot --joints=$joints >"$TMP/fk-a" || fail "fk $robot $joints"
    "$ROBCAL" fk --robot "$TMP/$robot.yaml" --joints=$joints >"$TMP/fk-b" || fail "fk of import"
    [[ -s "$TMP/fk-a" ]] && cmp -s <(tail -3 "$TMP/fk-a") <(tail -3 "$TMP/fk-b") ||
      fail "$robot: FK differs after URDF round trip at $joints"
  done
done

# 2. A tilted mount and joint 1 about -z: a nominal model file with the base placement.
"$ROBCAL" model import --urdf tests/data/urdf/skew6r.urdf --out "$TMP/skew.yaml" >"$TMP/skew.txt" ||
  fail "import skew6r"
grep -q "its placement is in the base parameters" "$TMP/skew.txt" || fail "skew6r: no base note"
grep -q "base_fitted: true" "$TMP/skew.yaml" || fail "skew6r: base not in the model file"
"$ROBCAL" model export --model "$TMP/skew.yaml" --out "$TMP/skew.urdf" >/dev/null ||
  fail "export of the imported skew6r model"

# 3. A calibrated model (full level: compliance): the warning names each compliance and its cost.
"$ROBCAL" calibrate --robot abb-irb120 --tool $REF/tool.yaml --measurements $REF/calibration.csv \
  --level full --out "$TMP/cal.yaml" >/dev/null || fail "calibrate"
"$ROBCAL" model export --model "$TMP/cal.yaml" --out "$TMP/cal.urdf" --seed 4 >"$TMP/cal.txt" ||
  fail "export calibrated"
grep -q "warning: not in the URDF: joint2.compliance" "$TMP/cal.txt" || fail "no compliance warning"
grep -q "mm RMS, .* mm at most (2000 configurations within the limits, seed 4)" "$TMP/cal.txt" ||
  fail "no cost of the left-out compliance: $(cat "$TMP/cal.txt")"
grep -q '<link name="tool0"/>' "$TMP/cal.urdf" || fail "calibrated URDF has no tool0 link"
# The same model's parameter table: link 3's a identified with a σ, as in the model file.
"$ROBCAL" model export --model "$TMP/cal.yaml" --format mdh-csv --out "$TMP/cal.csv" >/dev/null ||
  fail "export mdh-csv"
/usr/bin/python3 - "$TMP/cal.csv" "$TMP/cal.yaml" <<'PY' || fail "mdh-csv differs from the model file"
import csv, sys, yaml
rows = {r["name"]: r for r in csv.DictReader(open(sys.argv[1]))}
model = {p["name"]: p for p in yaml.safe_load(open(sys.argv[2]))["parameters"]}
bad = [n for n, p in model.items()
       if abs(float(rows[n]["value"]) - p["value"]) > 1e-9 * max(1, abs(p["value"]))
       or abs(float(rows[n]["std"]) - p["std"]) > 1e-9 * max(1e-9, p["std"])
       or rows[n]["status"] != p["status"]]
ok = not bad and rows["link3.a"]["status"] == "identified" and float(rows["link3.a"]["std"]) > 0
print("mismatch:", bad) if bad else None
sys.exit(0 if ok else 1)
PY

# 4. A UR calibration.conf onto the UR10e: a model file (its FK against UR's DH sums is
# tests/test_ur_calibration_file.cpp), exported back as the same deltas.
"$ROBCAL" model import --format ur-calibration --calibration tests/data/ur/ur10e-calibration.conf \
  --robot universal-robots-ur10e --out "$TMP/ur.yaml" >"$TMP/ur.txt" || fail "import calibration.conf"
grep -q "calibration_status linearised" "$TMP/ur.txt" || fail "no calibration status: $(cat "$TMP/ur.txt")"
grep -q "level: ur-calibration" "$TMP/ur.yaml" || fail "not a model file"
"$ROBCAL" model export --model "$TMP/ur.yaml" --format ur-calibration --out "$TMP/back.conf" \
  >"$TMP/back.txt" || fail "export calibration.conf"
/usr/bin/python3 - tests/data/ur/ur10e-calibration.conf "$TMP/back.conf" <<'PY' || fail "deltas differ"
import re, sys
def rows(path):
    return {m[1]: [float(x) for x in m[2].split(",")]
            for m in re.finditer(r"^(delta_\w+) = \[(.*)\]", open(path).read(), re.M)}
a, b = rows(sys.argv[1]), rows(sys.argv[2])
sys.exit(0 if a.keys() == b.keys() and all(abs(x - y) < 1e-9 for k in a for x, y in zip(a[k], b[k])) else 1)
PY
expect_error "coupled joints as calibration.conf" "joint map must be the identity" \
  model export --robot fanuc-crx10ia-l --format ur-calibration --out "$TMP/bad.conf"

# 5. Bad input: exit 2, the file and the joint named, nothing written.
sed 's/name="joint_3" type="revolute"/name="joint_3" type="prismatic"/' \
  "$TMP/abb-irb120.urdf" >"$TMP/prismatic.urdf"
expect_error "prismatic joint" "prismatic.urdf: joint 'joint_3' is not revolute" \
  model import --urdf "$TMP/prismatic.urdf" --out "$TMP/bad.yaml"
sed 's/<parent link="link_3"\/>/<parent link="nowhere"\/>/' \
  "$TMP/abb-irb120.urdf" >"$TMP/orphan.urdf"
expect_error "missing parent" "orphan.urdf: not a valid URDF robot" \
  model import --urdf "$TMP/orphan.urdf" --out "$TMP/bad.yaml"
expect_error "tip not after joint 6" "tip link 'link_2' does not follow joint 'joint_6'" \
  model import --urdf "$TMP/abb-irb120.urdf" --tip link_2 --out "$TMP/bad.yaml"
expect_error "robot and model" "give either a robot (--robot) or a calibrated model (--model)" \
  model export --robot abb-irb120 --model "$TMP/cal.yaml" --out "$TMP/bad.urdf"
expect_error "missing URDF" "nothing.urdf" \
  model import --urdf "$TMP/nothing.urdf" --out "$TMP/bad.yaml"

finish model_io.sh
