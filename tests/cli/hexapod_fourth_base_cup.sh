#!/usr/bin/env bash
# A fourth base cup end to end (issue 20 item 3): `hexapod plan --base-cup4-mm` (B4 on the
# circumcircle of B1..B3, opposite B1: every pose gets a seventh leg, B4–T at the ballbar's
# length), the plan file with B4's setting point, simulated readings, the session killed by SIGKILL
# while it reads B4's distances and resumed, and `hexapod calibrate` (poses by the over-determined
# DKP, and the leg fit with B4 free) validated at the laser-tracker noise floor, the fitted B4 where
# its measured distances put it. With T4 as well: both fourth cups' legs in every configuration.
# The two-stage way (±1 mm ballbar, re-plan of the retries with their leg from B4).
# `hexapod setup --base-cup4-mm` lists B4's setting point as the plan does.
# Bad input: a collinear B4 on plan/simulate/place/setup, a leg from B4 in a plan without it.
set -euo pipefail
ROBCAL="$1" tmp=$(mktemp -d) pid=""
trap '[ -n "$pid" ] && kill -9 "$pid" 2>/dev/null; rm -rf "$tmp"' EXIT
json() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(eval(sys.argv[2]))" "$@"; }
fail() { echo "hexapod fourth base cup: $*" >&2; exit 1; }
TMP="$tmp"
source "$(dirname "$0")/lib/killed_session.sh"
mkdir -p "$tmp/s" "$tmp/both"
# 2R, R, R with R = 300/√3: B4 opposite B1 on the circumcircle of the base triangle.
base4=346.41016151377545,173.20508075688772,173.20508075688772
tool4=173.20508075688772,86.60254037844386,86.60254037844386

"$ROBCAL" hexapod plan --placement 450,0,300,0 --gauge-range-mm 5 --base-cup4-mm "$base4" \
  --out "$tmp/s/plan.json" > "$tmp/plan.log"
grep -q "base cup B4: [0-9]* legs to it in" "$tmp/plan.log" || fail "plan: $(head -3 "$tmp/plan.log")"
python3 - "$tmp/s/plan.json" <<'PY' || fail "plan file"
import json, math, sys
p = json.load(open(sys.argv[1]))
assert abs(p["base_cup4_mm"][0] - 346.41016151377545) < 1e-9, p["base_cup4_mm"]
# Four setting points: B4's is B1 mirrored through the centroid of B1..B3, and reachable.
s = [e["ball_position_mm"] for e in p["setting_ball"]]
assert [e["cup"] for e in p["setting_ball"]] == ["B1", "B2", "B3", "B4"]
centroid = [sum(c[i] for c in s[:3]) / 3 for i in range(3)]
assert math.dist(s[3], [2 * centroid[i] - s[0][i] for i in range(3)]) < 1e-6, s
assert p["setting_ball"][3]["configurations"]
configs = p["configurations"]
assert len(configs) > 50, len(configs)
# The six legs of the design, then the leg from B4 to the design-T1 cup (the one with three legs).
for c in configs:
    legs = c["legs"]
    assert len(legs) == 7 and legs[6].startswith("B4-"), legs
    t1 = max({l[3:] for l in legs[:6]}, key=lambda t: sum(l.endswith(t) for l in legs[:6]))
    assert legs[6] == "B4-" + t1, legs
PY

# `hexapod setup` gives the same four setting points as the plan.
"$ROBCAL" hexapod setup --placement 450,0,300,0 --base-cup4-mm "$base4" --json > "$tmp/setup.json"
python3 - "$tmp/setup.json" "$tmp/s/plan.json" <<'PY' || fail "setup: $(cat "$tmp/setup.json")"
import json, sys
setup, plan = (json.load(open(f))["setting_ball"] for f in sys.argv[1:3])
assert setup == plan, (setup, plan)
PY

