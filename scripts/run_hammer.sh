#!/usr/bin/env bash
# The main job: the hydraulic hammer co-simulated (the bodies in fe_server on
# loopback, the hydraulics in tlm_host) in its running conditions, beside the
# monolithic reference; then the report (report.md, Table 3 quantities, the
# physics checks, the power plot) and plots.
#
#   scripts/run_hammer.sh [--scene rig|elastic|rigid] [--modes "tlm10 ..."]
#                         [--conditions "150:6.0 150:5.4 100:6.0 100:5.4"]
#                         [--stop S] [--jobs N] [--out out/hammer]
#                         [--deck FILE] [--ports FILE]
#
# Scenes: rig (default; scenes/hammer_rig: the hammer reworked against the
# thesis' rig, its flow following the restrictor and the pressure as
# measured; piston, tool, housing and anvil elastic axisymmetric bodies, the
# spool rigid; TLM coupling every 10 us, 40 FE steps each: mode tlm10 only;
# the reference is scenes/hammer_rig/model.tlm, each condition's relief
# setting from scenes/hammer_rig/conditions.csv), elastic
# (scenes/hammer_elastic: the same bodies in the first layout, whose flow
# hardly follows the restrictor; 36 FE steps per coupling step) or rigid
# (scenes/hammer: rigid piston and spool, 1D-bar tool; modes pressure, tlm,
# tlm10, pressure10, default "pressure tlm tlm10").
# Modes (rigid scene): pressure (the thesis' scheme, coupling step 1 us),
# tlm (TLM coupling, 1 us), tlm10 (TLM coupling every 10 us, 10 FE steps
# each), pressure10 (pressure coupling every 10 us, 10 FE steps each: what
# sub-cycling costs in pressure mode).
# Conditions: supply relief setting in bar, restrictor diameter in mm.
# Stop: simulated seconds per run (rig: default 1.6, start-up to 0.3 s, then
# at least 20 whole cycles at the slowest condition's 16.8 Hz; elastic and
# rigid: default 0.6, 6 blows after 0.3 s at 20.3 Hz).
# Jobs: conditions run side by side (default 2: each co-simulation's
# fe_server computes on one core while its tlm_host waits on the socket).
# Each run gets its own fe_server with a fresh token on an ephemeral port.
# While they run: every 30 s (PCS_PROGRESS_SECONDS) each running condition's
# progress line, prefixed with its name, and the job's time left.
# Deck: a variant of the scene's deck (a study: damping, mesh, contact
# settings), relative to the built scene's directory (build/scenes/<scene>,
# where the meshes it includes are) or absolute; default deck.k.
# Ports: a variant of the scene's port table (rig and elastic scenes: a
# study of the coupling step or the FE steps per coupling step, which the
# deck's mass scaling must then follow); the FMU is generated from it into
# the output folder. Relative to the current directory or absolute.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${PCS_BUILD_DIR:-$root/build}
scene_name=rig
modes=
conditions="150:6.0 150:5.4 100:6.0 100:5.4"
stop=
jobs=2
out=$root/out/hammer
deck=deck.k
ports_variant=
while [ $# -gt 0 ]; do
  case "$1" in
    --scene) scene_name=$2; shift 2 ;;
    --modes) modes=$2; shift 2 ;;
    --conditions) conditions=$2; shift 2 ;;
    --stop) stop=$2; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --deck) deck=$2; shift 2 ;;
    --ports) ports_variant=$2; shift 2 ;;
    *) echo "run_hammer.sh: unknown argument '$1' (see the header of $0)" >&2; exit 2 ;;
  esac
done
case "$scene_name" in
  rig) scene_dir=hammer_rig; modes=${modes:-tlm10}; stop=${stop:-1.6}
       # The reference's rows every 20 us, of what the report and plots
       # read (tlm_host --log, the *REPORT's series always): 6 MB per
       # simulated second instead of 58 (model_elastic.tlm's *LOG does the
       # same for the co-simulation's host)
       ref_log=(--set simulation.log_every=20 --log components/piston,components/spool,nodes/nodeT.P1/p,nodes/cavA.P2/p)
       host_model=$root/scenes/hammer_rig/model_elastic.tlm ref_model=$root/scenes/hammer_rig/model.tlm ;;
  elastic) scene_dir=hammer_elastic; modes=${modes:-tlm10}; stop=${stop:-0.6}
           ref_log=(--set simulation.log_every=20)  # the reference's rows every 20 us too
           host_model=$root/scenes/hammer_elastic/model.tlm ref_model=$root/scenes/hammer_monolithic/model.tlm ;;
  rigid) scene_dir=hammer; modes=${modes:-"pressure tlm tlm10"}; stop=${stop:-0.6}; ref_log=()
         host_model=$root/scenes/hammer/model.tlm ref_model=$root/scenes/hammer_monolithic/model.tlm ;;
  *) echo "run_hammer.sh: --scene '$scene_name': expected rig, elastic or rigid" >&2; exit 2 ;;
