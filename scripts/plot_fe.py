#!/usr/bin/env python3
"""Standard pictures of an fe_server run: stress at the gauge elements
(*DATABASE_HISTORY_SOLID, mean sigma_zz), node displacements
(*DATABASE_HISTORY_NODE), contact force, and the energy account."""
import argparse
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("results", help="fe_server history (HDF5)")
    ap.add_argument("-o", "--output", default="fe.png")
    a = ap.parse_args()
    f = h5py.File(a.results, "r")
    t = f["time"][:] * 1e6
    panels = []
    if "solids" in f:
        panels.append("stress")
    if "nodes" in f:
        panels.append("nodes")
    if "contact" in f:
        panels.append("contact")
    panels.append("energy")
    fig, ax = plt.subplots(len(panels), 1, figsize=(10, 3 * len(panels)), sharex=True, squeeze=False)
    ax = ax[:, 0]
    for axis, panel in zip(ax, panels):
        if panel == "stress":
            s = np.mean([f["solids"][k]["szz"][:] for k in f["solids"]], axis=0)
            axis.plot(t, s * 1e-6, label=f"gauge sigma_zz, mean of {len(f['solids'])} elements [MPa]")
        elif panel == "nodes":
            for k in f["nodes"]:
                axis.plot(t, f["nodes"][k]["uz"][:] * 1e3, label=f"node {k} u_z [mm]")
        elif panel == "contact":
            axis.plot(t, f["contact/force"][:] * 1e-3, label="contact force [kN]")
        else:
            for e in f["energy"]:
                axis.plot(t, f["energy"][e][:], label=e)
            axis.set_ylabel("J")
        axis.grid(True, alpha=0.3)
        axis.legend(fontsize=8)
    ax[-1].set_xlabel("time [us]")
    title = f.attrs.get("title", b"")
    fig.suptitle(title.decode() if isinstance(title, bytes) else title)
    fig.tight_layout()
    fig.savefig(a.output, dpi=100)
    print(f"plot: {a.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