"$ROBCAL" hexapod simulate-readings --plan "$tmp/s/plan.json" --seed 5 --out "$tmp/r.txt" \
  --tool-out "$tmp/tool.yaml" --validation-out "$tmp/val.csv" --validation 500 --json > "$tmp/sim.json"
[ "$(json "$tmp/sim.json" "d['legs_out_of_range']")" = 0 ] || fail "legs out of range"
n=$(json "$tmp/s/plan.json" "len(d['configurations'])")
# 3 tool sides, 6 base distances, 7 legs per configuration, a calibrator check every 5.
[ "$(wc -l < "$tmp/r.txt")" = $((9 + 7 * n + (n - 1) / 5)) ] || fail "readings: $(wc -l < "$tmp/r.txt")"

# The session killed (SIGKILL) once its journal holds 8 readings (B4's second distance), resumed.
valid_before_kill=8
kill_session_after "$valid_before_kill" "$tmp/s/plan.json" "$tmp/s/journal.jsonl" "$tmp/r.txt" \
  "$tmp/first.log" || fail "journal not at $valid_before_kill"
grep -q "Set the ballbar up at 346.41016151377545 mm. Attach the ballbar between base cups B1 and B4" \
  "$tmp/first.log" || fail "no B1-B4 step: $(cat "$tmp/first.log")"
[ "$(tail -n 1 "$tmp/s/journal.jsonl" | json /dev/stdin "d['key']")" = "base/B2-B4" ] ||
  fail "journal: $(tail -n 1 "$tmp/s/journal.jsonl")"
tail -n +$((valid_before_kill + 1)) "$tmp/r.txt" |
  "$ROBCAL" hexapod session --plan "$tmp/s/plan.json" --journal "$tmp/s/journal.jsonl" --resume \
    --out "$tmp/result.json" > "$tmp/resumed.log"
grep -q "$valid_before_kill readings replayed" "$tmp/resumed.log" || fail "resume: $(head -3 "$tmp/resumed.log")"
grep -q "Attach the ballbar between B4 and T[123]" "$tmp/resumed.log" || fail "no leg from B4"
[ "$(json "$tmp/result.json" "d['measured']")" = "$n" ] || fail "result: not all measured"
[ "$(json "$tmp/result.json" "len(d['base_sides_mm'])")" = 6 ] || fail "result: base distances"

for fit in poses legs; do
  "$ROBCAL" hexapod calibrate --session "$tmp/s" --tool "$tmp/tool.yaml" --fit "$fit" \
    --out "$tmp/$fit.yaml" --legs-out "$tmp/legs_$fit.csv" --json > "$tmp/cal_$fit.json"
  [ "$(json "$tmp/cal_$fit.json" "d['converged'] and d['configurations_measured'] == $n")" = True ] ||
    fail "calibrate $fit: $(cat "$tmp/cal_$fit.json")"
  [ "$(json "$tmp/cal_$fit.json" "len(d['base_cup4_mm']) == 3")" = True ] || fail "no base_cup4_mm"
  # Validation within 20 % of the tracker-noise floor (0.022·√(8/π) = 0.0351 mm).
  "$ROBCAL" validate --robot fanuc-lrmate200ic --tool "$tmp/tool.yaml" --model "$tmp/$fit.yaml" \
    --measurements "$tmp/val.csv" --json > "$tmp/val_$fit.json"
  [ "$(json "$tmp/val_$fit.json" "d['position_error_mm']['mean_mm'] < 1.2 * 0.0351")" = True ] ||
    fail "validation $fit: $(cat "$tmp/val_$fit.json")"
