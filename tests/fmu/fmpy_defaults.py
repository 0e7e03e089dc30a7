#!/usr/bin/env python3
"""FMPy with its defaults against a live fe_server (issue 18, item 2).

FMPy picks its own communication step (the DefaultExperiment's stepSize,
doubled while more than 1000 steps remain) and stop time; the FMU must run
with both, and with FMPy's command line. FMPy is not a dependency of this
project: the test needs FMPy's source tree outside the repository, named by
$PCS_FMPY_SRC (the folder that holds the `fmpy` package), and lxml and attrs
(Debian: python3-lxml python3-attr). Without them it is reported as skipped
(exit 77). Every wait is bounded; the server listens on an ephemeral
loopback port that the FMU learns from $PCS_SERVER_PORT.

With FMU3, the FMI 3.0 twin of FMU (fmugen --fmi 3): simulate_fmu() runs it
and the 2.0 FMU against one --sessions 2 server, and both give the same
results, bit for bit.

usage: fmpy_defaults.py FE_SERVER SCENE_DIR FMU [FMU3]
"""
import os
import secrets
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "support"))
from fe_server_process import start_fe_server  # noqa: E402
from fmpy_source import fmpy_source  # noqa: E402

SKIP = 77


def start_server(fe_server, scene, d, tag, extra, env):
    """fe_server for the one-DOF scene on an ephemeral loopback port; returns
    the process and the environment that points the FMU at it."""
    return start_fe_server(fe_server, scene / "piston.k", scene / "ports.cfg", d / f"port_{tag}", extra, env)


def main():
    fe_server, scene, fmu = sys.argv[1], Path(sys.argv[2]), sys.argv[3]
    fmu3 = sys.argv[4] if len(sys.argv) > 4 else None
    src = fmpy_source()
    if src is None:
        return SKIP
    env = {**os.environ, "PCS_TOKEN": secrets.token_hex(16), "PYTHONPATH": src}
    failures = []
    with tempfile.TemporaryDirectory() as d:
        d = Path(d)
        # simulate_fmu() and `fmpy simulate` as they come; with stop_time=0.1
        # FMPy doubles its step to 1.6e-4 s (16 coupling steps per fmi2DoStep).
        for name, how in (("simulate_fmu()", "api"), ("fmpy simulate", "cli"),
                          ("simulate_fmu(stop_time=0.1)", "api_long")):
            server, run_env = start_server(fe_server, scene, d, how, ["--out", str(d / f"fe_{how}.h5")], env)
            try:
                if how in ("api", "api_long"):
                    stop = 0.01 if how == "api" else 0.1
                    args = "" if how == "api" else ", stop_time=0.1"
                    code = ("import fmpy, sys\n"
                            f"r = fmpy.simulate_fmu({fmu!r}{args})\n"
                            "print(len(r), r['time'][1] - r['time'][0], r['time'][-1])\n")
                    run = subprocess.run([sys.executable, "-c", code], env=run_env, capture_output=True, text=True,
                                         timeout=120)
                    words = run.stdout.split()
                    ok = run.returncode == 0 and len(words) >= 3 and abs(float(words[-1]) - stop) < 1e-9
                    if ok and how == "api_long":
                        ok = float(words[-2]) > 1.5e-5  # FMPy's step was several coupling steps
                        print(f"  FMPy's step: {float(words[-2]):g} s")
                else:
                    out = d / "out.csv"
                    run = subprocess.run([sys.executable, "-m", "fmpy.cli", "simulate", fmu, "--output-file", str(out)],
                                         env=run_env, capture_output=True, text=True, timeout=120)
                    ok = run.returncode == 0 and out.exists() and len(out.read_text().splitlines()) > 10
                server_code = server.wait(timeout=30)
                if not ok or server_code != 0:
                    failures.append(f"{name}: FMPy exit {run.returncode}, fe_server exit {server_code}\n"
                                    f"{run.stdout[-2000:]}{run.stderr[-2000:]}\n{server.stdout.read()[-2000:]}")
                else:
                    print(f"{name}: ran to its stop time against fe_server (exit 0)")
            finally:
                if server.poll() is None:
                    server.kill()
        # Two simulate_fmu() calls in one Python process against one server
        # (--sessions 2): the second needs no new server, and gives the first's
        # results exactly (each session starts from the deck's state).
        server, run_env = start_server(fe_server, scene, d, "twice",
                                       ["--out", str(d / "fe_{session}.h5"), "--sessions", "2"], env)
        try:
            code = ("import fmpy, numpy\n"
                    f"a = fmpy.simulate_fmu({fmu!r})\n"
                    f"b = fmpy.simulate_fmu({fmu!r})\n"
                    "print(len(a), len(b), all(numpy.array_equal(a[n], b[n]) for n in a.dtype.names))\n")
            run = subprocess.run([sys.executable, "-c", code], env=run_env, capture_output=True, text=True, timeout=120)
            server_code = server.wait(timeout=30)
            lines = run.stdout.strip().splitlines()
            words = lines[-1].split() if lines else []  # FMPy may print its own lines first
            ok = run.returncode == 0 and len(words) == 3 and words[2] == "True" and int(words[0]) > 10
            if not ok or server_code != 0:
                failures.append(f"two simulate_fmu() on one server: FMPy exit {run.returncode}, fe_server exit "
                                f"{server_code}\n{run.stdout[-2000:]}{run.stderr[-2000:]}\n{server.stdout.read()[-2000:]}")
            else:
                print("two simulate_fmu() in one process, one fe_server (--sessions 2): identical results, exit 0")
        finally:
            if server.poll() is None:
                server.kill()
        if fmu3:
            server, run_env = start_server(fe_server, scene, d, "fmi3",
                                           ["--out", str(d / "fe3_{session}.h5"), "--sessions", "2"], env)
            try:
                code = ("import fmpy, numpy\n"
                        f"a = fmpy.simulate_fmu({fmu3!r})\n"
                        f"b = fmpy.simulate_fmu({fmu!r})\n"
                        "print(fmpy.read_model_description("
                        f"{fmu3!r}).fmiVersion, len(a), len(b), a.dtype.names == b.dtype.names and "
                        "all(numpy.array_equal(a[n], b[n]) for n in a.dtype.names))\n")
                run = subprocess.run([sys.executable, "-c", code], env=run_env, capture_output=True, text=True,
                                     timeout=120)
                server_code = server.wait(timeout=30)
                lines = run.stdout.strip().splitlines()
                words = lines[-1].split() if lines else []
                ok = run.returncode == 0 and len(words) == 4 and words[0] == "3.0" and words[3] == "True" \
                    and int(words[1]) > 10
                if not ok or server_code != 0:
                    failures.append(f"the FMI 3.0 FMU in FMPy: exit {run.returncode}, fe_server exit {server_code}\n"
                                    f"{run.stdout[-2000:]}{run.stderr[-2000:]}\n{server.stdout.read()[-2000:]}")
                else:
                    print(f"the FMI 3.0 FMU in FMPy: {words[1]} rows, the same bits as the FMI 2.0 FMU's")
            finally:
                if server.poll() is None:
                    server.kill()
    for f in failures:
        print("FAILED " + f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
