#!/usr/bin/env bash
# End-to-end checks of `robcal calibrate` on the reference data set: the JSON summary, the
# written model loads in `validate --model` territory (round trip through the file), K-fold
# cross-validation, and bad input of every kind (exit code 2, a message naming the flag, file
# or key, and no output file). Usage: calibrate_cli.sh path/to/robcal (cwd: repo root).
set -u
ROBCAL=${1:?usage: calibrate_cli.sh path/to/robcal}
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
source "$(dirname "$0")/lib/checks.sh"
REF=tests/data/irb120-published

# 1. Full calibration with JSON output and 5-fold cross-validation.
"$ROBCAL" calibrate --robot abb-irb120 --tool $REF/tool.yaml --measurements $REF/calibration.csv \
  --level full --kfold 5 --json --out "$TMP/model.yaml" >"$TMP/full.json" || fail "calibrate full failed"
/usr/bin/python3 - "$TMP/full.json" "$TMP/model.yaml" <<'PY' || FAILED=1
import json, sys
d = json.load(open(sys.argv[1]))
errors = []
if not d["converged"]: errors.append("not converged")
if d["identified"] != 30: errors.append(f"identified {d['identified']} (expected 30)")
if not 0.015 < d["sigma_mm"] < 0.025: errors.append(f"sigma {d['sigma_mm']} (noise 0.02)")
dropped = [p for p in d["parameters"] if p["status"] == "dropped"]
if [p["name"] for p in dropped] != ["link3.d"] or "link2.d" not in dropped[0]["reason"]:
    errors.append(f"dropped {dropped}")
cv = d["cross_validation"]["error_mm"]
if not 0.02 < cv["mean_mm"] < 0.06: errors.append(f"cross-validation mean {cv['mean_mm']}")
pred = d["predicted_position_error_mm"]
if not pred["against_truth"]["mean_mm"] < pred["against_new_measurements"]["mean_mm"]:
    errors.append("prediction against truth should be below that against measurements")
text = open(sys.argv[2]).read()
for key in ("format: robcal-calibrated-model", "level: full", "covariance:", "statistics:", "cross_validation:"):
    if key not in text: errors.append(f"model file lacks {key}")
for e in errors: print("FAIL:", e)
sys.exit(1 if errors else 0)
PY

# 2. Text output mentions the dropped parameter and why; base level works.
"$ROBCAL" calibrate --robot abb-irb120 --tool $REF/tool.yaml --measurements $REF/calibration.csv \
  --level kinematic --out "$TMP/kin.yaml" >"$TMP/kin.txt" || fail "calibrate kinematic failed"
grep -q "link3.d.*axes 2 and 3 are parallel" "$TMP/kin.txt" || fail "kinematic report lacks the link3.d explanation"
"$ROBCAL" calibrate --robot abb-irb120 --tool $REF/tool.yaml --measurements $REF/calibration.csv \
  --level base --loss huber --json --out "$TMP/base.yaml" >"$TMP/base.json" || fail "calibrate base failed"
/usr/bin/python3 -c "import json,sys; d=json.load(open('$TMP/base.json')); sys.exit(0 if d['identified']==6 and d['huber_scale_mm']>0 else 1)" \
  || fail "base/huber JSON wrong"

# 3. Bad input: clear errors, exit code 2, no output file.
expect_error "unknown level" "unknown level 'everything'" calibrate --robot abb-irb120 \
  --tool $REF/tool.yaml --measurements $REF/calibration.csv --level everything --out "$TMP/bad.yaml"
expect_error "unknown pattern" "'link9.*' matches no parameter" calibrate --robot abb-irb120 \
  --tool $REF/tool.yaml --measurements $REF/calibration.csv --fix 'link9.*' --out "$TMP/bad.yaml"
expect_error "unknown loss" "unknown loss 'cauchy'" calibrate --robot abb-irb120 \
  --tool $REF/tool.yaml --measurements $REF/calibration.csv --loss cauchy --out "$TMP/bad.yaml"
head -6 $REF/calibration.csv >"$TMP/few.csv"
expect_error "too few rows" "at least 11 rows are needed" calibrate --robot abb-irb120 \
  --tool $REF/tool.yaml --measurements "$TMP/few.csv" --out "$TMP/bad.yaml"
# All rows at one wrist orientation: joints 4..6 frozen → rank-deficient design.
/usr/bin/python3 - $REF/calibration.csv "$TMP/frozen.csv" <<'PY'
import sys
lines = open(sys.argv[1]).read().splitlines()
out = [lines[0]]
for line in lines[1:]:
    f = line.split(",")
    f[5], f[6], f[7] = "10", "20", "30"
    out.append(",".join(f))
