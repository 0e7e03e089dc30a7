#!/usr/bin/python3
"""scripts/pcs_results.py, the results reader, on files our tools write.

fe_server runs the bar impact standalone: its energies are on /time and its
element stresses on /time_elements, two axes of the same length (597 rows),
the case where pairing a series with an axis by its length would be a
guess. tlm_host runs a small circuit. Each frame must equal the raw
datasets, carry the writers' units, and sit on the axis the series names.
A copy of the fe file with the `time` attributes stripped (a file from an
older build) must be refused where two axes fit, and read where one does.
Usage: results_reader_test.py FE_SERVER TLM_HOST BAR_DECK PCS_RESULTS_PY WORKDIR"""
import importlib.util
import pathlib
import shutil
import subprocess
import sys

import h5py
import numpy as np

fe_server, tlm_host, deck, reader_py, work = sys.argv[1:6]
work = pathlib.Path(work)
shutil.rmtree(work, ignore_errors=True)
work.mkdir(parents=True)
spec = importlib.util.spec_from_file_location("pcs_results", reader_py)
pr = importlib.util.module_from_spec(spec)
spec.loader.exec_module(pr)
failures = []


def check(ok, what):
    print("ok  " if ok else "FAIL", what)
    if not ok:
        failures.append(what)


def refuses(fn, words, what):
    try:
        fn()
    except pr.ResultsError as e:
        check(all(w in str(e) for w in words), f"{what}: {e}")
        return
    check(False, f"{what}: no error")


fe = work / "fe.h5"
subprocess.run([fe_server, "--model", deck, "--out", str(fe)], check=True, timeout=120,
               stdout=subprocess.DEVNULL)
with pr.load(fe) as r, h5py.File(fe, "r") as raw:
    check(r.producer == "fe_server", f"producer {r.producer}")
    check(r.axes.get("/time") == r.axes.get("/time_elements") and r.axes["/time"] > 100,
          f"two axes of one length (the hard case): {r.axes}")
    en = r.frame("energy")
    check(en.attrs["axis"] == "/time" and set(en.attrs["units"].values()) == {"J"},
          f"energies on /time in J: {en.attrs['axis']}, {set(en.attrs['units'].values())}")
    check(np.array_equal(en.index.values, raw["time"][:]) and
          np.array_equal(en["kinetic"].values, raw["energy/kinetic"][:]), "energy frame equals the datasets")
    el = r.frame("solids")
    check(el.attrs["axis"] == "/time_elements" and np.array_equal(el.index.values, raw["time_elements"][:]),
          "element stresses indexed by /time_elements, not /time")
    some = next(c for c in el.columns if c.endswith("/syy"))
    check(el.attrs["units"][some] == "Pa" and np.array_equal(el[some].values, raw["solids/" + some][:]),
          f"{some} in Pa equals its dataset")
    # the bar's elements see the impact: a stress that is all zeros would pass the equality
    check(np.abs(el[some].values).max() > 1e6, f"{some} carries the pulse ({np.abs(el[some].values).max():.3g} Pa)")
    s = r.series("solids/" + some)
    check(s.attrs["unit"] == "Pa" and s.attrs["axis"] == "/time_elements" and len(s) == r.axes["/time_elements"],
          "series() with its unit and axis")
    refuses(lambda: r.frame(""), ["2 time axes", "axis="], "a frame over two axes")
    whole = r.frame("", axis="/time_elements")
    check(whole.shape[1] == len(r.names("solids")), "axis= picks the series on that axis")
    refuses(lambda: r.series("energy/kinetc"), ["no series"], "a misspelt series")

old = work / "old_fe.h5"  # as written before the series named their axes
shutil.copy(fe, old)
with h5py.File(old, "a") as h:
    h.visititems(lambda n, o: o.attrs.__delitem__("time") if isinstance(o, h5py.Dataset) and "time" in o.attrs else None)
with pr.load(old) as r:
    refuses(lambda: r.frame("energy"), ["cannot be told"], "an old file whose two axes have one length")
listing = subprocess.run([sys.executable, reader_py, str(old)], capture_output=True, text=True)
check(listing.returncode == 0 and "axis not recorded" in listing.stdout and "energy/kinetic [J], " in listing.stdout,
      f"an old file is still listed, its series under 'axis not recorded': exit {listing.returncode}")
with h5py.File(old, "a") as h:  # one axis of that length left: no ambiguity
    del h["time_elements"]
    for n in [k for k in h.keys() if k in ("solids", "sections", "axisymmetric", "bars")]:
        del h[n]
with pr.load(old) as r:
    check(r.frame("energy").attrs["axis"] == "/time", "an old file with one fitting axis is read by length")

model = work / "model.tlm"
model.write_text("*SIMULATION\ntimestep, 1e-5\nstoptime, 2e-3\n*COMPONENT\n"
                 "src, PressureSourceC, p=1e7\norifice, HydraulicTurbulentOrificeQ, Cd=0.7, A=1e-6\n"
                 "vol, HydraulicVolumeC, V=1e-4, ports=2\nleak, LaminarOrificeQ, Kc=1e-12\ntank, PressureSourceC, p=1e5\n"
                 "*CONNECT\nsrc.P1, orifice.P1\norifice.P2, vol.P1\nvol.P2, leak.P1\nleak.P2, tank.P1\n")
host = work / "host.h5"
subprocess.run([tlm_host, str(model), "--quiet", "--no-report", "--out", str(host)], check=True, timeout=60)
with pr.load(host) as r, h5py.File(host, "r") as raw:
    nodes = r.frame("nodes")
    p = next(c for c in nodes.columns if c.startswith("vol.P1"))
    check(r.producer == "tlm_host" and nodes.attrs["units"][p] == "Pa", f"host: {p} in Pa")
    check(np.array_equal(nodes[p].values, raw["nodes/" + p][:]) and nodes.index[0] == 0.0,
          "host frame equals its dataset, from t = 0")
    # the volume fills towards the supply through the orifice: the frame is the physics, not zeros
    check(nodes[p].values[-1] > nodes[p].values[0], f"the volume's pressure rises ({nodes[p].values[0]:.4g} -> {nodes[p].values[-1]:.4g} Pa)")

csv = work / "energy.csv"
out = subprocess.run([sys.executable, reader_py, str(fe), "energy", "--csv", str(csv)], capture_output=True, text=True)
header = csv.read_text().splitlines()[0] if csv.exists() else ""
check(out.returncode == 0 and header.startswith("time [s],") and "kinetic [J]" in header, f"--csv: {header}")
out = subprocess.run([sys.executable, reader_py, str(work / "none.h5")], capture_output=True, text=True)
check(out.returncode == 3 and "no such file" in out.stderr, f"a missing file: exit {out.returncode}, {out.stderr.strip()}")

print(f"{len(failures)} failed" if failures else "all passed")
sys.exit(1 if failures else 0)
