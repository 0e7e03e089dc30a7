#!/usr/bin/python3
"""Report of a hammer run (scripts/run_hammer.sh): report.md and plots.

For each running condition (a directory <p>bar_<d>mm with reference.json
from the monolithic model and one directory per coupling mode), the thesis'
Table 3 quantities for the monolithic reference and each co-simulation:

  W_kin        blow energy ½·m·v² at impact (both),
  W_stress     energy of the primary stress pulse in the tool,
               W = (A·c0/E)·∫σ_d² dt, σ_d the down-going stress at the gauge
               (co-simulation only: the reference's tool is a lumped mass),
  frequency, impact velocity, stroke, Q_in, p_in, p_out (mean at the return
  node T), peak p_A, p_B, p_control,
  peak tool stress (most compressive gauge stress of each blow, mean),
  peak piston stress (elastic scene: its gauge 165 mm above the striking face),
  time shift of the piston lift against the reference (cross-correlation),
  wall time per simulated second;

and for the elastic scene the physics checks of issue 14: the primary pulse
is a plateau within 5 % of the 1D impedance estimate from the measured
impact velocity, as long as 2·L_piston/c0 within 10 %; the FE energy balance
within its bound. Then the thesis' Fig. 16 (input power p_in·Q_in and output
power W·f against the restrictor diameter) over the conditions run.

Usage: hammer_report.py OUT_DIR   (writes OUT_DIR/report.md and *.png)
"""
import json
import pathlib
import re
import sys

import h5py
import numpy as np

# Steel (shared/scenes/hammer.md).
E, RHO = 2.1e11, 7850.0
C0 = (E / RHO) ** 0.5
# Each scene's geometry as its deck and meshes give it (scenes/CMakeLists.txt):
# the tool's radius, the piston's striking stem, its length and mass, and the
# housing's wall at its gauge section. The key is the scene's folder, which
# each fe.h5 names (its port_table attribute): the report reads the geometry
# of the runs it evaluates, never a guess.
GEOMETRY = {
    "hammer_elastic": dict(r_tool=0.0325, r_strike=0.0305, l_piston=0.64, m_piston=14.36, r_housing_bore=0.0329),
    "hammer": dict(r_tool=0.0325, r_strike=0.0305, l_piston=0.64, m_piston=14.4, r_housing_bore=0.0329),
    "hammer_rig": dict(r_tool=0.0335, r_strike=0.0305, l_piston=0.28337, m_piston=6.0, r_housing_bore=0.0320277),
}


def use_scene(name):
    """Set the module's geometry to scene NAME's."""
    global AREA, A_STRIKE, L_PISTON, M_PISTON, A_HOUSING, SCENE
    g = GEOMETRY[name]
    SCENE = name
    AREA = np.pi * g["r_tool"] ** 2            # tool section
    A_STRIKE = np.pi * g["r_strike"] ** 2      # piston's striking stem
    L_PISTON, M_PISTON = g["l_piston"], g["m_piston"]
    A_HOUSING = np.pi * (0.08 ** 2 - g["r_housing_bore"] ** 2)


use_scene("hammer_elastic")


def scene_of(conds, given=None):
    """The scene folder every co-simulation under the condition folders ran
    (fe.h5's port_table attribute, .../scenes/NAME/ports*.cfg). Exits naming
    the files when the runs come from different scenes or an unknown one.
    `given` (run_hammer.sh --ports: a study's port table outside the scene)
    names the scene of the runs whose table lies outside every scene; a run
    whose table is another scene's is still refused, so that no run is read
    with the wrong scene's geometry."""
    seen = {}
    for cond in conds:
        for m in MODES:
            fe = cond / m / "fe.h5"
            if fe.exists():
                with h5py.File(fe) as f:
                    table = f.attrs.get("port_table", b"")
                table = table.decode() if isinstance(table, bytes) else str(table)
                name = pathlib.Path(table).parent.name
                seen.setdefault(given if given and name not in GEOMETRY else name, []).append(str(fe))
    if len(seen) != 1 or next(iter(seen)) not in GEOMETRY or (given and given not in seen):
        sys.exit("hammer_report.py: the runs' scenes (fe.h5 port_table): " +
                 "; ".join(f"{k or '?'}: {', '.join(v)}" for k, v in seen.items()) +
                 (f"; --scene {given} given" if given else f"; expected one of {', '.join(GEOMETRY)}"))
    return next(iter(seen))


# Rigid scene (scenes/hammer): the 1D-bar tool's gauge element and its nodes.
BAR_GAUGE = "200040"
BAR_GAUGE_NODES = ("200040", "200041")
# Elastic scene (scenes/hammer_elastic): the cross sections fe_mesh puts
# through the tool's gauge layer (200 mm below the top) and the piston's
# (165 mm above its striking face, in the Ø61 mm stem).
SECTION = "111"
PISTON_SECTION = "101"
MODES = ("tlm10", "pressure", "tlm", "pressure10")  # the co-simulation folders under a condition
MODE_TEXT = {"pressure": "pressure, 1 µs", "tlm": "TLM, 1 µs", "tlm10": "TLM, 10 µs",
             "pressure10": "pressure, 10 µs, k = 10"}


def condition_words(name):
    """'150bar_6.0mm' -> '150 bar, restrictor Ø6.0 mm' (a run folder's name as its condition)."""
    try:
        p, d = name.split("bar_")
        return f"{int(p)} bar, restrictor Ø{float(d[:-2]):.1f} mm"
    except ValueError:
        return name


def elastic(fe):
    return "sections" in fe and SECTION in fe["sections"]


def gauge(fe):
    """Time, stress and axial particle velocity (up positive) at the tool's
    gauge. Elastic tool: the section force over the area and the cut's mean
    velocity; 1D bar: the element's stress and velocity (older files: the
    mean of its two nodes)."""
    if elastic(fe):
        return (fe["time_elements"][:], fe[f"sections/{SECTION}/fy"][:] / AREA, fe[f"sections/{SECTION}/vy"][:])
    if "time_elements" in fe:
        return (fe["time_elements"][:], fe[f"bars/{BAR_GAUGE}/axial_stress"][:],
                fe[f"bars/{BAR_GAUGE}/axial_velocity"][:])
    return (fe["time"][:], fe[f"bars/{BAR_GAUGE}/axial_stress"][:],
            0.5 * (fe[f"nodes/{BAR_GAUGE_NODES[0]}/vz"][:] + fe[f"nodes/{BAR_GAUGE_NODES[1]}/vz"][:]))


def piston_peak(fe, impact_times):
    """Most compressive mean axial stress through the piston's gauge section
    (elastic scene), mean over the blows; None for the rigid piston."""
    if not elastic(fe) or PISTON_SECTION not in fe["sections"]:
        return None
    t = fe["time_elements"][:]
    s = fe[f"sections/{PISTON_SECTION}/fy"][:] / A_STRIKE
    peaks = []
    for ti in impact_times:
        i0, i1 = np.searchsorted(t, [ti - 20e-6, ti + 1.0e-3])
        if i1 < len(t):
            peaks.append(s[i0:i1].min())
    return float(np.mean(peaks)) if peaks else None


