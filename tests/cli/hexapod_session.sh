#!/usr/bin/env bash
# The guided hexapod session: a session killed midway (SIGKILL) and resumed, and one stopped by
# the end of its input and resumed, give the same result file as one run straight through.
set -euo pipefail
ROBCAL="$1"
tmp=$(mktemp -d)
pid=""
cleanup() { [ -n "$pid" ] && kill -9 "$pid" 2>/dev/null; rm -rf "$tmp"; }
trap cleanup EXIT

legs='["B1-T1","B1-T2","B2-T1","B2-T2","B2-T3","B3-T1"]'
cat > "$tmp/plan.json" <<JSON
{"ballbar": {"tool_mm": 150, "leg_mm": 300, "range_mm": 1, "recheck_every": 2},
 "configurations": [
  {"pose": "P01", "labels": "front-up-noflip", "joints_deg": [10, 20, -5, 0, 45, 30], "legs": $legs},
  {"pose": "P07", "labels": "front-up-flip", "legs": ["B2-T1","B2-T2","B3-T1","B3-T2","B3-T3","B1-T1"]},
  {"pose": "P19", "legs": $legs},
  {"pose": "P25", "legs": $legs}]}
JSON
# 3 tool sides, 3 base sides, configuration 1 (6 legs), configuration 2 (3 legs, then one out of
# the ±1 mm range: retry), the calibrator re-check, configurations 3 and 4 (6 legs each).
cat > "$tmp/readings" <<TXT
150.0123
149.9876
150.0411
300.0021
299.9967
300.0102
300.1234
299.8765
300.4321
299.5678
300.0001
300.9999
300.2
299.9
300.05
301.5
300.0011
abc
300.3
300.31
300.32
300.33
300.34
300.35
299.1
299.2
299.3
299.4
299.5
out
TXT
valid_before_kill=12

"$ROBCAL" hexapod session --plan "$tmp/plan.json" --journal "$tmp/straight.jsonl" \
  --out "$tmp/straight.json" < "$tmp/readings" > "$tmp/straight.log"
grep -q 'Move to configuration 2 (P07, front-up-flip)' "$tmp/straight.log"
grep -q 'Attach the ballbar between B2 and T1' "$tmp/straight.log"
grep -q "retry after preliminary calibration" "$tmp/straight.log"
grep -q "Re-check the ballbar on its calibrator" "$tmp/straight.log"
grep -q "'abc' is not a reading" "$tmp/straight.log"
[ "$(grep -c '"status": "measured"' "$tmp/straight.json")" = 2 ]
[ "$(grep -c '"status": "retry"' "$tmp/straight.json")" = 2 ]  # config 2 and config 4 ('out')

# Killed midway: readings arrive through a FIFO; once the journal holds 12 entries the process
# gets SIGKILL (no chance to clean up), then --resume is fed the rest.
mkfifo "$tmp/fifo"
"$ROBCAL" hexapod session --plan "$tmp/plan.json" --journal "$tmp/killed.jsonl" \
  --out "$tmp/killed.json" < "$tmp/fifo" > /dev/null &
pid=$!
exec 3> "$tmp/fifo"
head -n "$valid_before_kill" "$tmp/readings" >&3
for _ in $(seq 1 1200); do
  [ -f "$tmp/killed.jsonl" ] && [ "$(wc -l < "$tmp/killed.jsonl")" -ge "$valid_before_kill" ] && break
  sleep 0.05
done
[ "$(wc -l < "$tmp/killed.jsonl")" -eq "$valid_before_kill" ]
kill -9 "$pid"
wait "$pid" 2>/dev/null || true
pid=""
exec 3>&-
[ ! -e "$tmp/killed.json" ]  # no result before the session is complete
tail -n +$((valid_before_kill + 1)) "$tmp/readings" |
  "$ROBCAL" hexapod session --plan "$tmp/plan.json" --journal "$tmp/killed.jsonl" --resume \
    --out "$tmp/killed.json" > "$tmp/resumed.log"
grep -q "$valid_before_kill readings replayed" "$tmp/resumed.log"
cmp "$tmp/straight.json" "$tmp/killed.json"
cmp "$tmp/straight.jsonl" "$tmp/killed.jsonl"

# Stopped by the end of the input after 5 readings, then resumed twice.
head -n 5 "$tmp/readings" |
  "$ROBCAL" hexapod session --plan "$tmp/plan.json" --journal "$tmp/eof.jsonl" --out "$tmp/eof.json" > /dev/null
[ ! -e "$tmp/eof.json" ]
sed -n 6,20p "$tmp/readings" |
  "$ROBCAL" hexapod session --plan "$tmp/plan.json" --journal "$tmp/eof.jsonl" --resume --out "$tmp/eof.json" > /dev/null
tail -n +21 "$tmp/readings" |
  "$ROBCAL" hexapod session --plan "$tmp/plan.json" --journal "$tmp/eof.jsonl" --resume --out "$tmp/eof.json" > /dev/null
cmp "$tmp/straight.json" "$tmp/eof.json"

# A journal is never overwritten; a journal of another plan is refused; both exit with code 2.
set +e
"$ROBCAL" hexapod session --plan "$tmp/plan.json" --journal "$tmp/straight.jsonl" < /dev/null 2> "$tmp/err"
rc=$?
set -e
[ "$rc" = 2 ]
grep -q "exists already" "$tmp/err"
sed 's/"P07"/"P08"/; s/"B2-T1","B2-T2","B3-T1"/"B1-T1","B2-T2","B3-T1"/' "$tmp/plan.json" > "$tmp/other.json"
set +e
"$ROBCAL" hexapod session --plan "$tmp/other.json" --journal "$tmp/killed.jsonl" --resume < /dev/null 2> "$tmp/err"
rc=$?
set -e
[ "$rc" = 2 ]
grep -q "does not match" "$tmp/err"
echo "hexapod session: kill/resume and EOF/resume reproduce the straight run"
