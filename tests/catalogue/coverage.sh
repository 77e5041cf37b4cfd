#!/usr/bin/env bash
# Flag coverage of the bad-input catalogue (issue 21): every flag of every robcal command (read
# from `robcal CMD --help`, recursively through sub-commands) that takes a value must appear in
# at least one row of cases.tsv run against that command. Switches (flags without a value) cannot
# be given a bad value and are listed as such; --help and --help-all are left out.
#
# Usage: coverage.sh ROBCAL CASES [--list]
#   prints one line per uncovered flag (every flag with --list: command, flag, value|switch,
#   covered|UNCOVERED) and a summary; exits 1 when more flags that take a value are uncovered
#   than MAX_UNCOVERED (default 0: every such flag has a row).
set -uo pipefail
ROBCAL="$1"
CASES="$2"
LIST="${3:-}"

# The arguments of every catalogue row, one line each.
rows=$(grep -v '^#' "$CASES" | awk -F'\t' 'NF >= 6 { print $6 }')

# The help of `robcal $1`, read once (robcal takes ~0.1 s to start).
# (Kept in files: the callers run in sub-shells.)
cache=$(mktemp -d)
trap 'rm -rf "$cache"' EXIT
help_of() {
  local file="$cache/help-${1// /-}"
  [ -f "$file" ] || "$ROBCAL" $1 --help > "$file" 2> /dev/null
  cat "$file"
}

# Commands below `robcal $1`: the first words of the sections other than "Options:" and
# "Positionals:" (the top level lists its commands under stage headings, the others under
# "Subcommands:").
subcommands() {
  help_of "$1" |
    awk '/^[^ ].*:$/ { s = ($0 != "Options:" && $0 != "Positionals:"); next }
         s && /^  [a-z][a-z0-9-]* / { print $1 }'
}

# "FLAG value" or "FLAG switch" for each flag of `robcal $1`: a value-taking flag has its type
# (TEXT, INT, FLOAT, UINT...) one blank after its name; a switch has its description (or
# nothing) after two or more blanks.
flags_of() {
  help_of "$1" |
    awk '/^Options:/ { s = 1; next } /^$/ { s = 0 }
         s && /^  -/ {
           line = substr($0, 3)
           name = line; sub(/[ ].*$/, "", name); sub(/^-[a-zA-Z],/, "", name)
           if (name == "--help" || name == "--help-all" || name !~ /^--/) next
           rest = substr(line, length(name) + 1)
           sub(/^-[a-zA-Z],/, "", rest)
           print name, (rest ~ /^ [A-Z]/ ? "value" : "switch")
         }'
}

commands=()
queue=($(subcommands ""))
while [ ${#queue[@]} -gt 0 ]; do
  cmd="${queue[0]}"
  queue=("${queue[@]:1}")
  commands+=("$cmd")
  for sub in $(subcommands "$cmd"); do queue+=("$cmd $sub"); done
done

values=0
covered=0
switches=0
for cmd in "${commands[@]}"; do
  # Rows of this command: their arguments start with its words (and no deeper sub-command's
  # flags are mistaken for its own: a row of `hexapod plan` does not cover `hexapod`).
  mine=$(grep -E "^${cmd}( |$)" <<< "$rows")
  while read -r flag kind; do
    [ -z "$flag" ] && continue
    if [ "$kind" = switch ]; then
      switches=$((switches + 1))
      [ -n "$LIST" ] && printf '%s\t%s\tswitch\n' "$cmd" "$flag"
      continue
    fi
    values=$((values + 1))
    if grep -qE -- "(^| )${flag}( |=|$)" <<< "$mine"; then
      covered=$((covered + 1))
      [ -n "$LIST" ] && printf '%s\t%s\tvalue\tcovered\n' "$cmd" "$flag"
    else
      printf '%s\t%s\tvalue\tUNCOVERED\n' "$cmd" "$flag"
    fi
  done <<< "$(flags_of "$cmd")"
done
echo "${#commands[@]} commands: $covered of $values flags that take a value appear in a" \
  "catalogue row of their command; $switches switches (no value to get wrong)"
[ $((values - covered)) -le "${MAX_UNCOVERED:-0}" ]