HOUSING_SECTION = "151"                 # the cylinder wall at the housing's gauge (elastic: y = 0.45 m, rig: 0.205 m)


def lowpass(x, dt, cutoff=500.0):
    """Gaussian low-pass with a -3 dB point at `cutoff` (the host's report
    filter, tlm_host/src/percussion_report.cpp)."""
    sigma = np.sqrt(np.log(2.0) / (4.0 * np.pi**2)) / cutoff / dt
    if sigma < 0.5:
        return x
    half = int(np.ceil(3.0 * sigma))
    k = np.exp(-0.5 * (np.arange(-half, half + 1) / sigma) ** 2)
    k /= k.sum()
    return np.convolve(np.pad(x, half, mode="edge"), k, mode="valid")


def housing(fe, impact_times):
    """The rig scene's housing over whole cycles (first to last evaluated
    impact), all low-passed at 500 Hz: displacement range [mm], peak
    acceleration [m/s²] and the range of the cylinder wall's mean axial
    stress [MPa]. None without a housing port."""
    if "ports/housing.x" not in fe or len(impact_times) < 2:
        return None
    t = fe["time"][:]
    dt = t[1] - t[0]
    s = (t >= impact_times[0]) & (t <= impact_times[-1])
    x = lowpass(fe["ports/housing.x"][:], dt)
    a = np.gradient(lowpass(fe["ports/housing.v"][:], dt), dt)
    out = {"h_x": 1e3 * (x[s].max() - x[s].min()), "h_a": float(np.abs(a[s]).max())}
    if "sections" in fe and HOUSING_SECTION in fe["sections"]:
        te = fe["time_elements"][:]
        sig = lowpass(fe[f"sections/{HOUSING_SECTION}/fy"][:] / A_HOUSING, te[1] - te[0])
        se = (te >= impact_times[0]) & (te <= impact_times[-1])
        out["h_sigma"] = 1e-6 * (sig[se].max() - sig[se].min())
    return out


def plateau_and_length(ts, s):
    """A compressive stress pulse's plateau and length: the plateau guessed as
    the median after the front's ringing (30–200 µs after it passes half the
    peak), its length between the crossings of half that plateau, and the
    plateau then the mean over the pulse's middle half. (nan, nan) if the
    record ends inside the pulse. Shared with bench/hammer_mesh_study.py."""
    k = int(np.argmin(s))
    first = int(np.argmax(s < 0.5 * s[k]))
    guess = np.median(s[(ts > ts[first] + 30e-6) & (ts < ts[first] + 200e-6)])
    rise = np.interp(0.5 * guess, [s[first], s[max(first - 1, 0)]], [ts[first], ts[max(first - 1, 0)]])
    after = first + int(np.argmax(s[first:] > 0.5 * guess))
    if after == first or after >= len(s):
        return float("nan"), float("nan")
    fall = np.interp(0.5 * guess, [s[after - 1], s[after]], [ts[after - 1], ts[after]])
    length = fall - rise
    mid = (ts > rise + 0.25 * length) & (ts < fall - 0.25 * length)
    return (float(np.mean(s[mid])) if mid.any() else float("nan")), float(length)


def primary_end(s):
    """Index where the primary (first) compressive pulse of the down-going
    stress s ends: from its first sample below 30 % of the window's most
    compressive value, the first sample above 2 % of the pulse's own peak so
    far (a rigid piston's pulse decays exponentially; an elastic piston's
    ends at its transit time). A later pulse in the same window (the
    housing's stop ring landing on the tool, a second contact) is not
    counted: on the rig one blow in 33 had the housing land 230 us after the
    piston, and W over both was 147 % of the piston's ½mv²."""
    start = int(np.argmax(s < 0.3 * s.min()))
    running = np.minimum.accumulate(s[start:])
    after = np.nonzero(s[start:] > 0.02 * running)[0]
    return start + (int(after[0]) if len(after) else len(s) - start)


def primary_pulses(fe, impact_times):
    """Per blow: W from the down-going stress of the primary pulse, the peak
    compressive stress, and the pulse's plateau (mean over its middle half)
    and length (between the crossings of half the plateau). σ_d = (σ + ρ·c0·v)/2
    separates the down-going wave from the one reflected at the rock (1D wave
    relations: σ = ρc·v for a wave moving down, σ = −ρc·v moving up)."""
    t, sigma, v = gauge(fe)
    sigma_d = 0.5 * (sigma + RHO * C0 * v)
    out = {"W": [], "peak": [], "plateau": [], "length": [], "t": []}
    for ti in impact_times:
        i0, i1 = np.searchsorted(t, [ti - 20e-6, ti + 1.0e-3])
        if i1 >= len(t) or i1 - i0 < 10:
            continue
        s, ts = sigma_d[i0:i1], t[i0:i1]
        end = primary_end(s)
        out["W"].append(AREA * C0 / E * np.trapz(s[:end] ** 2, ts[:end]))
        out["peak"].append(sigma[i0:i1].min())
        plateau, length = plateau_and_length(ts[:end], s[:end])
        out["plateau"].append(plateau)
        out["length"].append(length)
        out["t"].append(ti)
    means = {k: (float(np.mean(v)) if v else float("nan")) for k, v in out.items()}
    means["blows"] = out
    # The blows differ: each new pulse meets what is still ringing in the
    # piston, tool and anvil from the last (nothing but the contacts and
    # bulk viscosity damps the steel), so the spread is reported with the mean.
    means["plateau_sd"] = float(np.std(out["plateau"])) if len(out["plateau"]) > 1 else 0.0
    return means


def hourglass_per_cycle(fe, impact_times):
    """The FE's hourglass energy per impact cycle [J] between the first and
    the last impact, and per part where fe.h5 has it
    (part_energy/hourglass/<id>): the viscous hourglass control dissipates
    what the zero-energy modes take. None without two impacts."""
    if "energy" not in fe or "hourglass" not in fe["energy"] or len(impact_times) < 2:
        return None
    t = fe["time"][:]
    i0, i1 = (min(int(np.searchsorted(t, x)), len(t) - 1) for x in (impact_times[0], impact_times[-1]))
    cycles = len(impact_times) - 1
    per_part = {}
    if "part_energy/hourglass" in fe:
        for pid, series in fe["part_energy/hourglass"].items():
            e = (series[i1] - series[i0]) / cycles
            if e > 0.0:
                per_part[int(pid)] = float(e)
    return float((fe["energy/hourglass"][i1] - fe["energy/hourglass"][i0]) / cycles), per_part


def ringing(fe, impact_times, section, area):
    """What the next blow meets: the rms (about its mean) of the mean axial
    stress through a gauge section in the 4 ms before each impact (ending
    0.5 ms before it), mean over the impacts after the first [MPa]. Steel
    with nothing but the contacts to damp it rings on between blows."""
    if not elastic(fe) or section not in fe["sections"] or len(impact_times) < 2:
        return None
    t = fe["time_elements"][:]
    s = fe[f"sections/{section}/fy"][:] / area
    out = []
    for ti in impact_times[1:]:
        i0, i1 = np.searchsorted(t, [ti - 4.5e-3, ti - 0.5e-3])
        if i1 - i0 > 10:
            w = s[i0:i1]
            out.append(float(np.sqrt(np.mean((w - w.mean()) ** 2))))
    return 1e-6 * float(np.mean(out)) if out else None


