#!/usr/bin/env bash
# robcal program (measurement programs in five languages) and robcal compensate-program with
# tools, work objects, a frames file, --keep-going and the confidence side file; bad input
# exits with 2, names file and line, and writes nothing; the input is never overwritten.
set -euo pipefail
robcal="$1"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
data=tests/data/irb120-published

"$robcal" calibrate --robot abb-irb120 --tool "$data/tool.yaml" \
  --measurements "$data/calibration.csv" --out "$out/model.yaml" > /dev/null

expect_error() {  # expect_error WORD NO_FILE args...
  local word="$1" nofile="$2"; shift 2
  set +e
  "$robcal" "$@" 2> "$out/err" > /dev/null
  local code=$?
  set -e
  test "$code" -eq 2 || { echo "exit code $code for $*, expected 2"; cat "$out/err"; exit 1; }
  grep -qF -- "$word" "$out/err" || { echo "no '$word' in: $(cat "$out/err")"; exit 1; }
  test ! -e "$nofile" || { echo "$nofile written for $*"; exit 1; }
}

# Measurement programs: one file per language, split on request; the approach is q - 5.
printf 'config,target,j1,j2,j3,j4,j5,j6\nc1,,10,20,-10,30,40,50\nc2,,-30,35,5,-60,-50,20\n' > "$out/configs.csv"
for lang in rapid krl ls jbi urscript; do
  "$robcal" program --lang "$lang" --configs "$out/configs.csv" --out "$out/$lang" \
    --robot abb-irb120 --pulses-per-degree 1000,1000,1000,800,800,500 --json > "$out/$lang.json"
  test "$(ls "$out/$lang" | wc -l)" -eq 1
done
grep -q 'MoveAbsJ \[\[5.000000,15.000000,-15.000000,25.000000,35.000000,45.000000\]' "$out/rapid/RCMEAS.mod"
grep -q 'PTP {A1 -35.000000,A2 30.000000,A3 0.000000,A4 -65.000000,A5 -55.000000,A6 15.000000}' "$out/krl/rcmeas.src"
grep -q '^C00001=10000,20000,-10000,24000,32000,25000$' "$out/jbi/RCMEAS.jbi"
"$robcal" program --lang ls --configs "$out/configs.csv" --out "$out/split" --name CAL \
  --max-configs-per-file 1 > /dev/null
test -f "$out/split/CAL01.ls" -a -f "$out/split/CAL02.ls"

expect_error "--lang: expected rapid, krl, ls, jbi or urscript" "$out/none" program --lang vb \
  --configs "$out/configs.csv" --out "$out/none"
expect_error "--pulses-per-degree" "$out/none" program --lang jbi --configs "$out/configs.csv" \
  --out "$out/none"
printf 'config,target,j1,j2,j3,j4,j5,j6\nok,,0,0,0,0,30,0\nlow,,0,-107,0,0,30,0\n' > "$out/low.csv"
expect_error "low: joint 2 at -112.0000 deg (approach) is outside its limits" "$out/none" \
  program --lang rapid --configs "$out/low.csv" --out "$out/none" --robot abb-irb120

# Filtering: the input is never the output.
cp tests/data/programs/pick_place.mod "$out/in.mod"
expect_error "the output is the input program" "$out/none" compensate-program \
  --model "$out/model.yaml" --in "$out/in.mod" --out "$out/in.mod"
mkdir -p "$out/sub"
expect_error "the output is the input program" "$out/none" compensate-program \
  --model "$out/model.yaml" --in "$out/in.mod" --out "$out/sub/../in.mod"
cmp "$out/in.mod" tests/data/programs/pick_place.mod

# A work object the program does not define, given in a frames file; an unreachable target
# kept as written under --keep-going and listed; the confidence side file.
cat > "$out/cell.mod" <<'MOD'
MODULE Cell
  CONST robtarget pA:=[[20,-50,100],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pFar:=[[9000,0,0],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    MoveL pA, v100, fine, tool0\WObj:=wTable;
    MoveL pFar, v100, fine, tool0;
  ENDPROC
ENDMODULE
MOD
printf 'kind,name,x,y,z,qw,qx,qy,qz\nframe,wTable,350,0,300,1,0,0,0\n' > "$out/frames.csv"
expect_error "cell.mod:3:25 (pFar): no nominal solution" "$out/cell_out.mod" compensate-program \
  --model "$out/model.yaml" --in "$out/cell.mod" --out "$out/cell_out.mod" --frames "$out/frames.csv"
"$robcal" compensate-program --model "$out/model.yaml" --in "$out/cell.mod" \
  --out "$out/cell_out.mod" --frames "$out/frames.csv" --keep-going \
  --confidence-out "$out/conf.csv" > "$out/summary.txt"
grep -q "1 point left as written" "$out/summary.txt"
grep -q "cell.mod:3:25 (pFar)" "$out/summary.txt"
test "$(sed -n 3p "$out/cell.mod")" = "$(sed -n 3p "$out/cell_out.mod")"
test "$(sed -n 2p "$out/cell.mod")" != "$(sed -n 2p "$out/cell_out.mod")"
grep -q '^2,23,pA,[0-9.]*$' "$out/conf.csv"
expect_error "cell.mod:2:23 (pA): unknown work object 'WTABLE'" "$out/cell2.mod" \
  compensate-program --model "$out/model.yaml" --in "$out/cell.mod" --out "$out/cell2.mod"

# KRL: the tool of FDAT FP1 (TOOL_DATA[1]) must be known.
expect_error "weld_seam.dat:4:16 (XP1): unknown tool 'TOOL_DATA[1]'" "$out/w.dat" \
  compensate-program --model "$out/model.yaml" --in tests/data/programs/weld_seam.dat --out "$out/w.dat"
printf 'kind,name,x,y,z,qw,qx,qy,qz\ntool,TOOL_DATA[1],0,0,100,1,0,0,0\n' > "$out/kuka.csv"
"$robcal" compensate-program --model "$out/model.yaml" --in tests/data/programs/weld_seam.dat \
  --out "$out/w.dat" --frames "$out/kuka.csv" --keep-going > /dev/null

# Bad programs and files: located errors, nothing written.
printf 'DEF p( )\n  LIN {Y 100,X 364.35.4,Z 300,A 0,B 0,C 0}\nEND\n' > "$out/bad.src"
expect_error "bad.src:2:16: malformed number '364.35.4'" "$out/bad_out.src" compensate-program \
  --model "$out/model.yaml" --in "$out/bad.src" --out "$out/bad_out.src"
printf 'kind,name,x,y,z,qw,qx,qy,qz\nframe,wTable,350,0,300,2,0,0,0\n' > "$out/badframes.csv"
expect_error "badframes.csv:2:" "$out/cell3.mod" compensate-program --model "$out/model.yaml" \
  --in "$out/cell.mod" --out "$out/cell3.mod" --frames "$out/badframes.csv"
printf '/PROG X\n/MN\n/POS\n/END\n' > "$out/x.ls"
expect_error "ls programs are not filtered yet" "$out/y.ls" compensate-program \
  --model "$out/model.yaml" --in "$out/x.ls" --out "$out/y.ls"
expect_error "the output must be the same kind of program" "$out/y.src" compensate-program \
  --model "$out/model.yaml" --in "$out/cell.mod" --out "$out/y.src"
echo "programs CLI: all checks passed"
