#!/usr/bin/env bash
# Calibration from hexapod measurement sessions, the two-stage way, on a simulated cell: plan →
# simulated readings piped into the session → preliminary calibration → re-plan of the legs that
# were out of range → second session → final calibration on both → validation against simulated
# laser-tracker points (at the tracker-noise floor, 0.035 mm mean, while the nominal model is off by
# about 1 mm).
set -euo pipefail
ROBCAL="$1"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/s1" "$tmp/s2"
json() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(eval(sys.argv[2]))" "$@"; }

"$ROBCAL" hexapod plan --robot fanuc-lrmate200ic --placement 450,0,300,0 --out "$tmp/s1/plan.json" > /dev/null
"$ROBCAL" hexapod simulate-readings --plan "$tmp/s1/plan.json" --seed 5 --out "$tmp/r1.txt" \
  --tool-out "$tmp/tool.yaml" --validation-out "$tmp/val.csv" --validation 500 --json > "$tmp/sim1.json"
[ "$(json "$tmp/sim1.json" "d['legs_out_of_range'] > 10")" = True ]  # uncalibrated: many out of range
"$ROBCAL" hexapod session --plan "$tmp/s1/plan.json" --journal "$tmp/s1/journal.jsonl" < "$tmp/r1.txt" > /dev/null

# Stage 1: preliminary calibration on what was measurable.
"$ROBCAL" hexapod calibrate --session "$tmp/s1" --tool "$tmp/tool.yaml" --out "$tmp/prelim.yaml" \
  --poses-out "$tmp/poses.csv" --legs-out "$tmp/legs.csv" --json > "$tmp/prelim.json"
[ "$(json "$tmp/prelim.json" "d['converged'] and d['rms_mm'] < 0.01")" = True ]
retry=$(json "$tmp/prelim.json" "len(d['configurations_to_retry'])")
measured=$(json "$tmp/prelim.json" "d['configurations_measured']")
[ "$retry" -gt 10 ]
# The exported files: one pose row and six leg rows per measured configuration.
[ "$(grep -vc '^#' "$tmp/poses.csv")" = $((measured + 1)) ]
[ "$(grep -vc '^#' "$tmp/legs.csv")" = $((6 * measured + 1)) ]
head -n 2 "$tmp/poses.csv" | grep -q '^config,j1,j2,j3,j4,j5,j6,x,y,z,qw,qx,qy,qz$'
# The generic path gives the same fit from the exported poses file.
"$ROBCAL" calibrate --robot fanuc-lrmate200ic --tool "$tmp/tool.yaml" --measurements "$tmp/poses.csv" \
  --out "$tmp/generic.yaml" --json > "$tmp/generic.json"
python3 - "$tmp/prelim.json" "$tmp/generic.json" <<'PY'
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:])
assert abs(a["rms_mm"] - b["rms_mm"]) < 1e-6, (a["rms_mm"], b["rms_mm"])
# One definition of the residual (per-pose 3D TCP error) at the solution and at the start.
for key in ("residual_per_row_mm", "start_residual_per_row_mm"):
    for stat in ("mean_mm", "rms_mm", "max_mm"):
        assert abs(a[key][stat] - b[key][stat]) < 1e-6, (key, stat, a[key], b[key])
    s = a[key]
    assert 0 < s["mean_mm"] <= s["rms_mm"] <= s["max_mm"], (key, s)
assert a["start_residual_per_row_mm"]["rms_mm"] > 10 * a["residual_per_row_mm"]["rms_mm"]
assert "initial_rms_mm" not in a
PY

# Stage 2: re-plan the retries on the preliminary model, measure them (fixture sides are not asked
# again), calibrate on both sessions.
"$ROBCAL" hexapod replan --session "$tmp/s1" --model "$tmp/prelim.yaml" \
  --out "$tmp/s2/plan.json" --json > "$tmp/replan.json"
[ "$(json "$tmp/replan.json" "d['replanned']")" = "$retry" ]
"$ROBCAL" hexapod simulate-readings --plan "$tmp/s2/plan.json" --seed 5 --out "$tmp/r2.txt" --json > "$tmp/sim2.json"
[ "$(json "$tmp/sim2.json" "d['legs_out_of_range']")" = 0 ]
"$ROBCAL" hexapod session --plan "$tmp/s2/plan.json" --journal "$tmp/s2/journal.jsonl" < "$tmp/r2.txt" > "$tmp/s2.log"
! grep -q "tool cups T1 and T2" "$tmp/s2.log"
"$ROBCAL" hexapod calibrate --session "$tmp/s1" --session "$tmp/s2" --tool "$tmp/tool.yaml" \
  --out "$tmp/final.yaml" --json > "$tmp/final.json"
[ "$(json "$tmp/final.json" "d['configurations_measured']")" = $((measured + retry)) ]
[ "$(json "$tmp/final.json" "len(d['configurations_to_retry'])")" = 0 ]

