#!/usr/bin/env bash
# End-to-end checks of `robcal plan`: the chosen configurations file (config,target,j1..j6,
# read back by the simulator), the JSON indices (selected better than random), and bad input
# (exit code 2, a message naming the flag, no output file). Usage: plan_cli.sh path/to/robcal.
set -u
ROBCAL=${1:?usage: plan_cli.sh path/to/robcal}
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
source "$(dirname "$0")/lib/checks.sh"

# expect_region <plan JSON> <task configurations> "<substring of the task region>": the
# prediction is over that region, with 0 < mean ≤ max.
expect_region() {
  /usr/bin/python3 - "$@" <<'PY' || FAILED=1
import json, sys
p = json.load(open(sys.argv[1]))["predicted_error_mm"]
ok = p["task_configurations"] == int(sys.argv[2]) and sys.argv[3] in p["task_region"] and 0 < p["selected"]["mean_mm"] <= p["selected"]["max_mm"]
if not ok: print("FAIL: task region prediction", sys.argv[1], p)
sys.exit(0 if ok else 1)
PY
}

# 1. Laser tracker, full level: 40 rows, selected indices above the random ones.
"$ROBCAL" plan --robot abb-irb120 --instrument laser-tracker --level full --count 40 \
  --candidates 1500 --seed 3 --task-count 200 --json --out "$TMP/configs.csv" >"$TMP/plan.json" ||
  fail "plan failed: $(cat "$TMP/plan.json")"
/usr/bin/python3 - "$TMP/plan.json" "$TMP/configs.csv" <<'PY' || FAILED=1
import csv, json, sys
d = json.load(open(sys.argv[1]))
rows = list(csv.DictReader(open(sys.argv[2])))
errors = []
if d["count"] != 40 or len(rows) != 40: errors.append(f"count {d['count']}, rows {len(rows)}")
if list(rows[0].keys()) != ["config", "target", "j1", "j2", "j3", "j4", "j5", "j6"]:
    errors.append(f"columns {list(rows[0].keys())}")
for k in ["O1", "O3", "O5"]:
    if not d["selected"][k] > d["random"][k]: errors.append(f"{k}: {d['selected'][k]} vs {d['random'][k]}")
if not d["d_efficiency"] > d["d_efficiency_random"]: errors.append("D-efficiency")
if d["parameters"] != 30 or d["dropped"] != ["link3.d"]: errors.append(f"parameters {d['parameters']} {d['dropped']}")
p = d["predicted_error_mm"]
if not 0 < p["selected"]["mean_mm"] <= p["selected"]["max_mm"]: errors.append(f"prediction {p}")
for r in rows:
    j = [float(r[f"j{i}"]) for i in range(1, 7)]
    # published constraints
    if not (abs(j[0]) <= 90 and j[1] >= 0 and j[2] >= -80 and abs(j[3]) <= 150 and abs(j[4]) <= 90):
        errors.append(f"row {r['config']} outside the published constraints: {j}")
    if r["target"] not in ("1", "2", "3"): errors.append(f"target {r['target']}")
for e in errors: print("FAIL:", e)
sys.exit(1 if errors else 0)
PY

# 2. Same seed, same file.
"$ROBCAL" plan --count 40 --candidates 1500 --seed 3 --task-count 200 --out "$TMP/again.csv" \
  >/dev/null || fail "second plan failed"
cmp -s "$TMP/configs.csv" "$TMP/again.csv" || fail "same seed gave a different plan"

# 3. The optical CMM (poses) and the text output.
"$ROBCAL" plan --instrument optical-cmm --level kinematic --count 12 --candidates 500 \
  --task-count 100 --out "$TMP/cmm.csv" >"$TMP/cmm.txt" || fail "cmm plan failed: $(cat "$TMP/cmm.txt")"
grep -q "^O1" "$TMP/cmm.txt" || fail "cmm plan: no O1 line"
grep -q "predicted TCP error" "$TMP/cmm.txt" || fail "cmm plan: no prediction"

