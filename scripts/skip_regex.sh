#!/usr/bin/env bash
# The ctest regex of the tests a skip list names (one name first on each
# line, '#' comments), checked against the tests ctest has in the current
# build directory: prints ^(a|b|...)$, or nothing for an empty list; exits 1
# naming what is missing when the list names a test ctest does not have (a
# stale or mistyped name would otherwise skip nothing, silently).
#   scripts/skip_regex.sh LIST    (run in a build directory)
set -euo pipefail
list=$1
names=$(grep -v '^#' "$list" | awk 'NF {print $1}' | paste -sd '|')
[ -n "$names" ] || exit 0
have=$(ctest -N | sed -n 's/^ *Test *#[0-9]*: //p')
missing=$(echo "$names" | tr '|' '\n' | while read -r n; do grep -qxF "$n" <<< "$have" || echo "$n"; done)
[ -z "$missing" ] || { echo "skip_regex.sh: $list names tests this build does not have: $missing" >&2; exit 1; }
echo "^($names)\$"
