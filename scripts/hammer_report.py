#!/usr/bin/python3
"""Report of a hammer run (scripts/run_hammer.sh): report.md and plots.

For each running condition (a directory <p>bar_<d>mm with reference.json
from the monolithic model and one directory per coupling mode), the thesis'
Table 3 quantities for the monolithic reference and each co-simulation:

  W_kin        blow energy ½·m·v² at impact (both),
  W_stress     energy of the primary stress pulse in the tool,
               W = (A·c0/E)·∫σ_d² dt, σ_d the down-going stress at the gauge
               (co-simulation only: the reference's tool is a lumped mass),
  frequency, impact velocity, stroke, Q_in, p_in, peak p_A, p_B, p_control,
  peak tool stress (most compressive gauge stress of each blow, mean),
  time shift of the piston lift against the reference (cross-correlation),
  wall time per simulated second.

Usage: hammer_report.py OUT_DIR   (writes OUT_DIR/report.md and *.png)
"""
import json
import pathlib
import sys

import h5py
import numpy as np

# Tool: steel bar Ø65 mm (shared/scenes/hammer.md), as in scenes/hammer/deck.k.
E, RHO, AREA = 2.1e11, 7850.0, 3.3183e-3
C0 = (E / RHO) ** 0.5
GAUGE = "200040"                  # bar element 200 mm below the tool's top
GAUGE_NODES = ("200040", "200041")  # its two nodes
MODES = ("pressure", "tlm", "tlm10", "pressure10")
MODE_TEXT = {"pressure": "pressure, 1 us", "tlm": "TLM, 1 us", "tlm10": "TLM, 10 us, k = 10",
             "pressure10": "pressure, 10 us, k = 10"}


def gauge(fe):
    """Time, stress and axial particle velocity (+z) at the tool's gauge,
    from the element history stream (files of fe_server before the
    decimated histories: the every-step rows and the gauge nodes)."""
    if "time_elements" in fe:
        return (fe["time_elements"][:], fe[f"bars/{GAUGE}/axial_stress"][:],
                fe[f"bars/{GAUGE}/axial_velocity"][:])
    return (fe["time"][:], fe[f"bars/{GAUGE}/axial_stress"][:],
            0.5 * (fe[f"nodes/{GAUGE_NODES[0]}/vz"][:] + fe[f"nodes/{GAUGE_NODES[1]}/vz"][:]))


def primary_pulses(fe, impact_times):
    """W from the down-going stress of each blow's primary pulse, and the
    peak compressive stress. σ_d = (σ + ρ·c0·v)/2 separates the down-going
    wave from the one reflected at the rock (1D wave relations: σ = ρc·v
    for a wave moving towards −z, σ = −ρc·v towards +z)."""
    t, sigma, v = gauge(fe)
    sigma_d = 0.5 * (sigma + RHO * C0 * v)
    W, peaks = [], []
    for ti in impact_times:
        i0, i1 = np.searchsorted(t, [ti - 20e-6, ti + 1.0e-3])
        if i1 >= len(t) or i1 - i0 < 10:
            continue
        s = sigma_d[i0:i1]
        k = int(np.argmin(s))
        # The pulse ends where the down-going stress first falls below 2 % of
        # its peak after the peak (a rigid piston's pulse decays exponentially).
        tail = np.nonzero(s[k:] > 0.02 * s[k])[0]
        end = k + (tail[0] if len(tail) else len(s) - k)
        W.append(AREA * C0 / E * np.trapz(s[:end] ** 2, t[i0:i0 + end]))
        peaks.append(sigma[i0:i1].min())
    return (float(np.mean(W)) if W else float("nan"), float(np.mean(peaks)) if peaks else float("nan"))


def time_shift(ref, host):
    """Lag (s) maximising the cross-correlation of the piston lift after
    start-up, refined by a parabola through the three best lags; positive:
    the co-simulation runs later than the reference."""
    t = ref["time"][:]
    xr = ref["components/piston/x"][:]
    xc = np.interp(t, host["time"][:], host["components/mech/x"][:])
    s = t > 0.3 * t[-1]
    a, b = xr[s] - xr[s].mean(), xc[s] - xc[s].mean()
    dt = t[1] - t[0]
    lags = np.arange(-400, 401)
    n = len(a)
    cc = np.array([np.dot(a[max(0, -l):n - max(0, l)], b[max(0, l):n - max(0, -l)]) for l in lags])
    k = int(np.argmax(cc))
    frac = 0.0
    if 0 < k < len(cc) - 1:
        den = cc[k - 1] - 2 * cc[k] + cc[k + 1]
        frac = 0.5 * (cc[k - 1] - cc[k + 1]) / den if den != 0 else 0.0
    return (lags[k] + frac) * dt


def figures(js):
    pk = js["peak_pressure_Pa"]
    return {
        "W_kin": js["blow_energy_J"], "f": js["frequency_Hz"], "v": js["impact_velocity_m_s"],
        "stroke": 1e3 * js["stroke_m"], "Q_in": 6e4 * js["inlet_flow_m3_s"], "p_in": 1e-5 * js["inlet_pressure_Pa"],
        "p_A": 1e-5 * pk["p_A"], "p_B": 1e-5 * pk["p_B"], "p_control": 1e-5 * pk["p_control"],
    }


