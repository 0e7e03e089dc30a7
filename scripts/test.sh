#!/usr/bin/env bash
# The test command: install what is missing, build, run every test.
#   scripts/test.sh                 normal build
#   PCS_SANITIZE=1 scripts/test.sh  AddressSanitizer + UndefinedBehaviorSanitizer build in build-asan/
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install_deps.sh"
if [ "${PCS_SANITIZE:-0}" = 1 ]; then
  export PCS_BUILD_DIR=${PCS_BUILD_DIR:-$root/build-asan}
  "$root/scripts/build.sh" -DPCS_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo  # -O2: the FE scenes are too slow at -O0
else
  "$root/scripts/build.sh"
fi
cd "${PCS_BUILD_DIR:-$root/build}"
ctest --output-on-failure --parallel "$(nproc)"
