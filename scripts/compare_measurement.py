#!/usr/bin/python3
"""Simulated signals and figures beside measured ones, as the thesis compared
them (Andersson 2018, ch. 6: every signal except the tool stress low-passed at
500 Hz; time series normalised to the measured signal's maximum; Table 3 as
simulated / measured in %).

  compare_measurement.py signals SIM.h5 MEASURED.csv [--signal NAME=DATASET ...]
        [--lowpass 500] [--settle 0.3] [--align-on NAME] [--plot FILE.png] [--table FILE.md]
  compare_measurement.py figures MEASURED.csv CASE=REPORT.json ... [--table FILE.md]

signals: MEASURED.csv has a header row "time [s], piston_x [mm], p_A [bar], ...":
a time column and named signals, each with its unit in brackets. A name is a
dataset of SIM.h5 (components/piston/x) or one of the aliases below, or is
mapped with --signal NAME=DATASET. Both sides are resampled on the
measurement's step, low-passed (a Gaussian with its -3 dB point at --lowpass),
and the measurement is placed where it correlates best with the simulation
after --settle (cross-correlation of --align-on, default the first signal).
Per signal: the simulated peak and mean as % of the measured ones, the rms
difference as % of the measured range, and the correlation coefficient.

figures: MEASURED.csv has a header "case, FIGURE [unit], ..." (q_in [l/min],
p_in [bar], frequency [Hz] ...) and one row per case; each CASE=REPORT.json is
tlm_host's JSON report of that case. The table is Table 3's: simulated /
measured in %.

Exit codes: 0 done, 2 bad input (the message names the file, line or column).
"""
import argparse
import csv
import json
import math
import sys

import numpy as np

ALIASES = {
    "piston_x": "components/piston/x",
    "piston_v": "components/piston/v",
    "p_A": "nodes/cavA.P2/p",
    "p_B": "nodes/cavB.P2/p",
    "p_control": "nodes/sig.P3/p",
}
# The thesis filtered every signal but the tool's stress (its wave is the
# point of measuring it); a name with these words is left unfiltered.
UNFILTERED_WORDS = ("tool_stress", "tool_strain", "sigma_tool")

UNITS = {
    "s": 1.0, "ms": 1e-3, "m": 1.0, "mm": 1e-3, "Pa": 1.0, "kPa": 1e3, "MPa": 1e6, "bar": 1e5,
    "m/s": 1.0, "m3/s": 1.0, "l/min": 1e-3 / 60.0, "N": 1.0, "kN": 1e3, "m/s2": 1.0, "g": 9.80665,
    "Hz": 1.0, "J": 1.0, "W": 1.0, "kW": 1e3, "1": 1.0, "%": 1e-2, "": 1.0,
}
# The report's JSON keys for the figures a measurement may give.
REPORT_KEYS = {
    "frequency": "frequency_Hz", "v_impact": "impact_velocity_m_s", "stroke": "stroke_m",
    "p_in": "inlet_pressure_Pa", "q_in": "inlet_flow_m3_s", "P_in": "input_power_W",
    "W": "blow_energy_J", "P_out": "output_power_W",
}


class InputError(Exception):
    pass


def parse_header_cell(cell, where):
    """'p_A [bar]' -> ('p_A', factor to SI)."""
    cell = cell.strip()
    name, unit = cell, ""
    if "[" in cell:
        if not cell.endswith("]"):
            raise InputError(f"{where}: '{cell}': expected NAME [UNIT]")
        name, unit = cell[: cell.index("[")].strip(), cell[cell.index("[") + 1 : -1].strip()
    if unit not in UNITS:
        raise InputError(f"{where}: '{cell}': unknown unit '{unit}' (known: {', '.join(u for u in UNITS if u)})")
    if not name:
        raise InputError(f"{where}: '{cell}': a column needs a name")
    return name, UNITS[unit]


def read_csv(path):
    """Header cells and float rows; every cell must be a finite number."""
    try:
        with open(path, newline="") as f:
            rows = [r for r in csv.reader(f) if r and not r[0].lstrip().startswith("#")]
    except OSError as e:
        raise InputError(f"{path}: {e.strerror}")
    if len(rows) < 2:
        raise InputError(f"{path}: needs a header row and at least one data row")
    return rows[0], rows[1:]


def gaussian_lowpass(x, dt, cutoff_hz):
    """A Gaussian kernel whose response exp(-(2 pi f sigma)^2 / 2) is 1/sqrt(2) at cutoff_hz."""
    from scipy.ndimage import gaussian_filter1d

    sigma = math.sqrt(math.log(2.0)) / (2.0 * math.pi * cutoff_hz) / dt
    return gaussian_filter1d(x, sigma, mode="nearest") if sigma > 0.3 else x.copy()


