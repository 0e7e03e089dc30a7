#!/usr/bin/env bash
# Fuzz the input readers with libFuzzer (clang, ASan + UBSan):
#   scripts/fuzz.sh [RUNS [TARGET...]]   (default 1000000 executions of every target)
#   PCS_FUZZ_SECONDS=S scripts/fuzz.sh    at most S seconds per target instead (CI: a short pass)
# Targets: frame (wire protocol), port_table, deck (FE keyword deck), model
# (TLM host model), include (*INCLUDE in a deck), fmu_unpack (the importer's
# unzip and checks), handshake (fe_server's handshake state machine), set
# (tlm_host's --set overrides). Any crashing input is copied into tests/fuzz/corpus/<target>/,
# where the regular test suite replays it from then on.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
runs=${1:-1000000}
"$root/scripts/install_deps.sh"
for p in clang libclang-rt-14-dev; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="${missing:-} $p"
done
if [ -n "${missing:-}" ]; then
  sudo=""; [ "$(id -u)" -ne 0 ] && sudo=sudo
  $sudo apt-get update -qq && DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq $missing
fi
build=$root/build-fuzz
CC=clang CXX=clang++ cmake -S "$root" -B "$build" -G Ninja -DPCS_FUZZ=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo > /dev/null
targets=(frame port_table deck model include fmu_unpack handshake set)
[ $# -gt 1 ] && targets=("${@:2}")
cmake --build "$build" --target "${targets[@]/#/fuzz_}"
status=0
for t in "${targets[@]}"; do
  work=$(mktemp -d)
  cp -r "$root/tests/fuzz/corpus/$t/." "$work/"
  mkdir -p "$build/artifacts/$t"
  limit=(-runs="$runs") what="$runs runs"
  if [ -n "${PCS_FUZZ_SECONDS:-}" ]; then limit=(-max_total_time="$PCS_FUZZ_SECONDS") what="at most $PCS_FUZZ_SECONDS s"; fi
  echo "== fuzz_$t: $what"
  if ! (cd "$build/artifacts/$t" && "$build/tests/fuzz/fuzz_$t" "${limit[@]}" -max_len=4096 -timeout=10 \
        -rss_limit_mb=2048 -print_final_stats=1 "$work" 2>&1 | grep -E "stat::number_of_executed_units|ERROR|SUMMARY|Done"); then
    :
  fi
  for crash in "$build/artifacts/$t"/crash-* "$build/artifacts/$t"/timeout-* "$build/artifacts/$t"/oom-*; do
    [ -e "$crash" ] || continue
    cp "$crash" "$root/tests/fuzz/corpus/$t/"
    echo "   kept $(basename "$crash") as a regression input"
    status=1
  done
  rm -rf "$work"
done
exit $status
