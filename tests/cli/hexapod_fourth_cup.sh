#!/usr/bin/env bash
# A fourth tool cup end to end (issue 20 item 3): `hexapod plan --tool-cup4-mm` (T4 on the
# circumcircle of T1..T3, opposite T1: every pose gets a seventh leg, B–T4 at the ballbar's length),
# the plan file, simulated readings, the session stopped by the end of its input and resumed, and
# `hexapod calibrate` (poses by the over-determined DKP, and the leg fit) validated at the
# laser-tracker noise floor.
set -euo pipefail
ROBCAL="$1"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/s"
json() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(eval(sys.argv[2]))" "$@"; }
# 2R, R, R with R = 150/√3: T4 opposite T1 on the circumcircle.
cup4=173.20508075688772,86.60254037844386,86.60254037844386

"$ROBCAL" hexapod plan --robot fanuc-lrmate200ic --placement 450,0,300,0 --gauge-range-mm 5 \
  --tool-cup4-mm "$cup4" --out "$tmp/s/plan.json" > /dev/null
python3 - "$tmp/s/plan.json" <<'PY'
import json, sys
p = json.load(open(sys.argv[1]))
assert abs(p["tool_cup4_mm"][0] - 173.20508075688772) < 1e-9, p["tool_cup4_mm"]
configs = p["configurations"]
assert len(configs) > 50, len(configs)
# The six legs of the design, then the leg from the design-B2 cup (the one with three legs) to T4.
for c in configs:
    legs = c["legs"]
    assert len(legs) == 7 and legs[6].endswith("-T4"), legs
    b2 = max({l[:2] for l in legs[:6]}, key=lambda b: sum(l.startswith(b) for l in legs[:6]))
    assert legs[6] == b2 + "-T4", legs
PY

"$ROBCAL" hexapod simulate-readings --plan "$tmp/s/plan.json" --seed 5 --out "$tmp/r.txt" \
  --tool-out "$tmp/tool.yaml" --validation-out "$tmp/val.csv" --validation 500 --json > "$tmp/sim.json"
[ "$(json "$tmp/sim.json" "d['legs_out_of_range']")" = 0 ]
n=$(json "$tmp/s/plan.json" "len(d['configurations'])")
# 6 tool distances, 3 base sides, 7 legs per configuration, a calibrator check every 5.
[ "$(wc -l < "$tmp/r.txt")" = $((9 + 7 * n + (n - 1) / 5)) ]

# The session, stopped after 40 readings by the end of its input, then resumed.
head -n 40 "$tmp/r.txt" |
  "$ROBCAL" hexapod session --plan "$tmp/s/plan.json" --journal "$tmp/s/journal.jsonl" > "$tmp/first.log"
grep -q "Set the ballbar up at 173.20508075688772 mm. Attach the ballbar between tool cups T1 and T4" \
  "$tmp/first.log"
grep -q "Attach the ballbar between B[123] and T4" "$tmp/first.log"
tail -n +41 "$tmp/r.txt" |
  "$ROBCAL" hexapod session --plan "$tmp/s/plan.json" --journal "$tmp/s/journal.jsonl" --resume \
    --out "$tmp/result.json" > "$tmp/resumed.log"
grep -q "40 readings replayed" "$tmp/resumed.log"
[ "$(json "$tmp/result.json" "d['measured']")" = "$n" ]

for fit in poses legs; do
  "$ROBCAL" hexapod calibrate --session "$tmp/s" --tool "$tmp/tool.yaml" --fit "$fit" \
    --out "$tmp/$fit.yaml" --legs-out "$tmp/legs_$fit.csv" --json > "$tmp/cal_$fit.json"
  [ "$(json "$tmp/cal_$fit.json" "d['converged'] and d['configurations_measured'] == $n")" = True ]
  [ "$(json "$tmp/cal_$fit.json" "len(d['tool_cup4_mm']) == 3")" = True ]
  # Validation within 20 % of the tracker-noise floor (0.022·√(8/π) = 0.0351 mm).
  "$ROBCAL" validate --robot fanuc-lrmate200ic --tool "$tmp/tool.yaml" --model "$tmp/$fit.yaml" \
    --measurements "$tmp/val.csv" --json > "$tmp/val_$fit.json"
  [ "$(json "$tmp/val_$fit.json" "d['position_error_mm']['mean_mm'] < 1.2 * 0.0351")" = True ]