def read_measured_signals(path):
    header, rows = read_csv(path)
    cols = [parse_header_cell(c, f"{path}:1 column {i + 1}") for i, c in enumerate(header)]
    if cols[0][0] not in ("time", "t"):
        raise InputError(f"{path}:1: the first column must be the time (time [s])")
    data = np.empty((len(rows), len(cols)))
    for i, r in enumerate(rows):
        if len(r) != len(cols):
            raise InputError(f"{path}:{i + 2}: {len(r)} values where the header has {len(cols)}")
        for j, cell in enumerate(r):
            try:
                v = float(cell)
            except ValueError:
                raise InputError(f"{path}:{i + 2} column {j + 1}: '{cell}' is not a number")
            if not math.isfinite(v):
                raise InputError(f"{path}:{i + 2} column {j + 1}: '{cell}' is not finite")
            data[i, j] = v * cols[j][1]
    t = data[:, 0]
    dts = np.diff(t)
    if len(t) < 16 or np.any(dts <= 0):
        raise InputError(f"{path}: the time must rise strictly over at least 16 rows")
    if np.max(np.abs(dts - np.median(dts))) > 1e-3 * np.median(dts):
        raise InputError(f"{path}: the time step is not uniform (resample the measurement first)")
    return t, {cols[j][0]: data[:, j] for j in range(1, len(cols))}


def compare_signals(args):
    import h5py

    t_m, measured = read_measured_signals(args.measured)
    mapping = dict(ALIASES)
    for s in args.signal:
        if "=" not in s:
            raise InputError(f"--signal '{s}': expected NAME=DATASET")
        k, v = s.split("=", 1)
        mapping[k] = v
    dt = float(np.median(np.diff(t_m)))
    with h5py.File(args.sim, "r") as f:
        t_s = f["time"][:]
        sim = {}
        for name in measured:
            ds = mapping.get(name, name)
            if ds not in f:
                raise InputError(f"{args.measured}: signal '{name}' is dataset '{ds}', which {args.sim} does not hold "
                                 f"(map it with --signal {name}=DATASET)")
            sim[name] = f[ds][:]
    if t_s[-1] - args.settle < (t_m[-1] - t_m[0]) * 1.05:
        raise InputError(f"{args.sim}: {t_s[-1] - args.settle:.3f} s after --settle {args.settle} is shorter than "
                         f"the measurement's {t_m[-1] - t_m[0]:.3f} s")
    grid = np.arange(args.settle, t_s[-1], dt)
    filt = lambda name, x: x if any(w in name for w in UNFILTERED_WORDS) else gaussian_lowpass(x, dt, args.lowpass)
    sim_g = {n: filt(n, np.interp(grid, t_s, x)) for n, x in sim.items()}
    meas_f = {n: filt(n, x) for n, x in measured.items()}

    align = args.align_on or next(iter(measured))
    if align not in measured:
        raise InputError(f"--align-on {align}: the measurement has no such signal")
    a, b = sim_g[align], meas_f[align]
    n = len(b)
    b0 = b - b.mean()
    if not b0.std() > 1e-12 * max(abs(b).max(), 1e-300):
        # A flat signal correlates equally (not at all) with every window:
        # any offset would be a guess.
        raise InputError(f"{args.measured}: '{align}' is constant over the measurement; align on a signal that "
                         f"moves (--align-on NAME)")
    # Normalised cross-correlation of the measurement against every window
    # of the simulation after the settle time.
    csum, csum2 = np.cumsum(np.r_[0.0, a]), np.cumsum(np.r_[0.0, a * a])
    num = np.correlate(a, b0, mode="valid")
    win_mean = (csum[n:] - csum[:-n]) / n
    win_var = np.maximum((csum2[n:] - csum2[:-n]) / n - win_mean**2, 1e-300)
    rho = num / (n * np.sqrt(win_var) * b0.std())
    k = int(np.argmax(rho))
    offset = grid[k] - t_m[0]  # simulated time = measured time + offset
    rows = []
    for name in measured:
        s, m = sim_g[name][k : k + n], meas_f[name]
        rng = m.max() - m.min()
        rows.append({
            "signal": name,
            "peak_pct": 100.0 * s.max() / m.max() if m.max() != 0 else float("nan"),
            "mean_pct": 100.0 * s.mean() / m.mean() if m.mean() != 0 else float("nan"),
            "rms_diff_pct": 100.0 * math.sqrt(np.mean((s - m) ** 2)) / rng if rng > 0 else float("nan"),
            "correlation": float(np.corrcoef(s, m)[0, 1]) if rng > 0 and s.std() > 0 else float("nan"),
            "filtered": not any(w in name for w in UNFILTERED_WORDS),
        })
    result = {"offset_s": offset, "align_on": align, "align_correlation": float(rho[k]), "lowpass_Hz": args.lowpass,
              "signals": rows}
    if "piston_x" in measured:
        result["frequency_pct"] = 100.0 * cycle_frequency(sim_g["piston_x"][k : k + n], dt) / cycle_frequency(meas_f["piston_x"], dt)
        s, m = sim_g["piston_x"][k : k + n], meas_f["piston_x"]
        result["stroke_pct"] = 100.0 * (s.max() - s.min()) / (m.max() - m.min())

    lines = [f"Simulation {args.sim} against measurement {args.measured}: offset {offset:.6f} s "
             f"(correlation of {align} {rho[k]:.4f}); low-pass {args.lowpass:g} Hz except the tool's stress.", "",
             "| signal | peak sim/meas [%] | mean sim/meas [%] | rms difference [% of range] | correlation | filtered |",
             "|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['signal']} | {r['peak_pct']:.1f} | {r['mean_pct']:.1f} | {r['rms_diff_pct']:.2f} | "
                     f"{r['correlation']:.4f} | {'yes' if r['filtered'] else 'no'} |")
    for key, label in (("frequency_pct", "frequency"), ("stroke_pct", "stroke")):
        if key in result:
            lines.append(f"| {label} (from piston_x) | {result[key]:.1f} | | | | |")
    emit(args, lines, result)
    if args.plot:
        plot_signals(args, t_m, meas_f, {nm: x[k : k + n] for nm, x in sim_g.items()}, offset)
    return 0


