#!/usr/bin/env bash
# robcal compensate / compensate-program end to end: simulate a campaign on a true robot,
# calibrate, compensate wanted poses and check them on the true robot (the compensated error
# must be far below the uncompensated one); filter a RAPID program; bad input exits with 2,
# names file, line and column, and leaves no output file.
set -euo pipefail
robcal="$1"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
py=/usr/bin/python3

"$robcal" simulate --truth published --instrument laser-tracker --random 60 --seed 3 \
  --noise-mm 0.01 --out "$out/sim" > /dev/null
"$robcal" calibrate --robot abb-irb120 --tool "$out/sim/tool.yaml" \
  --measurements "$out/sim/measurements.csv" --out "$out/model.yaml" > /dev/null

# Wanted world poses: nominal flange poses of a few joint sets placed with the truth's base.
{
  echo "name,x,y,z,qw,qx,qy,qz,config"
  i=0
  for joints in "10,20,-10,30,40,50" "-30,35,5,-60,-50,20" "45,10,20,0,70,-90" "0,40,-30,10,30,10"; do
    i=$((i + 1))
    "$robcal" fk --robot abb-irb120 --joints "$joints" --json |
      $py -c "
import json, math, sys
import numpy as np
d = json.load(sys.stdin)
x, y, z, a, b, g = -812.25, 1503.5, -95.0, math.radians(0.25), math.radians(-0.4), math.radians(-57.0)
Rx = np.array([[1,0,0],[0,math.cos(a),-math.sin(a)],[0,math.sin(a),math.cos(a)]])
Ry = np.array([[math.cos(b),0,math.sin(b)],[0,1,0],[-math.sin(b),0,math.cos(b)]])
Rz = np.array([[math.cos(g),-math.sin(g),0],[math.sin(g),math.cos(g),0],[0,0,1]])
R = Rx @ Ry @ Rz
p = R @ np.array(d['position_mm']) + np.array([x, y, z])
w, qx, qy, qz = d['quaternion_wxyz']
q = np.array([w, qx, qy, qz])
# rotation of the base as a quaternion, composed with the flange's
from numpy.linalg import norm
def mat2q(M):
    w = math.sqrt(max(0, 1 + M[0,0] + M[1,1] + M[2,2])) / 2
    return np.array([w, (M[2,1]-M[1,2])/(4*w), (M[0,2]-M[2,0])/(4*w), (M[1,0]-M[0,1])/(4*w)])
def qmul(a, b):
    return np.array([a[0]*b[0]-a[1]*b[1]-a[2]*b[2]-a[3]*b[3], a[0]*b[1]+a[1]*b[0]+a[2]*b[3]-a[3]*b[2],
                     a[0]*b[2]-a[1]*b[3]+a[2]*b[0]+a[3]*b[1], a[0]*b[3]+a[1]*b[2]-a[2]*b[1]+a[3]*b[0]])
qw = qmul(mat2q(R), q); qw /= norm(qw)
print('p$i,' + ','.join(f'{v:.9f}' for v in list(p) + list(qw)) + ',')
"
  done
} > "$out/wanted.csv"

"$robcal" compensate --robot abb-irb120 --model "$out/model.yaml" --tool "$out/sim/tool.yaml" \
  --targets "$out/wanted.csv" --out "$out/corrected.csv" \
  --check-truth "$out/sim/truth/truth.yaml" --json > "$out/comp.json"
$py - "$out/comp.json" "$out/corrected.csv" <<'PY'
import csv, json, sys
d = json.load(open(sys.argv[1]))
rows = list(csv.DictReader(open(sys.argv[2])))
assert d["targets"] == 4 and len(rows) == 4, d
assert rows[0].keys() >= {"name", "config", "j1", "j6", "x", "qw", "qz", "confidence95_mm"}, rows[0].keys()
comp, plain = d["closed_loop"]["compensated"], d["closed_loop"]["uncompensated"]
assert comp["count"] == 4 and plain["count"] == 4, d
# The published IRB 120 is off by ~1 mm uncompensated; calibrated from 60 tracker points
# with 0.01 mm noise, the compensated error is a small fraction of that.
assert plain["mean_mm"] > 0.3, plain
assert comp["max_mm"] < 0.25 * plain["mean_mm"], (comp, plain)
assert all(float(r["confidence95_mm"]) > 0 for r in rows), rows
print(f"closed loop: compensated max {comp['max_mm']:.4f} mm, uncompensated mean {plain['mean_mm']:.4f} mm")
PY

# A heavier payload changes the corrected joints (compliance), not the file format.
"$robcal" compensate --model "$out/model.yaml" --tool "$out/sim/tool.yaml" \
  --targets "$out/wanted.csv" --out "$out/heavy.csv" --payload-mass-kg 3 --payload-cog-mm 0,0,80 > /dev/null
! cmp -s "$out/corrected.csv" "$out/heavy.csv"
# The same payload named in the tool file's 'payloads:' (--payload NAME) gives the same joints.
cp "$out/sim/tool.yaml" "$out/named.yaml"
printf 'payloads:\n  gripper: {mass_kg: 3, cog_mm: [0, 0, 80]}\n' >> "$out/named.yaml"
"$robcal" compensate --model "$out/model.yaml" --tool "$out/named.yaml" \
  --targets "$out/wanted.csv" --out "$out/named.csv" --payload gripper > /dev/null