done
# The raw legs CSV: seven rows per configuration, the seventh an extra leg to T4.
[ "$(grep -vc '^#' "$tmp/legs_poses.csv")" = $((7 * n + 1)) ]
[ "$(grep -c ',extra,B[123],T4,' "$tmp/legs_poses.csv")" = "$n" ]

# A leg to T4 in a plan without the fourth cup: the file and key are named, exit 2.
python3 -c "import json,sys; p=json.load(open(sys.argv[1])); p.pop('tool_cup4_mm'); json.dump(p, open(sys.argv[2],'w'))" \
  "$tmp/s/plan.json" "$tmp/nocup4.json"
set +e
"$ROBCAL" hexapod session --plan "$tmp/nocup4.json" --journal "$tmp/x.jsonl" < /dev/null 2> "$tmp/err"
rc=$?
set -e
[ "$rc" = 2 ] && grep -qF "nocup4.json (configurations[0].legs): leg '" "$tmp/err" && [ ! -e "$tmp/x.jsonl" ]

# The two-stage way with the ±1 mm ballbar: configurations out of range are re-planned on the
# preliminary model with their leg to T4, and the second session asks neither the sides nor T4's
# distances again.
mkdir -p "$tmp/p1" "$tmp/p2"
"$ROBCAL" hexapod plan --placement 450,0,300,0 --tool-cup4-mm "$cup4" --out "$tmp/p1/plan.json" > /dev/null
"$ROBCAL" hexapod simulate-readings --plan "$tmp/p1/plan.json" --seed 5 --out "$tmp/q1.txt" \
  --tool-out "$tmp/tool1.yaml" --json > "$tmp/sim1.json"
[ "$(json "$tmp/sim1.json" "d['legs_out_of_range'] > 10")" = True ]
"$ROBCAL" hexapod session --plan "$tmp/p1/plan.json" --journal "$tmp/p1/journal.jsonl" < "$tmp/q1.txt" > /dev/null
"$ROBCAL" hexapod calibrate --session "$tmp/p1" --tool "$tmp/tool1.yaml" --out "$tmp/prelim.yaml" \
  --json > "$tmp/prelim.json"
retry=$(json "$tmp/prelim.json" "len(d['configurations_to_retry'])")
"$ROBCAL" hexapod replan --session "$tmp/p1" --model "$tmp/prelim.yaml" --out "$tmp/p2/plan.json" > /dev/null
python3 - "$tmp/p2/plan.json" "$retry" <<'PY'
import json, sys
p = json.load(open(sys.argv[1]))
assert len(p["configurations"]) == int(sys.argv[2]) > 10, (len(p["configurations"]), sys.argv[2])
assert all(len(c["legs"]) == 7 and c["legs"][6].endswith("-T4") for c in p["configurations"])
assert len(p["measured_sides"]["tool_mm"]) == 6 and len(p["tool_cup4_mm"]) == 3
PY
"$ROBCAL" hexapod simulate-readings --plan "$tmp/p2/plan.json" --seed 5 --out "$tmp/q2.txt" --json > "$tmp/sim2.json"
[ "$(json "$tmp/sim2.json" "d['legs_out_of_range']")" = 0 ]
"$ROBCAL" hexapod session --plan "$tmp/p2/plan.json" --journal "$tmp/p2/journal.jsonl" < "$tmp/q2.txt" > "$tmp/p2.log"
! grep -q "tool cups T1 and T4" "$tmp/p2.log"
"$ROBCAL" hexapod calibrate --session "$tmp/p1" --session "$tmp/p2" --tool "$tmp/tool1.yaml" \
  --out "$tmp/final.yaml" --json > "$tmp/final.json"
[ "$(json "$tmp/final.json" "len(d['configurations_to_retry']) == 0 and d['converged']")" = True ]
