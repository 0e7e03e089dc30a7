#!/bin/sh
# Each benchmark and fe_mesh: --help prints its usage and exits 0 (they
# crashed with an uncaught exception, or said "unknown argument"); a bad
# argument exits 2 naming it (they ran with 0 or printed "inf us -nan"; 0.5
# round trips was 0 of them).
# Usage: help_and_bad_arguments.sh FE_MESH BENCH_TLM BENCH_COUPLING BENCH_FE [BENCH_MPI]
fail=0
expect() {  # rc pattern command...
  want=$1 pattern=$2; shift 2
  out=$("$@" 2>&1); rc=$?
  if [ "$rc" != "$want" ] || ! printf '%s' "$out" | grep -q -- "$pattern"; then
    echo "FAIL: $* -> exit $rc (wanted $want), output: $out"; fail=1
  else
    echo "ok   $* -> exit $rc"
  fi
}
expect 0 "usage: fe_mesh" "$1" --help
expect 0 "--radial-growth" "$1" -h
expect 2 "unknown argument --bogus" "$1" --bogus
expect 0 "usage: bench_tlm" "$2" --help
expect 2 "argument 1 'abc'" "$2" abc
expect 0 "usage: bench_coupling" "$3" --help
expect 2 "argument 1 '-5'" "$3" -5
expect 2 "must be a whole number" "$3" 0.5
expect 0 "hammer threads hex8" "$4" --help
expect 2 "unknown benchmark 'nope'" "$4" nope
if [ -n "$5" ]; then
  expect 0 "usage: \[mpirun" "$5" --help
  expect 2 "argument 2 'x'" "$5" 1.5 x
fi
exit $fail