done
# The leg fit's B4: its distances to B1..B3 within 2 σ of the ballbar (0.51 µm) of the measured.
python3 - "$tmp/cal_legs.json" <<'PY' || fail "fitted B4: $(cat "$tmp/cal_legs.json")"
import json, sys
d = json.load(open(sys.argv[1]))
gap = max(abs(f - m) for f, m in zip(d["base_cup4_fitted_mm"], d["base_cup4_mm"]))
assert gap < 2 * 0.00051, (d["base_cup4_fitted_mm"], d["base_cup4_mm"])
print(f"fitted B4: distances to B1..B3 within {gap * 1000:.2f} µm of the measured ones")
PY
# The raw legs CSV: seven rows per configuration, the seventh an extra leg from B4.
[ "$(grep -vc '^#' "$tmp/legs_poses.csv")" = $((7 * n + 1)) ] || fail "legs csv rows"
[ "$(grep -c ',extra,B4,T[123],' "$tmp/legs_poses.csv")" = "$n" ] || fail "legs csv B4 rows"
grep -q "^# base cup B4 b14, b24, b34 = " "$tmp/legs_poses.csv" || fail "legs csv header"

# Both fourth cups: a leg from B4 and one to T4 in every configuration; the session asks T4's
# distances after the tool sides and B4's after the base sides.
"$ROBCAL" hexapod plan --placement 450,0,300,0 --gauge-range-mm 5 --base-cup4-mm "$base4" \
  --tool-cup4-mm "$tool4" --out "$tmp/both/plan.json" > /dev/null
python3 - "$tmp/both/plan.json" <<'PY' || fail "plan with both fourth cups"
import json, sys
for c in json.load(open(sys.argv[1]))["configurations"]:
    extra = c["legs"][6:]
    assert any(l.startswith("B4-") for l in extra) and any(l.endswith("-T4") for l in extra), c
PY
"$ROBCAL" hexapod simulate-readings --plan "$tmp/both/plan.json" --seed 5 --out "$tmp/rb.txt" \
  --tool-out "$tmp/toolb.yaml" --validation-out "$tmp/valb.csv" --validation 500 --json > "$tmp/simb.json"
[ "$(json "$tmp/simb.json" "d['legs_out_of_range']")" = 0 ] || fail "both: legs out of range"
"$ROBCAL" hexapod session --plan "$tmp/both/plan.json" --journal "$tmp/both/journal.jsonl" < "$tmp/rb.txt" > /dev/null
"$ROBCAL" hexapod calibrate --session "$tmp/both" --tool "$tmp/toolb.yaml" --fit legs \
  --out "$tmp/bothlegs.yaml" --json > "$tmp/cal_both.json"
"$ROBCAL" validate --robot fanuc-lrmate200ic --tool "$tmp/toolb.yaml" --model "$tmp/bothlegs.yaml" \
  --measurements "$tmp/valb.csv" --json > "$tmp/val_both.json"
[ "$(json "$tmp/val_both.json" "d['position_error_mm']['mean_mm'] < 1.2 * 0.0351")" = True ] ||
  fail "validation with both: $(cat "$tmp/val_both.json")"

# The two-stage way with the ±1 mm ballbar: configurations out of range are re-planned on the
# preliminary model with their leg from B4, and the second session asks neither the sides nor B4's
# distances again; both sessions calibrate together with nothing left to retry.
mkdir -p "$tmp/p1" "$tmp/p2"
"$ROBCAL" hexapod plan --placement 450,0,300,0 --base-cup4-mm "$base4" --out "$tmp/p1/plan.json" > /dev/null
"$ROBCAL" hexapod simulate-readings --plan "$tmp/p1/plan.json" --seed 5 --out "$tmp/q1.txt" \
  --tool-out "$tmp/tool1.yaml" --json > "$tmp/sim1.json"
[ "$(json "$tmp/sim1.json" "d['legs_out_of_range'] > 10")" = True ] || fail "±1 mm: all in range"
"$ROBCAL" hexapod session --plan "$tmp/p1/plan.json" --journal "$tmp/p1/journal.jsonl" < "$tmp/q1.txt" > /dev/null
"$ROBCAL" hexapod calibrate --session "$tmp/p1" --tool "$tmp/tool1.yaml" --out "$tmp/prelim.yaml" \
  --json > "$tmp/prelim.json"
