#!/bin/sh
# fmugen: with SOURCE_DATE_EPOCH two runs a second apart write the same bytes
# (entries' times and generationDateAndTime from it); a value that is not a
# number of seconds is refused (exit 3); --binary without --binary-win64
# packs no win64 DLL (it would be another build's).
# Usage: reproducible_fmu.sh FMUGEN PORTS.cfg
fmugen=$1 ports=$2 fail=0
dir=$(mktemp -d "${TMPDIR:-/tmp}/pcs_fmugen_XXXXXX")
trap 'rm -rf "$dir"' EXIT
SOURCE_DATE_EPOCH=1700000000 "$fmugen" "$ports" -o "$dir/a.fmu" > /dev/null || fail=1
sleep 1.1
SOURCE_DATE_EPOCH=1700000000 "$fmugen" "$ports" -o "$dir/b.fmu" > /dev/null || fail=1
if cmp -s "$dir/a.fmu" "$dir/b.fmu"; then echo "ok   the same bytes a second apart"; else echo "FAIL: two runs differ"; fail=1; fi
unzip -p "$dir/a.fmu" modelDescription.xml | grep -q 'generationDateAndTime="2023-11-14T22:13:20Z"' \
  && echo "ok   generationDateAndTime from SOURCE_DATE_EPOCH" || { echo "FAIL: generationDateAndTime"; fail=1; }
out=$(SOURCE_DATE_EPOCH=abc "$fmugen" "$ports" -o "$dir/c.fmu" 2>&1); rc=$?
[ $rc -eq 3 ] && printf '%s' "$out" | grep -q "is not a number of seconds" \
  && echo "ok   a bad SOURCE_DATE_EPOCH: exit 3" || { echo "FAIL: bad SOURCE_DATE_EPOCH -> $rc: $out"; fail=1; }
so=$(unzip -Z1 "$dir/a.fmu" | grep '^binaries/linux64/') && unzip -q -o "$dir/a.fmu" "$so" -d "$dir/x"
"$fmugen" "$ports" -o "$dir/d.fmu" --binary "$dir/x/$so" > /dev/null || fail=1
if unzip -Z1 "$dir/d.fmu" | grep -q '^binaries/win64/'; then echo "FAIL: --binary kept the build's win64 DLL"; fail=1
else echo "ok   --binary alone packs no win64 DLL"; fi
exit $fail
