#!/usr/bin/env bash
# The main job: install what is missing, build, run the default scene.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install_deps.sh"
"$root/scripts/build.sh"
"$root/scripts/run_scene.sh" "${1:-one_dof}"
