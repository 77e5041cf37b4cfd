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
echo "sim_simulate: ok"
