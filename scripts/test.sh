#!/usr/bin/env bash
# The test command: install what is missing, build, run every test.
#   scripts/test.sh                 normal build
#   PCS_SANITIZE=1 scripts/test.sh  AddressSanitizer + UndefinedBehaviorSanitizer build in build-asan/
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install_deps.sh"
if [ "${PCS_SANITIZE:-0}" = 1 ]; then
  export PCS_BUILD_DIR=${PCS_BUILD_DIR:-$root/build-asan}
  # -O2: the FE scenes are too slow at -O0. No benchmarks: they are not tests.
  "$root/scripts/build.sh" -DPCS_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPCS_BUILD_BENCH=OFF
else
  "$root/scripts/build.sh"
fi
cd "${PCS_BUILD_DIR:-$root/build}"
exclude=()
if [ "${PCS_SANITIZE:-0}" = 1 ]; then
  # Long physical runs with a shorter twin in this suite (tests/sanitizer_skip.txt says which and why).
  regex=$("$root/scripts/skip_regex.sh" "$root/tests/sanitizer_skip.txt")
  [ -z "$regex" ] || exclude=(--exclude-regex "$regex")
fi
# A fresh build has no timings yet, and ctest would start the longest tests
# last (one core idle in the tail): tests/ctest_costs.txt holds measured
# seconds of the longest, so they start first. ctest keeps its own file after.
costs=Testing/Temporary/CTestCostData.txt
[ -f "$costs" ] || { mkdir -p Testing/Temporary && cp "$root/tests/ctest_costs.txt" "$costs"; }
ctest --output-on-failure --parallel "$(nproc)" "${exclude[@]}"
