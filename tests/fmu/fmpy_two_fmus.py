#!/usr/bin/env python3
"""FMPy stepping the hammer's two FMUs (piston and valve, one fe_server
session: scenes/hammer/two_fmus/) in one thread, as a sequential master
does, against the same two FMUs stepped on two threads at once.

1. Sequential, in one thread: every step both FMUs' inputs set
   (fmi2SetReal), then the piston's FMU stepped, then the valve's. The
   valve's inputs reach fe_server when they are set, so the piston's step
   runs; the valve's step then finds its result waiting.
2. Parallel: the inputs set the same way, the two fmi2DoStep on two
   threads at once (FMPy releases the GIL in its calls).
   Both runs must give every output of every step bit for bit alike: the
   same FE steps with the same loads in the same order. The outputs must
   move (the spool and the piston under 50 bar waves), or the comparison
   would be of nothing.
3. Set and stepped each in turn (the piston's FMU set and stepped before the
   valve's is set): refused, fe_server exits 6 and says why, within 10 s
   (0.8 of its 2 s step time-out when it deadlocks).

FMPy is not a dependency of this project: the test needs FMPy's source tree
outside the repository, named by $PCS_FMPY_SRC, and lxml and attrs (Debian:
python3-lxml python3-attr); without them it is reported as skipped (77).

usage: fmpy_two_fmus.py FE_SERVER SCENE_DIR BUILT_SCENE_DIR
"""
import os
import secrets
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "support"))
from fe_server_process import start_fe_server  # noqa: E402
from fmpy_source import fmpy_source  # noqa: E402

SKIP = 77
STEPS = 400  # 4 ms at the tables' 10 us coupling step: the spool is moving by then

DRIVER = r'''
import sys, threading
import numpy as np
from fmpy import read_model_description, extract
from fmpy.fmi2 import FMU2Slave

order, out = sys.argv[1], sys.argv[2]
paths, steps = sys.argv[3:5], int(sys.argv[5])
fmus = []
for path in paths:
    md = read_model_description(path)
    f = FMU2Slave(guid=md.guid, unzipDirectory=extract(path), modelIdentifier=md.coSimulation.modelIdentifier,
                  instanceName=md.modelName)
    f.instantiate()
    f.setupExperiment(startTime=0.0)
    f.enterInitializationMode()
    f.exitInitializationMode()
    ins = [v for v in md.modelVariables if v.causality == "input"]
    # 50 bar waves into every chamber with a chamber's impedance, no forces.
    values = [50e5 if v.name.endswith(".c") else 1e11 if v.name.endswith(".Zc") else 0.0 for v in ins]
    outs = [v.valueReference for v in md.modelVariables if v.causality == "output"]
    dt = md.defaultExperiment.stepSize
    fmus.append((f, [v.valueReference for v in ins], values, outs, float(dt)))
rows = []
for k in range(steps):
    t = k * fmus[0][4]
    if order == "one-by-one":
        for f, vr, values, outs, dt in fmus:
            f.setReal(vr, values)
            f.doStep(t, dt)
    else:
        for f, vr, values, outs, dt in fmus:
            f.setReal(vr, values)
        if order == "sequential":
            for f, vr, values, outs, dt in fmus:
                f.doStep(t, dt)
        else:
            th = [threading.Thread(target=f.doStep, args=(t, dt)) for f, vr, values, outs, dt in fmus]
            for x in th: x.start()
            for x in th: x.join()
    rows.append(np.concatenate([np.array(f.getReal(outs)) for f, vr, values, outs, dt in fmus]))
for f, *_ in fmus:
    f.terminate()
    f.freeInstance()
np.save(out, np.array(rows))
'''


def main():
    fe_server, scene, built = sys.argv[1], Path(sys.argv[2]), Path(sys.argv[3])
    src = fmpy_source()
    if src is None:
        return SKIP
    import numpy as np
    env = {**os.environ, "PCS_TOKEN": secrets.token_hex(16), "PYTHONPATH": src}
    fmus = [str(built / "hammer_piston.fmu"), str(built / "hammer_valve.fmu")]
    failures, results = [], {}
    with tempfile.TemporaryDirectory() as d:
        d = Path(d)
        for order in ("sequential", "parallel", "one-by-one"):
            server, run_env = start_fe_server(
                fe_server, built / "deck.k", [scene / "two_fmus/piston.cfg", scene / "two_fmus/valve.cfg"],
                d / f"port_{order}", ["--step-timeout", "2", "--out", d / f"fe_{order}.h5"], env)
            try:
                t0 = time.monotonic()
                run = subprocess.run([sys.executable, "-c", DRIVER, order, str(d / f"{order}.npy")] + fmus +
                                     [str(STEPS)], env=run_env, capture_output=True, text=True, timeout=240)
                waited = time.monotonic() - t0
                code = server.wait(timeout=30)
                log = server.stdout.read()
                if order == "one-by-one":
                    # Told at the valve's first inputs (they differ from its start values, which step 0
                    # ran with), or at the deadlock of a step both met with the same values.
                    told = "sets and steps each FMU in turn"
                    if run.returncode == 0 or code != 6 or told not in log or waited > 10:
                        failures.append(f"set and stepped in turn: FMPy exit {run.returncode} after {waited:.1f} s, "
                                        f"fe_server exit {code}\n{log[-1500:]}")
                    else:
                        print(f"set and stepped in turn: refused after {waited:.1f} s, fe_server exit 6 with the reason")
                elif run.returncode != 0 or code != 0:
                    failures.append(f"{order}: FMPy exit {run.returncode}, fe_server exit {code}\n"
                                    f"{run.stdout[-1500:]}{run.stderr[-1500:]}\n{log[-1500:]}")
                else:
                    results[order] = np.load(d / f"{order}.npy")
                    print(f"{order}: {STEPS} steps of both FMUs in {waited:.1f} s")
            finally:
                if server.poll() is None:
                    server.kill()
    if len(results) == 2:
        a, b = results["sequential"], results["parallel"]
        moved = np.ptp(a, axis=0)
        if a.shape != b.shape or not np.array_equal(a.view(np.uint64), b.view(np.uint64)):
            worst = np.max(np.abs(a - b)) if a.shape == b.shape else float("nan")
            failures.append(f"sequential and parallel differ: shapes {a.shape} {b.shape}, largest difference {worst:g}")
        elif np.count_nonzero(moved) < a.shape[1] // 2:
            failures.append(f"only {np.count_nonzero(moved)} of {a.shape[1]} outputs moved: nothing was compared")
        else:
            print(f"sequential = parallel, bit for bit: {a.shape[0]} steps x {a.shape[1]} outputs "
                  f"({np.count_nonzero(moved)} of them moving)")
    for f in failures:
        print("FAILED " + f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
