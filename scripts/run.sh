#!/usr/bin/env bash
# The main job: install what is missing, build, and run the hydraulic hammer
# co-simulation in its four running conditions and three coupling modes
# (fe_server and tlm_host on loopback), with the report and plots in
# out/hammer/. Arguments go to scripts/run_hammer.sh, e.g. --modes tlm10.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install_deps.sh"
"$root/scripts/build.sh"
"$root/scripts/run_hammer.sh" "$@"