def impact_velocities(host, times):
    """Each blow's impact velocity [m/s, down positive]: the piston's velocity
    relative to the housing on the last row before the impact time (as
    tlm_host's report reads it)."""
    t = host["time"][:]
    v = host["components/mech/v"][:]
    return [float(-v[max(int(np.searchsorted(t, ti)) - 1, 0)]) for ti in times]


def blow_statistics(pulses, velocities):
    """Per-blow figures of one co-simulation: for each blow whose primary
    pulse the record holds, ½mv² (m: the FE piston's), W from the tool's
    stress, their ratio, the plateau against the 1D estimate at that blow's
    velocity, the length, the peak stress; and the impact period from the
    blows' times. Returns {figure: list}."""
    b = pulses["blows"]
    stats = {"v": [], "W_kin": [], "W_stress": [], "W_ratio": [], "plateau": [], "plateau_ratio": [],
             "length": [], "peak": []}
    for i, ti in enumerate(b["t"]):
        v = velocities[i]
        w_kin = 0.5 * M_PISTON * v * v
        level = -v * RHO * C0 * A_STRIKE / (A_STRIKE + AREA)
        stats["v"].append(v)
        stats["W_kin"].append(w_kin)
        stats["W_stress"].append(b["W"][i])
        stats["W_ratio"].append(b["W"][i] / w_kin if w_kin > 0 else float("nan"))
        stats["plateau"].append(1e-6 * b["plateau"][i])
        stats["plateau_ratio"].append(b["plateau"][i] / level if level != 0 else float("nan"))
        stats["length"].append(1e6 * b["length"][i])
        stats["peak"].append(1e-6 * b["peak"][i])
    stats["period"] = [1e3 * d for d in np.diff(b["t"])]
    return stats


STAT_ROWS = [("v", "impact velocity [m/s]", "{:.3f}"), ("period", "impact period [ms]", "{:.2f}"),
             ("W_kin", "½mv² [J]", "{:.0f}"), ("W_stress", "W from tool stress [J]", "{:.0f}"),
             ("W_ratio", "W / ½mv²", "{:.3f}"), ("plateau", "tool pulse plateau [MPa]", "{:.1f}"),
             ("plateau_ratio", "plateau / 1D estimate", "{:.3f}"), ("length", "tool pulse length [us]", "{:.0f}"),
             ("peak", "peak tool stress [MPa]", "{:.0f}")]


def statistics_table(stats):
    """Mean, standard deviation, range and count of each per-blow figure."""
    lines = ["| per blow | mean | sd | min | max | blows |", "|---|---|---|---|---|---|"]
    for key, text, fmt in STAT_ROWS:
        x = np.array([v for v in stats.get(key, []) if np.isfinite(v)])
        if len(x) == 0:
            continue
        cells = [fmt.format(x.mean()), fmt.format(x.std(ddof=1) if len(x) > 1 else 0.0), fmt.format(x.min()),
                 fmt.format(x.max()), str(len(x))]
        lines.append(f"| {text} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def blow_checks(stats):
    """The pulse checks on every blow: W at most 101 % of ½mv² (a primary pulse
    cannot carry more than the blow's kinetic energy; 1 % for the gauge's
    discretisation), each plateau within ±10 % of the 1D estimate."""
    w, pl = np.array(stats["W_ratio"]), np.array(stats["plateau_ratio"])
    if len(w) == 0:
        return [("every blow's pulse", "no blow's primary pulse in the record", "", False)]
    return [("every blow's W / ½mv²", f"{w.min():.3f}..{w.max():.3f} over {len(w)} blows", "≤ 1.01",
             bool(np.all(w <= 1.01))),
            ("every blow's plateau / 1D estimate", f"{pl.min():.3f}..{pl.max():.3f} over {len(pl)} blows",
             "0.90–1.10", bool(np.all(np.abs(pl - 1.0) <= 0.10)))]


def time_shift(ref, host):
    """Lag (s) maximising the cross-correlation of the piston lift after
    start-up, refined by a parabola through the three best lags; positive:
    the co-simulation runs later than the reference. NaN (printed "—") when
    the best lag lies on the ±400-sample window's edge: no peak within it."""
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
    # A best lag on the window's edge is no peak: the two runs' cycles drift
    # apart (their frequencies differ by a few %, so over 1.3 s the lift
    # slips by whole cycles) and any lag there is meaningless. The main job's
    # rig scene printed -8000 us, the window's bound, as if it were a shift.
    if k == 0 or k == len(cc) - 1:
        return float("nan")
    frac = 0.0
    if 0 < k < len(cc) - 1:
        den = cc[k - 1] - 2 * cc[k] + cc[k + 1]
        frac = 0.5 * (cc[k - 1] - cc[k + 1]) / den if den != 0 else 0.0
    return (lags[k] + frac) * dt


def outlet_pressure(h5, impact_times):
    """p_out: the mean pressure at the hammer's return node T over whole
    cycles (first to last evaluated impact), bar abs."""
    t = h5["time"][:]
    s = (t >= impact_times[0]) & (t <= impact_times[-1])
    return 1e-5 * float(np.mean(h5["nodes/nodeT.P1/p"][s]))


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
        ("p_in", "inlet pressure p_in [bar abs]", "{:.1f}"), ("p_out", "outlet pressure p_out [bar abs]", "{:.2f}"),
        ("p_A", "peak p_A [bar abs]", "{:.1f}"),
        ("p_B", "peak p_B [bar abs]", "{:.1f}"), ("p_control", "peak p_control [bar abs]", "{:.1f}"),
        ("sigma", "peak tool stress [MPa]", "{:.0f}"), ("plateau", "tool pulse plateau [MPa]", "{:.1f}"),
        ("length", "tool pulse length [us]", "{:.0f}"), ("sigma_p", "peak piston stress [MPa]", "{:.0f}"),
        ("h_x", "housing displacement range [mm]", "{:.3f}"), ("h_a", "housing peak acceleration [m/s²]", "{:.0f}"),
        ("h_sigma", "housing wall stress range [MPa]", "{:.2f}"),
        ("ring_p", "piston ringing before the next blow, rms [MPa]", "{:.2f}"),
        ("ring_t", "tool ringing before the next blow, rms [MPa]", "{:.2f}"),
        ("hg", "FE hourglass energy per cycle [J]", "{:.1f}"),
        ("shift", "time shift vs reference [us]", "{:.0f}"), ("wall", "wall time per simulated s [s]", "{:.1f}")]


PART_NAMES = {1: "piston", 2: "tool", 4: "anvil", 5: "housing"}


