#!/bin/sh
# scripts/skip_regex.sh in this build directory: the sanitizer suite's real
# list gives a regex naming each of its tests; a list with a name ctest does
# not have exits 1 naming it (a stale name would skip nothing, silently).
# Usage: skip_regex_test.sh SOURCE_DIR  (run in the build directory)
src=$1
fail=0
regex=$("$src/scripts/skip_regex.sh" "$src/tests/sanitizer_skip.txt") || { echo "FAIL: the real list is refused"; fail=1; }
for n in $(grep -v '^#' "$src/tests/sanitizer_skip.txt" | awk 'NF {print $1}'); do
  case "$regex" in *"$n"*) ;; *) echo "FAIL: $n missing from $regex"; fail=1 ;; esac
done
tmp=$(mktemp)
grep -v '^#' "$src/tests/sanitizer_skip.txt" > "$tmp"
echo "Calibration.NoSuchTest  a mistyped name" >> "$tmp"
out=$("$src/scripts/skip_regex.sh" "$tmp" 2>&1) && { echo "FAIL: a list with a mistyped name was accepted"; fail=1; }
echo "$out" | grep -q "Calibration.NoSuchTest" || { echo "FAIL: the refusal does not name the test: $out"; fail=1; }
rm -f "$tmp"
[ $fail = 0 ] && echo "ok: $regex"
exit $fail