# 4. Task box: the prediction is over TCP positions in the box.
"$ROBCAL" plan --count 20 --candidates 600 --task-count 50 --json \
  --task-box "-500,-300,1100,1300,150,350" --out "$TMP/box.csv" >"$TMP/box.json" ||
  fail "plan with --task-box failed: $(cat "$TMP/box.json")"
expect_region "$TMP/box.json" 50 "box"

# 4b. Task poses (the file `robcal compensate` reads): the prediction is over their IK
# solutions; a pose out of reach or a malformed cell names file:line; one task region only.
cat >"$TMP/poses.csv" <<'CSV'
# TCP poses in the world frame, tool pointing down
name,x,y,z,qw,qx,qy,qz,config
p1,-400,1200,250,0,1,0,0,
p2,-450,1150,200,0,1,0,0,front-up-noflip
p3,-350,1250,300,0,0.7071067811865476,0.7071067811865476,0,
CSV
"$ROBCAL" plan --count 20 --candidates 600 --json --task-poses "$TMP/poses.csv" \
  --out "$TMP/poses_plan.csv" >"$TMP/poses.json" ||
  fail "plan with --task-poses failed: $(cat "$TMP/poses.json")"
expect_region "$TMP/poses.json" 3 "poses.csv"
printf 'name,x,y,z,qw,qx,qy,qz\np1,-400,1200,250,0,1,0,0\nfar,5000,0,0,0,1,0,0\n' >"$TMP/far.csv"
expect_error "task pose out of reach" "far.csv:3 (far): task pose" plan --count 20 \
  --candidates 300 --task-poses "$TMP/far.csv" --out "$TMP/bad.csv"
printf 'name,x,y,z,qw,qx,qy,qz,config\np1,-400,1200,250,0,1,0,0,back-down-flip\n' >"$TMP/branch.csv"
expect_error "task pose in a branch that does not reach it" \
  "branch.csv:2 (p1): task pose (-400.000, 1200.000, 250.000) mm in the world frame: configuration back-down-flip does not reach it" \
  plan --count 20 --candidates 300 --task-poses "$TMP/branch.csv" --out "$TMP/bad.csv"
printf 'name,x,y,z,qw,qx,qy,qz\np1,-400,1200,oops,0,1,0,0\n' >"$TMP/malformed.csv"
expect_error "malformed task poses" "malformed.csv:2:14 (z): expected a number, found 'oops'" \
  plan --task-poses "$TMP/malformed.csv" --out "$TMP/bad.csv"
printf 'name,x,y,z\np1,1,2,3\n' >"$TMP/header.csv"
expect_error "task poses without quaternion columns" "header.csv:1" plan --task-poses \
  "$TMP/header.csv" --out "$TMP/bad.csv"
expect_error "missing task poses file" "nowhere.csv" plan --task-poses "$TMP/nowhere.csv" \
  --out "$TMP/bad.csv"
expect_error "two task regions" "excludes" plan --task-poses "$TMP/poses.csv" \
  --task-box "-500,-300,1100,1300,150,350" --out "$TMP/bad.csv"

# 5. plan-study: seeded JSON, every planned configuration measured, optimal beats random.
"$ROBCAL" plan-study --counts 15,40 --seeds 2 --candidates 500 --task-count 40 --json \
  >"$TMP/study.json" || fail "plan-study failed: $(cat "$TMP/study.json")"
/usr/bin/python3 - "$TMP/study.json" <<'PY' || FAILED=1
import json, sys
d = json.load(open(sys.argv[1]))
errors = []
if d["seeds"] != [1, 11]: errors.append(f"seeds {d['seeds']}")
for r in d["rows"]:
    for k in ("optimal", "random"):
        for p in r[k]["per_seed"]:
            if p["measured"] != r["count"]: errors.append(f"count {r['count']} {k}: measured {p['measured']}")
    if not r["optimal"]["O1"] > r["random"]["O1"]: errors.append(f"O1 at {r['count']}")
    if not 0 < r["optimal"]["achieved_mean_mm"] < d["nominal_mean_mm"]: errors.append("no gain over nominal")
