#!/usr/bin/env bash
# Two base-fixture placements calibrated together (issue 20 item 1): plans at two placements, a
# ±5 mm gauge (every leg readable on the uncalibrated robot), simulated readings of one true robot
# (same seed), the first session run straight, the second killed midway (SIGKILL) and resumed;
# `hexapod calibrate --fit legs` on both sessions identifies each placement's base cups and is
# validated on simulated laser-tracker points of the first placement's world. `hexapod place
# --measured` proposes the next placement. Bad input: the pose fit with two placements, the same
# placement given twice (overlapping cups), a measured plan given twice, a design whose second
# --out cannot be written (neither written).
# Further arguments are given to every `hexapod plan` and `hexapod place` (a fourth tool cup:
# hexapod_placements_fourth_cup.sh).
set -euo pipefail
ROBCAL="$1" tmp=$(mktemp -d) pid=""
shift
fixture=("$@")
trap '[ -n "$pid" ] && kill -9 "$pid" 2>/dev/null; rm -rf "$tmp"' EXIT
json() { python3 -c "import json,sys; d=json.load(open(sys.argv[1])); print(eval(sys.argv[2]))" "$@"; }
fail() { echo "hexapod placements: $*" >&2; exit 1; }
TMP="$tmp"
source "$(dirname "$0")/lib/killed_session.sh"
mkdir -p "$tmp/a" "$tmp/b" "$tmp/c"

"$ROBCAL" hexapod plan --placement 500,300,150,0 --gauge-range-mm 5 "${fixture[@]}" --out "$tmp/a/plan.json" > /dev/null
"$ROBCAL" hexapod plan --placement 350,0,300,0 --gauge-range-mm 5 "${fixture[@]}" --out "$tmp/b/plan.json" > /dev/null
"$ROBCAL" hexapod simulate-readings --plan "$tmp/a/plan.json" --seed 5 --out "$tmp/ra.txt" \
  --tool-out "$tmp/tool.yaml" --validation-out "$tmp/val.csv" --validation 500 --json > "$tmp/sa.json"
"$ROBCAL" hexapod simulate-readings --plan "$tmp/b/plan.json" --seed 5 --out "$tmp/rb.txt" --json > "$tmp/sb.json"
[ "$(json "$tmp/sa.json" "d['legs_out_of_range']")" = 0 ] || fail "legs out of the ±5 mm range"
[ "$(json "$tmp/sb.json" "d['legs_out_of_range']")" = 0 ] || fail "legs out of the ±5 mm range"
"$ROBCAL" hexapod session --plan "$tmp/a/plan.json" --journal "$tmp/a/journal.jsonl" < "$tmp/ra.txt" > /dev/null

# The second placement's session: killed once its journal holds 40 readings, then resumed.
valid_before_kill=40
kill_session_after "$valid_before_kill" "$tmp/b/plan.json" "$tmp/b/journal.jsonl" "$tmp/rb.txt" \
  /dev/null || fail "journal not at $valid_before_kill"
# Before the resume, the partial second session calibrates with the first (its measured part).
"$ROBCAL" hexapod calibrate --session "$tmp/a" --session "$tmp/b" --fit legs --tool "$tmp/tool.yaml" \
  --out "$tmp/partial.yaml" --json > "$tmp/partial.json"
[ "$(json "$tmp/partial.json" "d['configurations_pending'] > 0 and len(d['placements']) == 2")" = True ] ||
  fail "partial: $(cat "$tmp/partial.json")"
tail -n +$((valid_before_kill + 1)) "$tmp/rb.txt" |
  "$ROBCAL" hexapod session --plan "$tmp/b/plan.json" --journal "$tmp/b/journal.jsonl" --resume > "$tmp/resumed.log"
grep -q "$valid_before_kill readings replayed" "$tmp/resumed.log" || fail "resume: $(cat "$tmp/resumed.log")"

"$ROBCAL" hexapod calibrate --session "$tmp/a" --session "$tmp/b" --fit legs --tool "$tmp/tool.yaml" \
  --out "$tmp/both.yaml" --json > "$tmp/both.json"
