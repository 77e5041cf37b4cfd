#!/usr/bin/env bash
# The CLI conventions (issue 14): --version, --help grouped by pipeline stage, "-" for standard
# input and output, and --out that follows a symbolic link, writes into a FIFO without replacing
# it, and refuses to overwrite an input. Usage: conventions.sh path/to/robcal (cwd: repo root).
set -u
ROBCAL=${1:?usage: conventions.sh path/to/robcal}
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
source "$(dirname "$0")/lib/checks.sh"
REF=tests/data/irb120-published

# 1. --version: exit 0, the version of CMakeLists.txt's project().
version=$(sed -n 's/^project(robcal VERSION \([0-9.]*\).*/\1/p' CMakeLists.txt)
out=$("$ROBCAL" --version) || fail "--version exit code $?"
[[ $out == "robcal $version" ]] || fail "--version printed '$out' (expected 'robcal $version')"

# 2. --help: the commands under their stage headings, in pipeline order.
"$ROBCAL" --help >"$TMP/help" || fail "--help exit code $?"
/usr/bin/python3 - "$TMP/help" <<'PY' || FAILED=1
import re, sys
sections, current = {}, None
for line in open(sys.argv[1]):
    if re.match(r"^\S.*:\s*$", line):
        current = line.strip().rstrip(":")
        sections[current] = []
    elif current and re.match(r"^  [a-z]", line):
        sections[current].append(line.split()[0])
want = {"1. Model": ["robots", "robot", "fk", "ik", "model"], "2. Plan": ["plan", "plan-study"],
        "3. Measure": ["program", "simulate", "import", "frames", "session"], "4. Identify": ["calibrate"], "5. Validate": ["validate", "iso9283", "axis-test", "ballbar-path"],
        "6. Compensate": ["compensate", "compensate-program"]}
errors = [f"{k}: {sections.get(k)} (expected {v})" for k, v in want.items()
          if sorted(sections.get(k, [])) != sorted(v)]
stages = [k for k in sections if k[0].isdigit()]
if stages != sorted(stages): errors.append(f"stages out of order: {stages}")
if errors: print("FAIL: --help grouping:", *errors, sep="\n  ")
sys.exit(1 if errors else 0)
PY

# 3. "-": measurements from standard input give the same model as from the file; a plan written
#    to standard output is the plan written to a file.
"$ROBCAL" calibrate --robot abb-irb120 --tool $REF/tool.yaml --measurements $REF/calibration.csv \
  --level kinematic --out "$TMP/from-file.yaml" >/dev/null || fail "calibrate from a file"
"$ROBCAL" calibrate --robot abb-irb120 --tool $REF/tool.yaml --measurements - --level kinematic \
  --out "$TMP/from-stdin.yaml" <$REF/calibration.csv >/dev/null || fail "calibrate --measurements -"
# The provenance (date, command line, input names) differs by design; everything else may not.
without_provenance() { awk '/^  provenance:/ {skip = 1; next} skip && /^    / {next} {skip = 0; print}' "$1"; }
cmp -s <(without_provenance "$TMP/from-file.yaml") <(without_provenance "$TMP/from-stdin.yaml") ||
  fail "model from stdin differs from file"
plan=(plan --robot abb-irb120 --instrument laser-tracker --level kinematic --count 30
      --candidates 400 --seed 3)
"$ROBCAL" "${plan[@]}" --out "$TMP/plan.csv" >/dev/null || fail "plan --out file"
"$ROBCAL" "${plan[@]}" --out - >"$TMP/plan-stdout" 2>"$TMP/plan-stderr" || fail "plan --out -"
grep -q '^wrote -$' "$TMP/plan-stderr" || fail "plan --out -: the report is not on stderr"
# Standard output holds the data alone (no "wrote -" after it); the report goes to stderr.
[[ $(stat -c %s "$TMP/plan.csv") -gt 100 ]] && cmp -s "$TMP/plan.csv" "$TMP/plan-stdout" ||
  fail "plan --out - does not print the plan file alone"