open(sys.argv[2], "w").write("\n".join(out) + "\n")
PY
expect_error "rank-deficient design" "rank-deficient design" calibrate --robot abb-irb120 \
  --tool $REF/tool.yaml --measurements "$TMP/frozen.csv" --out "$TMP/bad.yaml"
sed 's/^5,2,/5,7,/' $REF/calibration.csv >"$TMP/badtarget.csv"
expect_error "unknown target" "badtarget.csv" calibrate --robot abb-irb120 \
  --tool $REF/tool.yaml --measurements "$TMP/badtarget.csv" --out "$TMP/bad.yaml"
expect_error "kfold too large" "--kfold" calibrate --robot abb-irb120 --tool $REF/tool.yaml \
  --measurements $REF/calibration.csv --kfold 500 --out "$TMP/bad.yaml"
expect_error "missing file" "nonexistent.csv" calibrate --robot abb-irb120 --tool $REF/tool.yaml \
  --measurements "$TMP/nonexistent.csv" --out "$TMP/bad.yaml"

# 4. The written model loads back (validate reads it); its base is fitted.
grep -q "base_fitted: true" "$TMP/model.yaml" || fail "model has no fitted base"

# 5. Poses: the orientation weight is settable, reported, and changes the fit; zero is refused.
"$ROBCAL" simulate --instrument optical-cmm --truth published --random 30 --seed 5 \
  --out "$TMP/cmm" >/dev/null
for w in 100 50; do
  "$ROBCAL" calibrate --robot abb-irb120 --tool "$TMP/cmm/tool.yaml" \
    --measurements "$TMP/cmm/measurements.csv" --orientation-weight $w --out "$TMP/cmm$w.yaml" \
    --json >"$TMP/cmm$w.json"
done
/usr/bin/python3 - "$TMP/cmm100.json" "$TMP/cmm50.json" <<'PY' || FAILED=1
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
assert a["orientation_weight_mm_per_rad"] == 100 and b["orientation_weight_mm_per_rad"] == 50
assert a["converged"] and b["converged"]
# Position residuals are weighted alike, orientation ones differently: a different solution.
va = {p["name"]: p["value"] for p in a["parameters"]}
vb = {p["name"]: p["value"] for p in b["parameters"]}
assert any(abs(va[k] - vb[k]) > 1e-9 for k in va), "the weight changed nothing"
PY
"$ROBCAL" calibrate --robot abb-irb120 --tool "$TMP/cmm/tool.yaml" \
  --measurements "$TMP/cmm/measurements.csv" --orientation-weight 50 --out "$TMP/cmm.yaml" \
  >"$TMP/cmm.txt"
grep -q "orientation residuals weighted 50 mm per rad" "$TMP/cmm.txt" || fail "weight not printed"
expect_error "negative orientation weight" "--orientation-weight" calibrate --robot abb-irb120 \
  --tool "$TMP/cmm/tool.yaml" --measurements "$TMP/cmm/measurements.csv" --orientation-weight -1 \
  --out "$TMP/bad.yaml"

# 4. Shop files: metres without a declaration are refused; declared (header or --units) they
# calibrate; another robot's model is not written unless --force (exit 1, what to check).
awk -F, 'NR==1 {print; next} {printf "%s,%s,%s,%s,%s,%s,%s,%s,%.9f,%.9f,%.9f\n", $1,$2,$3,$4,$5,$6,$7,$8,$9/1000,$10/1000,$11/1000}' \
  $REF/calibration.csv >"$TMP/metres.csv"
expect_error "metres read as mm" "they look like metres, not millimetres" calibrate \
  --robot abb-irb120 --tool $REF/tool.yaml --measurements "$TMP/metres.csv" --out "$TMP/bad.yaml"
expect_error "bad --units" "--units: unknown unit 'inch'" calibrate --robot abb-irb120 \
  --tool $REF/tool.yaml --measurements "$TMP/metres.csv" --units inch --out "$TMP/bad.yaml"
"$ROBCAL" calibrate --robot abb-irb120 --tool $REF/tool.yaml --measurements "$TMP/metres.csv" \
  --units m --sigma 0.02 --out "$TMP/metres.yaml" >"$TMP/metres.txt" || fail "--units m failed"
grep -q "calibrated:               mean 0.0320  rms 0.0338  max 0.0564 mm" "$TMP/metres.txt" ||
  fail "metres file gives other residuals: $(grep -A2 'residual per row' "$TMP/metres.txt")"