def fatigue_hot_spots(csv_path, blows, f):
    """The element with the most damage in each part (fe_server's
    <results>_fatigue.csv, *PCS_FATIGUE_PART), per blow: the run's damage
    over its blows (the start-up's blows included, so the figure per blow is
    on the safe side), the blows to crack initiation (damage 1) and the hours
    of operation they mean at the run's frequency f."""
    best = {}
    with open(csv_path) as fh:
        header = fh.readline().strip().split(",")
        for line in fh:
            r = dict(zip(header, line.strip().split(",")))
            part, damage = int(r["part"]), float(r["damage"])
            if part not in best or damage > best[part]["damage"]:
                best[part] = {"part": part, "element": int(r["element"]), "r_mm": 1e3 * float(r["x"]),
                              "y_mm": 1e3 * float(r["y"]), "range_MPa": 1e-6 * float(r["largest_range"]),
                              "damage": damage}
    out = []
    for part in sorted(best):
        b = best[part]
        b["per_blow"] = b["damage"] / blows if blows > 0 else float("nan")
        b["blows_to_initiation"] = 1.0 / b["per_blow"] if b["per_blow"] > 0 else float("inf")
        b["hours"] = b["blows_to_initiation"] / f / 3600.0 if f > 0 else float("nan")
        out.append(b)
    return out


def fatigue_section(results):
    """The report's fatigue table: per condition and part, its hot spot."""
    rows = []
    for cond, cols in results:
        for m, col in cols.items():
            for b in col.get("fatigue", []):
                rows.append(f"| {cond.name} | {PART_NAMES.get(b['part'], b['part'])} | {b['element']} at r {b['r_mm']:.1f}, "
                            f"y {b['y_mm']:.1f} mm | {b['range_MPa']:.0f} | {b['per_blow']:.3g} | "
                            f"{b['blows_to_initiation']:.3g} | {b['hours']:.3g} |")
    if not rows:
        return []
    return ["## Fatigue: crack initiation per part", "",
            "Counted during the co-simulation (`*PCS_FATIGUE_PART` in the deck: signed von Mises, rainflow, Basquin "
            "with Haibach's extension, Goodman; docs/fatigue.md), each part's element with the most damage. The "
            "S-N curves are smooth specimens' and the 9 mm mesh resolves no fillet: a fillet's notch factor KF "
            "raises its stress by KF and its damage by about KF^m (m 8-10 here), which the deck's KF takes when a "
            "design's fillets are known. Per blow: the run's damage over its blows, start-up included.", "",
            "| condition | part | hot spot | largest range [MPa] | damage per blow | blows to initiation | hours at the run's frequency |",
            "|---|---|---|---|---|---|---|"] + rows + [""]


def energy_balance(log):
    """fe_server's closing energy account: (error in % of the scale, bound in %)."""
    m = re.search(r"energy balance error \S+ J \(([-\d.e+]+) % of \S+ J, bound ([\d.]+) %\)", log)
    return (float(m.group(1)), float(m.group(2))) if m else (float("nan"), float("nan"))


def checks(col):
    """Issue 14's physics checks on one co-simulation (elastic scene)."""
    plateau_1d = -col["v"] * RHO * C0 * A_STRIKE / (A_STRIKE + AREA) / 1e6
    length_1d = 2.0 * L_PISTON / C0 * 1e6
    dp = 100.0 * (col["plateau"] / plateau_1d - 1.0)
    dl = 100.0 * (col["length"] / length_1d - 1.0)
    err, bound = col["balance"]
    spread = f" (sd {col['plateau_sd']:.1f} over the blows)" if col.get("plateau_sd") else ""
    return [("tool pulse plateau (mean of the blows) vs 1D impedance estimate",
             f"{col['plateau']:.1f}{spread} vs {plateau_1d:.1f} MPa ({dp:+.1f} %)",
             "≤ 5 %", abs(dp) <= 5.0),
            ("tool pulse length vs 2·L_piston/c0", f"{col['length']:.0f} vs {length_1d:.0f} us ({dl:+.1f} %)", "≤ 10 %",
             abs(dl) <= 10.0),
            ("FE energy balance over the run", f"{err:.3g} % of the energy held", f"≤ {bound:g} %", abs(err) <= bound)] + \
        hourglass_check(col)


def hourglass_check(col):
    """Hourglass energy per cycle against the blow's energy (issue 34: under
    5 %), with the parts that take most."""
    if col.get("hg") is None or not col.get("W_kin"):
        return []
    share = 100.0 * col["hg"] / col["W_kin"]
    parts = sorted(col.get("hg_parts", {}).items(), key=lambda kv: -kv[1])
    where = ", ".join(f"{PART_NAMES.get(pid, pid)} {100.0 * e / col['W_kin']:.1f}" for pid, e in parts[:4])
    return [("hourglass energy per cycle vs ½mv²", f"{share:.1f} %" + (f" ({where})" if where else ""), "≤ 5 %",
             share <= 5.0)]


