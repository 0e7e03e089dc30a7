#!/usr/bin/env python3
"""Hopsan's own runs of our Hopsan test models against tlm_host's.

Usage: hopsan_cli_compare.py TLM_HOST MODEL.hmf [MODEL.hmf ...]
       hopsan_cli_compare.py --fmu FMU FE_SERVER DECK PORTS TLM_HOST MODEL.hmf

Runs each model in HopsanCLI ($PCS_HOPSAN_CLI: the hopsancli executable of a
Hopsan built outside this repository; skipped, exit 77, when unset) and in
tlm_host, tlm_host logging every step and Hopsan every k-th (at most 10000
samples), and compares every column both write (Hopsan's CSV names,
component#port#variable) at every time Hopsan logs; the two CSV files must
have the same columns in the same order (less Hopsan's Temperature and
HeatFlow, and a subsystem's own port and time columns and a sensor's).

Tolerance: Hopsan's CSV prints 7 significant digits (%e with 6 decimals), so
its value is within half a unit of the 7th digit, 5e-7 of the value; 1e-6
allows for that rounding twice. Added to it, 2e-7 of the column's largest
value, for values near zero where round-off is all that differs: a
turbulent orifice's flow near Δp = 0 is K·√Δp, so a round-off difference of
1e-16 of the pressures (1.5e-9 Pa at 150 bar) makes up to K·√1.5e-9 of flow,
1.8e-7 of the largest flow in the accumulator model (measured: 6e-10 there,
where the runs' linear solves differ, Eigen's LU here and Hopsan's own);
Hopsan's clock, a running sum of the time step, differs from ours (n·dt) by
about n·1e-16·t, far less. A one-step shift in either run (the error this
test is for) differs by 1e-3 to 1 of the value.

With --fmu, the model holds Hopsan's FMIWrapperQ with our FMU (a Hopsan-
convention FMU from fmugen), copied beside the model: fe_server serves two
sessions on an ephemeral loopback port, one for tlm_host (which reads the
wrapper as our FmuQ) and one for Hopsan, each with its own results file.
The same tolerance: both hosts send fe_server the same c and Zc.
"""
import csv
import os
import re
import secrets
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from fe_server_process import start_fe_server  # noqa: E402


def read_hopsan_csv(path):
    """Columns by name from a CSV in Hopsan's layout (name, alias, unit lines)."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    names = rows[0]
    data = [[float(x) for x in r] for r in rows[3:] if r]
    return {n: [r[i] for r in data] for i, n in enumerate(names)}


def compare(hopsan, tlm_host, model, tmp, env):
    """Runs the model in both; prints the comparison; True if within the tolerance."""
    name = os.path.splitext(os.path.basename(model))[0]
    theirs, ours = os.path.join(tmp, name + "_hopsan.csv"), os.path.join(tmp, name + "_ours.csv")
    # Hopsan logs at most one sample per step; N + 1 samples with N dividing
    # the steps (every second step at least, at most 10000 samples) put its
    # samples exactly on the steps.
    subprocess.run([tlm_host, model, "--set", "simulation.log_every=1", "--out", os.path.join(tmp, name + ".h5"),
                    "--csv", ours, "--quiet"], check=True, timeout=120, stderr=subprocess.DEVNULL, env=env)
    b = read_hopsan_csv(ours)
    steps = len(b["Time"]) - 1
    dt = b["Time"][1] - b["Time"][0]
    stride = next(k for k in range(2, steps + 1) if steps % k == 0 and steps // k <= 10000)
    run = subprocess.run([hopsan, "-m", model, "-s", "hmf", "-l", str(steps // stride + 1), "--resultsFullCSV", theirs,
                          "--resultsCSVSort", "cols"], capture_output=True, text=True, timeout=120, cwd=tmp, env=env)
    if run.returncode != 0 or not os.path.exists(theirs):
        print(f"{name}: hopsancli failed ({run.returncode}):\n{run.stdout}\n{run.stderr}")
        return False
    a = read_hopsan_csv(theirs)
    # The same columns in the same order, but for Hopsan's Temperature and
    # HeatFlow (the model here is isothermal) and a subsystem's own ports and
    # time (sub#port#…, sub$Time) and a sensor's (the same values are under
    # the names of the components at those nodes).
    subsystems = {n.split("$")[0] for n in a if "$" in n}
    sensors = set(re.findall(r'typename="Hydraulic\w*Sensor" name="([^"]+)"', open(model).read()))
    expected = [n for n in a if not n.endswith("#Temperature") and not n.endswith("#HeatFlow")
                and n.split("#")[0] not in subsystems | sensors and not n.endswith("$Time")]
    if list(b) != expected:
        print(f"{name}: columns differ from Hopsan's: ours only {[n for n in b if n not in a]}, "
              f"Hopsan's only {[n for n in expected if n not in b]}, same order: "
              f"{[n for n in expected if n in b] == [n for n in b if n in a]}")
        return False
    common = [n for n in b if n in a and n != "Time"]
    if len(common) < 4:
        print(f"{name}: only {len(common)} columns in common")
        return False
    worst, where = 0.0, ""
    for n in common:
        scale = max(abs(v) for v in b[n])
        for t, va in zip(a["Time"], a[n]):
            vb = b[n][round(t / dt)]
            excess = abs(va - vb) - (1e-6 * max(abs(va), abs(vb)) + 2e-7 * scale)
            if excess > worst:
                worst, where = excess, f"{n} at t = {t:g}: Hopsan {va:.7e}, ours {vb:.12e}"
    print(f"{name}: {len(common)} columns x {len(a['Time'])} times compared"
          + (f"; beyond the tolerance: {where}" if where else ", all within the tolerance"))
    return not where


def main():
    hopsan = os.environ.get("PCS_HOPSAN_CLI")
    if not hopsan:
        print("skipped: set PCS_HOPSAN_CLI to HopsanCLI's hopsancli (Hopsan built outside the repository)")
        return 77
    args = sys.argv[1:]
    with tempfile.TemporaryDirectory() as tmp:
        if args[0] == "--fmu":
            fmu, fe_server, deck, ports, tlm_host, model = args[1:7]
            shutil.copy(fmu, tmp)
            shutil.copy(model, tmp)
            # Two sessions: one for tlm_host, one for Hopsan.
            server, env = start_fe_server(fe_server, deck, ports, os.path.join(tmp, "port"),
                                          ["--sessions", "2", "--out", os.path.join(tmp, "fe_{session}.h5")],
                                          {**os.environ, "PCS_TOKEN": secrets.token_hex(16)}, accept_timeout=60)
            try:
                ok = compare(hopsan, tlm_host, os.path.join(tmp, os.path.basename(model)), tmp, env)
                code = server.wait(timeout=60)
                if code != 0:
                    print(f"fe_server exit {code}:\n{server.stdout.read()[-3000:]}")
                    ok = False
            finally:
                if server.poll() is None:
                    server.kill()
            return 0 if ok else 1
        tlm_host, models = args[0], [os.path.abspath(m) for m in args[1:]]
        failures = sum(not compare(hopsan, tlm_host, m, tmp, dict(os.environ)) for m in models)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