na=$(python3 -c "import json; print(len(json.load(open('$tmp/a/plan.json'))['configurations']))")
nb=$(python3 -c "import json; print(len(json.load(open('$tmp/b/plan.json'))['configurations']))")
python3 - "$tmp/both.json" "$na" "$nb" <<'PY' || fail "calibrate: $(cat "$tmp/both.json")"
import json, sys
d = json.load(open(sys.argv[1])); na, nb = int(sys.argv[2]), int(sys.argv[3])
assert d["converged"], d
assert len(d["placements"]) == 2
assert [p["configurations_measured"] for p in d["placements"]] == [na, nb], d["placements"]
assert d["configurations_measured"] == na + nb and d["configurations_pending"] == 0
assert d["rms_mm"] < 1.2 * 0.00051, d["rms_mm"]  # the ballbar's σ: both world frames fitted
assert any(h.startswith("link3.d") or h.startswith("link2.d") for h in d["held"])
PY
# The leg fit's covariance: every identified parameter has a positive std in the model file, and
# the a-posteriori σ̂ that scales them is the ballbar's.
python3 - "$tmp/both.yaml" <<'PY' || fail "leg-fit std: $(cat "$tmp/both.yaml")"
import re, sys
text = open(sys.argv[1]).read()
rows = re.findall(r"\{name: ([^,]+),.*status: identified", text)
stds = dict(re.findall(r"\{name: ([^,]+),[^}]*std: ([-0-9.e+]+)[^}]*status: identified", text))
assert len(rows) > 20 and sorted(rows) == sorted(stds), (rows, stds)
assert all(float(v) > 0 for v in stds.values()), stds
sigma = float(re.search(r"sigma_mm: ([0-9.e+-]+)", text).group(1))
assert 0.5 * 0.00051 < sigma < 1.5 * 0.00051, sigma
PY
"$ROBCAL" hexapod calibrate --session "$tmp/a" --fit legs --tool "$tmp/tool.yaml" --out "$tmp/one.yaml" > /dev/null
# The joint-periodic group identified from both placements as well (the design's --identify):
# the fit still reaches the ballbar's σ and the model file holds the periodic terms.
"$ROBCAL" hexapod calibrate --session "$tmp/a" --session "$tmp/b" --fit legs --tool "$tmp/tool.yaml" \
  --identify periodic --out "$tmp/periodic.yaml" --json > "$tmp/periodic.json"
