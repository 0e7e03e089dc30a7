#!/usr/bin/env python3
"""fatigue_cycles, the command-line entry (issue 35): ASTM E1049-85's worked
example as a CSV gives its cycle table and the Miner damage computed here
from the same S-N curve by hand; a bad row stops it with file:line (exit 3);
a missing curve or strength is a usage error (exit 2).

usage: fatigue_cycles_test.py FATIGUE_CYCLES
"""
import re
import subprocess
import sys
import tempfile
from pathlib import Path


def main():
    exe = sys.argv[1]
    failures = []
    with tempfile.TemporaryDirectory() as d:
        d = Path(d)
        history = [-2, 1, -3, 5, -1, 3, -4, 4, -2]
        csv = d / "astm.csv"
        csv.write_text("time,stress\n" + "".join(f"{0.1 * i:g},{s}\n" for i, s in enumerate(history)))
        run = subprocess.run([exe, str(csv), "--sn", "10,1000,3"], capture_output=True, text=True, timeout=30)
        if run.returncode != 0:
            failures.append(f"exit {run.returncode}: {run.stderr}")
        rows = {}
        for line in run.stdout.splitlines():
            w = line.split()
            if len(w) == 5 and re.match(r"^[0-9.]+$", w[0]):
                rows[float(w[0])] = rows.get(float(w[0]), 0.0) + float(w[2])
        want = {9.0: 0.5, 8.0: 1.0, 6.0: 0.5, 4.0: 1.5, 3.0: 0.5}
        if rows != want:
            failures.append(f"cycle table {rows}, ASTM's is {want}\n{run.stdout}")
        # Miner by hand: N = 1000 (10 / Sa)^3, Sa = range / 2.
        damage = sum(n / (1000.0 * (10.0 / (r / 2.0)) ** 3) for r, n in want.items())
        m = re.search(r"Miner damage of one pass ([0-9.eE+-]+)", run.stdout)
        if not m or abs(float(m.group(1)) - damage) > 1e-5 * damage:
            failures.append(f"damage {m.group(1) if m else '-'}, by hand {damage:.6g}")
        m = re.search(r"passes to crack initiation ([0-9.eE+-]+), ([0-9.eE+-]+) s", run.stdout)
        if not m or abs(float(m.group(2)) - 0.8 / damage) > 1e-5 * 0.8 / damage:
            failures.append(f"time to initiation {m.group(2) if m else '-'} s, by hand {0.8 / damage:.6g} s "
                            "(0.8 s per pass)")
        bad = d / "bad.csv"
        bad.write_text("time,stress\n0,1\n0.1,oops\n")
        run = subprocess.run([exe, str(bad), "--sn", "10,1000,3"], capture_output=True, text=True, timeout=30)
        if run.returncode != 3 or f"{bad}:3:" not in run.stderr:
            failures.append(f"a bad row: exit {run.returncode}, {run.stderr!r} (want 3 and {bad}:3)")
        for args, why in (([str(csv)], "no --sn"), ([str(csv), "--sn", "10,1000,3", "--mean", "goodman"], "no --su"),
                          ([str(csv), "--sn", "10,1000"], "a short --sn"), ([str(csv), "--sn", "10,1000,3", "--gat", "1"],
                                                                            "a misspelt option")):
            run = subprocess.run([exe] + args, capture_output=True, text=True, timeout=30)
            if run.returncode != 2:
                failures.append(f"{why}: exit {run.returncode} (want 2): {run.stderr}")
        if "did you mean --gate" not in run.stderr:
            failures.append(f"a misspelt option is not told the nearest: {run.stderr}")
        for flag, text in (("--version", "fatigue_cycles "), ("--help", "usage: fatigue_cycles")):
            run = subprocess.run([exe, flag], capture_output=True, text=True, timeout=30)
            if run.returncode != 0 or text not in run.stdout:
                failures.append(f"{flag}: exit {run.returncode}, {run.stdout[:200]!r}")
    for f in failures:
        print("FAIL:", f)
    print(f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