def emit(args, lines, data):
    """The table on stdout and in --table, the numbers in --json."""
    text = "\n".join(lines) + "\n"
    print(text, end="")
    if args.table:
        with open(args.table, "w") as f:
            f.write(text)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(data, f, indent=1)


def cycle_frequency(x, dt):
    """Upward crossings of the signal's mid level, whole cycles only."""
    mid = 0.5 * (x.max() + x.min())
    up = np.nonzero((x[:-1] < mid) & (x[1:] >= mid))[0]
    if len(up) < 2:
        raise InputError("piston_x: fewer than two cycles in the measurement window")
    return (len(up) - 1) / ((up[-1] - up[0]) * dt)


def plot_signals(args, t_m, meas, sim, offset):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = list(meas)
    fig, axes = plt.subplots(len(names), 1, figsize=(8, 2.2 * len(names)), sharex=True, squeeze=False)
    for ax, name in zip(axes[:, 0], names):
        scale = np.max(np.abs(meas[name])) or 1.0
        ax.plot(t_m - t_m[0], meas[name] / scale, color="k", lw=1.2, label="measured")
        ax.plot(t_m - t_m[0], sim[name] / scale, color="tab:red", lw=1.0, ls="--", label="simulated")
        ax.set_ylabel(f"{name} / max(measured)")
        ax.grid(alpha=0.3)
    axes[0, 0].legend(loc="upper right", fontsize=8)
    axes[-1, 0].set_xlabel(f"time in the measurement [s] (simulation shifted by {offset:.4f} s)")
    fig.suptitle(f"Simulated against measured, normalised to the measured maximum ({args.lowpass:g} Hz low-pass)", fontsize=10)
    fig.tight_layout()
    fig.savefig(args.plot, dpi=110)


def compare_figures(args):
    header, rows = read_csv(args.measured)
    if header[0].strip() != "case":
        raise InputError(f"{args.measured}:1: the first column must be 'case'")
    cols = [parse_header_cell(c, f"{args.measured}:1 column {i + 2}") for i, c in enumerate(header[1:])]
    for name, _ in cols:
        if name not in REPORT_KEYS:
            raise InputError(f"{args.measured}:1: no report figure '{name}' (known: {', '.join(REPORT_KEYS)})")
    reports = {}
    for item in args.reports:
        if "=" not in item:
            raise InputError(f"'{item}': expected CASE=REPORT.json")
        case, path = item.split("=", 1)
        try:
            with open(path) as f:
                reports[case] = json.load(f)
        except (OSError, ValueError) as e:
            raise InputError(f"{path}: {e}")
    lines = ["| case | " + " | ".join(f"{n} sim/meas [%]" for n, _ in cols) + " |", "|---" * (len(cols) + 1) + "|"]
    out = {}
    for i, r in enumerate(rows):
        case = r[0].strip()
        if case not in reports:
            raise InputError(f"{args.measured}:{i + 2}: no report given for case '{case}' ({case}=REPORT.json)")
        cells = []
        for (name, factor), cell in zip(cols, r[1:]):
            try:
                meas = float(cell) * factor
            except ValueError:
                raise InputError(f"{args.measured}:{i + 2}: '{cell}' is not a number")
            sim = reports[case][REPORT_KEYS[name]]
            pct = 100.0 * sim / meas
            out.setdefault(case, {})[name] = pct
            cells.append(f"{pct:.1f}")
        lines.append(f"| {case} | " + " | ".join(cells) + " |")
    emit(args, lines, out)
    return 0


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = p.add_subparsers(dest="mode", required=True)
    s = sub.add_parser("signals", help="time series against a measurement")
    s.add_argument("sim")
    s.add_argument("measured")
    s.add_argument("--signal", action="append", default=[], help="NAME=DATASET")
    s.add_argument("--lowpass", type=float, default=500.0)
    s.add_argument("--settle", type=float, default=0.3)
    s.add_argument("--align-on")
    s.add_argument("--plot")
    s.add_argument("--table")
    s.add_argument("--json")
    g = sub.add_parser("figures", help="report figures against measured ones (Table 3)")
    g.add_argument("measured")
    g.add_argument("reports", nargs="+", help="CASE=REPORT.json")
    g.add_argument("--table")
    g.add_argument("--json")
    args = p.parse_args()
    try:
        return compare_signals(args) if args.mode == "signals" else compare_figures(args)
    except InputError as e:
        print(f"compare_measurement: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
