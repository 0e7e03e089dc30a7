#!/usr/bin/python3
"""scripts/compare_measurement.py against measurements we made ourselves.

1. The monolithic hammer's own signals, cut at a known time, in mm and bar,
   sampled every other step, with seeded noise of 0.3 % of each range: the
   comparison must find the cut within one sample and put every peak within
   1.5 % of 100 % (noise of 0.3 % moves a peak by about three times its
   sigma at most over the window's ~7500 samples; the low-pass takes most).
2. A perturbed model (relief 140 bar) against the 150 bar run: its
   frequency ratio must match the ratio of tlm_host's own reports (C++, over
   whole blows) within 2 %: the Python count spans only ~3 cycles of the
   measurement window, so one sample in a ~120 ms span plus cycle-to-cycle
   spread bound it.
3. The four running conditions against the thesis' Table 2 flows: each % is
   100 x the report's flow / the table's, to the table's rounding.
4. A measurement with a NaN is refused, naming file and line; one whose
   alignment signal is flat is refused (any offset would be a guess).
Usage: compare_measurement_test.py TLM_HOST WORKDIR
"""
import json
import os
import pathlib
import subprocess
import sys

import h5py
import numpy as np

root = pathlib.Path(__file__).resolve().parents[2]
tlm_host, work = sys.argv[1], pathlib.Path(sys.argv[2])
work.mkdir(parents=True, exist_ok=True)
model = root / "scenes/hammer_monolithic/model.tlm"
script = [sys.executable, str(root / "scripts/compare_measurement.py")]
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def run_host(tag, *sets):
    out, rep = work / f"{tag}.h5", work / f"{tag}.json"
    cmd = [tlm_host, str(model), "--quiet", "--out", str(out), "--report", str(rep)]
    for s in sets:
        cmd += ["--set", s]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, timeout=120)
    return out, json.loads(rep.read_text())


def write_measurement(h5, path, t0, t1, noise, every=2):
    with h5py.File(h5, "r") as f:
        t = f["time"][:]
        sel = np.nonzero((t >= t0) & (t < t1))[0][::every]
        cols = {"piston_x [mm]": f["components/piston/x"][:][sel] * 1e3,
                "p_A [bar]": f["nodes/cavA.P2/p"][:][sel] / 1e5,
                "p_B [bar]": f["nodes/cavB.P2/p"][:][sel] / 1e5}
    rng = np.random.default_rng(7)
    with open(path, "w") as out:
        out.write("time [s], " + ", ".join(cols) + "\n")
        noisy = {k: v + noise * (v.max() - v.min()) * rng.standard_normal(len(v)) for k, v in cols.items()}
        for i, ti in enumerate(t[sel] - t[sel][0]):
            out.write(f"{ti:.9g}, " + ", ".join(f"{noisy[k][i]:.9g}" for k in cols) + "\n")
    return t[sel][0], t[sel][1] - t[sel][0]


base_h5, base_rep = run_host("base")
t_cut, dt = write_measurement(base_h5, work / "self.csv", 0.40, 0.55, 0.003)
r = subprocess.run(script + ["signals", str(base_h5), str(work / "self.csv"), "--json", str(work / "self.json"),
                             "--plot", str(work / "self.png")], capture_output=True, text=True)
check(r.returncode == 0, f"signals runs ({r.stderr.strip()})")
res = json.loads((work / "self.json").read_text())
check(abs(res["offset_s"] - t_cut) <= dt * 1.01, f"offset {res['offset_s']:.6f} s against the cut {t_cut:.6f} s (one sample {dt:g} s)")
for s in res["signals"]:
    check(abs(s["peak_pct"] - 100.0) < 1.5, f"{s['signal']}: peak {s['peak_pct']:.2f} % of itself")
    check(s["correlation"] > 0.99, f"{s['signal']}: correlation {s['correlation']:.4f}")
check(os.path.getsize(work / "self.png") > 10000, "the overlay plot is written")

low_h5, low_rep = run_host("p140", "relief.p_crack=140e5")
r = subprocess.run(script + ["signals", str(low_h5), str(work / "self.csv"), "--json", str(work / "p140.json")],
                   capture_output=True, text=True)
check(r.returncode == 0, f"signals on the perturbed model runs ({r.stderr.strip()})")
res = json.loads((work / "p140.json").read_text())
want = 100.0 * low_rep["frequency_Hz"] / base_rep["frequency_Hz"]
check(abs(res["frequency_pct"] - want) < 2.0, f"frequency {res['frequency_pct']:.2f} % against the reports' {want:.2f} %")
check(res["frequency_pct"] < 99.0, "the lower pressure shows as a lower frequency")

areas = {"6.0": "2.827e-5", "5.4": "2.290e-5"}
reports = {}
for case, p, d in (("c11", "150e5", "6.0"), ("c12", "150e5", "5.4"), ("c21", "100e5", "6.0"), ("c22", "100e5", "5.4")):
    _, rep = run_host(case, f"relief.p_crack={p}", f"restrictor.A={areas[d]}")
    reports[case] = rep
table2 = root / "scenes/hammer_monolithic/thesis_table2.csv"
r = subprocess.run(script + ["figures", str(table2)] + [f"{c}={work / (c + '.json')}" for c in reports] +
                   ["--json", str(work / "table3.json")], capture_output=True, text=True)
check(r.returncode == 0, f"figures runs ({r.stderr.strip()})")
t3 = json.loads((work / "table3.json").read_text())
for case, meas in (("c11", 80), ("c12", 66), ("c21", 59), ("c22", 50)):
    want = 100.0 * reports[case]["inlet_flow_m3_s"] * 6e4 / meas
    check(abs(t3[case]["q_in"] - want) < 1e-6, f"{case}: q_in {t3[case]['q_in']:.2f} % of Table 2")
print(r.stdout)

bad = work / "bad.csv"
bad.write_text("time [s], p_A [bar]\n" + "".join(f"{i * 1e-5}, {'nan' if i == 5 else 100}\n" for i in range(40)))
r = subprocess.run(script + ["signals", str(base_h5), str(bad)], capture_output=True, text=True)
check(r.returncode == 2 and f"{bad}:7 column 2" in r.stderr, f"a NaN is refused with its line: {r.stderr.strip()}")

flat = work / "flat.csv"
flat.write_text("time [s], p_B [bar]\n" + "".join(f"{i * 2e-5}, 150\n" for i in range(400)))
r = subprocess.run(script + ["signals", str(base_h5), str(flat)], capture_output=True, text=True)
check(r.returncode == 2 and "is constant over the measurement" in r.stderr, f"a flat alignment signal is refused: {r.stderr.strip()}")

sys.exit(1 if failures else 0)
