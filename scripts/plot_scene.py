#!/usr/bin/env python3
"""Standard pictures of a coupled run: port displacement and flow from the FE
side, node pressures from the host, the FE energy account. Prints the dominant
frequency of the port displacement (zero crossings)."""
import argparse
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np


def frequency(t, x):
    x = x - x.mean()
    i = np.where((x[:-1] < 0) & (x[1:] >= 0))[0]
    if len(i) < 3:
        return float("nan")
    tc = t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i])
    return (len(tc) - 1) / (tc[-1] - tc[0])


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("fe", help="fe_server results (HDF5), or - for a host-only scene")
    ap.add_argument("host", help="tlm_host results (HDF5), or - for an FE-only scene")
    ap.add_argument("-o", "--output", default="scene.png")
    ap.add_argument("--title", default="", help="the figure's title (the scene, in words)")
    a = ap.parse_args()
    fe = h5py.File(a.fe, "r", swmr=True) if a.fe != "-" else None
    host = h5py.File(a.host, "r", swmr=True) if a.host != "-" else None
    fig, ax = plt.subplots(2, 2, figsize=(12, 7), sharex=True)
    if fe is not None and "ports" in fe:
        t = fe["time"][:]
        for name in fe["ports"]:
            ds = fe["ports"][name]
            unit = ds.attrs.get("unit", b"")
            unit = unit.decode() if isinstance(unit, bytes) else unit
            target = {"x": ax[0, 0], "q": ax[0, 1], "p": ax[1, 0]}.get(name.split(".")[-1])
            if target is None:
                continue
            scale = {"m": 1e3, "m3/s": 6e4, "Pa": 1e-5}.get(unit, 1.0)
            label = {"m": "mm", "m3/s": "l/min", "Pa": "bar"}.get(unit, unit)
            target.plot(t * 1e3, ds[:] * scale, label=f"FE {name} [{label}]")
            if name.endswith(".x"):
                print(f"{name}: dominant frequency {frequency(t, ds[:]):.2f} Hz")
    elif fe is not None and "nodes" in fe:  # FE only: the history nodes' axial motion
        tn = fe["time_nodes"][:]
        for node in list(fe["nodes"])[:6]:
            for axis_name in ("uz", "uy"):
                if axis_name in fe["nodes"][node] and np.ptp(fe["nodes"][node][axis_name][:]) > 0:
                    ax[0, 0].plot(tn * 1e3, fe["nodes"][node][axis_name][:] * 1e3, label=f"node {node} {axis_name} [mm]")
                    break
    if host is not None:
        th = host["time"][:]
        # Hydraulic nodes only (mechanical ones have F, v, x); the first eight by name.
        hydraulic = [n for n in host["nodes"] if "p" in host["nodes"][n]][:8]
        for node in hydraulic:
            ax[1, 0].plot(th * 1e3, host["nodes"][node]["p"][:] * 1e-5, "--", label=f"host {node} p [bar]")
    if fe is not None and "energy" in fe:
        t = fe["time"][:]
        for e in fe["energy"]:
            if e != "damping":
                v = fe["energy"][e][:]
                ax[1, 1].plot(t * 1e3, v - v[0], label=e)
    first = "port displacement" if fe is None or "ports" in fe else "history nodes' displacement"
    titles = [first, "port flow", "pressures", "FE energies, change since t = 0 [J]"]
    for axis, title in zip(ax.flat, titles):
        axis.set_title(title)
        axis.grid(True, alpha=0.3)
        if axis.lines:
            axis.legend(fontsize=8)
    for axis in ax[1]:
        axis.set_xlabel("time [ms]")
    if a.title:
        fig.suptitle(a.title)
    fig.tight_layout()
    fig.savefig(a.output, dpi=110)
    print(f"plot: {a.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