retry=$(json "$tmp/prelim.json" "len(d['configurations_to_retry'])")
"$ROBCAL" hexapod replan --session "$tmp/p1" --model "$tmp/prelim.yaml" --out "$tmp/p2/plan.json" > /dev/null
python3 - "$tmp/p2/plan.json" "$retry" <<'PY' || fail "replan: $(head -c 600 "$tmp/p2/plan.json")"
import json, sys
p = json.load(open(sys.argv[1]))
assert len(p["configurations"]) == int(sys.argv[2]) > 10, (len(p["configurations"]), sys.argv[2])
assert all(len(c["legs"]) == 7 and c["legs"][6].startswith("B4-") for c in p["configurations"])
assert len(p["measured_sides"]["base_mm"]) == 6 and len(p["setting_ball"]) == 4
PY
"$ROBCAL" hexapod simulate-readings --plan "$tmp/p2/plan.json" --seed 5 --out "$tmp/q2.txt" --json > "$tmp/sim2.json"
[ "$(json "$tmp/sim2.json" "d['legs_out_of_range']")" = 0 ] || fail "re-planned legs out of range"
"$ROBCAL" hexapod session --plan "$tmp/p2/plan.json" --journal "$tmp/p2/journal.jsonl" < "$tmp/q2.txt" > "$tmp/p2.log"
! grep -q "base cups B1 and B4" "$tmp/p2.log" || fail "B4's distances asked again"
"$ROBCAL" hexapod calibrate --session "$tmp/p1" --session "$tmp/p2" --tool "$tmp/tool1.yaml" \
  --out "$tmp/final.yaml" --json > "$tmp/final.json"
[ "$(json "$tmp/final.json" "len(d['configurations_to_retry']) == 0 and d['converged']")" = True ] ||
  fail "two-stage: $(cat "$tmp/final.json")"

# The simulated end to end reads every leg from B4.
"$ROBCAL" hexapod simulate --gauge-range-mm 5 --base-cup4-mm "$base4" --seed 5 --validation 300 \
  --json > "$tmp/e2e.json"
[ "$(json "$tmp/e2e.json" "d['legs_read_base_cup4'] == d['measured_first_pass'] > 50")" = True ] ||
  fail "simulate: $(cat "$tmp/e2e.json")"

# Bad input: exit 2, the flag or file key named, nothing written.
expect_refusal() {  # fragment, command...
  local fragment="$1"; shift
  set +e
  "$@" 2> "$tmp/err" > /dev/null
  local rc=$?
  set -e
  [ "$rc" = 2 ] && grep -qF -- "$fragment" "$tmp/err" || fail "expected exit 2 and '$fragment': $(cat "$tmp/err")"
}
collinear=150,150,259.8076211353316
for cmd in "plan --out $tmp/x.json" "simulate --validation 10" "place" "setup"; do
  # shellcheck disable=SC2086
  expect_refusal "--base-cup4-mm: base fixture: the fourth cup B4 is collinear with B1 and B2" \
    "$ROBCAL" hexapod $cmd --base-cup4-mm "$collinear"
done
[ ! -e "$tmp/x.json" ]
python3 -c "import json,sys; p=json.load(open(sys.argv[1])); p.pop('base_cup4_mm'); p['setting_ball'].pop(); json.dump(p, open(sys.argv[2],'w'))" \
  "$tmp/s/plan.json" "$tmp/nocup4.json"
expect_refusal "nocup4.json (configurations[0].legs): leg 'B4-" \
  "$ROBCAL" hexapod session --plan "$tmp/nocup4.json" --journal "$tmp/x.jsonl"
[ ! -e "$tmp/x.jsonl" ]
echo "hexapod fourth base cup: $n configurations, session killed at B2-B4 and resumed; validation mean poses $(json "$tmp/val_poses.json" "d['position_error_mm']['mean_mm']") legs $(json "$tmp/val_legs.json" "d['position_error_mm']['mean_mm']") mm, with T4 too $(json "$tmp/val_both.json" "d['position_error_mm']['mean_mm']") mm"
