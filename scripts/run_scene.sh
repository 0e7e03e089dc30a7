#!/usr/bin/env bash
# Run any scene on this machine, results and a plot in out/<scene>/:
#   scripts/run_scene.sh [SCENE] [--out DIR] [tlm_host options, e.g. --set orifice.A=1e-12]
#   scripts/run_scene.sh --list
# A co-simulated scene starts fe_server on loopback (any free port, a fresh
# token in the environment) and connects tlm_host to it; an FE-only scene
# runs fe_server alone (its deck's end time); a host-only scene runs
# tlm_host alone. tlm_host's options (--set simulation.stoptime=0.05, --log,
# --no-report) go to the host; an FE-only scene takes none.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${PCS_BUILD_DIR:-$root/build}
src=$root/scenes
built=$build/scenes

# scene: kind | deck | port table | host model | FMU | host options the scene needs
# (decks with meshes are the built ones: the build writes the meshes beside them)
table() {
  cat <<EOF
one_dof|cosim|$src/one_dof/piston.k|$src/one_dof/ports.cfg|$src/one_dof/model.tlm|$built/one_dof/one_dof.fmu|
one_dof_tlm|cosim|$src/one_dof/piston.k|$src/one_dof_tlm/ports.cfg|$src/one_dof/model.tlm|$built/one_dof_tlm/one_dof_tlm.fmu|
one_dof_hopsan|cosim|$src/one_dof/piston.k|$src/one_dof_hopsan/ports.cfg|$src/one_dof/model.tlm|$built/one_dof_hopsan/one_dof_hopsan.fmu|
hammer|cosim|$built/hammer/deck.k|$src/hammer/ports.cfg|$src/hammer/model.tlm|$built/hammer/hammer.fmu|
hammer_elastic|cosim|$built/hammer_elastic/deck.k|$src/hammer_elastic/ports.cfg|$src/hammer_elastic/model.tlm|$built/hammer_elastic/hammer_elastic.fmu|--set simulation.timestep=1e-5 --set simulation.log_every=2
hammer_rig|cosim|$built/hammer_rig/deck.k|$src/hammer_rig/ports.cfg|$src/hammer_rig/model_elastic.tlm|$built/hammer_rig/hammer_rig.fmu|--set simulation.timestep=1e-5 --set simulation.log_every=2 --set relief.p_crack=14720218.04
hammer_monolithic|host|||$src/hammer_monolithic/model.tlm||
bar_impact|fe|$built/bar_impact/deck.k||||
bar_impact_axi|fe|$built/bar_impact_axi/deck.k||||
stepped_piston|fe|$built/stepped_piston/deck.k||||
EOF
}

if [ "${1:-}" = "--list" ]; then
  table | cut -d'|' -f1,2 | tr '|' ' '
  exit 0
fi
scene=${1:-one_dof}
[ $# -gt 0 ] && shift
out=$root/out/$scene
if [ "${1:-}" = "--out" ]; then out=$2; shift 2; fi
row=$(table | grep "^$scene|" || true)
if [ -z "$row" ]; then
  echo "run_scene: no scene '$scene'; the scenes: $(table | cut -d'|' -f1 | tr '\n' ' ')" >&2
  exit 2
fi
IFS='|' read -r _ kind deck ports model fmu needs <<< "$row"
for f in $deck $ports $model $fmu; do
  [ -f "$f" ] || { echo "run_scene: $f missing: build first (scripts/build.sh)" >&2; exit 2; }
done
[ "$kind" != fe ] || [ $# -eq 0 ] || { echo "run_scene: $scene runs fe_server alone and takes no host options ($*)" >&2; exit 2; }
mkdir -p "$out"
read -r -a need <<< "$needs"

case "$kind" in
  fe)
    (cd "$(dirname "$deck")" && "$build/fe_server/fe_server" --model "$deck" --out "$out/fe_results.h5") \
      | tee "$out/fe_server.log"
    /usr/bin/python3 "$root/scripts/plot_scene.py" "$out/fe_results.h5" - -o "$out/$scene.png" --title "$scene (FE only)"
    ;;
  host)
    "$build/tlm_host/tlm_host" "$model" --out "$out/host_results.h5" "${need[@]}" "$@"
    /usr/bin/python3 "$root/scripts/plot_scene.py" - "$out/host_results.h5" -o "$out/$scene.png" --title "$scene (host only)"
    ;;
  cosim)
    rm -f "$out/port"
    # The token travels in the environment (private to this user), never on a command line.
    PCS_TOKEN=$(od -An -N16 -tx1 /dev/urandom | tr -d ' \n')
    export PCS_TOKEN
    (cd "$(dirname "$deck")" && exec "$build/fe_server/fe_server" --model "$deck" --ports "$ports" \
       --listen 127.0.0.1:0 --port-file "$out/port" --out "$out/fe_results.h5" --accept-timeout 60) \
      > "$out/fe_server.log" 2>&1 &
    server=$!
    trap 'kill $server 2>/dev/null || true' EXIT
    for _ in $(seq 1200); do [ -s "$out/port" ] && break; kill -0 $server 2>/dev/null || break; sleep 0.05; done
    [ -s "$out/port" ] || { cat "$out/fe_server.log" >&2; echo "run_scene: fe_server did not start" >&2; exit 1; }
    rc=0
    "$build/tlm_host/tlm_host" "$model" --fmu "$fmu" --server "127.0.0.1:$(cat "$out/port")" \
      --out "$out/host_results.h5" "${need[@]}" "$@" || rc=$?
    wait $server || { cat "$out/fe_server.log" >&2; echo "run_scene: fe_server failed" >&2; exit 1; }
    trap - EXIT
    cat "$out/fe_server.log"
    [ $rc -eq 0 ] || { echo "run_scene: tlm_host exited $rc" >&2; exit $rc; }
    /usr/bin/python3 "$root/scripts/plot_scene.py" "$out/fe_results.h5" "$out/host_results.h5" -o "$out/$scene.png" \
      --title "$scene (co-simulated)"
    ;;
esac
echo "run_scene: results in $out/ ($(cd "$out" && ls -- *.h5 | tr '\n' ' ')$scene.png)"