esac
[[ "$jobs" =~ ^[1-9][0-9]*$ ]] || { echo "run_hammer.sh: --jobs '$jobs': a positive integer" >&2; exit 2; }
every=${PCS_PROGRESS_SECONDS:-30}
[[ "$every" =~ ^[1-9][0-9]*$ ]] || { echo "run_hammer.sh: PCS_PROGRESS_SECONDS '$every': a positive whole number of seconds" >&2; exit 2; }
scene=$build/scenes/$scene_dir
[ -f "$scene/deck.k" ] || { echo "run_hammer.sh: $scene/deck.k missing: build first (scripts/build.sh)" >&2; exit 2; }
(cd "$scene" && [ -f "$deck" ]) || { echo "run_hammer.sh: --deck '$deck': no such file in $scene" >&2; exit 2; }
mkdir -p "$out"
variant_fmu=
if [ -n "$ports_variant" ]; then
  [ "$scene_name" != rigid ] || { echo "run_hammer.sh: --ports: the rigid scene has a port table per mode" >&2; exit 2; }
  [ -f "$ports_variant" ] || { echo "run_hammer.sh: --ports '$ports_variant': no such file" >&2; exit 2; }
  ports_variant=$(cd "$(dirname "$ports_variant")" && pwd)/$(basename "$ports_variant")
  variant_fmu=$(cd "$out" && pwd)/variant.fmu
  "$build/fmugen/fmugen" "$ports_variant" -o "$variant_fmu" --no-win64 > "$out/fmugen.log" 2>&1 ||
    { cat "$out/fmugen.log" >&2; echo "run_hammer.sh: --ports '$ports_variant': fmugen refused it" >&2; exit 2; }
fi

run_mode() {  # condition directory, mode, common --set arguments...
  local dir=$1 mode=$2; shift 2
  local ports fmu host_step=()
  if [ "$scene_name" != rigid ]; then
    [ "$mode" = tlm10 ] || { echo "run_hammer.sh: mode '$mode': the $scene_name scene runs tlm10 (TLM, 10 us)" >&2; return 2; }
    ports=$root/scenes/$scene_dir/ports.cfg; fmu=$scene/$scene_dir.fmu
    [ -z "$ports_variant" ] || { ports=$ports_variant; fmu=$variant_fmu; }
    # A row every 20 us (the impact velocity is read from the row before
    # contact: 0.02 m/s at most), keeping the whole job under 0.5 GB.
    host_step=(--set simulation.timestep=1e-5 --set simulation.log_every=2)
  else
    case "$mode" in
      pressure) ports=ports.cfg; fmu=$scene/hammer.fmu ;;
      tlm) ports=ports_tlm.cfg; fmu=$scene/hammer_tlm.fmu ;;
      tlm10) ports=ports_tlm10.cfg; fmu=$scene/hammer_tlm10.fmu
             host_step=(--set simulation.timestep=1e-5 --set simulation.log_every=1) ;;
      pressure10) ports=ports_pressure10.cfg; fmu=$scene/hammer_p10.fmu
             host_step=(--set simulation.timestep=1e-5 --set simulation.log_every=1) ;;
      *) echo "run_hammer.sh: mode '$mode': expected pressure, tlm, tlm10 or pressure10" >&2; return 2 ;;
    esac
    ports=$root/scenes/hammer/$ports
  fi
  local run=$dir/$mode
  mkdir -p "$run"
  rm -f "$run/port"
  # The token travels in the environment (private to this user), never on a
  # command line; both sides read $PCS_TOKEN.
  local PCS_TOKEN
  PCS_TOKEN=$(od -An -N16 -tx1 /dev/urandom | tr -d ' \n')
  export PCS_TOKEN
  (cd "$scene" && exec "$build/fe_server/fe_server" --model "$deck" --ports "$ports" \
     --listen 127.0.0.1:0 --port-file "$run/port" --out "$run/fe.h5" --accept-timeout 60) \
     > "$run/fe_server.log" 2>&1 &
  local server=$!
  trap "kill $server 2>/dev/null || true" EXIT
  for _ in $(seq 400); do [ -s "$run/port" ] && break; sleep 0.05; done
  [ -s "$run/port" ] || { cat "$run/fe_server.log" >&2; return 1; }
  local start wall
  start=$(date +%s.%N)
  "$build/tlm_host/tlm_host" "$host_model" --fmu "$fmu" \
    --server "127.0.0.1:$(cat "$run/port")" "$@" "${host_step[@]}" \
    --out "$run/host.h5" --report "$run/host.json" > "$run/tlm_host.log"
  wall=$(echo "$(date +%s.%N) - $start" | bc)
  wait $server || { echo "fe_server failed, see $run/fe_server.log" >&2; return 1; }
  trap - EXIT
  echo "$wall" > "$run/wall_seconds"
  printf '   %-8s %6.1f s wall (%.1f s per simulated second)\n' "$mode" "$wall" "$(echo "$wall / $stop" | bc -l)"
}