python3 - "$tmp/periodic.json" <<'PY' || fail "calibrate --identify periodic: $(cat "$tmp/periodic.json")"
import json, sys
d = json.load(open(sys.argv[1]))
assert d["converged"] and d["rms_mm"] < 1.2 * 0.00051, d
PY
grep -q "joint2.periodic1.cos" "$tmp/periodic.yaml" || fail "no periodic terms in $(cat "$tmp/periodic.yaml")"
if [ ${#fixture[@]} -gt 0 ]; then
  # With a fourth tool cup: seven legs in every configuration of both sessions, and the fitted T4
  # (a target of the calibrated tool, flange frame) where its measured distances put it: the true
  # distances are those within the ballbar's σ (0.51 µm), the fit's within 2 µm (measured
  # 0.27 µm); the one- and two-placement fits agree within 5 µm.
  python3 - "$tmp/a/plan.json" "$tmp/b/plan.json" "$tmp/both.json" "$tmp/both.yaml" "$tmp/one.yaml" <<'PY' ||
import json, math, re, sys
for plan in sys.argv[1:3]:
    assert all(len(c["legs"]) == 7 and c["legs"][6].endswith("-T4")
               for c in json.load(open(plan))["configurations"]), plan
measured = json.load(open(sys.argv[3]))["tool_cup4_mm"]
def targets(path):
    text = open(path).read()
    return {n: [float(v) for v in xyz.split(",")]
            for n, xyz in re.findall(r'^    "(T[1-4])": \[([^\]]*)\]', text, re.M)}
both, one = targets(sys.argv[4]), targets(sys.argv[5])
assert sorted(both) == ["T1", "T2", "T3", "T4"], both
fitted = [math.dist(both["T4"], both[t]) for t in ("T1", "T2", "T3")]
gap = max(abs(f - m) for f, m in zip(fitted, measured))
assert gap < 0.002, (fitted, measured)
apart = math.dist(both["T4"], one["T4"])
assert apart < 0.005, (both["T4"], one["T4"])
print(f"fitted T4: distances to T1..T3 within {gap * 1000:.2f} µm of the measured ones; "
      f"{apart * 1000:.2f} µm from the one-placement fit's")
PY
    fail "fourth cup: $(cat "$tmp/both.json")"
fi
for m in both one; do
  "$ROBCAL" validate --robot fanuc-lrmate200ic --tool "$tmp/tool.yaml" --model "$tmp/$m.yaml" \
    --measurements "$tmp/val.csv" --json > "$tmp/val_$m.json"
  # At the tracker-noise floor (mean of |N(0, 0.022² I)| = 0.0351 mm).
  [ "$(json "$tmp/val_$m.json" "d['position_error_mm']['mean_mm'] < 1.2 * 0.0351")" = True ] ||
    fail "validation of $m: $(cat "$tmp/val_$m.json")"
done

# The next placement after the first.
"$ROBCAL" hexapod place "${fixture[@]}" --measured "$tmp/a/plan.json" --x-mm 350,500 --y-mm -300,0,300 --z-mm 150,300 \
  --yaw-deg 0,90 --validation 300 --best 3 --json > "$tmp/next.json"
python3 - "$tmp/next.json" <<'PY' || fail "place --measured: $(cat "$tmp/next.json")"
import json, sys
d = json.load(open(sys.argv[1]))
assert len(d["next"]) == 3
assert d["next"][0]["placement"] != "500,300,150,0"
assert d["next"][0]["predicted_mean_mm"] < d["measured"]["predicted_mean_mm"]
PY

# Which configurations to measure at each of the two placements: every plan written again with
# only its chosen ones (a placement with none chosen gets no plan).
"$ROBCAL" hexapod design --plan "$tmp/a/plan.json" --plan "$tmp/b/plan.json" --count 60 \
  --validation 300 --out "$tmp/a/design.json" --out "$tmp/b/design.json" --json > "$tmp/design.json"
python3 - "$tmp/design.json" "$tmp/a/design.json" "$tmp/b/design.json" <<'PY' || fail "design: $(cat "$tmp/design.json")"
import json, os, sys
d = json.load(open(sys.argv[1]))
chosen = [p["chosen"] for p in d["placements"]]
assert sum(chosen) == d["count"] == 60, d
for n, path in zip(chosen, sys.argv[2:]):
    assert (len(json.load(open(path))["configurations"]) == n) if n else not os.path.exists(path), path
assert d["design"]["undetermined"] == 0 and d["design"]["predicted_mean_mm"] > 0, d
PY

# Every configuration of both placements chosen, the second reduced plan's folder impossible to
# make (a file stands there): exit 2, the first --out left as it was, no temporary beside it.
echo "before" > "$tmp/a/kept.json"
echo "a file" > "$tmp/blocker"
set +e
"$ROBCAL" hexapod design --plan "$tmp/a/plan.json" --plan "$tmp/b/plan.json" --count $((na + nb)) \
  --validation 50 --out "$tmp/a/kept.json" --out "$tmp/blocker/sub/design.json" 2> "$tmp/err" > /dev/null
rc=$?
set -e
[ "$rc" = 2 ] && grep -qF "$tmp/blocker/sub/design.json" "$tmp/err" || fail "design all or nothing: rc $rc $(cat "$tmp/err")"
[ "$(cat "$tmp/a/kept.json")" = before ] || fail "design wrote the first --out although the second failed"
! ls "$tmp/a" | grep -q '\.tmp-' || fail "design left a temporary: $(ls "$tmp/a")"

# Bad input: exit 2, the place named, no output.
expect_refusal() {  # fragment, command...
  local fragment="$1"; shift
  set +e
  "$@" 2> "$tmp/err" > /dev/null
  local rc=$?
  set -e
  [ "$rc" = 2 ] && grep -qF -- "$fragment" "$tmp/err" || fail "expected exit 2 and '$fragment': $(cat "$tmp/err")"
}
expect_refusal "(--fit): sessions of 2 base-fixture placements: the pose fit has one world frame" \
  "$ROBCAL" hexapod calibrate --session "$tmp/a" --session "$tmp/b" --out "$tmp/x.yaml"
[ ! -e "$tmp/x.yaml" ]
# The same placement planned again 10 mm away: its cups would stand on the first's.
"$ROBCAL" hexapod plan --placement 510,300,150,0 --gauge-range-mm 5 "${fixture[@]}" --out "$tmp/c/plan.json" > /dev/null
head -n "$(json "$tmp/a/plan.json" "6 + 3 * ('tool_cup4_mm' in d)")" "$tmp/a/journal.jsonl" \
  > "$tmp/c/journal.jsonl"  # its fixture sides (and T4's distances)
expect_refusal "$tmp/c (setting_ball): placement 2 overlaps placement 1 ($tmp/a): its base cup B1 is 10.0 mm" \
  "$ROBCAL" hexapod calibrate --session "$tmp/a" --session "$tmp/c" --fit legs --out "$tmp/x.yaml"
[ ! -e "$tmp/x.yaml" ]
expect_refusal "(--measured): this placement overlaps the one of $tmp/a/plan.json" \
  "$ROBCAL" hexapod place --measured "$tmp/a/plan.json" --measured "$tmp/a/plan.json"
echo "hexapod placements: two placements (one session killed and resumed) calibrate together; fit rms $(json "$tmp/both.json" "d['rms_mm']") mm, validation mean $(json "$tmp/val_both.json" "d['position_error_mm']['mean_mm']") mm (one placement $(json "$tmp/val_one.json" "d['position_error_mm']['mean_mm']"))"
