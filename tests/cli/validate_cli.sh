#!/usr/bin/env bash
# robcal validate end to end: refusal without a world frame, --fit-base on the reference data,
# JSON keys, thread-count independence, bad input with exit code 2 and file:line:column.
set -euo pipefail
robcal="$1"
data=tests/data/irb120-published
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# The nominal robot has no world frame: refused, with the way out named.
set +e
"$robcal" validate --robot abb-irb120 --tool $data/tool.yaml --measurements $data/validation.csv \
  >"$tmp/out" 2>"$tmp/err"
rc=$?
set -e
[ $rc -eq 2 ] || fail "nominal without --fit-base: exit $rc, expected 2"
grep -q -- "--level base" "$tmp/err" || fail "no --level base suggestion: $(cat "$tmp/err")"
grep -q -- "--fit-base" "$tmp/err" || fail "no --fit-base suggestion"
[ ! -s "$tmp/out" ] || fail "output printed on error"

# --fit-base, JSON, 1 and 2 threads.
for t in 1 2; do
  "$robcal" validate --robot abb-irb120 --tool $data/tool.yaml --measurements $data/validation.csv \
    --fit-base --json --threads $t >"$tmp/t$t.json"
done
python3 - "$tmp/t1.json" "$tmp/t2.json" <<'PY'
import json, sys
one, two = (json.load(open(p)) for p in sys.argv[1:3])
assert one["points"] == 1000, one["points"]
pe = one["position_error_mm"]
for key in ("count", "mean_mm", "std_mm", "mean_plus_3std_mm", "min_mm", "max_mm"):
    assert key in pe, key
assert abs(pe["mean_plus_3std_mm"] - (pe["mean_mm"] + 3 * pe["std_mm"])) < 1e-12
# Nominal IRB 120 placed by a rigid fit: millimetres off (docs/method/11-published-results.md: 1-5 mm).
assert 0.8 < pe["mean_mm"] < 3.5, pe
de = one["distance_error_mm"]
assert de["pairs"] == 1000 * 999 // 2, de["pairs"]
for key in ("mean_mm", "std_mm", "max_mm"):
    assert key in de, key
assert sum(de["histogram"]["counts"]) == de["pairs"]
assert len(de["histogram"]["counts"]) == 128
assert [t["target"] for t in one["per_target"]] == ["1", "2", "3"]
assert sum(t["rows"] for t in one["per_target"]) == 1000
del one["threads"], two["threads"]
assert one == two, "results differ between 1 and 2 threads"
PY

# Human output: the table and both histograms.
"$robcal" validate --robot abb-irb120 --tool $data/tool.yaml --measurements $data/validation.csv \
  --fit-base >"$tmp/human"
grep -q "mean+3std" "$tmp/human" || fail "no table"
grep -q "distance error over all 499500 pairs" "$tmp/human" || fail "no distance errors"

# Bad input: exit 2 naming file, line, column.
printf 'config,target,j1,j2,j3,j4,j5,j6,x,y,z\n1,1,0,0,0,0,0,0,1,2,3\n2,1,0,0,x,0,0,0,1,2,3\n' >"$tmp/bad.csv"
set +e
"$robcal" validate --robot abb-irb120 --tool $data/tool.yaml --measurements "$tmp/bad.csv" \
  --fit-base 2>"$tmp/err"
rc=$?
set -e
[ $rc -eq 2 ] || fail "bad value: exit $rc"
grep -q "bad.csv:3:5 (j3): 'x' is not a number" "$tmp/err" || fail "message: $(cat "$tmp/err")"

# Ballbar (distances) files: length errors against an identified centre (no world frame needed),
# then against that centre given: the same errors.
"$robcal" simulate --instrument ballbar --truth published --random 40 --seed 5 --out "$tmp/bb" \
  >/dev/null
"$robcal" validate --robot abb-irb120 --tool "$tmp/bb/tool.yaml" \
  --measurements "$tmp/bb/measurements.csv" --json >"$tmp/bb.json"
