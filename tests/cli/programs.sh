#!/usr/bin/env bash
# robcal program (measurement programs in five languages) and robcal compensate-program with
# tools, work objects, a frames file, --keep-going and the confidence side file; bad input
# exits with 2, names file and line, and writes nothing; the input is never overwritten.
# Usage: programs.sh path/to/robcal (cwd: repo root).
set -u
ROBCAL=${1:?usage: programs.sh path/to/robcal}
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
source "$(dirname "$0")/lib/checks.sh"
REF=tests/data/irb120-published
PROGRAMS=tests/data/programs

"$ROBCAL" calibrate --robot abb-irb120 --tool "$REF/tool.yaml" \
  --measurements "$REF/calibration.csv" --out "$TMP/model.yaml" > /dev/null ||
  fail "calibrate on the reference set"

# Measurement programs: one file per language, split on request; the approach is q - 5.
printf 'config,target,j1,j2,j3,j4,j5,j6\nc1,,10,20,-10,30,40,50\nc2,,-30,35,5,-60,-50,20\n' > "$TMP/configs.csv"
for lang in rapid krl ls jbi urscript; do
  "$ROBCAL" program --lang "$lang" --configs "$TMP/configs.csv" --out "$TMP/$lang" \
    --robot abb-irb120 --pulses-per-degree 1000,1000,1000,800,800,500 --json > "$TMP/$lang.json" ||
    fail "program --lang $lang"
  [[ $(ls "$TMP/$lang" | wc -l) -eq 1 ]] || fail "$lang: expected one file"
done
grep -q 'MoveAbsJ \[\[5.000000,15.000000,-15.000000,25.000000,35.000000,45.000000\]' \
  "$TMP/rapid/RCMEAS.mod" || fail "rapid: approach of c1"
grep -q 'PTP {A1 -35.000000,A2 30.000000,A3 0.000000,A4 -65.000000,A5 -55.000000,A6 15.000000}' \
  "$TMP/krl/rcmeas.src" || fail "krl: approach of c2"
grep -q '^C00001=10000,20000,-10000,24000,32000,25000$' "$TMP/jbi/RCMEAS.jbi" || fail "jbi: c1 pulses"
"$ROBCAL" program --lang ls --configs "$TMP/configs.csv" --out "$TMP/split" --name CAL \
  --max-configs-per-file 1 > /dev/null || fail "program split"
[[ -f "$TMP/split/CAL01.ls" && -f "$TMP/split/CAL02.ls" ]] || fail "split: CAL01.ls, CAL02.ls"

expect_error "unknown language" "--lang: expected rapid, krl, ls, jbi or urscript" program \
  --lang vb --configs "$TMP/configs.csv" --out "$TMP/bad.dir"
expect_error "jbi without pulses" "--pulses-per-degree" program --lang jbi \
  --configs "$TMP/configs.csv" --out "$TMP/bad.dir"
printf 'config,target,j1,j2,j3,j4,j5,j6\nok,,0,0,0,0,30,0\nlow,,0,-107,0,0,30,0\n' > "$TMP/low.csv"
expect_error "approach outside the limits" \
  "low: joint 2 at -112.0000 deg (approach) is outside its limits" program --lang rapid \
  --configs "$TMP/low.csv" --out "$TMP/bad.dir" --robot abb-irb120

# Filtering: the input is never the output.
cp "$PROGRAMS/pick_place.mod" "$TMP/in.mod"
expect_error "out = in" "refusing to overwrite it" compensate-program \
  --model "$TMP/model.yaml" --in "$TMP/in.mod" --out "$TMP/in.mod"
mkdir -p "$TMP/sub"
expect_error "out = in through .." "refusing to overwrite it" compensate-program \
  --model "$TMP/model.yaml" --in "$TMP/in.mod" --out "$TMP/sub/../in.mod"
cmp -s "$TMP/in.mod" "$PROGRAMS/pick_place.mod" || fail "the input was changed"