grep -q "the residuals are the instrument's noise" "$TMP/metres.txt" || fail "noise test missing"
# Another robot whose joint limits hold the data (a KUKA's do not: its rows are refused by line).
expect_error "joints far outside another robot's limits" \
  "calibration.csv:3 (j2): 66.147° is more than 20° outside the joint's limits [-190, 45]°" \
  calibrate --robot kuka-kr6-r900-sixx --tool $REF/tool.yaml --measurements $REF/calibration.csv \
  --out "$TMP/kuka.yaml"
"$ROBCAL" calibrate --robot abb-irb1600-6-12 --tool $REF/tool.yaml \
  --measurements $REF/calibration.csv --out "$TMP/kuka.yaml" >"$TMP/kuka.txt" 2>"$TMP/kuka.err"
[[ $? -eq 1 ]] || fail "another robot's model: exit code not 1"
[[ ! -e "$TMP/kuka.yaml" ]] || fail "another robot's model was written"
grep -q "not written: the fit is not trustworthy" "$TMP/kuka.err" || fail "no refusal message"
grep -q "PROBLEM: .*check the robot (--robot" "$TMP/kuka.txt" || fail "no advice what to check"
"$ROBCAL" calibrate --robot abb-irb1600-6-12 --tool $REF/tool.yaml \
  --measurements $REF/calibration.csv --force --out "$TMP/kuka.yaml" >/dev/null 2>&1
[[ -s "$TMP/kuka.yaml" ]] || fail "--force did not write the model"

# 5. validate with a calibrated model: --fit-base re-registers a moved instrument (+1 m in x);
# a tool file that contradicts the model's tool is refused, not silently ignored.
awk -F, 'NR==1 {print; next} {printf "%s,%s,%s,%s,%s,%s,%s,%s,%.6f,%s,%s\n", $1,$2,$3,$4,$5,$6,$7,$8,$9+1000,$10,$11}' \
  $REF/validation.csv >"$TMP/moved.csv"
"$ROBCAL" validate --robot abb-irb120 --tool $REF/tool.yaml --model "$TMP/metres.yaml" \
  --measurements "$TMP/moved.csv" --fit-base --json >"$TMP/moved.json" || fail "validate --fit-base"
/usr/bin/python3 -c "
import json, sys
d = json.load(open('$TMP/moved.json'))
assert d['position_error_mm']['mean_mm'] < 0.1, d['position_error_mm']" || fail "base not re-registered"
sed 's/"1": \[0.0, 0.0, 125.0\]/"1": [0.0, 0.0, 200.0]/' $REF/tool.yaml >"$TMP/other_tool.yaml"
expect_error "another tool" "target '1' is at (0, 0, 200) mm here" validate --robot abb-irb120 \
  --tool "$TMP/other_tool.yaml" --model "$TMP/metres.yaml" --measurements $REF/validation.csv

# 6. Cross-validation with the user's folds (config → fold): per-fold and pooled statistics.
{ echo "config,fold"; awk -F, 'NR>1 {print $1 "," ($1 % 4) + 1}' $REF/calibration.csv; } >"$TMP/folds.csv"
"$ROBCAL" calibrate --robot abb-irb120 --tool $REF/tool.yaml --measurements $REF/calibration.csv \
  --folds "$TMP/folds.csv" --json --out "$TMP/folds.yaml" >"$TMP/folds.json" || fail "--folds failed"
/usr/bin/python3 - "$TMP/folds.json" <<'PY' || FAILED=1
import json, sys
cv = json.load(open(sys.argv[1]))["cross_validation"]
folds = cv["per_fold"]
assert cv["folds"] == 4 and cv["user_folds"] and len(folds) == 4, cv
assert [f["rows"] for f in folds] == [15, 15, 15, 15], folds
pooled = sum(f["rows"] * f["mean_mm"] for f in folds) / 60
assert abs(pooled - cv["error_mm"]["mean_mm"]) < 1e-6, (pooled, cv["error_mm"])
assert max(f["max_mm"] for f in folds) == cv["error_mm"]["max_mm"], cv
assert 0.02 < cv["error_mm"]["mean_mm"] < 0.06, cv
PY
{ echo "config,fold"; echo "1,1"; echo "2,x"; } >"$TMP/badfolds.csv"
expect_error "bad fold" "badfolds.csv:3:3 (fold): '2,x': expected config,fold with fold an integer" \
  calibrate --robot abb-irb120 --tool $REF/tool.yaml --measurements $REF/calibration.csv \
  --folds "$TMP/badfolds.csv" --out "$TMP/bad.yaml"
{ echo "config,fold"; echo "1,1"; echo "2,2"; } >"$TMP/fewfolds.csv"
expect_error "config without fold" "configuration '3' of $REF/calibration.csv has no fold" \
  calibrate --robot abb-irb120 --tool $REF/tool.yaml --measurements $REF/calibration.csv \
  --folds "$TMP/fewfolds.csv" --out "$TMP/bad.yaml"