# The fit straight from the raw legs (cups and ballbar offset identified), in the same frame.
"$ROBCAL" hexapod calibrate --session "$tmp/s1" --session "$tmp/s2" --tool "$tmp/tool.yaml" \
  --fit legs --out "$tmp/legs.yaml" --json > "$tmp/legs.json"
[ "$(json "$tmp/legs.json" "d['converged'] and d['rms_mm'] < 0.005")" = True ]

# Validation: calibrated models within 20% of the tracker-noise floor (mean of |N(0, 0.022² I)|
# = 0.022·√(8/π) = 0.0351 mm) and 0.15 mm max; the nominal one is off by about 1 mm.
for m in prelim final legs; do
  "$ROBCAL" validate --robot fanuc-lrmate200ic --tool "$tmp/tool.yaml" --model "$tmp/$m.yaml" \
    --measurements "$tmp/val.csv" --json > "$tmp/val_$m.json"
  [ "$(json "$tmp/val_$m.json" "d['position_error_mm']['mean_mm'] < 1.2 * 0.0351 and d['position_error_mm']['max_mm'] < 0.15")" = True ]
done
"$ROBCAL" validate --robot fanuc-lrmate200ic --tool "$tmp/tool.yaml" --fit-base \
  --measurements "$tmp/val.csv" --json > "$tmp/val_nominal.json"
[ "$(json "$tmp/val_nominal.json" "d['position_error_mm']['mean_mm'] > 0.5")" = True ]

# Errors exit with code 2 and name what is wrong; no output file is left behind.
set +e
"$ROBCAL" hexapod calibrate --session "$tmp/s1/journal.jsonl" --out "$tmp/x.yaml" 2> "$tmp/err"
rc=$?
set -e
[ "$rc" = 2 ] && grep -q -- "--plan" "$tmp/err" && [ ! -e "$tmp/x.yaml" ]
python3 -c "import json,sys; p=json.load(open(sys.argv[1])); [c.pop('mode') for c in p['configurations']]; json.dump(p, open(sys.argv[2],'w'))" \
  "$tmp/s1/plan.json" "$tmp/nomode.json"
set +e
"$ROBCAL" hexapod calibrate --session "$tmp/s1/journal.jsonl" --plan "$tmp/nomode.json" --out "$tmp/x.yaml" 2> "$tmp/err"
rc=$?
set -e
[ "$rc" = 2 ] && grep -q "configurations\[0\].mode" "$tmp/err" && [ ! -e "$tmp/x.yaml" ]
set +e
"$ROBCAL" hexapod calibrate --session "$tmp/s1" --orientation-weight -1 --out "$tmp/x.yaml" \
  --poses-out "$tmp/x.csv" 2> "$tmp/err"
rc=$?
set -e
[ "$rc" = 2 ] && grep -q -- "--orientation-weight" "$tmp/err" && [ ! -e "$tmp/x.yaml" ] && [ ! -e "$tmp/x.csv" ]
set +e
"$ROBCAL" hexapod calibrate --session "$tmp/none" --out "$tmp/x.yaml" 2> "$tmp/err"
rc=$?
set -e
[ "$rc" = 2 ] && grep -q "$tmp/none (--session): no such session" "$tmp/err" && [ ! -e "$tmp/x.yaml" ]
# A plan the simulator cannot read: the file and key are named, exit 2, no readings file.
while IFS='|' read -r key edit; do
  python3 -c "import json,sys; p=json.load(open(sys.argv[1])); $edit; json.dump(p, open(sys.argv[2],'w'))" \
    "$tmp/s1/plan.json" "$tmp/badplan.json"
  set +e
  "$ROBCAL" hexapod simulate-readings --plan "$tmp/badplan.json" --out "$tmp/x.txt" \
    --tool-out "$tmp/x.yaml" 2> "$tmp/err"
  rc=$?
  set -e
  [ "$rc" = 2 ] && grep -q "badplan.json" "$tmp/err" && grep -qF "($key)" "$tmp/err" \
    && [ ! -e "$tmp/x.txt" ] && [ ! -e "$tmp/x.yaml" ] || { echo "bad plan ($edit):"; cat "$tmp/err"; exit 1; }
done <<'EDITS'
placement|p['placement'] = '450,0'
geometry.base_sides_mm|p['geometry']['base_sides_mm'] = 'x'
geometry.tool_sides_mm|p['geometry']['tool_sides_mm'] = [150, 150]
ballbar.leg_mm|p['ballbar']['leg_mm'] = -1
tool_offset_mm|p.pop('tool_offset_mm')
EDITS
python3 - "$tmp" <<'PY'
import json, sys
t = sys.argv[1]
for m in ("prelim", "final", "legs", "nominal"):
    d = json.load(open(f"{t}/val_{m}.json"))["position_error_mm"]
    print(f"hexapod calibrate: {m} model, validation mean {d['mean_mm']:.4f} max {d['max_mm']:.4f} mm")
PY
