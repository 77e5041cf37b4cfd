# A hexapod session killed by SIGKILL midway, for the resume checks of the CLI test scripts
# (sourced; not a test itself). The script sets ROBCAL (the program) and TMP (a scratch folder).
#
# kill_session_after N PLAN JOURNAL READINGS LOG: feeds the first N lines of READINGS to
# `robcal hexapod session` through a FIFO, waits (at most 60 s) until JOURNAL holds N readings and
# kills the session. `pid` names it while it runs (for the caller's EXIT trap). Fails (status 1)
# when the journal does not hold exactly N readings.
kill_session_after() {
  local n=$1 plan=$2 journal=$3 readings=$4 log=$5 lines
  rm -f "$TMP/session.fifo"
  mkfifo "$TMP/session.fifo"
  "$ROBCAL" hexapod session --plan "$plan" --journal "$journal" < "$TMP/session.fifo" > "$log" &
  pid=$!
  exec 3> "$TMP/session.fifo"
  head -n "$n" "$readings" >&3
  for _ in $(seq 1 1200); do
    [ -f "$journal" ] && [ "$(wc -l < "$journal")" -ge "$n" ] && break
    sleep 0.05
  done
  lines=$(wc -l < "$journal" 2>/dev/null || echo 0)
  kill -9 "$pid"
  wait "$pid" 2>/dev/null || true
  pid=""
  exec 3>&-
  [ "$lines" -eq "$n" ]
}