run_condition() {  # p:d
  local c=$1 p d dir
  p=${c%%:*}; d=${c##*:}
  dir=$out/${p}bar_${d}mm
  mkdir -p "$dir"
  echo "== $p bar, restrictor $d mm"
  local set_args=(--set relief.p_crack=${p_crack[$c]:-${p}e5} --set restrictor.A=${area[$d]} --set simulation.stoptime=$stop)
  "$build/tlm_host/tlm_host" "$ref_model" --quiet "${set_args[@]}" "${ref_log[@]}" \
    --out "$dir/reference.h5" --report "$dir/reference.json" > /dev/null
  for m in $modes; do run_mode "$dir" "$m" "${set_args[@]}"; done
}

declare -A area=([6.0]=2.827e-5 [5.4]=2.290e-5)
# The rig scene's relief settings, calibrated per condition (the other
# scenes crack at the operating pressure itself).
declare -A p_crack=()
if [ "$scene_name" = rig ]; then
  while IFS=, read -r _ bar mm pc _; do
    p_crack[$(echo "$bar:$mm" | tr -d ' ')]=$(echo "$pc" | tr -d ' ')
  done < <(grep -v '^#' "$root/scenes/hammer_rig/conditions.csv" | tail -n +2)
fi
for c in $conditions; do
  d=${c##*:}
  [ -n "${area[$d]:-}" ] || { echo "run_hammer.sh: restrictor '$d': 6.0 or 5.4 mm" >&2; exit 2; }
  [[ "${c%%:*}" =~ ^[0-9]+$ ]] || { echo "run_hammer.sh: condition '$c': expected <bar>:<mm>, e.g. 150:6.0" >&2; exit 2; }
  [ "$scene_name" != rig ] || [ -n "${p_crack[$c]:-}" ] ||
    { echo "run_hammer.sh: condition '$c': scenes/hammer_rig/conditions.csv has no relief setting for it (150 or 100 bar, 6.0 or 5.4 mm)" >&2; exit 2; }
done
echo "run_hammer.sh: $scene_name scene, modes: $modes, stop $stop s, conditions: $conditions ($jobs at a time)"
t0=$(date +%s.%N)
pids=() logs=() failed=0
# Ctrl-C: each run's fe_server and tlm_host stop (the host tells the server).
trap 'for p in "${pids[@]}"; do pkill -TERM -P "$p"; kill "$p"; done 2>/dev/null; exit 130' INT TERM
# Progress while the runs go on: every $PCS_PROGRESS_SECONDS (default 30) s,
# each running condition's last progress line with its name in front, and
# (one mode per condition) the whole job's time left: the running runs'
# own estimates and, for each condition still queued, one run's whole
# length (elapsed + left of a running one), shared by the job slots, and
# never less than the longest running run's own time left.
n_conditions=$(echo $conditions | wc -w)
last_tick=$(date +%s)
progress() {
  local now; now=$(date +%s)
  [ $((now - last_tick)) -ge "$every" ] || return 0
  last_tick=$now
  local i line est sum=0 whole=0 longest=0 alive=0 estimated=0
  for i in "${!pids[@]}"; do
    kill -0 "${pids[$i]}" 2>/dev/null || continue
    alive=$((alive + 1))
    line=$(grep -a '^t = ' "${logs[$i]}" | tail -n 1 || true)
    [ -n "$line" ] || line="starting (the reference run, then fe_server's preload)"
    echo "  [$(basename "${logs[$i]}" .log | sed 's/^run_//')] $line"
    est=$(echo "$line" | sed -n 's/.*, \([0-9.]*\) s elapsed, about \([0-9.]*\) s left.*/\1 \2/p')
    if [ -n "$est" ]; then
      estimated=$((estimated + 1))
      sum=$(echo "$sum + ${est#* }" | bc -l)
      longest=$(echo "if (${est#* } > $longest) ${est#* } else $longest" | bc -l)
      whole=$(echo "${est% *} + ${est#* }" | bc -l)
    fi
  done
  local queued=$((n_conditions - ${#pids[@]}))
  if [ "$(echo $modes | wc -w)" -eq 1 ] && [ "$estimated" -gt 0 ]; then
    printf 'run_hammer.sh: %d of %d conditions done, %d running, %d queued; about %.0f s left (then the impact run%s and the report)\n' \
      "$(( ${#pids[@]} - alive ))" "$n_conditions" "$alive" "$queued" \
      "$(echo "t = ($sum + ($queued + $alive - $estimated) * $whole) / $jobs; if ($longest > t) $longest else t" | bc -l)" \
      "$([ "$scene_name" = rig ] && echo ", the restrictor sweep" || true)"
  fi
}
for c in $conditions; do
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do sleep 1; progress; done
  log=$out/run_${c/:/bar_}mm.log
  ( run_condition "$c" ) > "$log" 2>&1 &
  pids+=($!); logs+=("$log")
done
while [ "$(jobs -rp | wc -l)" -gt 0 ]; do sleep 1; progress; done
for i in "${!pids[@]}"; do
  wait "${pids[$i]}" || failed=1
  cat "${logs[$i]}"
done
[ $failed -eq 0 ] || { echo "run_hammer.sh: a run failed (see the logs above and under $out)" >&2; exit 1; }
# The picture of the stress field at impact (elastic scene): the blow alone
# (impact.k: piston, tool, anvil) at the impact velocity the first
# condition's co-simulation measured, field snapshots every 20 us.
if [ "$scene_name" != rigid ]; then
  first=$out/$(echo "$conditions" | awk '{print $1}' | sed 's/:/bar_/')mm
  v=$(/usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['impact_velocity_m_s'])" \
      "$first/${modes%% *}/host.json")
  mkdir -p "$out/impact"
  cp "$scene"/{piston,tool,anvil}_mesh.k "$out/impact/"
  sed "s/^1,2,0,0,-8.0,0$/1,2,0,0,-$v,0/" "$scene/impact.k" > "$out/impact/impact.k"
  grep -q "^1,2,0,0,-$v,0$" "$out/impact/impact.k" || { echo "run_hammer.sh: impact.k has no velocity card to set" >&2; exit 1; }
  (cd "$out/impact" && "$build/fe_server/fe_server" --model impact.k --out impact.h5 --quiet) \
    || { echo "run_hammer.sh: the impact run failed" >&2; exit 1; }
  echo "run_hammer.sh: the blow alone at $v m/s: $out/impact/impact_fields.xdmf (ParaView)"
fi
# The thesis' Fig. 16 as a sweep (rig scene): seven restrictor diameters at
# 100 and 150 bar on the monolithic model (scripts/sweep.py fig16, 14 runs
# of 1.2 s, about a minute on 2 cores), which the report shows beside the
# four co-simulated conditions.
if [ "$scene_name" = rig ]; then
  rm -rf "$out/fig16"
  echo "run_hammer.sh: the restrictor sweep (thesis Fig. 16) on the monolithic model, $jobs at a time"
  /usr/bin/python3 "$root/scripts/sweep.py" fig16 --out "$out/fig16" --model "$ref_model" \
    --host "$build/tlm_host/tlm_host" --jobs "$jobs" > "$out/fig16.log" 2>&1 ||
    { cat "$out/fig16.log" >&2; echo "run_hammer.sh: the restrictor sweep failed (see $out/fig16.log)" >&2; exit 1; }
fi
printf 'run_hammer.sh: all runs in %.0f s wall; results %s\n' "$(echo "$(date +%s.%N) - $t0" | bc)" "$(du -sh "$out" | cut -f1)"
for c in $conditions; do
  d=$out/${c%%:*}bar_${c##*:}mm
  printf 'run_hammer.sh: %s wrote %.1f MB per simulated second\n' "$(basename "$d")" \
    "$(echo "$(du -sb "$d" | cut -f1) / $stop / 1000000" | bc -l)"
done
/usr/bin/python3 "$root/scripts/hammer_report.py" "$out" --scene "$scene_dir"