for e in errors: print("FAIL:", e)
sys.exit(1 if errors else 0)
PY
"$ROBCAL" plan-study --counts 15 --seeds 1 --candidates 300 --task-poses "$TMP/poses.csv" \
  --json >"$TMP/study_poses.json" || fail "plan-study --task-poses failed"
/usr/bin/python3 - "$TMP/study_poses.json" <<'PY' || FAILED=1
import json, sys
d = json.load(open(sys.argv[1]))
ok = d["task_configurations"] == 3 and "poses.csv" in d["task_region"]
if not ok: print("FAIL: plan-study task poses", d["task_configurations"], d["task_region"])
sys.exit(0 if ok else 1)
PY
expect_error "plan-study task pose out of reach" "far.csv:3 (far)" plan-study --counts 15 \
  --seeds 1 --candidates 300 --task-poses "$TMP/far.csv"
expect_error "bad counts" "--counts" plan-study --counts 15,x
expect_error "bad task box" "--task-box" plan --task-box 1,2,3 --out "$TMP/bad.csv"

# 6. Bad input.
expect_error "count too small" "at least 10 configurations" plan --count 5 --candidates 300 \
  --out "$TMP/bad.csv"
expect_error "floor above the robot" "no feasible candidate" plan --floor-mm 5000 \
  --candidates 50 --out "$TMP/bad.csv"
expect_error "unknown constraints" "--constraints" plan --constraints loose --out "$TMP/bad.csv"
expect_error "unknown level" "--level" plan --level everything --out "$TMP/bad.csv"
expect_error "unknown instrument" "--instrument" plan --instrument sextant --out "$TMP/bad.csv"
expect_error "unknown method" "--method" plan --method magic --out "$TMP/bad.csv"
printf 'payload: {mass_kg: 1, cog_mm: [0, 0, 50]}\ntargets: {}\n' >"$TMP/empty_tool.yaml"
expect_error "tool without targets" "no targets" plan --tool "$TMP/empty_tool.yaml" \
  --candidates 50 --out "$TMP/bad.csv"

# 12. Task-aware default with a task box, the shipped default cell, and the user's candidates.
DATA="$(dirname "$0")/../../data"
"$ROBCAL" plan --count 12 --candidates 400 --task-count 60 --task-box -500,-300,1100,1300,150,350 \
  --cell "$DATA/cells/default-tracker.yaml" --json --out "$TMP/cell.csv" >"$TMP/cell.json" ||
  fail "plan --cell failed: $(cat "$TMP/cell.json")"
/usr/bin/python3 - "$TMP/cell.json" <<'PY' || FAILED=1
import json, sys
d = json.load(open(sys.argv[1]))
ok = d["criterion"] == "I-optimal" and d["guard"] and d["near_edge"]["selected"] <= d["near_edge"]["limit"] == 3
if not ok: print("FAIL: task-aware plan in the default cell", d)
sys.exit(0 if ok else 1)
PY
"$ROBCAL" plan --count 10 --candidates-file "$TMP/configs.csv" --out "$TMP/sub.csv" >/dev/null ||
  fail "plan --candidates-file failed"
/usr/bin/python3 - "$TMP/configs.csv" "$TMP/sub.csv" <<'PY' || FAILED=1
import csv, sys
rows = lambda f: [[float(r[f"j{i}"]) for i in range(1, 7)] for r in csv.DictReader(open(f))]
given, chosen = rows(sys.argv[1]), rows(sys.argv[2])
listed = lambda c: any(max(abs(a - b) for a, b in zip(c, g)) < 1e-9 for g in given)
if len(chosen) != 10 or not all(listed(c) for c in chosen): print("FAIL: chosen rows not among the listed ones", chosen); sys.exit(1)
PY

