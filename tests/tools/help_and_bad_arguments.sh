#!/bin/sh
# Each benchmark and fe_mesh: --help prints its usage and exits 0 (they
# crashed with an uncaught exception, or said "unknown argument"); a bad
# argument exits 2 naming it (they ran with 0 or printed "inf us -nan"; 0.5
# round trips was 0 of them). Every executable: --version prints its name,
# the project's version and the coupling protocol, and exits 0.
# Usage: help_and_bad_arguments.sh FE_SERVER TLM_HOST TLM_FIT FMUGEN FE_MESH BENCH_TLM BENCH_COUPLING BENCH_FE [BENCH_MPI]
FE_SERVER=$1 TLM_HOST=$2 TLM_FIT=$3 FMUGEN=$4 FE_MESH=$5 BENCH_TLM=$6 BENCH_COUPLING=$7 BENCH_FE=$8 BENCH_MPI=$9
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
expect 0 "usage: fe_mesh" "$FE_MESH" --help
expect 0 "--radial-growth" "$FE_MESH" -h
expect 2 "unknown argument --bogus" "$FE_MESH" --bogus
expect 0 "usage: bench_tlm" "$BENCH_TLM" --help
expect 2 "argument 1 'abc'" "$BENCH_TLM" abc
expect 0 "usage: bench_coupling" "$BENCH_COUPLING" --help
expect 2 "argument 1 '-5'" "$BENCH_COUPLING" -5
expect 2 "must be a whole number" "$BENCH_COUPLING" 0.5
expect 0 "hammer threads hex8" "$BENCH_FE" --help
expect 2 "unknown benchmark 'nope'" "$BENCH_FE" nope
if [ -n "$BENCH_MPI" ]; then
  expect 0 "usage: \[mpirun" "$BENCH_MPI" --help
  expect 2 "argument 2 'x'" "$BENCH_MPI" 1.5 x
fi
# A mistake: the error and a pointer to --help, not 30 lines of usage that
# scroll it away; fmugen exits 3 for an input it cannot use (it exited 1).
for exe in "$FE_SERVER" "$TLM_HOST" "$FMUGEN"; do
  name=$(basename "$exe")
  expect 2 "($name --help lists the options)" "$exe" --bogus
  out=$("$exe" --bogus 2>&1)
  if printf '%s' "$out" | grep -q "usage:"; then echo "FAIL: $name --bogus printed the usage: $out"; fail=1; fi
done
expect 3 "cannot open port configuration '/nonexistent/ports.cfg': No such file or directory" "$FMUGEN" /nonexistent/ports.cfg -o /tmp/never.fmu
for exe in "$FE_SERVER" "$TLM_HOST" "$TLM_FIT" "$FMUGEN" "$FE_MESH" "$BENCH_TLM" "$BENCH_COUPLING" "$BENCH_FE" "$BENCH_MPI"; do
  [ -n "$exe" ] || continue
  expect 0 "^$(basename "$exe") [0-9][0-9.]* (percussion co-simulation; coupling protocol [0-9][0-9]*)$" "$exe" --version
done
# The main job's study options: a variant that is not there, or does not
# fit the scene, stops before any run with exit 2 and says which.
root=$(cd "$(dirname "$0")/../.." && pwd)
build=$(cd "$(dirname "$FE_SERVER")/.." && pwd)
tmp=$(mktemp -d)
if [ -f "$build/scenes/hammer_rig/deck.k" ]; then
  expect 2 "--ports '/nonexistent/ports.cfg': no such file" env PCS_BUILD_DIR="$build" "$root/scripts/run_hammer.sh" --ports /nonexistent/ports.cfg --out "$tmp/a"
  expect 2 "--deck 'nope.k': no such file" env PCS_BUILD_DIR="$build" "$root/scripts/run_hammer.sh" --deck nope.k --out "$tmp/b"
  expect 2 "--ports: the rigid scene has a port table per mode" env PCS_BUILD_DIR="$build" "$root/scripts/run_hammer.sh" --scene rigid --ports "$root/scenes/hammer_rig/ports.cfg" --out "$tmp/c"
  expect 2 "PCS_PROGRESS_SECONDS 'soon': a positive whole number of seconds" env PCS_PROGRESS_SECONDS=soon PCS_BUILD_DIR="$build" "$root/scripts/run_hammer.sh" --conditions 150:6.0 --out "$tmp/d"
  # The progress line while conditions run: run_hammer.sh's own progress()
  # on a running condition's log. One condition, 150 s left, 2 job slots:
  # the job has 150 s left, not 75 (a run uses one slot).
  sed -n '/^progress() {/,/^}/p' "$root/scripts/run_hammer.sh" > "$tmp/progress.sh"
  echo "t = 0.2 of 0.45 s (40%), 100.0 s elapsed, about 150.0 s left" > "$tmp/run_150bar_6.0mm.log"
  sleep 30 & sleeper=$!
  got=$(bash -c 'set -euo pipefail; source "$1"; pids=($2); logs=("$3"); n_conditions=1; every=1; last_tick=0
                 modes=tlm10; scene_name=rig; jobs=2; progress' _ "$tmp/progress.sh" "$sleeper" "$tmp/run_150bar_6.0mm.log" 2>&1)
  kill "$sleeper"
  if printf '%s' "$got" | grep -q '^  \[150bar_6.0mm\] t = 0.2 of 0.45 s' &&
     printf '%s' "$got" | grep -q '0 of 1 conditions done, 1 running, 0 queued; about 150 s left'; then
    echo "ok   run_hammer.sh progress: $got"
  else
    echo "FAIL: run_hammer.sh progress: $got"; fail=1
  fi
  printf 'not a port table\n' > "$tmp/bad.cfg"
  expect 2 "fmugen refused it" env PCS_BUILD_DIR="$build" "$root/scripts/run_hammer.sh" --ports "$tmp/bad.cfg" --out "$tmp/d"
fi
rm -rf "$tmp"
exit $fail