centre=$(python3 -c "import json,sys; print(','.join(repr(v) for v in json.load(open(sys.argv[1]))['ballbar_centre_mm']))" "$tmp/bb.json")
"$robcal" validate --robot abb-irb120 --tool "$tmp/bb/tool.yaml" \
  --measurements "$tmp/bb/measurements.csv" --ballbar-centre="$centre" --json >"$tmp/bb_given.json"
python3 - "$tmp/bb.json" "$tmp/bb_given.json" "$tmp/bb/measurements.csv" <<'PY'
import json, sys
fitted, given = (json.load(open(p)) for p in sys.argv[1:3])
rows = sum(1 for line in open(sys.argv[3]) if line[0].isalnum()) - 1
assert fitted["kind"] == "distances" and fitted["rows"] == rows, (fitted["rows"], rows)
assert fitted["ballbar_centre"] == "identified" and given["ballbar_centre"] == "given"
le = fitted["length_error_mm"]
for key in ("mean_mm", "std_mm", "mean_plus_3std_mm", "max_mm", "signed_mean_mm", "signed_std_mm"):
    assert key in le, key
# The nominal robot against the published truth: tenths of a millimetre, the least-squares centre
# leaves no mean length error.
assert 0.02 < le["mean_mm"] < 1.0, le
assert abs(le["signed_mean_mm"]) < 0.1 * le["std_mm"] + 1e-6, le
assert sum(le_count for le_count in fitted["length_error_histogram_mm"]["counts"]) == rows
for key in ("mean_mm", "std_mm", "max_mm", "signed_mean_mm"):
    assert abs(given["length_error_mm"][key] - le[key]) < 1e-9, key
# Every reading was checked against the bar: the median reading ± 1 mm by default.
assert fitted["ballbar_range_mm"] == 1 and fitted["ballbar_length"] == "median of the readings"
assert abs(fitted["ballbar_length_mm"] - 150) < 1, fitted["ballbar_length_mm"]
for t in fitted["classes"]:
    assert sum(r["length_error_mm"]["rows"] for r in t["rows"]) == rows, t
PY
"$robcal" validate --robot abb-irb120 --tool "$tmp/bb/tool.yaml" \
  --measurements "$tmp/bb/measurements.csv" >"$tmp/bb.txt"
grep -q "centre identified from these rows" "$tmp/bb.txt" || fail "ballbar centre not reported"
grep -q "length error (mm)" "$tmp/bb.txt" || fail "no ballbar table"
grep -q "every reading within the bar's range" "$tmp/bb.txt" || fail "ballbar range not reported"
grep -q "length error by class" "$tmp/bb.txt" || fail "no ballbar class table"
# The simulated bar is a 150 mm one: a 100 mm bar could not have read these lengths.
set +e
"$robcal" validate --robot abb-irb120 --tool "$tmp/bb/tool.yaml" \
  --measurements "$tmp/bb/measurements.csv" --ballbar-length 100 2>"$tmp/err" >"$tmp/out"
rc=$?
set -e
[ $rc -eq 2 ] || fail "readings outside the bar's range: exit $rc"
grep -q "measurements.csv:3 (length): reading .* is outside the ballbar's range 100 ± 1 mm" \
  "$tmp/err" || fail "message: $(cat "$tmp/err")"
[ ! -s "$tmp/out" ] || fail "output printed for readings outside the range"
set +e
"$robcal" validate --robot abb-irb120 --tool "$tmp/bb/tool.yaml" \
  --measurements "$tmp/bb/measurements.csv" --fit-base 2>"$tmp/err" >"$tmp/out"
rc=$?
set -e
[ $rc -eq 2 ] || fail "distances with --fit-base: exit $rc"
grep -q "no positions to fit a world frame" "$tmp/err" || fail "message: $(cat "$tmp/err")"
[ ! -s "$tmp/out" ] || fail "output printed on error"
set +e
"$robcal" validate --robot abb-irb120 --tool $data/tool.yaml --measurements $data/validation.csv \
  --fit-base --ballbar-centre 1,2,3 2>"$tmp/err" >/dev/null