# 13. plan-study in a cell with a fixture: its name in the report, and the study runs in it.
cat >"$TMP/fixture-cell.yaml" <<'YAML'
format: robcal-cell
name: fixture cell
robot_base:
  position_mm: [-812.25, 1503.5, -95]
  rotation_xyz_deg: [0.25, -0.4, -57]
instrument:
  kind: laser-tracker
  position_mm: [0, 0, 0]
  range_mm: [0, 35000]
  cone_half_angle_deg: 30
floor_z_mm: -95
link_radius_mm: 60
keep_out:
  - {name: fixture, min_mm: [-700, 1000, -95], max_mm: [-300, 1300, 400]}
YAML
"$ROBCAL" plan-study --cell "$TMP/fixture-cell.yaml" --seeds 1 --counts 20 --candidates 300 \
  --task-count 50 --json >"$TMP/study-cell.json" || fail "plan-study --cell failed"
/usr/bin/python3 - "$TMP/study-cell.json" <<'PY' || FAILED=1
import json, sys
d = json.load(open(sys.argv[1]))
if d["cell"] != "fixture cell" or d["rows"][0]["optimal"]["per_seed"][0]["measured"] < 15:
    print("FAIL: plan-study in the fixture cell", {k: d[k] for k in d if k != "rows"}); sys.exit(1)
PY
expect_error "cannot open" "nowhere.yaml" plan-study --cell "$TMP/nowhere.yaml" --seeds 1

# 14. The model misfit: without it the prediction is labelled noise-only and says what is
# missing; with --misfit-mm it is added in quadrature (docs/method/05-observability.md §6);
# plan-study's prior calibration gives every true robot its allowance.
"$ROBCAL" plan --count 12 --candidates 300 --task-count 40 --out "$TMP/m.csv" >"$TMP/m.txt" ||
  fail "plan without misfit failed"
grep -qF "from instrument noise only" "$TMP/m.txt" || fail "noise-only prediction not labelled"
grep -qF "note: a real robot adds the misfit" "$TMP/m.txt" || fail "no note on the misfit"
"$ROBCAL" plan --count 12 --candidates 300 --task-count 40 --misfit-mm 0.04 --json \
  --out "$TMP/m.csv" >"$TMP/m.json" || fail "plan --misfit-mm failed"
/usr/bin/python3 - "$TMP/m.json" <<'PY' || FAILED=1
import json, math, sys
d = json.load(open(sys.argv[1]))
noise, m = d["predicted_error_mm"], d["predicted_error_with_misfit_mm"]
want = math.hypot(noise["selected"]["rms_mm"], 0.04)
ok = noise["basis"] == "instrument noise only" and m["misfit_rms_mm"] == 0.04 and abs(m["selected"]["rms_mm"] - want) < 1e-5
if not ok: print("FAIL: plan --misfit-mm", noise, m)
sys.exit(0 if ok else 1)
PY
"$ROBCAL" plan-study --counts 20 --seeds 2 --candidates 300 --task-count 40 \
  --effects mass-error --json >"$TMP/study-misfit.json" || fail "plan-study with a prior failed"
/usr/bin/python3 - "$TMP/study-misfit.json" <<'PY' || FAILED=1
import json, sys
d = json.load(open(sys.argv[1]))
o = d["rows"][0]["optimal"]
ok = d["prior_count"] == 60 and len(d["misfit_mm"]) == 2 and any(m["misfit"] > 0 for m in d["misfit_mm"]) \
    and o["predicted_rms_with_misfit_mm"] > o["predicted_rms_mm"]
if not ok: print("FAIL: plan-study misfit", d["misfit_mm"], o["predicted_rms_mm"], o["predicted_rms_with_misfit_mm"])
sys.exit(0 if ok else 1)
PY
expect_error "misfit twice" "excludes" plan --misfit-mm 0.1 --prior-model "$TMP/none.yaml" \
  --out "$TMP/bad.csv"
expect_error "prior count" "--prior-count" plan-study --prior-count 5 --seeds 1

finish plan_cli
