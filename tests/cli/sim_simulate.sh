#!/usr/bin/env bash
# robcal simulate: each instrument writes the measurement file, the tool, the instrument and the
# truth under truth/; bad input exits with 2 and leaves no file.
set -euo pipefail
robcal="$1"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT

for instrument in laser-tracker optical-cmm ballbar; do
  "$robcal" simulate --instrument "$instrument" --truth published --random 12 --seed 5 \
    --out "$out/$instrument" --json > "$out/$instrument.json"
  for f in measurements.csv tool.yaml instrument.yaml truth/truth.yaml; do
    test -s "$out/$instrument/$f" || { echo "missing $instrument/$f"; exit 1; }
  done
  grep -q '"measured"' "$out/$instrument.json"
done
grep -v '^#' "$out/laser-tracker/measurements.csv" | head -1 | grep -q '^config,target,j1,j2,j3,j4,j5,j6,x,y,z$'
grep -v '^#' "$out/optical-cmm/measurements.csv" | head -1 | grep -q '^config,j1,j2,j3,j4,j5,j6,x,y,z,qw,qx,qy,qz$'
grep -v '^#' "$out/ballbar/measurements.csv" | head -1 | grep -q '^config,target,j1,j2,j3,j4,j5,j6,length$'

# Same seed, same files; a truth file and a configurations file feed a new simulation.
"$robcal" simulate --random 12 --seed 5 --out "$out/again" > /dev/null
cmp "$out/laser-tracker/measurements.csv" "$out/again/measurements.csv"
printf 'config,target,j1,j2,j3,j4,j5,j6\nA,1,10,40,10,0,-30,0\nB,,20,50,0,10,-40,5\n' > "$out/configs.csv"
"$robcal" simulate --truth "$out/laser-tracker/truth/truth.yaml" --configs "$out/configs.csv" \
  --effects backlash,j6-periodic,mass-error,thermal --approach sequence --noise-mm 0.07 \
  --out "$out/from-file" > /dev/null
grep -q 'backlash_deg' "$out/from-file/truth/truth.yaml"
grep -q 'mass_error: 0.1' "$out/from-file/truth/truth.yaml"

# Bad input: exit 2, a message naming the flag, and no output folder.
expect_error() {  # expect_error WORD args...: exit 2, WORD in the message, no output
  local word="$1"; shift
  set +e
  "$robcal" simulate "$@" --out "$out/bad" 2> "$out/err"
  local code=$?
  set -e
  test "$code" -eq 2 || { echo "exit code $code for $*, expected 2"; cat "$out/err"; exit 1; }
  grep -q -- "$word" "$out/err" || { echo "no '$word' in: $(cat "$out/err")"; exit 1; }
  test ! -e "$out/bad" || { echo "output written for $*"; exit 1; }
}
expect_error --instrument --random 5 --instrument theodolite
expect_error gremlins --random 5 --effects gremlins
expect_error "IRB 120" --robot fanuc-lrmate200ic --truth published --random 5
printf 'config,target,j1,j2,j3,j4,j5,j6\nA,9,10,40,10,0,-30,0\n' > "$out/bad-configs.csv"
expect_error "bad-configs.csv:2" --configs "$out/bad-configs.csv"
# --cell (issue 16): the cell places the robot and the instrument. The shipped default cell is the
# simulator's own placement, so it simulates exactly what no --cell does; a moved cell moves both.
"$robcal" simulate --cell data/cells/default-tracker.yaml --random 12 --seed 5 \
  --out "$out/cell-default" > /dev/null
cmp <(grep -v '^#' "$out/laser-tracker/measurements.csv") \
  <(grep -v '^#' "$out/cell-default/measurements.csv")
sed -e 's/position_mm: \[-812.25, 1503.5, -95\]/position_mm: [-700, 1400, -95]/' \
  -e 's/position_mm: \[0, 0, 0\]/position_mm: [500, -300, 200]/' \
  data/cells/default-tracker.yaml > "$out/moved-cell.yaml"
"$robcal" simulate --cell "$out/moved-cell.yaml" --random 12 --seed 5 --json \
  --out "$out/cell-moved" > "$out/cell-moved.json"
/usr/bin/python3 - "$out" <<'PY'
import json, sys, yaml
out = sys.argv[1]
truth = yaml.safe_load(open(f"{out}/cell-moved/truth/truth.yaml"))
assert (truth["base"]["x_mm"], truth["base"]["y_mm"], truth["base"]["z_mm"]) == (-700, 1400, -95), truth["base"]
assert abs(truth["base"]["gamma_deg"] + 57) < 1e-9, truth["base"]
instrument = yaml.safe_load(open(f"{out}/cell-moved/instrument.yaml"))
text = json.dumps(instrument)
assert "500" in text and "-300" in text, instrument
assert json.load(open(f"{out}/cell-moved.json"))["cell"].endswith("moved-cell.yaml")
PY
expect_error "--truth FILE or --cell" --cell "$out/moved-cell.yaml" --random 5 \
  --truth "$out/laser-tracker/truth/truth.yaml"
expect_error "holds a laser-tracker; --instrument optical-cmm contradicts it" --cell "$out/moved-cell.yaml" --random 5 \
  --instrument optical-cmm
echo "sim_simulate: ok"