"$ROBCAL" calibrate --robot abb-irb120 --tool $REF/tool.yaml --measurements $REF/calibration.csv \
  --level kinematic --json --out - >"$TMP/model-stdout.yaml" 2>"$TMP/calibrate.err" ||
  fail "calibrate --out -"
cmp -s <(without_provenance "$TMP/from-file.yaml") <(without_provenance "$TMP/model-stdout.yaml") ||
  fail "calibrate --out - does not print the model file alone"
grep -q '"rms_mm"' "$TMP/calibrate.err" && grep -q '"output": "-"' "$TMP/calibrate.err" ||
  fail "calibrate --out - lost its report (expected on stderr)"
"$ROBCAL" validate --robot abb-irb120 --tool $REF/tool.yaml --model "$TMP/model-stdout.yaml" \
  --measurements $REF/validation.csv \
  >/dev/null 2>&1 || fail "the model written to stdout does not load"

# 4. --out through a symbolic link: the file it names is written, the link stays a link.
echo old >"$TMP/real.csv"
ln -s real.csv "$TMP/link.csv"
"$ROBCAL" "${plan[@]}" --out "$TMP/link.csv" >/dev/null || fail "plan --out link"
[[ -L $TMP/link.csv ]] || fail "--out replaced the symbolic link"
cmp -s "$TMP/plan.csv" "$TMP/real.csv" || fail "--out link did not write the file it names"

# 5. --out into a FIFO (as /dev/stdout would be a device): written into, never replaced.
mkfifo "$TMP/fifo"
cat "$TMP/fifo" >"$TMP/from-fifo" &
reader=$!
"$ROBCAL" "${plan[@]}" --out "$TMP/fifo" >/dev/null || fail "plan --out fifo"
wait $reader
[[ -p $TMP/fifo ]] || fail "--out replaced the FIFO"
cmp -s "$TMP/plan.csv" "$TMP/from-fifo" || fail "--out fifo: the reader did not get the plan"

# 6. --out onto an input (directly or through a link): refused, the input untouched.
cp $REF/calibration.csv "$TMP/m.csv"
ln -s m.csv "$TMP/m-link.csv"
for target in "$TMP/m.csv" "$TMP/m-link.csv"; do
  "$ROBCAL" calibrate --robot abb-irb120 --tool $REF/tool.yaml --measurements "$TMP/m.csv" \
    --out "$target" >"$TMP/out" 2>"$TMP/err"
  rc=$?
  [[ $rc -eq 2 ]] || fail "--out $target onto the input: exit code $rc (expected 2)"
  grep -q "refusing to overwrite" "$TMP/err" || fail "--out onto the input: $(cat "$TMP/err")"
  cmp -s $REF/calibration.csv "$TMP/m.csv" || fail "--out onto the input changed it"
done
expect_error "--out a directory" "is a directory" "${plan[@]}" --out "$TMP"

# 7. Bash completion: commands, subcommands, flags and robot names from robcal itself.
if [[ -f /usr/share/bash-completion/bash_completion ]]; then
  ROBCAL_ABS=$(realpath "$ROBCAL")
  completions=$(bash -c '
    source /usr/share/bash-completion/bash_completion
    source scripts/robcal.bash-completion
    complete_line() {
      COMP_WORDS=("$@"); COMP_CWORD=$((${#COMP_WORDS[@]} - 1)); COMP_LINE="${COMP_WORDS[*]}"
      COMP_POINT=${#COMP_LINE}; COMPREPLY=(); _robcal; echo "${COMPREPLY[*]}"
    }
    complete_line "$0" cal
    complete_line "$0" hexapod dk
    complete_line "$0" calibrate --lev
    complete_line "$0" plan --robot kuka-kr6-r9' "$ROBCAL_ABS" 2>&1)
  [[ $completions == $'calibrate\ndkp\n--level\nkuka-kr6-r900-sixx' ]] ||
    fail "bash completion gave: $completions"
fi

finish conventions.sh