# A work object the program does not define, given in a frames file; an unreachable target
# kept as written under --keep-going and listed; the confidence side file.
cat > "$TMP/cell.mod" <<'MOD'
MODULE Cell
  CONST robtarget pA:=[[20,-50,100],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  CONST robtarget pFar:=[[9000,0,0],[0,0,1,0],[0,0,0,0],[9E9,9E9,9E9,9E9,9E9,9E9]];
  PROC main()
    MoveL pA, v100, fine, tool0\WObj:=wTable;
    MoveL pFar, v100, fine, tool0;
  ENDPROC
ENDMODULE
MOD
printf 'kind,name,x,y,z,qw,qx,qy,qz\nframe,wTable,350,0,300,1,0,0,0\n' > "$TMP/frames.csv"
expect_error "unreachable target" "cell.mod:3:25 (pFar): no nominal solution" compensate-program \
  --model "$TMP/model.yaml" --in "$TMP/cell.mod" --out "$TMP/bad.mod" --frames "$TMP/frames.csv"
"$ROBCAL" compensate-program --model "$TMP/model.yaml" --in "$TMP/cell.mod" \
  --out "$TMP/cell_out.mod" --frames "$TMP/frames.csv" --keep-going \
  --confidence-out "$TMP/conf.csv" > "$TMP/summary.txt" || fail "--keep-going"
grep -q "1 point left as written" "$TMP/summary.txt" || fail "keep-going summary"
grep -q "cell.mod:3:25 (pFar)" "$TMP/summary.txt" || fail "keep-going names pFar"
[[ "$(sed -n 3p "$TMP/cell.mod")" == "$(sed -n 3p "$TMP/cell_out.mod")" ]] || fail "pFar changed"
[[ "$(sed -n 2p "$TMP/cell.mod")" != "$(sed -n 2p "$TMP/cell_out.mod")" ]] || fail "pA unchanged"
grep -q '^2,23,pA,[0-9.]*$' "$TMP/conf.csv" || fail "confidence row of pA"
expect_error "unknown work object" "cell.mod:2:23 (pA): unknown work object 'WTABLE'" \
  compensate-program --model "$TMP/model.yaml" --in "$TMP/cell.mod" --out "$TMP/bad.mod"

# KRL: the tool of FDAT FP1 (TOOL_DATA[1]) must be known (a .dat alone: no .src beside it).
mkdir -p "$TMP/datonly"
cp "$PROGRAMS/weld_seam.dat" "$TMP/datonly/"
expect_error "unknown KRL tool" "weld_seam.dat:4:16 (XP1): unknown tool 'TOOL_DATA[1]'" \
  compensate-program --model "$TMP/model.yaml" --in "$TMP/datonly/weld_seam.dat" --out "$TMP/bad.dat"
printf 'kind,name,x,y,z,qw,qx,qy,qz\ntool,TOOL_DATA[1],0,0,100,1,0,0,0\n' > "$TMP/kuka.csv"
"$ROBCAL" compensate-program --model "$TMP/model.yaml" --in "$TMP/datonly/weld_seam.dat" \
  --out "$TMP/w.dat" --frames "$TMP/kuka.csv" --keep-going > /dev/null || fail "KRL with frames"
[[ ! -e "$TMP/w.src" ]] || fail "a .dat alone wrote a .src"
# A KUKA module: the .src given, its .dat beside it read and corrected with it; both written.
cp "$PROGRAMS/glue_cell.src" "$PROGRAMS/glue_cell.dat" "$TMP/"
printf 'kind,name,x,y,z,qw,qx,qy,qz\ntool,TOOL_DATA[1],0,0,100,1,0,0,0\nframe,BASE_DATA[1],300,-100,0,1,0,0,0\nframe,BASE_DATA[2],300,0,0,1,0,0,0\n' > "$TMP/glue.csv"
"$ROBCAL" compensate-program --model "$TMP/model.yaml" --in "$TMP/glue_cell.src" \
  --out "$TMP/glue_out/glue_cell.src" --frames "$TMP/glue.csv" --keep-going --json > "$TMP/glue.json" ||
  fail "KRL module"
[[ -f "$TMP/glue_out/glue_cell.src" && -f "$TMP/glue_out/glue_cell.dat" ]] || fail "module: both files"
grep -q '"out_companion": ".*out/glue_cell.dat"' "$TMP/glue.json" || fail "module json: $(cat "$TMP/glue.json")"
[[ $(grep -c "no nominal solution" "$TMP/glue.json") -eq 11 ]] || fail "module: the 11 unreachable points listed"
# A point used under two tools: refused naming both motions, neither file written.
mkdir -p "$TMP/two"
sed 's/^  LIN XSEAM\[1\]          ;/  $TOOL=TOOL_DATA[1]\n  LIN XSEAM[1] ;/' "$TMP/glue_cell.src" > "$TMP/two/glue_cell.src"
cp "$TMP/glue_cell.dat" "$TMP/two/"
expect_error "KRL point under two tools" \
  "glue_cell.dat:28:10 (XSEAM[1]): used with tool TNOZZLE and base BASE_DATA[2] at" \
  compensate-program --model "$TMP/model.yaml" --in "$TMP/two/glue_cell.src" \
  --out "$TMP/two_out/glue_cell.src" --frames "$TMP/glue.csv"
[[ ! -e "$TMP/two_out" ]] || fail "a refused module wrote $(ls "$TMP/two_out")"
# Both or none: the .src cannot be written (a folder holds its name), so the .dat written just
# before it is taken back.
mkdir -p "$TMP/half/g.src"
expect_error "module half written" "is a directory" compensate-program --model "$TMP/model.yaml" \
  --in "$TMP/glue_cell.src" --out "$TMP/half/g.src" --frames "$TMP/glue.csv" --keep-going
[[ ! -e "$TMP/half/g.dat" ]] || fail "the .dat of a module whose .src failed was left"
mkdir -p "$TMP/lnk"
ln -s "$TMP/glue_cell.dat" "$TMP/lnk/g.dat"
expect_error "module output onto its .dat" "the output is the input module's" compensate-program \
  --model "$TMP/model.yaml" --in "$TMP/glue_cell.src" --out "$TMP/lnk/g.src" --frames "$TMP/glue.csv"
[[ ! -e "$TMP/lnk/g.src" ]] || fail "refused module output written"
# No BAS before the point: corrected for the default tool in the base frame, and said so.
printf 'DEF q( )\n  LIN {X 370,Y -50,Z 400,A 180,B 0,C 180}\nEND\n' > "$TMP/q.src"
"$ROBCAL" compensate-program --model "$TMP/model.yaml" --in "$TMP/q.src" --out "$TMP/q_out.src" \
  > "$TMP/q.txt" || fail "KRL point without BAS"
grep -q "q.src:2:7: no FDAT or BAS" "$TMP/q.txt" || fail "assumption not reported: $(cat "$TMP/q.txt")"

# Bad programs and files: located errors, nothing written.
printf 'DEF p( )\n  LIN {Y 100,X 364.35.4,Z 300,A 0,B 0,C 0}\nEND\n' > "$TMP/p.src"
expect_error "malformed number" "p.src:2:16: malformed number '364.35.4'" compensate-program \
  --model "$TMP/model.yaml" --in "$TMP/p.src" --out "$TMP/bad.src"
printf 'kind,name,x,y,z,qw,qx,qy,qz\nframe,wTable,350,0,300,2,0,0,0\n' > "$TMP/badframes.csv"
expect_error "frames file quaternion" "badframes.csv:2:" compensate-program \
  --model "$TMP/model.yaml" --in "$TMP/cell.mod" --out "$TMP/bad.mod" --frames "$TMP/badframes.csv"
# Yaskawa: the measurement job's pulse positions filtered with the robot file's pulses per
# degree (a copy of the IRB 120 file with pulses_per_degree: the model names that robot).
expect_error "jbi pulses without the robot's pulses per degree" \
  "pulse positions need the robot's pulses per degree" compensate-program \
  --model "$TMP/model.yaml" --in "$TMP/jbi/RCMEAS.jbi" --out "$TMP/bad.jbi" --joints
{ cat data/robots/abb-irb120.yaml; echo "pulses_per_degree: [1000, 1000, 1000, 800, 800, 500]"; } \
  > "$TMP/irb120-pulses.yaml"
"$ROBCAL" compensate-program --model "$TMP/model.yaml" --robot "$TMP/irb120-pulses.yaml" \
  --in "$TMP/jbi/RCMEAS.jbi" --out "$TMP/jbi_out.jbi" --joints --json > "$TMP/jbi_out.json" ||
  fail "jbi filtering with --robot pulses"
grep -q '"joint_points": 4' "$TMP/jbi_out.json" || fail "jbi: 4 joint targets: $(cat "$TMP/jbi_out.json")"
printf 'def p():\n  movel(p[0.4,0,0.3,0,3.14], a=1)\nend\n' > "$TMP/p.script"
expect_error "URScript pose" "p.script:2:27: pose p[x, y, z, rx, ry, rz]: expected ','" \
  compensate-program --model "$TMP/model.yaml" --in "$TMP/p.script" --out "$TMP/bad.script"
expect_error "wrong output language" "the output must be the same kind of program" \
  compensate-program --model "$TMP/model.yaml" --in "$TMP/cell.mod" --out "$TMP/bad.src"
finish programs.sh
