#!/usr/bin/env python3
"""Standard signals of a hammer run (tlm_host results): piston stroke and
velocity, spool position, cavity and control pressures, inlet flow, over the
last `--window` seconds."""
import argparse
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("results")
    ap.add_argument("-o", "--output", default="hammer.png")
    ap.add_argument("--window", type=float, default=0.12, help="seconds at the end of the run to show")
    a = ap.parse_args()
    h = h5py.File(a.results, "r")
    t = h["time"][:]
    s = t >= t[-1] - a.window
    c = h["components"]
    tm = t[s] * 1e3
    fig, ax = plt.subplots(4, 1, figsize=(11, 10), sharex=True)
    ax[0].plot(tm, c["piston/x"][s] * 1e3, label="piston lift x [mm]")
    ax[0].plot(tm, c["piston/y_tool"][s] * 1e3, label="tool y [mm]")
    ax[0].plot(tm, c["spool/x"][s] * 1e3 * 5, label="spool x_v [mm] ×5")
    ax[1].plot(tm, c["piston/v"][s], label="piston velocity [m/s]")
    for label, name in [("p_A", "nodes/cavA.P2/p"), ("p_B", "nodes/cavB.P2/p"), ("p_control", "nodes/sig.P3/p"),
                        ("p_inlet", "nodes/supply_hose.P2/p"), ("p_T", "nodes/nodeT.P1/p")]:
        ax[2].plot(tm, h[name][s] * 1e-5, label=f"{label} [bar abs]")
    ax[3].plot(tm, c["restrictor/q"][s] * 6e4, label="inlet flow [l/min]")
    ax[3].plot(tm, c["relief/q"][s] * 6e4, label="relief flow [l/min]")
    for axis in ax:
        axis.grid(True, alpha=0.3)
        axis.legend(fontsize=8, loc="upper right")
    ax[-1].set_xlabel("time [ms]")
    fig.suptitle(h.attrs.get("model", b"").decode() if isinstance(h.attrs.get("model", b""), bytes) else h.attrs.get("model", ""))
    fig.tight_layout()
    fig.savefig(a.output, dpi=100)
    print(f"plot: {a.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