rc=$?
set -e
[ $rc -eq 2 ] || fail "--ballbar-centre on points: exit $rc"
grep -q "this is a points file" "$tmp/err" || fail "message: $(cat "$tmp/err")"
for centre in "nan,0,0" "1,2" "1,2,x"; do
  set +e
  "$robcal" validate --robot abb-irb120 --tool "$tmp/bb/tool.yaml" \
    --measurements "$tmp/bb/measurements.csv" --ballbar-centre="$centre" 2>"$tmp/err" >"$tmp/out"
  rc=$?
  set -e
  [ $rc -eq 2 ] || fail "--ballbar-centre $centre: exit $rc"
  grep -q -- "--ballbar-centre" "$tmp/err" || fail "message: $(cat "$tmp/err")"
  [ ! -s "$tmp/out" ] || fail "output printed for --ballbar-centre $centre"
done

# Poses files: the orientation weight is settable, printed, and enters the pose error only.
"$robcal" simulate --instrument optical-cmm --truth published --random 30 --seed 5 \
  --out "$tmp/cmm" >/dev/null
for w in 100 50; do
  "$robcal" validate --robot abb-irb120 --tool "$tmp/cmm/tool.yaml" \
    --measurements "$tmp/cmm/measurements.csv" --fit-base --orientation-weight $w --json \
    >"$tmp/cmm$w.json"
done
python3 - "$tmp/cmm100.json" "$tmp/cmm50.json" <<'PY'
import json, math, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
assert a["orientation_weight_mm_per_rad"] == 100 and b["orientation_weight_mm_per_rad"] == 50
assert a["position_error_mm"] == b["position_error_mm"]
assert a["orientation_error_deg"] == b["orientation_error_deg"]
# Each row's pose error lies between its position error and the hypotenuse with the largest
# orientation error; a heavier weight gives a larger pose error.
assert a["pose_error_mm"]["mean_mm"] > b["pose_error_mm"]["mean_mm"] > b["position_error_mm"]["mean_mm"]
bound = math.hypot(a["position_error_mm"]["max_mm"], 100 * math.radians(a["orientation_error_deg"]["max_deg"]))
assert a["pose_error_mm"]["max_mm"] <= bound + 1e-12
PY
"$robcal" validate --robot abb-irb120 --tool "$tmp/cmm/tool.yaml" \
  --measurements "$tmp/cmm/measurements.csv" --fit-base --orientation-weight 50 >"$tmp/cmm.txt"
grep -q "50 mm/rad" "$tmp/cmm.txt" || fail "orientation weight not printed"
set +e
"$robcal" validate --robot abb-irb120 --tool "$tmp/cmm/tool.yaml" \
  --measurements "$tmp/cmm/measurements.csv" --fit-base --orientation-weight 0 2>"$tmp/err"
rc=$?
set -e
[ $rc -eq 2 ] || fail "zero orientation weight: exit $rc"
grep -q -- "--orientation-weight" "$tmp/err" || fail "message: $(cat "$tmp/err")"

# Unused columns: a warning on stderr, results unchanged.
sed '1s/$/,humidity/; 2,$s/$/,41/' $data/validation.csv >"$tmp/extra.csv"
"$robcal" validate --robot abb-irb120 --tool $data/tool.yaml --measurements "$tmp/extra.csv" \
  --fit-base --json 2>"$tmp/err" >"$tmp/extra.json"
grep -q "column 'humidity' is not used" "$tmp/err" || fail "no warning"
python3 - "$tmp/t2.json" "$tmp/extra.json" <<'PY'
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
assert a["position_error_mm"] == b["position_error_mm"]
PY
# Calibrated models (robcal calibrate) against the reference validation set: the full model is
# at the noise floor (reference README: 0.0343 mm mean), the base-only one is not (1.394 mm).
for level in base full; do
  "$robcal" calibrate --robot abb-irb120 --tool $data/tool.yaml --measurements $data/calibration.csv \
    --level $level --out "$tmp/$level.yaml" >/dev/null
  "$robcal" validate --robot abb-irb120 --tool $data/tool.yaml --model "$tmp/$level.yaml" \
    --measurements $data/validation.csv --json >"$tmp/$level.json"
