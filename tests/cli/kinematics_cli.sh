#!/usr/bin/env bash
# End-to-end checks of `robcal fk` and `robcal ik`: round trips through the JSON output,
# negative numbers in option values, and every kind of bad input (exit code 2, a message that
# names the flag, file, line or key). Usage: kinematics_cli.sh path/to/robcal (cwd: repo root).
set -u
ROBCAL=${1:?usage: kinematics_cli.sh path/to/robcal}
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
source "$(dirname "$0")/lib/checks.sh"

# 1. fk → ik round trip with negative joint values: the input joints are among the solutions.
JOINTS="-10,20,-30,40,-50,60"
"$ROBCAL" fk --robot abb-irb120 --joints "$JOINTS" --json >"$TMP/fk.json" || fail "fk failed"
POSE=$(/usr/bin/python3 -c "import json; d=json.load(open('$TMP/fk.json')); print(','.join(repr(v) for v in d['position_mm']+d['quaternion_wxyz']))")
"$ROBCAL" ik --robot abb-irb120 --pose "$POSE" --json >"$TMP/ik.json" || fail "ik failed for pose $POSE"
FOUND=$(/usr/bin/python3 - "$TMP/ik.json" "$JOINTS" <<'PY'
import json, sys
sols = json.load(open(sys.argv[1]))["solutions"]
want = [float(v) for v in sys.argv[2].split(",")]
best = min(max(abs(a - b) for a, b in zip(s["joints_deg"], want)) for s in sols)
labels = {s["config"] for s in sols}
print(f"{len(sols)} {best:.3e} {','.join(sorted(labels))}")
PY
)
read -r COUNT BEST LABELS <<<"$FOUND"
/usr/bin/python3 -c "import sys; sys.exit(0 if float('$BEST') < 1e-6 else 1)" ||
  fail "ik round trip: nearest solution is $BEST deg from $JOINTS"
[[ $COUNT -ge 2 ]] || fail "ik round trip: only $COUNT solutions"
[[ $LABELS == *front-up-noflip* ]] || fail "ik labels: $LABELS"

# 2. The IRB 120 home pose (374, 0, 630): text output lists the home joints.
"$ROBCAL" ik --robot abb-irb120 --pose "374,0,630,0.7071067811865476,0,0.7071067811865476,0" \
  --seed-joints "-15,0,0,-15,0,0" >"$TMP/home.txt" || fail "ik home failed"
grep -q "front-up-noflip" "$TMP/home.txt" || fail "ik home: no front-up-noflip line"
grep -q "wrist singular" "$TMP/home.txt" || fail "ik home: the wrist singularity is not flagged"
grep -qE -- "-15\.0000" "$TMP/home.txt" || fail "ik home: J4 not kept at the seed -15"

# 2b. The Fanuc CRX (general 6R inverse): the fk joints among 12 solutions, every one of which
# fk maps back onto the pose (1e-6 mm in the printed digits).
"$ROBCAL" fk --robot fanuc-crx10ia-l --joints 10,20,30,40,50,60 --json >"$TMP/crx_fk.json" || fail "crx fk failed"
CRX_POSE=$(/usr/bin/python3 -c "import json; d=json.load(open('$TMP/crx_fk.json')); print(','.join(repr(v) for v in d['position_mm']+d['quaternion_wxyz']))")
"$ROBCAL" ik --robot fanuc-crx10ia-l --pose "$CRX_POSE" --json >"$TMP/crx_ik.json" || fail "crx ik failed"
grep -q "general 6R" <("$ROBCAL" ik --robot fanuc-crx10ia-l --pose "$CRX_POSE") || fail "crx ik: method not named"
/usr/bin/python3 - "$TMP/crx_ik.json" "$TMP/crx_fk.json" "$ROBCAL" <<'PY' || fail "crx ik round trip"
import json, subprocess, sys
sols = json.load(open(sys.argv[1]))["solutions"]
want = json.load(open(sys.argv[2]))["position_mm"]
assert len(sols) == 12, len(sols)
assert min(max(abs(a - b) for a, b in zip(s["joints_deg"], [10, 20, 30, 40, 50, 60])) for s in sols) < 1e-6
for s in sols:
    out = subprocess.run([sys.argv[3], "fk", "--robot", "fanuc-crx10ia-l", "--joints",
                          ",".join(repr(v) for v in s["joints_deg"]), "--json"],
                         capture_output=True, text=True, check=True).stdout
    got = json.loads(out)["position_mm"]
    assert max(abs(a - b) for a, b in zip(got, want)) < 1e-6, (s, got, want)
PY

# 3. Bad input.
expect_error "unknown robot" "unknown robot 'no-such-robot'" fk --robot no-such-robot --joints 0,0,0,0,0,0
expect_error "unknown robot (ik)" "unknown robot" ik --robot no-such-robot --pose 300,0,500,1,0,0,0
expect_error "five joints" "expected 6 comma-separated values, got 5" fk --robot abb-irb120 --joints 1,2,3,4,5
expect_error "seven joints" "expected 6" fk --robot abb-irb120 --joints 1,2,3,4,5,6,7
expect_error "non-numeric joint" "value 3 is 'abc', expected a finite number" fk --robot abb-irb120 --joints 1,2,abc,4,5,6
expect_error "NaN joint" "expected a finite number" fk --robot abb-irb120 --joints 1,2,nan,4,5,6
expect_error "joint outside limits" "J5=130.000 outside [-120.0, 120.0]" fk --robot abb-irb120 --joints 0,0,0,0,130,0
expect_error "six-value pose" "--pose: expected 7 comma-separated values, got 6" ik --robot abb-irb120 --pose 300,0,500,1,0,0
expect_error "non-numeric pose" "--pose: value 2 is 'y'" ik --robot abb-irb120 --pose 300,y,500,1,0,0,0
expect_error "non-unit quaternion" "--pose" ik --robot abb-irb120 --pose 300,0,500,2,0,0,0
expect_error "unreachable pose" "unreachable" ik --robot abb-irb120 --pose 2000,0,500,1,0,0,0
expect_error "bad seed" "--seed-joints" ik --robot abb-irb120 --pose 300,0,500,1,0,0,0 --seed-joints 1,2,3

# A malformed robot file: the error names the file, the line and the key.
sed 's/^  - \[-90, 0, -90, 0\]$/  - [-90, zero, -90, 0]/' data/robots/abb-irb120.yaml >"$TMP/bad-robot.yaml"
grep -q "zero" "$TMP/bad-robot.yaml" || fail "could not build the malformed robot file"
LINE=$(grep -n "zero" "$TMP/bad-robot.yaml" | cut -d: -f1)
expect_error "malformed robot file" "$TMP/bad-robot.yaml:$LINE" ik --robot "$TMP/bad-robot.yaml" --pose 300,0,500,1,0,0,0
expect_error "malformed robot file key" "mdh" fk --robot "$TMP/bad-robot.yaml" --joints 0,0,0,0,0,0
# A robot file missing a required key.
grep -v "^joint_limits_deg\|^  - \[-1[0-9][0-9], \|^  - \[-400" data/robots/abb-irb120.yaml >"$TMP/no-limits.yaml"
expect_error "robot file without limits" "joint_limits_deg" fk --robot "$TMP/no-limits.yaml" --joints 0,0,0,0,0,0

finish kinematics_cli
