#!/usr/bin/python3
"""docs/own_hammer.md's port table and host model are files the tools take:
fmugen makes the FMU from the port table (exit 0, the labels as its
variables), and tlm_host reads the model against it, gets as far as
connecting to a server that is not there (its time-out shortened to 1 s)
and exits 4 for that, not 3 for an input it refuses. A guide whose example
no longer reads would fail here.
Usage: own_hammer_guide_test.py FMUGEN TLM_HOST GUIDE.md"""
import os
import pathlib
import re
import subprocess
import sys
import tempfile

fmugen, tlm_host, guide = sys.argv[1:4]
text = pathlib.Path(guide).read_text()
blocks, current = [], None
for line in text.splitlines(keepends=True):  # fenced blocks, in order
    if line.lstrip().startswith("```"):
        if current is None:
            current = ""
        else:
            blocks.append(current)
            current = None
    elif current is not None:
        current += line.lstrip() if line.startswith("  ") else line
ports = next(b for b in blocks if b.startswith("$FMU_SETTINGS"))
model = next(b for b in blocks if b.startswith("*SIMULATION"))
failures = []


def check(ok, what):
    print("ok  " if ok else "FAIL", what)
    if not ok:
        failures.append(what)


with tempfile.TemporaryDirectory() as d:
    p = pathlib.Path(d)
    (p / "ports.cfg").write_text(re.sub(r"\ntimeout, *\d+", "\ntimeout,    1", ports))
    (p / "model.tlm").write_text(model)
    g = subprocess.run([fmugen, "ports.cfg", "-o", "my_hammer.fmu"], cwd=d, capture_output=True, text=True, timeout=60)
    check(g.returncode == 0, f"fmugen takes the guide's port table: {g.stdout}{g.stderr}")
    check("3 inputs, 3 outputs" in g.stdout, "its FMU has the table's 3 inputs and 3 outputs")
    env = dict(os.environ, PCS_TOKEN="guide-test-token-0123")
    h = subprocess.run([tlm_host, "model.tlm", "--server", "127.0.0.1:1", "--out", "h.h5", "--quiet"], cwd=d,
                       capture_output=True, text=True, timeout=60, env=env)
    check(h.returncode == 4 and "cannot connect to fe_server" in h.stderr,
          f"tlm_host reads the guide's model and only misses the server: exit {h.returncode}: {h.stderr.strip()}")
sys.exit(1 if failures else 0)
