#!/usr/bin/env bash
# Runs the README's five-minute tour in a scratch folder and prints each command with its real
# output, so the README can be refreshed from the binary. Usage: scripts/readme-tour.sh [build]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
robcal="$root/${1:-build}/robcal"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
run() {
  echo "\$ robcal $*"
  "$robcal" "$@"
  echo
}
run robots
run fk --robot abb-irb120 --joints -10,20,-30,40,50,60
run ik --robot abb-irb120 --pose 300,-100,400,0,0,1,0
run plan --robot abb-irb120 --instrument laser-tracker --level full --count 40 --candidates 5000 \
  --seed 1 --out configs.csv
run simulate --robot abb-irb120 --truth published --instrument laser-tracker --configs configs.csv \
  --seed 1 --out cal
run simulate --robot abb-irb120 --truth published --instrument laser-tracker --random 1000 \
  --seed 2 --out val
run calibrate --robot abb-irb120 --tool cal/tool.yaml --measurements cal/measurements.csv \
  --level full --out model.yaml
run validate --robot abb-irb120 --tool val/tool.yaml --model model.yaml \
  --measurements val/measurements.csv
printf 'name,x,y,z,qw,qx,qy,qz\nP1,-497.2,1297.8,302.3,0.014997563,0.007998700,0.999837540,-0.005999025\n' >wanted.csv
run compensate --model model.yaml --tool cal/tool.yaml --targets wanted.csv --out corrected.csv
echo "\$ cat corrected.csv"
cat corrected.csv
echo
run hexapod uncertainty --sigma-um 0.51 --seed 3
