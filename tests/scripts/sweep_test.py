#!/usr/bin/python3
"""scripts/sweep.py: the local runner and the SLURM job array give the same
sweep, a failing point is reported without losing the others, and fig16
sweeps what it says.

1. A 2 x 2 grid (pressure x restrictor area, 0.45 s runs) on every core, and
   the same grid through the job script `sweep.py slurm` writes, run here
   task by task with SLURM_ARRAY_TASK_ID set as SLURM would: the two
   sweep.csv files must be identical (the runs are deterministic).
2. A grid with one area of -1 (tlm_host refuses it): exit 4, the refusal is
   named, the valid point's report is kept.
3. A task of another grid into a folder that holds a plan is refused: its
   report would be collected under the plan's labels.
4. fig16 over Ø5.4/6.0 at 100/150 bar: its flows are the grid runs' flows
   (the same settings), and Case 11's normalised output power is 1.
Usage: sweep_test.py TLM_HOST WORKDIR
"""
import csv
import json
import os
import pathlib
import shutil
import subprocess
import sys

root = pathlib.Path(__file__).resolve().parents[2]
host, work = sys.argv[1], pathlib.Path(sys.argv[2])
shutil.rmtree(work, ignore_errors=True)
work.mkdir(parents=True)
sweep = [sys.executable, str(root / "scripts/sweep.py")]
model = str(root / "scenes/hammer_monolithic/model.tlm")
grid = ["--grid", "relief.p_crack=100e5,150e5", "--grid", "restrictor.A=2.290e-5,2.827e-5",
        "--set", "simulation.stoptime=0.45"]
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


r = subprocess.run(sweep + ["run", model, "--out", str(work / "local"), "--host", host] + grid, capture_output=True, text=True)
check(r.returncode == 0, f"run exits 0 ({r.stderr.strip()})")
local = list(csv.reader(open(work / "local/sweep.csv")))
check(len(local) == 5 and "inlet_flow_m3_s" in local[0], f"4 points and their figures in sweep.csv: {local[0]}")

r = subprocess.run(sweep + ["slurm", model, "--out", str(work / "array"), "--host", host] + grid, capture_output=True, text=True)
check(r.returncode == 0 and "#SBATCH" in r.stdout and "--array=0-3" in r.stdout, "slurm prints a job array of 4 tasks")
job = work / "job.sh"
job.write_text(r.stdout)
for task in range(4):
    t = subprocess.run(["bash", str(job)], env=dict(os.environ, SLURM_ARRAY_TASK_ID=str(task)), capture_output=True, text=True)
    check(t.returncode == 0, f"task {task} runs ({t.stderr.strip()})")
subprocess.run(sweep + ["collect", str(work / "array")], check=True, capture_output=True)
array = list(csv.reader(open(work / "array/sweep.csv")))
check(array == local, "the job array's sweep.csv is the local runner's, value for value")

r = subprocess.run(sweep + ["point", model, "--out", str(work / "array"), "--host", host, "--index", "0",
                            "--grid", "relief.p_crack=120e5"], capture_output=True, text=True)
check(r.returncode == 2 and "plans another sweep" in r.stderr, f"a task of another sweep into the folder is refused ({r.stderr.strip()})")
r = subprocess.run(sweep + ["run", model, "--out", str(work / "bad"), "--host", host, "--grid", "restrictor.A=-1,2.827e-5",
                            "--set", "simulation.stoptime=0.45"], capture_output=True, text=True)
check(r.returncode == 4 and "restrictor.A=-1" in r.stderr and "exit 3" in r.stderr, f"a refused point: exit 4, named ({r.stderr.strip()})")
check((work / "bad/point_1.json").exists(), "the valid point's report is kept")
r = subprocess.run(sweep + ["run", model, "--out", str(work / "bad2"), "--grid", "restrictor.A=abc"], capture_output=True, text=True)
check(r.returncode == 2 and "'abc' is not a finite number" in r.stderr, f"a bad grid value: exit 2 ({r.stderr.strip()})")

r = subprocess.run(sweep + ["fig16", "--out", str(work / "fig16"), "--host", host, "--model", model, "--diameters", "5.4,6.0",
                            "--set", "simulation.stoptime=0.45"], capture_output=True, text=True)
check(r.returncode == 0 and (work / "fig16/fig16.png").exists(), f"fig16 runs and plots ({r.stderr.strip()})")
rows = [l.split("|")[1:-1] for l in (work / "fig16/fig16.md").read_text().splitlines()[2:]]
flows = {(float(p), float(d)): float(q) for p, d, q, *_ in rows}
for line in local[1:]:
    p, a, q = float(line[1]) / 1e5, float(line[2]), float(line[local[0].index("inlet_flow_m3_s")]) * 6e4
    d = round((4 * a / 3.141592653589793) ** 0.5 * 1e3, 1)
    check(abs(flows[(p, d)] - q) < 0.051 + 0.002 * q, f"fig16 at {p:g} bar, Ø{d:g}: {flows[(p, d)]} l/min, the grid's {q:.2f}")
c11 = [r for r in rows if float(r[0]) == 150 and float(r[1]) == 6.0][0]
check(abs(float(c11[4]) - 1.0) < 1e-9, "Case 11's output power is its own reference")

# fig16 on the rig scene (its default) sets each pressure's relief from the
# calibrated conditions.csv beside the model: the mean of the two settings
# per pressure, read here from the file itself.
sys.path.insert(0, str(root / "scripts"))
import sweep as sweep_module  # noqa: E402
rig = root / "scenes/hammer_rig/model.tlm"
rows = [l.split(",") for l in (rig.parent / "conditions.csv").read_text().splitlines() if l[:1].isdigit()]
want = {p: sum(float(r[3]) for r in rows if float(r[1]) == p) / 2 for p in (150.0, 100.0)}
got = sweep_module.relief_settings(rig, [150.0, 100.0])
check(all(abs(got[p] - want[p]) < 1e-6 * want[p] for p in want) and abs(got[150.0] - 150e5) > 1e4,
      f"the rig's relief settings come from conditions.csv: {got}")
try:
    sweep_module.relief_settings(rig, [120.0])
    check(False, "a pressure without a calibrated setting is refused")
except sweep_module.InputError as e:
    check("no calibrated relief setting for 120 bar" in str(e), f"a pressure without a calibrated setting is refused: {e}")
check(sweep_module.relief_settings(pathlib.Path(model), [150.0]) == {150.0: 150e5},
      "without conditions.csv the relief cracks at the operating pressure")
bad_dir = work / "bad_conditions"
bad_dir.mkdir(exist_ok=True)
(bad_dir / "conditions.csv").write_text("case, bar, mm, relief.p_crack, restrictor.A\n11, 150, 6.0, abc, 2.827e-5\n")
try:
    sweep_module.relief_settings(bad_dir / "model.tlm", [150.0])
    check(False, "a malformed conditions.csv is refused")
except sweep_module.InputError as e:
    check("conditions.csv:2:" in str(e), f"a malformed conditions.csv is refused at its line: {e}")
sys.exit(1 if failures else 0)
