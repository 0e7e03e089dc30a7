#!/usr/bin/env python3
"""Hopsan's own runs of our Hopsan test models against tlm_host's.

Usage: hopsan_cli_compare.py TLM_HOST MODEL.hmf [MODEL.hmf ...]

Runs each model in HopsanCLI ($PCS_HOPSAN_CLI: the hopsancli executable of a
Hopsan built outside this repository; skipped, exit 77, when unset) and in
tlm_host, both logging every step, and compares every column both write
(Hopsan's CSV names, component#port#variable) at every time Hopsan logs.

Tolerance: Hopsan's CSV prints 7 significant digits (%e with 6 decimals), so
its value is within half a unit of the 7th digit, 5e-7 of the value; 1e-6
allows for that rounding twice. Added to it, 1e-12 of the column's largest
value: Hopsan's clock is a running sum of the time step (mTime += dt), which
after n steps differs from ours (n·dt) by about n·1e-16·t; a ramp evaluated
at the two clocks differs by that fraction of its amplitude (8.7e-21 against
0 where a ramp starts), far below 1e-12. A one-step shift in either run
(the error this test is for) differs by 1e-3 to 1 of the value.
"""
import csv
import os
import subprocess
import sys
import tempfile


def read_hopsan_csv(path):
    """Columns by name from a CSV in Hopsan's layout (name, alias, unit lines)."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    names = rows[0]
    data = [[float(x) for x in r] for r in rows[3:] if r]
    return {n: [r[i] for r in data] for i, n in enumerate(names)}


def main():
    hopsan = os.environ.get("PCS_HOPSAN_CLI")
    if not hopsan:
        print("skipped: set PCS_HOPSAN_CLI to HopsanCLI's hopsancli (Hopsan built outside the repository)")
        return 77
    tlm_host, models = sys.argv[1], sys.argv[2:]
    failures = 0
    with tempfile.TemporaryDirectory() as tmp:
        for model in models:
            name = os.path.splitext(os.path.basename(model))[0]
            theirs, ours = os.path.join(tmp, name + "_hopsan.csv"), os.path.join(tmp, name + "_ours.csv")
            # Hopsan logs at most one sample per step; every second step
            # (steps/2 + 1 samples) puts its samples exactly on the steps.
            subprocess.run([tlm_host, model, "--set", "simulation.log_every=1", "--out",
                            os.path.join(tmp, name + ".h5"), "--csv", ours, "--quiet"],
                           check=True, timeout=120, stderr=subprocess.DEVNULL)
            b = read_hopsan_csv(ours)
            steps = len(b["Time"]) - 1
            dt = b["Time"][1] - b["Time"][0]
            run = subprocess.run([hopsan, "-m", model, "-s", "hmf", "-l", str(steps // 2 + 1),
                                  "--resultsFullCSV", theirs, "--resultsCSVSort", "cols"],
                                 capture_output=True, text=True, timeout=120, cwd=tmp)
            if run.returncode != 0 or not os.path.exists(theirs):
                print(f"{name}: hopsancli failed ({run.returncode}):\n{run.stdout}\n{run.stderr}")
                failures += 1
                continue
            a = read_hopsan_csv(theirs)
            common = [n for n in b if n in a and n != "Time"]
            if len(common) < 4:
                print(f"{name}: only {len(common)} columns in common")
                failures += 1
                continue
            worst, where = 0.0, ""
            for n in common:
                scale = max(abs(v) for v in b[n])
                for t, va in zip(a["Time"], a[n]):
                    vb = b[n][round(t / dt)]
                    excess = abs(va - vb) - (1e-6 * max(abs(va), abs(vb)) + 1e-12 * scale)
                    if excess > worst:
                        worst, where = excess, f"{n} at t = {t:g}: Hopsan {va:.7e}, ours {vb:.12e}"
            print(f"{name}: {len(common)} columns x {len(a['Time'])} times compared"
                  + (f"; beyond the tolerance: {where}" if where else ", all within the tolerance"))
            failures += bool(where)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