done
python3 - "$tmp/base.json" "$tmp/full.json" <<'PY'
import json, sys
base, full = (json.load(open(p)) for p in sys.argv[1:3])
assert 1.2 < base["position_error_mm"]["mean_mm"] < 1.6, base["position_error_mm"]
assert 0.028 < full["position_error_mm"]["mean_mm"] < 0.045, full["position_error_mm"]
assert full["position_error_mm"]["max_mm"] < 0.15, full["position_error_mm"]
assert full["level"] == "full" and not full["base_fitted_to_measurements"]
PY
# The model file records where it came from: version, command, inputs with their SHA-256.
sha=$(sha256sum $data/calibration.csv | cut -d' ' -f1)
grep -q "^  provenance:" "$tmp/full.yaml" || fail "no provenance in the model file"
grep -q "sha256: $sha" "$tmp/full.yaml" || fail "no SHA-256 of the measurements in the model file"
grep -q "command_line: .* calibrate .*--level full" "$tmp/full.yaml" || fail "no command line"
grep -q "robcal_version: [0-9]" "$tmp/full.yaml" || fail "no version"
# Statistics by class: every table's rows add up to all rows, the empty "back" class says
# "no data" (no number, no NaN), regions need --calibration; signed pair errors are reported.
"$robcal" validate --robot abb-irb120 --tool $data/tool.yaml --model "$tmp/full.yaml" \
  --measurements $data/validation.csv --calibration $data/calibration.csv --json >"$tmp/classes.json"
python3 - "$tmp/classes.json" "$tmp/full.json" <<'PY'
import json, sys
c, plain = (json.load(open(p)) for p in sys.argv[1:3])
tables = {t["table"]: t["rows"] for t in c["classes"]}
assert list(tables) == ["front/back", "up/down", "flip/no-flip", "target", "region"], list(tables)
assert "region" not in {t["table"] for t in plain["classes"]}
for name, rows in tables.items():
    assert sum(r["position_error_mm"]["rows"] for r in rows) == 1000, name
back = tables["front/back"][1]
assert back["class"] == "back" and back["position_error_mm"] == {"rows": 0, "status": "no data"}, back
de = c["distance_error_mm"]
assert 0 < de["positive_share"] < 1 and abs(de["signed_mean_mm"]) <= de["mean_mm"], de
# Pair distances by configuration class: the pairs with both rows in the class.
for name in ("front/back", "up/down", "flip/no-flip"):
    for r in tables[name]:
        n = r["position_error_mm"]["rows"]
        if n < 2:
            assert r["distance_error_mm"] == {"pairs": 0, "status": "no data"}, r
        else:
            assert r["distance_error_mm"]["pairs"] == n * (n - 1) // 2, r
            assert 0 <= r["distance_error_mm"]["positive_share"] <= 1, r
assert "distance_error_mm" not in tables["target"][0]
PY
"$robcal" validate --robot abb-irb120 --tool $data/tool.yaml --model "$tmp/full.yaml" \
  --measurements $data/validation.csv --calibration $data/calibration.csv >"$tmp/classes.txt"
grep -q "^  back  *0  *no data$" "$tmp/classes.txt" || fail "no 'no data' row: $(cat "$tmp/classes.txt")"
grep -q "^  ≥ 200 mm" "$tmp/classes.txt" || fail "no region table"
grep -q "% positive (measured distance the longer)" "$tmp/classes.txt" || fail "no signed pair errors"
grep -q "^distance error by class (mm), over the pairs of rows both in the class" "$tmp/classes.txt" \
  || fail "no pair distances by class"
! grep -qi "nan" "$tmp/classes.txt" || fail "NaN printed"

# ISO 9283: plan the cube, "measure" 30 cycles of the poses with known offsets, analyse.
"$robcal" iso9283 plan --robot abb-irb120 --region 300,-150,300,500,150,520 --cycles 30 \
  --out-poses "$tmp/iso-poses.csv" --out-cycles "$tmp/iso-cycles.csv" >"$tmp/iso-plan.txt"
