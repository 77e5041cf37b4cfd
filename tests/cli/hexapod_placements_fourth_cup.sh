#!/usr/bin/env bash
# hexapod_placements.sh with a fourth tool cup (issue 20): every plan and the placement search
# with T4 on the circumcircle of T1..T3, opposite T1 (2R, R, R with R = 150/√3: a seventh leg in
# every pose); the second placement's session is the one killed (SIGKILL) and resumed, and both
# calibrate together with --fit legs, T4 fitted where its measured distances put it.
exec bash "$(dirname "$0")/hexapod_placements.sh" "$1" \
  --tool-cup4-mm 173.20508075688772,86.60254037844386,86.60254037844386