cmp "$out/heavy.csv" "$out/named.csv"
# A row's own payload (the targets' `payload` column) corrects that row as --payload does; rows
# without one keep the run's. The output records each row's condition.
{ sed -n '1s/$/,payload/p' "$out/wanted.csv"; sed -n '2s/$/,gripper/p' "$out/wanted.csv"
  sed -n '3,$p' "$out/wanted.csv"; } > "$out/rowwise.csv"
"$robcal" compensate --model "$out/model.yaml" --tool "$out/named.yaml" \
  --targets "$out/rowwise.csv" --out "$out/rowwise_out.csv" --json > "$out/rowwise.json"
$py - "$out/rowwise.json" "$out/rowwise_out.csv" "$out/named.csv" "$out/corrected.csv" <<'PY'
import csv, json, sys
assert json.load(open(sys.argv[1]))["conditions"] == 2
rows, named, plain = (list(csv.DictReader(open(f))) for f in sys.argv[2:])
for got, want in zip(rows, named[:1] + plain[1:]):
    assert all(abs(float(got[j]) - float(want[j])) < 1e-5 for j in ("j1", "j2", "j3", "j4", "j5", "j6")), (got, want)
assert [(r["approach"], r["temperature"], r["payload"]) for r in rows] == \
    [("++++++", "20", "gripper")] + [("++++++", "20", "")] * 3, rows
PY

# Program filtering: only the robtarget lines change, the original stays.
cp tests/data/programs/pick_place.mod "$out/in.mod"
"$robcal" compensate-program --model "$out/model.yaml" --tool "$out/sim/tool.yaml" \
  --in "$out/in.mod" --out "$out/out.mod" --json > "$out/prog.json"
cmp "$out/in.mod" tests/data/programs/pick_place.mod
changed=$(diff <(cat "$out/in.mod") <(cat "$out/out.mod") | grep -c '^<' || true)
test "$changed" -eq 6 || { echo "expected 6 changed lines, got $changed"; exit 1; }
grep -q '"cartesian_points": 6' "$out/prog.json"
# Each point under the side of its move: the model has no backlash group, so the same program.
"$robcal" compensate-program --model "$out/model.yaml" --tool "$out/sim/tool.yaml" \
  --in "$out/in.mod" --out "$out/motion.mod" --approach motion > /dev/null
cmp "$out/out.mod" "$out/motion.mod"

# Bad input: exit 2, the place named, no output.
expect_error() {  # expect_error WORD args...
  local word="$1"; shift
  set +e
  "$robcal" "$@" 2> "$out/err" > /dev/null
  local code=$?
  set -e
  test "$code" -eq 2 || { echo "exit code $code for $*, expected 2"; cat "$out/err"; exit 1; }
  grep -qF -- "$word" "$out/err" || { echo "no '$word' in: $(cat "$out/err")"; exit 1; }
  test ! -e "$out/bad.csv" -a ! -e "$out/bad.mod" || { echo "output written for $*"; exit 1; }
}
printf 'name,x,y,z,qw,qx,qy,qz\np1,100,200,300,1,0,0,0\np2,100,2x0,300,1,0,0,0\n' > "$out/badnum.csv"
expect_error "badnum.csv:3:8 (y): expected a number" compensate --model "$out/model.yaml" \
  --targets "$out/badnum.csv" --out "$out/bad.csv"
printf 'name,x,y,z,qw,qx,qy,qz\nfar,9000,0,0,1,0,0,0\n' > "$out/far.csv"
expect_error "far.csv:2 (far)" compensate --model "$out/model.yaml" --targets "$out/far.csv" --out "$out/bad.csv"
expect_error "--payload-cog-mm" compensate --model "$out/model.yaml" --targets "$out/wanted.csv" \
  --out "$out/bad.csv" --payload-mass-kg 2
expect_error "--payload: the tool has no payload 'vise': expected one of its 'payloads:' ('gripper')" \
  compensate --model "$out/model.yaml" --tool "$out/named.yaml" --targets "$out/wanted.csv" \
  --out "$out/bad.csv" --payload vise
printf 'name,x,y,z,qw,qx,qy,qz,approach\np1,100,200,300,1,0,0,0,+-+\n' > "$out/badside.csv"
expect_error "badside.csv:2:24 (approach): '+-+' is not an approach" compensate \
  --model "$out/model.yaml" --targets "$out/badside.csv" --out "$out/bad.csv"
expect_error "give the payload either by name (--payload) or by --payload-mass-kg" compensate \
  --model "$out/model.yaml" --tool "$out/named.yaml" --targets "$out/wanted.csv" \
  --out "$out/bad.csv" --payload gripper --payload-mass-kg 3 --payload-cog-mm 0,0,80
printf 'MODULE m\n  CONST robtarget p10:=[[400,0,500],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];\n  PROC main()\n    MoveL p10, v100, fine, tool0\\WObj:=wobjTable;\n  ENDPROC\nENDMODULE\n' > "$out/wobj.mod"
expect_error "--approach: " compensate --model "$out/model.yaml" --targets "$out/targets.csv" \
  --out "$out/bad.csv" --approach motion
expect_error "wobj.mod:2:24 (p10): unknown work object 'WOBJTABLE'" compensate-program \
  --model "$out/model.yaml" --in "$out/wobj.mod" --out "$out/bad.mod"
expect_error "not a KUKA" compensate --robot kuka-kr6-r900-sixx --model "$out/model.yaml" \
  --targets "$out/wanted.csv" --out "$out/bad.csv"
echo "compensate CLI: all checks passed"
