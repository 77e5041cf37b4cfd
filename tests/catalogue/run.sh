#!/usr/bin/env bash
# The bad-input catalogue (issue 21): every line of cases.tsv is one malformed input, run as a
# user would. Each must end with the expected exit code, a message holding the expected
# fragment (which names the file:line:column or the key/flag), no file written (the case's
# folder holds only its input afterwards) and no NaN printed.
#
# cases.tsv columns (tab-separated, '#' lines are comments):
#   id  exit  message-fragment  input-file-name  input-content  arguments
# input-content is printf %b text (\n, \t, \xHH); "-" for no input file; or @SOURCE:SED, a
# valid file edited by a sed expression (SOURCE a fixture name below or a path in the
# repository, e.g. @model:s/^level: .*/level: 7/ or @tests/data/urdf/skew6r.urdf:/mimic/d).
# In the arguments {in} is the input file, {out} an output path in the case's folder, {dir}
# that folder ({dir} in the message fragment too: a message naming a file of the case's folder),
# {link} a symbolic link in it to the input, and {tool} {cal} {val} {truth}
# {model} {plan} {poses} {journal} are valid fixtures.
# MIN_CASES (default 150) is the least number of cases the file must hold: lower it to run a
# subset (grep some lines into a file of their own).
set -uo pipefail
ROBCAL="$1"
CASES="$2"
root=$(cd "$(dirname "$0")/../.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

fix="$tmp/fixtures"
mkdir -p "$fix"
data="$root/tests/data/irb120-published"
cp "$data/tool.yaml" "$fix/tool.yaml"
head -40 "$data/calibration.csv" > "$fix/cal.csv"
head -20 "$data/validation.csv" > "$fix/val.csv"
cp "$data/truth.yaml" "$fix/truth.yaml"
"$ROBCAL" calibrate --robot abb-irb120 --tool "$fix/tool.yaml" --measurements "$data/calibration.csv" \
  --out "$fix/model.yaml" > /dev/null || { echo "fixture: calibrate failed"; exit 1; }
cp "$root/tests/fuzz/corpus/plan/plan.json" "$fix/plan.json"
cp "$root/tests/fuzz/corpus/journal/journal.jsonl" "$fix/journal.jsonl"
printf 'name,x,y,z,qw,qx,qy,qz\np1,400,0,500,0,0,1,0\n' > "$fix/poses.csv"

failed=0
count=0
while IFS=$'\t' read -r id code fragment name content args; do
  [[ -z "$id" || "$id" == \#* ]] && continue
  count=$((count + 1))
  dir="$tmp/case-$count"
  mkdir -p "$dir"
  input="$dir/$name"
  if [[ "$content" == @* ]]; then
    source_file=${content%%:*}
    source_file=${source_file#@}
    fixture=$(ls "$fix" | grep "^$source_file\." | head -1)
    [ -n "$fixture" ] && source_file="$fix/$fixture" || source_file="$root/$source_file"
    sed -e "${content#*:}" "$source_file" > "$input"
  elif [ "$content" != "-" ]; then
    printf '%b' "$content" > "$input"
  fi
  [[ "$args" == *"{link}"* ]] && ln -s "$input" "$dir/link"
  fragment=${fragment//\{dir\}/$dir}
  expanded=${args//\{in\}/$input}
  expanded=${expanded//\{out\}/$dir/out}
  expanded=${expanded//\{dir\}/$dir}
  expanded=${expanded//\{link\}/$dir/link}
  for f in tool cal val truth model plan poses journal; do
    ext=$(ls "$fix" | grep "^$f\." | head -1)
    expanded=${expanded//\{$f\}/$fix/$ext}
  done
  # Arguments are split on blanks; an argument that holds blanks is written with \x20.
  read -r -a argv <<< "$expanded"
  for i in "${!argv[@]}"; do argv[$i]=$(printf '%b' "${argv[$i]}"); done
  before=$(ls -A "$dir")
  "$ROBCAL" "${argv[@]}" > "$dir.stdout" 2> "$dir.stderr" < /dev/null
  got=$?
  problem=""
  [ "$got" != "$code" ] && problem="exit code $got, expected $code"
  grep -qF -- "$fragment" "$dir.stderr" || problem="$problem; message lacks '$fragment'"
  [ "$(ls -A "$dir")" != "$before" ] && problem="$problem; wrote $(ls -A "$dir" | tr '\n' ' ')"
  grep -qiwE 'nan|-nan' "$dir.stdout" && problem="$problem; NaN on stdout"
  if [ -n "$problem" ]; then
    failed=$((failed + 1))
    echo "FAIL $id: ${problem#; }"
    echo "  robcal $expanded"
    sed 's/^/  stderr: /' "$dir.stderr" | head -5
  fi
done < "$CASES"
echo "$((count - failed)) of $count bad-input cases passed"
[ "$count" -ge "${MIN_CASES:-150}" ] || { echo "the catalogue must hold at least 150 cases"; exit 1; }
[ "$failed" -eq 0 ]
