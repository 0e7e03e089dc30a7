#!/usr/bin/env bash
# The main job: install what is missing, build, and run the hydraulic hammer
# co-simulation (the elastic piston and tool in fe_server, the hydraulics in
# tlm_host, on loopback) in its four running conditions beside the monolithic
# reference, with the report and plots in out/hammer/. Arguments go to
# scripts/run_hammer.sh, e.g. --conditions 150:6.0 or --scene rigid.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/install_deps.sh"
# Only what the main job runs (about half of a full build's time; the test
# command builds the rest).
PCS_BUILD_TARGETS="fe_server tlm_host scene_hammer_elastic scene_hammer scene_hammer_rig" "$root/scripts/build.sh"
"$root/scripts/run_hammer.sh" "$@"
