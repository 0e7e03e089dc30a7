#!/usr/bin/env bash
# The hammer co-simulated (piston in fe_server on loopback, the rest in
# tlm_host) for one running condition, beside the monolithic reference:
#   scripts/run_hammer_cosim.sh [pressure|tlm|tlm10] [P_SET_BAR] [RESTRICTOR_MM] [STOPTIME]
# (tlm10: TLM coupling every 10 us with 10 FE steps of 1 us each; the host runs at 10 us too)
# Writes out/hammer_cosim/<mode>_<p>bar_<d>mm/: results, reports, and
# comparison.txt (figures side by side, time shift of the piston lift by
# cross-correlation).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${PCS_BUILD_DIR:-$root/build}
mode=${1:-pressure}; p=${2:-150}; d=${3:-6.0}; stop=${4:-0.6}
case "$d" in 6.0) area=2.827e-5 ;; 5.4) area=2.290e-5 ;; *) echo "restrictor: 6.0 or 5.4 mm" >&2; exit 2 ;; esac
case "$mode" in
  pressure) ports=$root/scenes/hammer_cosim/ports.cfg; fmu=$build/scenes/hammer_cosim/hammer_cosim.fmu ;;
  tlm) ports=$root/scenes/hammer_cosim/ports_tlm.cfg; fmu=$build/scenes/hammer_cosim/hammer_cosim_tlm.fmu ;;
  tlm10) ports=$root/scenes/hammer_cosim/ports_tlm10.cfg; fmu=$build/scenes/hammer_cosim/hammer_cosim_tlm10.fmu ;;
  *) echo "mode: pressure, tlm or tlm10" >&2; exit 2 ;;
esac
out=$root/out/hammer_cosim/${mode}_${p}bar_${d}mm
mkdir -p "$out"
rm -f "$out/port"
token=$(od -An -N16 -tx1 /dev/urandom | tr -d ' \n')
set_args=(--set relief.p_crack=${p}e5 --set restrictor.A=$area --set simulation.stoptime=$stop)
"$build/tlm_host/tlm_host" "$root/scenes/hammer_monolithic/model.tlm" --quiet "${set_args[@]}" \
  --out "$out/reference.h5" --report "$out/reference.txt" > /dev/null
"$build/fe_server/fe_server" --model "$build/scenes/hammer_cosim/deck.k" --ports "$ports" --listen 127.0.0.1:0 \
  --port-file "$out/port" --token "$token" --out "$out/fe.h5" --accept-timeout 60 > "$out/fe_server.log" 2>&1 &
server=$!
trap 'kill $server 2>/dev/null || true' EXIT
for _ in $(seq 200); do [ -s "$out/port" ] && break; sleep 0.05; done
[ -s "$out/port" ] || { cat "$out/fe_server.log" >&2; exit 1; }
start=$(date +%s.%N)
host_step=()
[ "$mode" = tlm10 ] && host_step=(--set simulation.timestep=1e-5 --set simulation.log_every=1)
"$build/tlm_host/tlm_host" "$root/scenes/hammer_cosim/model.tlm" --fmu "$fmu" --server "127.0.0.1:$(cat "$out/port")" \
  --token "$token" "${set_args[@]}" "${host_step[@]}" --out "$out/cosim.h5" --report "$out/cosim.txt"
wall=$(echo "$(date +%s.%N) - $start" | bc)
wait $server; trap - EXIT
/usr/bin/python3 - "$out" "$wall" "$stop" <<'PY'
import sys, h5py, numpy as np
out, wall, stop = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
r, c = h5py.File(f"{out}/reference.h5"), h5py.File(f"{out}/cosim.h5")
t = r["time"][:]; xr = r["components/piston/x"][:]
xc = np.interp(t, c["time"][:], c["components/mech/x"][:])  # the co-simulation may log at another step
# Time shift of the co-simulation against the reference: the lag that
# maximises the cross-correlation of the piston lift after start-up.
s = t > 0.3 * t[-1]
a, b = xr[s] - xr[s].mean(), xc[s] - xc[s].mean()
dt = t[1] - t[0]; lags = np.arange(-200, 201)
cc = [np.dot(a[max(0, -l):len(a) - max(0, l)], b[max(0, l):len(b) - max(0, -l)]) for l in lags]
shift = lags[int(np.argmax(cc))] * dt
lines = ["figures (left: monolithic reference, right: co-simulation)"]
for x, y in zip(open(f"{out}/reference.txt"), open(f"{out}/cosim.txt")):
    lines.append(f"  {x.rstrip():55s} | {y.strip()}")
lines.append(f"time shift of the piston lift: {shift * 1e6:.1f} us (co-simulation later when positive)")
lines.append(f"wall time: {wall:.1f} s for {stop} s simulated ({wall / stop:.1f} s per simulated second)")
open(f"{out}/comparison.txt", "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
PY