# 8. Re-use a calibrated robot (issue 13 item 5): --model re-identifies only what is asked.
"$ROBCAL" calibrate --robot abb-irb120 --tool $REF/tool.yaml --measurements $REF/calibration.csv \
  --level kinematic --out "$TMP/calibrated.yaml" >/dev/null || fail "calibrate for --model"
"$ROBCAL" calibrate --model "$TMP/calibrated.yaml" --level tool --tool $REF/tool.yaml \
  --measurements $REF/calibration.csv --json --out "$TMP/newtool.yaml" >"$TMP/newtool.json" ||
  fail "calibrate --model --level tool"
head -300 $REF/validation.csv >"$TMP/moved.csv"
"$ROBCAL" calibrate --model "$TMP/newtool.yaml" --level base --measurements "$TMP/moved.csv" \
  --json --out "$TMP/moved.yaml" >"$TMP/moved.json" || fail "calibrate --model --level base"
/usr/bin/python3 - "$TMP" <<'PY' || FAILED=1
import json, sys, yaml
tmp = sys.argv[1]
before = yaml.safe_load(open(f"{tmp}/calibrated.yaml"))
tool = yaml.safe_load(open(f"{tmp}/newtool.yaml"))
moved = yaml.safe_load(open(f"{tmp}/moved.yaml"))
summary = json.load(open(f"{tmp}/newtool.json"))
values = summary["reidentified"]["values"]
assert summary["reidentified"]["what"] == "tool" and len(values) == 9, summary["reidentified"]
for v in values:  # the tool file's coordinates, which the calibration was fitted with
    assert 0 < v["std"] < 0.05 and abs(v["value"] - v["before"]) < 3 * v["std"] + 0.02, v
params = lambda m: {p["name"]: (p["value"], p["status"]) for p in m["parameters"]}
assert params(tool) == params(before), "level tool changed a model parameter"
assert tool["statistics"] == before["statistics"], "the calibration's statistics were not kept"
assert tool["reidentified"][0]["what"] == "tool", tool["reidentified"]
new_targets = {v["name"]: v["value"] for v in values}
for name, xyz in tool["tool"]["targets"].items():
    assert all(abs(xyz[k] - new_targets[f"target.{name}.{'xyz'[k]}"]) < 1e-9 for k in range(3))
# level base: only the six base parameters change, by at most a few σ on the same robot.
p0, p1 = params(tool), params(moved)
base = json.load(open(f"{tmp}/moved.json"))["reidentified"]["values"]
assert sorted(v["name"] for v in base) == sorted(
    f"base.{k}" for k in ("x", "y", "z", "alpha", "beta", "gamma")), base
for v in base:
    assert abs(v["value"] - v["before"]) < 5 * v["std"] + 0.05, v
for name in p0:
    if not name.startswith("base."):
        assert p1[name] == p0[name], name
assert [r["what"] for r in moved["reidentified"]] == ["tool", "base"], moved["reidentified"]
assert moved["statistics"]["provenance"] == before["statistics"]["provenance"]
PY
head -4 $REF/calibration.csv >"$TMP/three.csv"
expect_error "tool from 3 points" "level tool: target '1' is measured in 1 configuration; a new tool point needs at least 4" \
  calibrate --model "$TMP/calibrated.yaml" --level tool --tool $REF/tool.yaml \
  --measurements "$TMP/three.csv" --out "$TMP/bad.yaml"
expect_error "--model without a request" "say what to re-identify" calibrate \
  --model "$TMP/calibrated.yaml" --measurements $REF/calibration.csv --out "$TMP/bad.yaml"
expect_error "--model and --robot" "give either --robot or --model" calibrate --robot abb-irb120 \
  --model "$TMP/calibrated.yaml" --level base --measurements $REF/calibration.csv --out "$TMP/bad.yaml"
expect_error "level tool without --model" "unknown level 'tool'" calibrate --robot abb-irb120 \
  --tool $REF/tool.yaml --level tool --measurements $REF/calibration.csv --out "$TMP/bad.yaml"

finish calibrate_cli