ROWS = [("W_kin", "blow energy ½mv² [J]", "{:.0f}"), ("W_stress", "W from tool stress [J]", "{:.0f}"),
        ("f", "impact frequency [Hz]", "{:.2f}"), ("v", "impact velocity [m/s]", "{:.3f}"),
        ("stroke", "piston stroke [mm]", "{:.1f}"), ("Q_in", "inlet flow Q_in [l/min]", "{:.1f}"),
        ("p_in", "inlet pressure p_in [bar abs]", "{:.1f}"), ("p_A", "peak p_A [bar abs]", "{:.1f}"),
        ("p_B", "peak p_B [bar abs]", "{:.1f}"), ("p_control", "peak p_control [bar abs]", "{:.1f}"),
        ("sigma", "peak tool stress [MPa]", "{:.0f}"), ("shift", "time shift vs reference [us]", "{:.0f}"),
        ("wall", "wall time per simulated s [s]", "{:.1f}")]


def evaluate(cond):
    ref_js = json.loads((cond / "reference.json").read_text())
    cols = {"reference": figures(ref_js)}
    with h5py.File(cond / "reference.h5") as ref:
        t_end = ref["time"][-1]
        for m in MODES:
            d = cond / m
            if not (d / "host.json").exists():
                continue
            js = json.loads((d / "host.json").read_text())
            col = figures(js)
            with h5py.File(d / "host.h5") as host, h5py.File(d / "fe.h5") as fe:
                col["W_stress"], sigma = primary_pulses(fe, js["impact_times_s"])
                col["sigma"] = 1e-6 * sigma
                col["shift"] = 1e6 * time_shift(ref, host)
            col["wall"] = float((d / "wall_seconds").read_text()) / t_end
            cols[m] = col
    return cols


def table(cols):
    names = list(cols)
    head = "| quantity | " + " | ".join("reference" if n == "reference" else MODE_TEXT[n] for n in names) + " |"
    lines = [head, "|---" * (len(names) + 1) + "|"]
    ref = cols["reference"]
    for key, text, fmt in ROWS:
        cells = []
        for n in names:
            val = cols[n].get(key)
            if val is None or (isinstance(val, float) and np.isnan(val)):
                cells.append("—")
                continue
            cell = fmt.format(val)
            if n != "reference" and key in ref and ref[key] != 0:
                cell += f" ({100 * (val / ref[key] - 1):+.1f} %)"
            cells.append(cell)
        lines.append(f"| {text} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def plot(cond, cols):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(3, 1, figsize=(9, 10))
    with h5py.File(cond / "reference.h5") as ref:
        t = ref["time"][:]
        s = t > t[-1] - 0.1
        ax[0].plot(1e3 * t[s], 1e3 * ref["components/piston/x"][s], "k", lw=2, label="monolithic reference")
        ax[1].plot(1e3 * t[s], ref["components/spool/x"][s] * 1e3, "k", lw=2, label="monolithic reference")
    for m in MODES:
        if m not in cols:
            continue
        with h5py.File(cond / m / "host.h5") as host:
            t = host["time"][:]
            s = t > t[-1] - 0.1
            ax[0].plot(1e3 * t[s], 1e3 * host["components/mech/x"][s], label=MODE_TEXT[m])
            ax[1].plot(1e3 * t[s], 1e3 * host["components/smech/x"][s], label=MODE_TEXT[m])
        with h5py.File(cond / m / "fe.h5") as fe:
            js = json.loads((cond / m / "host.json").read_text())
            ti = js["impact_times_s"][-1]
            t, sigma, _ = gauge(fe)
            s = (t > ti - 50e-6) & (t < ti + 800e-6)
            ax[2].plot(1e6 * (t[s] - ti), 1e-6 * sigma[s], label=MODE_TEXT[m])
    ax[0].set(xlabel="time [ms]", ylabel="piston lift [mm]", title=f"{cond.name}: last 0.1 s")
    ax[1].set(xlabel="time [ms]", ylabel="spool position [mm]")
    ax[2].set(xlabel="time after the last evaluated impact [µs]", ylabel="tool stress at the gauge [MPa]",
              title="stress 200 mm below the tool's top (compression negative)")
    for a in ax:
        a.grid(alpha=0.3)
        a.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(cond / "hammer.png", dpi=110)
    plt.close(fig)


def main():
    out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "out/hammer")
    conds = sorted((d for d in out.glob("*bar_*mm") if (d / "reference.json").exists()),
                   key=lambda d: (-int(d.name.split("bar")[0]), -float(d.name.split("_")[1][:-2])))
    if not conds:
        sys.exit(f"hammer_report.py: no runs under {out}")
    md = ["# Hydraulic hammer: co-simulation against the monolithic reference", "",
          "Written by scripts/run_hammer.sh (scripts/hammer_report.py). Piston, spool, tool and rock",
          "in fe_server (rigid piston and spool, 1D-bar tool); the rest in tlm_host. Reference: the",
          "monolithic TLM model (lumped tool). In brackets: difference to the reference. Whole cycles",
          "after 0.3 s; pressures low-pass filtered at 500 Hz. W from tool stress: the down-going",
          "primary pulse 200 mm below the tool's top, W = (A·c0/E)·∫σ² dt. Time shift: lag of the",
          "piston lift's cross-correlation, positive when the co-simulation is later.", ""]
    for cond in conds:
        cols = evaluate(cond)
        md += [f"## {cond.name.replace('bar_', ' bar, restrictor Ø').replace('mm', ' mm')}", "", table(cols), "",
               f"![{cond.name}]({cond.name}/hammer.png)", ""]
        plot(cond, cols)
        print(f"{cond.name}:")
        print(table(cols))
    (out / "report.md").write_text("\n".join(md) + "\n")
    print(f"report: {out / 'report.md'}")


if __name__ == "__main__":
    main()
