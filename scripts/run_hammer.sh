#!/usr/bin/env bash
# The main job: the hydraulic hammer co-simulated (piston, spool, tool and
# rock in fe_server on loopback; the hydraulics in tlm_host) in its running
# conditions and coupling modes, beside the monolithic reference; then the
# report (report.md, Table 3 quantities, time shift per mode) and plots.
#
#   scripts/run_hammer.sh [--modes "pressure tlm tlm10"]
#                         [--conditions "150:6.0 150:5.4 100:6.0 100:5.4"]
#                         [--stop 0.6] [--out out/hammer]
#
# Modes: pressure (the thesis' scheme, coupling step 1 us), tlm (TLM
# coupling, 1 us), tlm10 (TLM coupling every 10 us, 10 FE steps each),
# pressure10 (pressure coupling every 10 us, 10 FE steps each: what
# sub-cycling costs in pressure mode; not in the default set).
# Conditions: supply relief setting in bar, restrictor diameter in mm.
# Each run gets its own fe_server with a fresh token on an ephemeral port.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${PCS_BUILD_DIR:-$root/build}
modes="pressure tlm tlm10"
conditions="150:6.0 150:5.4 100:6.0 100:5.4"
stop=0.6
out=$root/out/hammer
while [ $# -gt 0 ]; do
  case "$1" in
    --modes) modes=$2; shift 2 ;;
    --conditions) conditions=$2; shift 2 ;;
    --stop) stop=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    *) echo "run_hammer.sh: unknown argument '$1' (see the header of $0)" >&2; exit 2 ;;
  esac
done
scene=$build/scenes/hammer
for f in deck.k hammer.fmu; do
  [ -f "$scene/$f" ] || { echo "run_hammer.sh: $scene/$f missing: build first (scripts/build.sh)" >&2; exit 2; }
done
mkdir -p "$out"
server=
trap '[ -n "$server" ] && kill $server 2>/dev/null || true' EXIT

run_mode() {  # condition directory, mode, common --set arguments...
  local dir=$1 mode=$2; shift 2
  local ports fmu host_step=()
  case "$mode" in
    pressure) ports=ports.cfg; fmu=hammer.fmu ;;
    tlm) ports=ports_tlm.cfg; fmu=hammer_tlm.fmu ;;
    tlm10) ports=ports_tlm10.cfg; fmu=hammer_tlm10.fmu
           host_step=(--set simulation.timestep=1e-5 --set simulation.log_every=1) ;;
    pressure10) ports=ports_pressure10.cfg; fmu=hammer_p10.fmu
           host_step=(--set simulation.timestep=1e-5 --set simulation.log_every=1) ;;
    *) echo "run_hammer.sh: mode '$mode': expected pressure, tlm, tlm10 or pressure10" >&2; exit 2 ;;
  esac
  local run=$dir/$mode
  mkdir -p "$run"
  rm -f "$run/port"
  # The token travels in the environment (private to this user), never on a
  # command line; both sides read $PCS_TOKEN.
  local PCS_TOKEN
  PCS_TOKEN=$(od -An -N16 -tx1 /dev/urandom | tr -d ' \n')
  export PCS_TOKEN
  (cd "$scene" && exec "$build/fe_server/fe_server" --model deck.k --ports "$root/scenes/hammer/$ports" \
     --listen 127.0.0.1:0 --port-file "$run/port" --out "$run/fe.h5" --accept-timeout 60 --quiet) \
     > "$run/fe_server.log" 2>&1 &
  server=$!
  for _ in $(seq 400); do [ -s "$run/port" ] && break; sleep 0.05; done
  [ -s "$run/port" ] || { cat "$run/fe_server.log" >&2; exit 1; }
  local start wall
  start=$(date +%s.%N)
  "$build/tlm_host/tlm_host" "$root/scenes/hammer/model.tlm" --fmu "$scene/$fmu" \
    --server "127.0.0.1:$(cat "$run/port")" "$@" "${host_step[@]}" \
    --out "$run/host.h5" --report "$run/host.json" > "$run/tlm_host.log"
  wall=$(echo "$(date +%s.%N) - $start" | bc)
  wait $server || { echo "fe_server failed, see $run/fe_server.log" >&2; exit 1; }
  server=
  echo "$wall" > "$run/wall_seconds"
  printf '   %-8s %6.1f s wall (%.1f s per simulated second)\n' "$mode" "$wall" "$(echo "$wall / $stop" | bc -l)"
}

declare -A area=([6.0]=2.827e-5 [5.4]=2.290e-5)
for c in $conditions; do
  p=${c%%:*}; d=${c##*:}
  [ -n "${area[$d]:-}" ] || { echo "run_hammer.sh: restrictor '$d': 6.0 or 5.4 mm" >&2; exit 2; }
  dir=$out/${p}bar_${d}mm
  mkdir -p "$dir"
  echo "== $p bar, restrictor $d mm"
  set_args=(--set relief.p_crack=${p}e5 --set restrictor.A=${area[$d]} --set simulation.stoptime=$stop)
  "$build/tlm_host/tlm_host" "$root/scenes/hammer_monolithic/model.tlm" --quiet "${set_args[@]}" \
    --out "$dir/reference.h5" --report "$dir/reference.json" > /dev/null
  for m in $modes; do run_mode "$dir" "$m" "${set_args[@]}"; done
done
/usr/bin/python3 "$root/scripts/hammer_report.py" "$out"