grep -q "edge 200.000 mm" "$tmp/iso-plan.txt" || fail "cube: $(cat "$tmp/iso-plan.txt")"
[ "$(wc -l <"$tmp/iso-cycles.csv")" -eq 151 ] || fail "cycles file: not 150 moves"
python3 - "$tmp/iso-poses.csv" "$tmp/iso-meas.csv" <<'PY'
import csv, math, sys
poses = {r["name"]: r for r in csv.DictReader(open(sys.argv[1]))}
with open(sys.argv[2], "w") as out:
    out.write("pose,cycle,x,y,z\n")
    for cycle in range(1, 31):
        for k in range(1, 6):
            p = poses[f"P{k}"]
            # every pose 0.05 mm off in x, plus ±0.01 mm alternating in y
            dy = 0.01 if cycle % 2 else -0.01
            out.write(f"P{k},{cycle},{float(p['x']) + 0.05},{float(p['y']) + dy},{p['z']}\n")
PY
"$robcal" iso9283 analyse --poses "$tmp/iso-poses.csv" --measurements "$tmp/iso-meas.csv" --json \
  >"$tmp/iso.json"
python3 - "$tmp/iso.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
assert len(r["poses"]) == 5
for p in r["poses"]:
    # AP = 0.05 mm (the y offsets cancel over 30 cycles); every l_j = 0.01, S_l = 0: RP = 0.01.
    assert abs(p["AP_mm"] - 0.05) < 1e-6 and abs(p["RP_mm"] - 0.01) < 1e-6, p
assert abs(r["distance"]["AD_mm"]) < 1e-6 and r["distance"]["RD_mm"] < 1e-6, r["distance"]
PY
head -n 100 "$tmp/iso-meas.csv" >"$tmp/iso-few.csv"
set +e
"$robcal" iso9283 analyse --poses "$tmp/iso-poses.csv" --measurements "$tmp/iso-few.csv" \
  >"$tmp/out" 2>"$tmp/err"
rc=$?
set -e
[ $rc -eq 2 ] || fail "too few cycles: exit $rc"
grep -q "cycles: at least 30 are needed" "$tmp/err" || fail "message: $(cat "$tmp/err")"
[ ! -s "$tmp/out" ] || fail "output printed on error"
set +e
"$robcal" iso9283 plan --robot abb-irb120 --region 2000,0,0,2100,100,100 \
  --out-poses "$tmp/x.csv" --out-cycles "$tmp/y.csv" >/dev/null 2>"$tmp/err"
rc=$?
set -e
[ $rc -eq 2 ] || fail "unreachable cube: exit $rc"
grep -q "P1 at (2050.000, 50.000, 50.000) mm is not reachable" "$tmp/err" || fail "message: $(cat "$tmp/err")"
[ ! -e "$tmp/x.csv" ] || fail "plan written for an unreachable cube"
# The multi-directional test and the cycles as programs (programs layer): RAPID modules with
# one configuration per move; a Yaskawa job is refused before anything is written.
"$robcal" iso9283 plan --robot abb-irb120 --region 300,-150,300,500,150,520 --cycles 2 \
  --vap-approach 50 --program rapid --program-dir "$tmp/iso-prog" --out-poses "$tmp/v-poses.csv" \
  --out-cycles "$tmp/v-cycles.csv" --out-vap-cycles "$tmp/v-vap.csv" >"$tmp/v-plan.txt"
[ "$(wc -l <"$tmp/v-vap.csv")" -eq 61 ] || fail "vAP cycles file: not 60 moves"
[ "$(grep -c "MoveAbsJ" "$tmp/iso-prog/ISOCYC.mod")" -eq 10 ] || fail "cycle program: not 10 configurations"
[ "$(grep -c "MoveAbsJ" "$tmp/iso-prog/ISOVAP.mod")" -eq 60 ] || fail "vAP program: not 60 configurations"
[ "$(grep -c "WaitDI" "$tmp/iso-prog/ISOVAP.mod")" -eq 30 ] || fail "vAP program: a hook at a pre-pose"
grep -q "V02-P2-D3-from" "$tmp/iso-prog/ISOVAP.mod" || fail "vAP program: pre-pose names"
set +e
"$robcal" iso9283 plan --robot abb-irb120 --region 300,-150,300,500,150,520 --program jbi \
  --program-dir "$tmp/jbi" --out-poses "$tmp/j.csv" --out-cycles "$tmp/jc.csv" >/dev/null 2>"$tmp/err"
