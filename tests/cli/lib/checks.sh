# Assertions shared by the CLI test scripts (sourced; not a test itself: ctest runs tests/cli/*.sh).
# The script sets ROBCAL (the program) and TMP (a scratch folder) before sourcing this file.
FAILED=0

fail() { echo "FAIL: $*"; FAILED=1; }

# expect_error "<description>" "<substring of stderr>" robcal-args...
# Bad input must exit with 2, say what is wrong on stderr, print nothing on stdout and write no
# output file (commands under test write to $TMP/bad.*).
expect_error() {
  local what=$1 needle=$2
  shift 2
  rm -f "$TMP"/bad.*
  "$ROBCAL" "$@" >"$TMP/out" 2>"$TMP/err"
  local rc=$?
  [[ $rc -eq 2 ]] || fail "$what: exit code $rc (expected 2) for: $*"
  grep -qF -- "$needle" "$TMP/err" || fail "$what: stderr lacks '$needle': $(cat "$TMP/err")"
  [[ ! -s "$TMP/out" ]] || fail "$what: wrote to stdout: $(cat "$TMP/out")"
  compgen -G "$TMP/bad.*" >/dev/null && fail "$what: an output file was written"
  return 0
}

# finish <script name>: the closing line and the exit code of the script.
finish() {
  if [[ $FAILED -ne 0 ]]; then
    echo "$1: FAILED"
    exit 1
  fi
  echo "$1: all checks passed"
}
