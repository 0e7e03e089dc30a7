#!/usr/bin/env bash
# Run one scene on this machine: fe_server on loopback (any free port, a
# fresh token), tlm_host connected to it, results and plots in out/<scene>/.
#   scripts/run_scene.sh [SCENE] [tlm_host options, e.g. --set orifice.A=1e-12]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${PCS_BUILD_DIR:-$root/build}
scene=${1:-one_dof}
[ $# -gt 0 ] && shift
dir=$root/scenes/$scene
out=$root/out/$scene
[ -d "$dir" ] || { echo "run_scene: no scene folder $dir" >&2; exit 2; }
mkdir -p "$out"
rm -f "$out/port"
# The token travels in the environment (private to this user), never on a command line.
PCS_TOKEN=$(od -An -N16 -tx1 /dev/urandom | tr -d ' \n')
export PCS_TOKEN

"$build/fe_server/fe_server" --model "$dir/piston.k" --ports "$dir/ports.cfg" \
  --listen 127.0.0.1:0 --port-file "$out/port" \
  --out "$out/fe_results.h5" --accept-timeout 60 > "$out/fe_server.log" 2>&1 &
server=$!
trap 'kill $server 2>/dev/null || true' EXIT
for _ in $(seq 200); do [ -s "$out/port" ] && break; sleep 0.05; done
[ -s "$out/port" ] || { cat "$out/fe_server.log" >&2; echo "run_scene: fe_server did not start" >&2; exit 1; }

"$build/tlm_host/tlm_host" "$dir/model.tlm" --fmu "$build/scenes/$scene/$scene.fmu" \
  --server "127.0.0.1:$(cat "$out/port")" --out "$out/host_results.h5" "$@"
wait $server
trap - EXIT
cat "$out/fe_server.log"
/usr/bin/python3 "$root/scripts/plot_scene.py" "$out/fe_results.h5" "$out/host_results.h5" -o "$out/$scene.png"
echo "run_scene: results in $out/ (fe_results.h5, host_results.h5, $scene.png)"