def evaluate(cond):
    ref_js = json.loads((cond / "reference.json").read_text())
    cols = {"reference": figures(ref_js)}
    cols["reference"]["P_in"] = ref_js["input_power_W"]
    cols["reference"]["P_out"] = ref_js["output_power_W"]
    with h5py.File(cond / "reference.h5") as ref:
        cols["reference"]["p_out"] = outlet_pressure(ref, ref_js["impact_times_s"])
        for m in MODES:
            d = cond / m
            if not (d / "host.json").exists():
                continue
            js = json.loads((d / "host.json").read_text())
            col = figures(js)
            with h5py.File(d / "host.h5") as host, h5py.File(d / "fe.h5") as fe:
                pulses = primary_pulses(fe, js["impact_times_s"])
                col["W_stress"] = pulses["W"]
                col["sigma"] = 1e-6 * pulses["peak"]
                col["elastic"] = elastic(fe)
                if col["elastic"]:
                    col["plateau"] = 1e-6 * pulses["plateau"]
                    col["plateau_sd"] = 1e-6 * pulses["plateau_sd"]
                    col["length"] = 1e6 * pulses["length"]
                    peak_p = piston_peak(fe, js["impact_times_s"])
                    col["sigma_p"] = 1e-6 * peak_p if peak_p is not None else None
                    col["ring_p"] = ringing(fe, js["impact_times_s"], PISTON_SECTION, A_STRIKE)
                    col["ring_t"] = ringing(fe, js["impact_times_s"], SECTION, AREA)
                    hg = hourglass_per_cycle(fe, js["impact_times_s"])
                    if hg:
                        col["hg"], col["hg_parts"] = hg
                col["shift"] = 1e6 * time_shift(ref, host)
                col["p_out"] = outlet_pressure(host, js["impact_times_s"])
                col.update(housing(fe, js["impact_times_s"]) or {})
                if col["elastic"]:
                    col["stats"] = blow_statistics(pulses, impact_velocities(host, pulses["blows"]["t"]))
                t_end = host["time"][-1]
            col["wall"] = float((d / "wall_seconds").read_text()) / t_end
            col["balance"] = energy_balance((d / "fe_server.log").read_text()) if (d / "fe_server.log").exists() \
                else (float("nan"), float("nan"))
            if (d / "fe_fatigue.csv").exists():
                col["fatigue"] = fatigue_hot_spots(d / "fe_fatigue.csv", len(js["impact_times_s"]), col["f"])
            col["P_in"] = js["input_power_W"]
            col["P_out"] = col["W_stress"] * col["f"] if np.isfinite(col["W_stress"]) else js["output_power_W"]
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
    """One condition's signals over the last 0.1 s, co-simulation against the
    monolithic reference: piston lift, spool, the pressures (cavity A raw and
    at the report's 500 Hz, cavity B, the inlet), the p-x indicator diagram
    of cavities A and B over the last whole cycles, and the tool's stress
    pulse of the last evaluated blow (total and down-going)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig = plt.figure(figsize=(13, 13))
    grid = fig.add_gridspec(4, 2, width_ratios=[1.6, 1])
    ax = [fig.add_subplot(grid[0, 0]), fig.add_subplot(grid[1, 0]), fig.add_subplot(grid[2, 0]),
          fig.add_subplot(grid[3, 0])]
    px = fig.add_subplot(grid[0:2, 1])
    fq = fig.add_subplot(grid[2, 1])
    words = condition_words(cond.name)

    def signals(h5, x_name, spool_name, label, style):
        t = h5["time"][:]
        s = t > t[-1] - 0.1
        dt = t[1] - t[0]
        x = h5[x_name][:]
        ax[0].plot(1e3 * t[s], 1e3 * x[s], **style, label=label)
        ax[1].plot(1e3 * t[s], 1e3 * h5[spool_name][s], **style, label=label)
        pa = h5["nodes/cavA.P2/p"][:]
        ax[2].plot(1e3 * t[s], 1e-5 * pa[s], **style, alpha=0.35)
        ax[2].plot(1e3 * t[s], 1e-5 * lowpass(pa, dt)[s], **style, label=f"{label}: p_A (500 Hz)")
        if "nodes/cavB.P2/p" in h5:
            ax[2].plot(1e3 * t[s], 1e-5 * lowpass(h5["nodes/cavB.P2/p"][:], dt)[s], **style, ls="--",
                       label=f"{label}: p_B (500 Hz)")
        if "nodes/supply_hose.P2/p" in h5:
            ax[2].plot(1e3 * t[s], 1e-5 * lowpass(h5["nodes/supply_hose.P2/p"][:], dt)[s], **style, ls=":",
                       label=f"{label}: p_in (500 Hz)")
        if "components/fit_P/q" in h5:  # the hammer's inlet flow (the report's Q_in)
            q = 6e4 * h5["components/fit_P/q"][:]
            fq.plot(1e3 * t[s], q[s], **style, alpha=0.35)
            fq.plot(1e3 * t[s], lowpass(q, dt)[s], **style, label=f"{label} (500 Hz; mean of this 0.1 s {q[s].mean():.1f})")
        # the indicator diagram: each cavity's pressure over the piston's lift, last 0.1 s
        px.plot(1e3 * x[s], 1e-5 * pa[s], **style, label=f"{label}: cavity A")
        if "nodes/cavB.P2/p" in h5:
            px.plot(1e3 * x[s], 1e-5 * h5["nodes/cavB.P2/p"][s], **style, ls="--", label=f"{label}: cavity B")

    with h5py.File(cond / "reference.h5") as ref:
        signals(ref, "components/piston/x", "components/spool/x", "monolithic", dict(color="k", lw=1.6))
    for m in MODES:
        if m not in cols:
            continue
        with h5py.File(cond / m / "host.h5") as host:
            signals(host, "components/mech/x", "components/smech/x", f"co-simulation ({MODE_TEXT[m]})",
                    dict(color="C0", lw=1.2))
        with h5py.File(cond / m / "fe.h5") as fe:
            js = json.loads((cond / m / "host.json").read_text())
            ti = js["impact_times_s"][-1]
            t, sigma, v = gauge(fe)
            s = (t > ti - 50e-6) & (t < ti + 800e-6)
            line = ax[3].plot(1e6 * (t[s] - ti), 1e-6 * sigma[s], label=f"{MODE_TEXT[m]}: stress")[0]
            ax[3].plot(1e6 * (t[s] - ti), 1e-6 * 0.5 * (sigma[s] + RHO * C0 * v[s]), "--", color=line.get_color(),
                       label=f"{MODE_TEXT[m]}: down-going part")
            if cols[m].get("elastic"):
                ax[3].axhline(-cols[m]["v"] * RHO * C0 * A_STRIKE / (A_STRIKE + AREA) / 1e6, color="k", ls=":",
                              label="1D impedance estimate (measured impact velocity)")
    fig.suptitle(f"{words}: the last 0.1 s of the run", fontsize=13)
    ax[0].set(xlabel="time [ms]", ylabel="piston lift [mm]")
    ax[1].set(xlabel="time [ms]", ylabel="spool position [mm]")
    ax[2].set(xlabel="time [ms]", ylabel="pressure [bar abs]",
              title="cavity A raw (faint) and at 500 Hz, cavity B and the inlet at 500 Hz")
    ax[3].set(xlabel="time after the last evaluated impact [µs]", ylabel="tool stress at the gauge [MPa]",
              title="stress 200 mm below the tool's top (compression negative)")
    px.set(xlabel="piston lift [mm]", ylabel="pressure [bar abs]",
           title="indicator diagram: the cavities' pressure over the lift")
    fq.set(xlabel="time [ms]", ylabel="inlet flow [l/min]", title="the hammer's inlet flow, raw (faint) and at 500 Hz")
    for a in ax + [px, fq]:
        a.grid(alpha=0.3)
    for a in ax[:2]:
        a.legend(fontsize=8, loc="upper right")
    top = ax[2].get_ylim()[1]
    ax[2].set_ylim(top=1.45 * top)  # room for the legend above the traces
    ax[2].legend(fontsize=7, loc="upper center", ncol=2)
    if fq.lines:
        fq.legend(fontsize=8, loc="upper right")
    ax[3].legend(fontsize=8, loc="lower right")
    px.legend(fontsize=8, loc="upper right")
    fig.tight_layout(rect=(0, 0, 1, 0.97))
    fig.savefig(cond / "hammer.png", dpi=110)
    plt.close(fig)


def blows_plot(cond, cols):
    """One condition's whole run, blow by blow (blows.png): the impact
    velocity and the period per blow, co-simulation against the monolithic
    reference; every blow's tool pulse at the gauge overlaid on its impact
    time; the housing's recoil over the run (raw and at 500 Hz); and the FE
    energies over the run, with the balance error (what the energy verdict
    sums). Returns the number of pulses overlaid (a blow whose record ends
    within 800 µs of its impact is left out), None without an elastic
    co-simulation."""
    m = next((m for m in MODES if m in cols and cols[m].get("elastic")), None)
    if m is None:
        return None
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(2, 2, figsize=(13, 9))
    trend, pulses, recoil, energy = ax[0, 0], ax[0, 1], ax[1, 0], ax[1, 1]
    js = json.loads((cond / m / "host.json").read_text())
    ref_js = json.loads((cond / "reference.json").read_text())
    times = js["impact_times_s"]
    with h5py.File(cond / m / "host.h5") as host:
        v = impact_velocities(host, times)
    with h5py.File(cond / "reference.h5") as ref:
        t = ref["time"][:]
        vr = ref["components/piston/v"][:]
        v_ref = [float(-vr[max(int(np.searchsorted(t, ti)) - 1, 0)]) for ti in ref_js["impact_times_s"]]
    twin = trend.twinx()
    for label, ts, vs, style in (("monolithic", ref_js["impact_times_s"], v_ref, dict(color="k", marker="s", ms=4)),
                                 (f"co-simulation ({MODE_TEXT[m]})", times, v, dict(color="C0", marker="o", ms=4))):
        trend.plot(1e3 * np.array(ts), vs, lw=1, **style, label=f"{label}: impact velocity")
        twin.plot(1e3 * np.array(ts[1:]), 1e3 * np.diff(ts), lw=1, ls="--", mfc="none", **style,
                  label=f"{label}: period to the blow")
    trend.set(xlabel="impact time [ms]", ylabel="impact velocity [m/s]",
              title="per blow: impact velocity (solid) and the period before it (dashed)")
    twin.set_ylabel("period [ms]")
    lines = trend.get_legend_handles_labels(), twin.get_legend_handles_labels()
    trend.legend(lines[0][0] + lines[1][0], lines[0][1] + lines[1][1], fontsize=7, loc="upper center",
                 bbox_to_anchor=(0.5, -0.13), ncol=2)  # below the axes: the points fill them
    with h5py.File(cond / m / "fe.h5") as fe:
        tg, sigma, _ = gauge(fe)
        cmap = plt.get_cmap("viridis")
        drawn = 0
        for i, ti in enumerate(times):
            s = (tg > ti - 50e-6) & (tg < ti + 800e-6)
            if s.sum() > 10 and tg[-1] > ti + 800e-6:
                drawn += 1
                pulses.plot(1e6 * (tg[s] - ti), 1e-6 * sigma[s], color=cmap(i / max(1, len(times) - 1)), lw=0.7)
        pulses.axhline(-cols[m]["v"] * RHO * C0 * A_STRIKE / (A_STRIKE + AREA) / 1e6, color="k", ls=":",
                       label="1D impedance estimate (mean impact velocity)")
        sm = plt.cm.ScalarMappable(cmap=cmap, norm=plt.Normalize(1e3 * times[0], 1e3 * times[-1]))
        fig.colorbar(sm, ax=pulses, label="impact time [ms]")
        pulses.set(xlabel="time after each impact [µs]", ylabel="tool stress at the gauge [MPa]",
                   title=f"every blow's tool pulse, overlaid ({drawn} blows; compression negative)")
        pulses.legend(fontsize=7, loc="lower right")
        if "ports/housing.x" in fe:
            t = fe["time"][:]
            x = 1e3 * fe["ports/housing.x"][:]
            recoil.plot(1e3 * t, x, color="C0", alpha=0.35, lw=0.7, label="raw")
            recoil.plot(1e3 * t, lowpass(x, t[1] - t[0]), color="C0", label="500 Hz")
            for ti in times:
                recoil.axvline(1e3 * ti, color="0.85", lw=0.5, zorder=0)
            recoil.set(xlabel="time [ms]", ylabel="housing displacement [mm] (up positive)",
                       title="the housing's recoil on its rig springs (grey: impacts)")
            recoil.legend(fontsize=8, loc="upper right")
        else:
            recoil.set_axis_off()
        if "energy" in fe:
            t = fe["time"][:]
            for name in ("kinetic", "internal", "hourglass", "damping", "contact", "external_work", "balance_error"):
                if name in fe["energy"]:
                    energy.plot(1e3 * t, 1e-3 * fe[f"energy/{name}"][:], lw=1.8 if name == "balance_error" else 1,
                                ls=":" if name == "balance_error" else "-", label=name.replace("_", " "))
            energy.set(xlabel="time [ms]", ylabel="energy [kJ]",
                       title="FE energies over the run (external work: oil and rig)")
            energy.legend(fontsize=7, loc="upper left")
    for a in (trend, pulses, recoil, energy):
        a.grid(alpha=0.3)
    fig.suptitle(f"{condition_words(cond.name)}: the whole run, blow by blow", fontsize=13)
    fig.tight_layout(rect=(0, 0, 1, 0.96))
    fig.savefig(cond / "blows.png", dpi=110)
    plt.close(fig)
    return drawn


def power_plot(out, results):
    """The thesis' Fig. 16: input power p_in·Q_in and output power W·f
    against the restrictor diameter, one line per supply pressure."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 4.5))
    by_p = {}
    for cond, cols in results:
        p, d = int(cond.name.split("bar")[0]), float(cond.name.split("_")[1][:-2])
        mode = next((m for m in MODES if m in cols), None)
        by_p.setdefault(p, []).append((d, cols["reference"], cols.get(mode)))
    for p, rows in sorted(by_p.items()):
        rows.sort()
        d = [r[0] for r in rows]
        line = ax.plot(d, [r[1]["P_in"] / 1e3 for r in rows], "o--", label=f"{p} bar: input p_in·Q_in (reference)")[0]
        if all(r[2] for r in rows):
            ax.plot(d, [r[2]["P_in"] / 1e3 for r in rows], "o-", color=line.get_color(),
                    label=f"{p} bar: input (co-simulation)")
            ax.plot(d, [r[2]["P_out"] / 1e3 for r in rows], "s-", color=line.get_color(), mfc="none",
                    label=f"{p} bar: output W·f (co-simulation, W from tool stress)")
        ax.plot(d, [r[1]["P_out"] / 1e3 for r in rows], "s--", color=line.get_color(), mfc="none",
                label=f"{p} bar: output ½mv²·f (reference)")
    ax.set(xlabel="restrictor diameter [mm]", ylabel="power [kW]", title="Input and output power (thesis Fig. 16)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "power.png", dpi=110)
    plt.close(fig)


def stress_field_picture(out):
    """The blow alone (run_hammer.sh: impact/impact_fields.h5): the axial
    stress in piston, tool and anvil at four moments after the first
    contact, drawn on the undeformed r–y mesh mirrored about the axis, the
    axis lying along the page (the bodies are long and slender: upright, the
    radius got too little room for its labels). Returns the part ids drawn;
    None when the run is absent."""
    h5, xdmf = out / "impact" / "impact_fields.h5", out / "impact" / "impact_fields.xdmf"
    if not h5.exists() or not xdmf.exists():
        return None
    import re
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import PolyCollection
    times = [float(t) for t in re.findall(r'Time Value="([^"]+)"', xdmf.read_text())]
    with h5py.File(h5) as f:
        xy = 1e3 * f["mesh/coordinates"][:, :2]  # mm
        quads = f["mesh/topology"][:]
        part = f["mesh/part"][:]
        keys = sorted(f["fields"].keys())
        picks = [k for k in (2, 6, 11, 15) if k < len(keys)]
        sigma = [f[f"fields/{keys[k]}/stress_axial"][:] / 1e6 for k in picks]
    # y along the page, r across it; mirrored about the axis. Every part:
    # the anvil under the tool too.
    shown = np.ones(len(quads), dtype=bool)
    polys = xy[quads[shown]][:, :, ::-1]
    mirrored = polys * np.array([1.0, -1.0])
    lim = max(np.abs(s).max() for s in sigma)
    fig, ax = plt.subplots(len(picks), 1, figsize=(12, 2.1 * len(picks) + 1.2), sharex=True)
    ax = np.atleast_1d(ax)
    for a, k, s in zip(ax, picks, sigma):
        for p in (polys, mirrored):
            pc = PolyCollection(p, array=s[shown], cmap="RdBu", clim=(-lim, lim), edgecolors="none")
            a.add_collection(pc)
        a.set_xlim(xy[:, 1].min() - 10, xy[:, 1].max() + 10)
        a.set_ylim(-1.3 * xy[:, 0].max(), 1.3 * xy[:, 0].max())
        a.set_aspect("equal")
        a.set_ylabel("r [mm]")
        a.set_title(f"{1e6 * times[k]:.0f} µs after contact", fontsize=9, loc="left")
        bodies = {1: "piston", 2: "tool", 4: "anvil"}
        for pid, name in bodies.items():
            nodes = np.unique(quads[part == pid])
            if len(nodes):
                a.text(0.5 * (xy[nodes, 1].min() + xy[nodes, 1].max()), 1.05 * xy[:, 0].max(), name, ha="center",
                       va="bottom", fontsize=8)
    ax[-1].set_xlabel("y [mm] (the contact at 0: tool below, piston above, the anvil under the tool)")
    fig.colorbar(pc, ax=ax, shrink=0.8, label="axial stress [MPa] (compression negative)")
    fig.suptitle("The blow: axial stress in piston, tool and anvil", fontsize=11)
    fig.savefig(out / "stress_field.png", dpi=110)
    plt.close(fig)
    return sorted(int(i) for i in np.unique(part[shown]))


TABLE2_CSV = pathlib.Path(__file__).resolve().parents[1] / "scenes/hammer_monolithic/thesis_table2.csv"
CASE_OF = {("150", "6.0"): "c11", ("150", "5.4"): "c12", ("100", "6.0"): "c21", ("100", "5.4"): "c22"}


def rig_section(results):
    """Flow against the rig's Table 2 (Andersson 2018), as Table 3 states it: simulated / measured in %,
    and the three ratios the rig's trend is made of."""
    measured = {}
    for line in TABLE2_CSV.read_text().splitlines():
        cells = [c.strip() for c in line.split(",")]
        if len(cells) == 2 and cells[0].startswith("c") and cells[0] != "case":
            measured[cells[0]] = float(cells[1])
    flows, figs = {}, {}
    for cond, cols in results:
        p, d = cond.name.split("bar_")[0], cond.name.split("_")[1][:-2]
        case = CASE_OF.get((p, d))
        if case:
            flows[case] = {n: col["Q_in"] for n, col in cols.items()}
            figs[case] = (float(p), cols)
    if len(flows) < 4:
        return [], []
    names = list(flows["c11"])
    label = lambda n: "reference" if n == "reference" else MODE_TEXT[n]
    md = ["## Against the rig: oil flow (thesis Table 2)", "",
          "Measured flows from H. Andersson, *A Co-Simulation Approach for Hydraulic Percussion Units* (Linköping 2018), "
          "Table 2; our flow as % of them (the thesis' own model gave 105.3 / 108.8 / 114.9 / 117.3 %, Table 3).", "",
          "| case | measured [l/min] | " + " | ".join(f"{label(n)} [l/min] (% of measured)" for n in names) + " |",
          "|---" * (len(names) + 2) + "|"]
    for case in ("c11", "c12", "c21", "c22"):
        md.append(f"| {case[1:]} | {measured[case]:.0f} | " +
                  " | ".join(f"{flows[case][n]:.1f} ({100 * flows[case][n] / measured[case]:.1f} %)" for n in names) + " |")
    ratios = [("Ø5.4 / Ø6.0 at 150 bar", "c12", "c11", "0.80–0.86"), ("Ø5.4 / Ø6.0 at 100 bar", "c22", "c21", "0.82–0.88"),
              ("100 / 150 bar at Ø6.0", "c21", "c11", "0.71–0.79")]
    md += ["", "| flow ratio | measured | " + " | ".join(label(n) for n in names) + " | wanted |",
           "|---" * (len(names) + 3) + "|"]
    failed = []
    for text, a, b, band in ratios:
        lo, hi = (float(x) for x in band.split("–"))
        cells = []
        for n in names:
            r = flows[a][n] / flows[b][n]
            ok = lo <= r <= hi
            cells.append(f"{r:.3f}" + ("" if ok else " (**outside**)"))
            if not ok:
                failed.append(f"flow ratio {text} ({label(n)}): {r:.3f} outside {band}")
        md.append(f"| {text} | {measured[a] / measured[b]:.3f} | " + " | ".join(cells) + f" | {band} |")
    # The acceptance figures per condition (the validated-hammer work's bands).
    md += ["", "| case | " + " | ".join(f"{label(n)}: Q / measured, p_in / set, f" for n in names) + " |",
           "|---" * (len(names) + 1) + "|"]
    for case in ("c11", "c12", "c21", "c22"):
        p_bar, cols = figs[case]
        p_set = p_bar + 1.013
        cells = []
        for n in names:
            col = cols[n]
            q_r, p_r, f = col["Q_in"] / measured[case], col["p_in"] / p_set, col["f"]
            bad = [what for what, ok in (("Q ±10 %", abs(q_r - 1) <= 0.10), ("p_in ±1 %", abs(p_r - 1) <= 0.01),
                                         ("f 15–30 Hz", 15.0 <= f <= 30.0)) if not ok]
            cells.append(f"{q_r:.3f}, {p_r:.4f}, {f:.1f} Hz" + (f" (**outside: {', '.join(bad)}**)" if bad else ""))
            failed += [f"case {case[1:]} ({label(n)}): {b}" for b in bad]
        md.append(f"| {case[1:]} | " + " | ".join(cells) + " |")
    md += ["", "Wanted: each flow within ±10 % of the measured one, the mean inlet pressure within ±1 % of the set "
           "(gauge + 1.013 bar), the frequency in 15–30 Hz. Where a ratio is near 1, the layout's flow does not "
           "follow the restrictor as the rig's did.", ""]
    return md, failed


# What the rig scene's housing figures depend on: case 11 co-simulated for
# 0.8 s with one rig parameter changed at a time (docs/hammer.md, "The
# housing's figures and the rig"), against the deck's own rig.
RIG_HOUSING_NOTE = (
    "The housing's figures are this rig's as much as the hammer's: with the feed spring half as stiff (2e6 to "
    "1e6 N/m, the same 10 kN preload) the housing's displacement range rises by 27 % and its peak acceleration "
    "falls by 10 %; with the carrier bracket's mass doubled (30 to 60 kg) they move by -4 % and -7 % and the "
    "wall's stress range by +8 % (case 11, 0.8 s runs; docs/hammer.md). Compare them between designs on the "
    "same rig settings. A rerun of the same build gives the same figures bit for bit.")


def sweep_section(out):
    """The thesis' Fig. 16 as a sweep: run_hammer.sh runs scripts/sweep.py
    fig16 on the scene's monolithic model into out/fig16; shown only when
    that sweep is of this scene's model (a folder left from another scene's
    run is named, not shown)."""
    plan_file, table_file = out / "fig16" / "points.json", out / "fig16" / "fig16.md"
    if not (plan_file.exists() and table_file.exists()):
        return []
    model = pathlib.Path(json.loads(plan_file.read_text())["model"]).resolve()
    ours = (pathlib.Path(__file__).resolve().parents[1] / "scenes" / SCENE / "model.tlm").resolve()
    if model != ours:
        return ["## Restrictor sweep", "", f"`fig16/` holds a sweep of `{model}`, not of this scene's `{ours}`: "
                "not shown (rerun scripts/run_hammer.sh, or scripts/sweep.py fig16 --model for this scene).", ""]
    rows = {}
    for line in table_file.read_text().splitlines():
        cells = [c.strip() for c in line.strip("|").split("|")]
        try:
            rows[(float(cells[0]), float(cells[1]))] = float(cells[3])
        except (IndexError, ValueError):
            continue  # the header
    md = ["## Restrictor sweep on the monolithic model (thesis Fig. 16)", "",
          "Seven restrictor diameters at 100 and 150 bar (`scripts/sweep.py fig16`, each pressure's relief setting "
          "as calibrated in conditions.csv): input power p_in·Q_in normalised to the rig's measured Case 11 "
          "(150 bar × 80 l/min), output power W·f and efficiency normalised to the simulated Case 11; the open "
          "squares are the rig's Table 2 points.", ""]
    if (150.0, 5.4) in rows and (150.0, 6.0) in rows:
        slope = (rows[(150.0, 6.0)] - rows[(150.0, 5.4)]) / 0.6
        rig = (80.0 - 66.0) / 80.0 / 0.6  # Table 2: 80 and 66 l/min at 150 bar
        md += [f"Input power against the diameter at 150 bar, Ø5.4 to 6.0 mm: {slope:.3f} of Case 11 per mm "
               f"(the rig: {rig:.3f}).", ""]
    md += table_file.read_text().splitlines() + ["", "![restrictor sweep](fig16/fig16.png)", ""]
    return md


def main():
    args = sys.argv[1:]
    scene_name = None  # --scene NAME: the runs' scene, where a study's port table lies outside it
    if "--scene" in args:
        i = args.index("--scene")
        if i + 1 >= len(args) or args[i + 1] not in GEOMETRY:
            sys.exit(f"hammer_report.py: --scene: expected one of {', '.join(GEOMETRY)}")
        scene_name = args[i + 1]
        del args[i:i + 2]
    out = pathlib.Path(args[0] if args else "out/hammer")
    conds = sorted((d for d in out.glob("*bar_*mm") if (d / "reference.json").exists()),
                   key=lambda d: (-int(d.name.split("bar")[0]), -float(d.name.split("_")[1][:-2])))
    if not conds:
        sys.exit(f"hammer_report.py: no runs under {out}")
    use_scene(scene_of(conds, scene_name))
    results = [(cond, evaluate(cond)) for cond in conds]
    is_elastic = any(col.get("elastic") for _, cols in results for col in cols.values())
    scene = ("the elastic piston, tool, housing and anvil (axisymmetric) on the test rig, preloaded, with the "
             "rigid spool in its bore, in fe_server" if is_elastic
             else "the rigid piston and spool, the 1D-bar tool and the rock in fe_server")
    if SCENE == "hammer_rig":
        scene = "the hammer reworked against the thesis' rig (scenes/hammer_rig): " + scene
    md = ["# Hydraulic hammer: co-simulation against the monolithic reference", "",
          f"Written by scripts/run_hammer.sh (scripts/hammer_report.py). Co-simulation: {scene};",
          "the hydraulics in tlm_host. Reference: the monolithic TLM model (rigid piston, lumped tool).",
          "In brackets: difference to the reference. Whole cycles after 0.3 s; pressures low-pass",
          "filtered at 500 Hz, the housing's quantities too. W from tool stress: the down-going primary pulse 200 mm below the tool's",
          "top, W = (A·c0/E)·∫σ² dt. Time shift: lag of the piston lift's cross-correlation (— where its best lag lies on the ±400-sample window's edge: the cycles drift apart), positive",
          "when the co-simulation is later.", ""]
    if SCENE == "hammer_rig" and is_elastic:
        md += [RIG_HOUSING_NOTE, ""]
    failed = []
    for cond, cols in results:
        md += [f"## {cond.name.replace('bar_', ' bar, restrictor Ø').replace('mm', ' mm')}", "", table(cols), ""]
        for m, col in cols.items():
            if m == "reference" or not col.get("elastic"):
                continue
            md += [f"Physics checks ({MODE_TEXT[m]}):", "", "| check | measured | bound | |", "|---|---|---|---|"]
            for what, measured, bound, ok in checks(col) + blow_checks(col["stats"]):
                md.append(f"| {what} | {measured} | {bound} | {'holds' if ok else '**fails**'} |")
                if not ok:
                    failed.append(f"{cond.name} {m}: {what}: {measured}")
            md += ["", f"Per-blow statistics ({MODE_TEXT[m]}, every blow after the settle time whose primary pulse "
                   "the record holds):", "", statistics_table(col["stats"]), ""]
        md += [f"![{cond.name}]({cond.name}/hammer.png)", ""]
        plot(cond, cols)
        if blows_plot(cond, cols) is not None:
            md += [f"![{cond.name}, blow by blow]({cond.name}/blows.png)", ""]
        print(f"{cond.name}:")
        print(table(cols))
    if len(results) > 1:
        power_plot(out, results)
        md += ["## Input and output power against the restrictor (thesis Fig. 16)", "", "![power](power.png)", ""]
    rig_md, rig_failed = rig_section(results)
    md += rig_md
    md += sweep_section(out)
    md += fatigue_section(results)
    failed += rig_failed
    if stress_field_picture(out):
        md += ["## The stress field at impact", "",
               "The blow alone (`impact/impact.k`: the same piston, tool and anvil meshes, no housing or oil) at the "
               "impact velocity of the first condition's co-simulation; the stress wave enters the tool while the "
               "piston's own wave runs up and back. The snapshots are in `impact/impact_fields.xdmf` for ParaView.", "",
               "![stress field](stress_field.png)", ""]
    if failed:
        md += ["## Checks that fail", ""] + [f"- {f}" for f in failed] + [""]
    (out / "report.md").write_text("\n".join(md) + "\n")
    print(f"report: {out / 'report.md'}")
    for f in failed:
        print(f"hammer_report.py: check fails: {f}", file=sys.stderr)


if __name__ == "__main__":
    main()