rc=$?
set -e
[ $rc -eq 2 ] || fail "jbi: exit $rc"
grep -q "pulses per degree" "$tmp/err" || fail "message: $(cat "$tmp/err")"
[ ! -e "$tmp/j.csv" ] && [ ! -e "$tmp/jbi" ] || fail "files written for a refused program"
# Axis test: the plan's moves, and a circle of radius 300 mm with a 0.05° step between the two
# approach sides, analysed exactly.
"$robcal" axis-test plan --joint 2 --home 0,10,10,0,45,0 --range -30,30 --steps 5 \
  --out "$tmp/moves.csv" >/dev/null
[ "$(grep -c ',below,' "$tmp/moves.csv")" -eq 5 ] || fail "axis moves: $(cat "$tmp/moves.csv")"
python3 - "$tmp/axis.csv" <<'PY'
import math, sys
with open(sys.argv[1], "w") as f:
    f.write("joint_deg,side,x,y,z\n")
    for k in range(12):
        q = -30 + 60 * k / 11
        for side, b in (("below", 0.0), ("above", 0.05)):
            a = math.radians(q + b)
            f.write(f"{q},{side},{300 * math.cos(a) + 10},{300 * math.sin(a)},500\n")
PY
"$robcal" axis-test analyse --measurements "$tmp/axis.csv" --json >"$tmp/axis.json"
python3 - "$tmp/axis.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
assert abs(r["backlash_deg"] - 0.05) < 1e-9 and abs(r["radius_mm"] - 300) < 1e-9, r
assert abs(abs(r["axis_direction"][2]) - 1) < 1e-12 and r["axial_mm"]["max_abs_mm"] < 1e-9, r
PY
sed '3s/,above,/,sideways,/' "$tmp/axis.csv" >"$tmp/axis-bad.csv"
set +e
"$robcal" axis-test analyse --measurements "$tmp/axis-bad.csv" >"$tmp/out" 2>"$tmp/err"
rc=$?
set -e
[ $rc -eq 2 ] || fail "bad side: exit $rc"
grep -q "axis-bad.csv:3:.* (side): expected below or above, found 'sideways'" "$tmp/err" || fail "message: $(cat "$tmp/err")"
# Ballbar path: 3 rings of 8 points written; an unreachable centre writes nothing, exit 2.
"$robcal" ballbar-path --robot abb-irb120 --tool $data/tool.yaml --target 1 --centre 400,0,300 \
  --length 100 --elevations -30,0,30 --points 8 --out "$tmp/bbpath.csv" >"$tmp/bbpath.txt" \
  2>"$tmp/bbpath.err"
[ "$(wc -l <"$tmp/bbpath.csv")" -eq 25 ] || fail "ballbar path: $(cat "$tmp/bbpath.csv")"
grep -q "all reachable in front-up-noflip" "$tmp/bbpath.txt" || fail "$(cat "$tmp/bbpath.txt")"
# Without a reading model the range check is vacuous, and the user is told so.
grep -q "note: no --reading-model: .* range check cannot see the real robot's error" \
  "$tmp/bbpath.err" || fail "no vacuous-range note: $(cat "$tmp/bbpath.err")"
set +e
"$robcal" ballbar-path --robot abb-irb120 --tool $data/tool.yaml --target 1 --centre 3000,0,300 \
  --length 100 --out "$tmp/bbpath2.csv" >"$tmp/out" 2>"$tmp/err"
rc=$?
set -e
[ $rc -eq 2 ] || fail "unreachable ballbar path: exit $rc"
grep -q "12 of 12 path points fail the checks" "$tmp/err" || fail "message: $(cat "$tmp/err")"
[ ! -e "$tmp/bbpath2.csv" ] || fail "ballbar path written despite failures"
echo "validate CLI: ok"
