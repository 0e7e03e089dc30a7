#!/usr/bin/env bash
# The monolithic hammer in its four running conditions (150/100 bar ×
# restrictor Ø6.0/5.4 mm): results, per-condition reports and a table in
# out/hammer_monolithic/report.md. Extra arguments go to every tlm_host run
# (e.g. --set simulation.stoptime=1.0).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${PCS_BUILD_DIR:-$root/build}
out=$root/out/hammer_monolithic
mkdir -p "$out"
declare -A area=([6.0]=2.827e-5 [5.4]=2.290e-5)
for p in 150 100; do
  for d in 6.0 5.4; do
    tag="${p}bar_${d}mm"
    echo "== $tag"
    "$build/tlm_host/tlm_host" "$root/scenes/hammer_monolithic/model.tlm" --quiet \
      --set relief.p_crack=${p}e5 --set restrictor.A=${area[$d]} \
      --out "$out/$tag.h5" --report "$out/$tag.txt" "$@" > /dev/null
  done
done
/usr/bin/python3 - "$out" <<'PY'
import pathlib, re, sys
out = pathlib.Path(sys.argv[1])
rows = []
for f in sorted(out.glob("*bar_*mm.txt"), key=lambda p: (-int(p.stem.split("bar")[0]), -float(p.stem.split("_")[1][:-2]))):
    vals = {}
    for line in f.read_text().splitlines():
        m = re.match(r"\s+(.+?)\s{2,}([-\d.]+)", line)
        if m:
            vals[m.group(1).strip()] = m.group(2)
    rows.append((f.stem, vals))
keys = ["impact frequency", "impact velocity", "stroke", "inlet flow", "inlet pressure", "blow energy W",
        "input power p*Q", "output power W*f", "peak p_A", "peak p_B", "peak p_control"]
units = ["Hz", "m/s", "mm", "l/min", "bar abs", "J", "kW", "kW", "bar abs", "bar abs", "bar abs"]
lines = ["| condition | " + " | ".join(f"{k} [{u}]" for k, u in zip(keys, units)) + " |",
         "|---" * (len(keys) + 1) + "|"]
for name, v in rows:
    lines.append(f"| {name} | " + " | ".join(v.get(k, "?") for k in keys) + " |")
(out / "report.md").write_text("# Monolithic hammer, four running conditions\n\n" + "\n".join(lines) + "\n")
print("\n".join(lines))
PY
for f in "$out"/*bar_*mm.h5; do /usr/bin/python3 "$root/scripts/plot_hammer.py" "$f" -o "${f%.h5}.png" > /dev/null; done
echo "run_hammer_conditions: results, plots and report.md in $out"
