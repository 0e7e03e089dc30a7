#!/usr/bin/env bash
# Every benchmark in one run: builds, runs the micro-benchmarks and the
# speed-against-error studies, and writes bench/RESULTS.md with its plots in
# bench/results/. Takes about 10 minutes on 2 cores.
#   bench/run.sh [--quick]    (--quick: fewer points, for a smoke run)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/build.sh"
exec /usr/bin/python3 "$root/bench/run_benchmarks.py" "$@"
