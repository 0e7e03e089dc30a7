#!/usr/bin/env python3
"""fmusim (the Modelica Association's Reference-FMUs importer) runs the FMI
2.0 FMU and its FMI 3.0 twin against a live fe_server (issue 38), with the
DefaultExperiment as it comes: both to the stop time (within fmusim's last
step), and the same CSV.

fmusim is not a dependency: build it outside the repository (docs/testing.md
says how, against Debian's libxml2, minizip and SUNDIALS) and name the binary
in $PCS_FMUSIM; without it the test is reported as skipped (exit 77).

usage: fmusim_test.py FE_SERVER SCENE_DIR FMU FMU3
"""
import os
import secrets
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "support"))
from fe_server_process import start_fe_server  # noqa: E402


def main():
    fe_server, scene, fmu2, fmu3 = sys.argv[1], Path(sys.argv[2]), sys.argv[3], sys.argv[4]
    fmusim = os.environ.get("PCS_FMUSIM")
    if not fmusim or not os.access(fmusim, os.X_OK):
        print("skipped: set PCS_FMUSIM to an fmusim binary (Reference-FMUs v0.0.39, built outside the repository)")
        return 77
    env = {**os.environ, "PCS_TOKEN": secrets.token_hex(16)}
    failures = []
    with tempfile.TemporaryDirectory() as d:
        d = Path(d)
        server, run_env = start_fe_server(fe_server, scene / "piston.k", scene / "ports.cfg", d / "port",
                                          ["--out", str(d / "fe_{session}.h5"), "--sessions", "2"], env)
        csv = {}
        try:
            for tag, fmu in (("2.0", fmu2), ("3.0", fmu3)):
                out = d / f"out_{tag}.csv"
                run = subprocess.run([fmusim, "--output-file", str(out), fmu], env=run_env, capture_output=True,
                                     text=True, timeout=120)
                rows = out.read_text().splitlines() if out.exists() else []
                # fmusim sums its steps and stops within one step of the stop
                # time (0.00999 s of 0.01 s here): that is fmusim's, not the FMU's.
                last = float(rows[-1].split(",")[0]) if len(rows) > 1 else -1.0
                if run.returncode != 0 or len(rows) < 1000 or abs(last - 0.01) > 1.01e-5:
                    failures.append(f"FMI {tag}: fmusim exit {run.returncode}, {len(rows)} rows, last "
                                    f"{rows[-1] if rows else '-'}\n{run.stdout[-1500:]}{run.stderr[-1500:]}")
                csv[tag] = rows
            code = server.wait(timeout=60)
            if code != 0:
                failures.append(f"fe_server exit {code}\n{server.stdout.read()[-2000:]}")
        finally:
            if server.poll() is None:
                server.kill()
        if not failures:
            if csv["2.0"] != csv["3.0"]:
                failures.append("the FMI 2.0 and 3.0 FMUs' CSVs differ")
            else:
                print(f"fmusim: FMI 2.0 and 3.0 FMUs ran {len(csv['2.0']) - 1} rows, the same CSV "
                      f"(last: {csv['2.0'][-1]})")
    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
