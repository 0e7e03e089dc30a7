#!/usr/bin/python3
"""Parameter sweeps of a monolithic model: every point of a grid is one
tlm_host run with its percussion report, on every core of this machine, or
as a SLURM job array whose tasks run the same points with the same code.

  sweep.py run MODEL --grid C.P=V1,V2,... [--grid ...] [--set C.P=V ...] --out DIR [--jobs N]
  sweep.py slurm MODEL --grid ... [--set ...] --out DIR [--time 00:10:00]   (prints the job script)
  sweep.py point MODEL --grid ... [--set ...] --out DIR --index I            (one point: a SLURM task)
  sweep.py collect DIR                                                       (DIR/sweep.csv from the points)
  sweep.py fig16 --out DIR [--model MODEL] [--diameters 5.0,5.4,...] [--pressures 100,150] [--jobs N] [--set ...]

The grid is the product of the --grid lists, the last varying fastest; point
I's report is DIR/point_I.json and DIR/points.json lists every point's
settings. fig16 sweeps the hammer's restrictor diameter at each operating
pressure (thesis Fig. 16, Andersson 2018) and plots the input power p_in*Q_in,
the output power W*f and the efficiency, each normalised to Case 11
(150 bar, 6.0 mm), with the rig's Table 2 input powers marked. Its model is
scenes/hammer_rig/model.tlm unless --model names another; where a
conditions.csv lies beside the model (scenes/hammer_rig's), each pressure's
relief setting is the mean of that file's calibrated settings for it (the
rig's operator set the relief for the operating pressure); else the relief
cracks at the operating pressure itself.
Exit codes: 0 done, 2 bad input, 4 a run failed (its message is printed; the
other points still run and are kept).
"""
import argparse
import concurrent.futures
import csv
import itertools
import json
import math
import os
import pathlib
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
DEFAULT_HOST = os.environ.get("PCS_TLM_HOST", str(ROOT / "build/tlm_host/tlm_host"))
HAMMER = ROOT / "scenes/hammer_rig/model.tlm"
# Table 2 (measured on the rig): case, gauge pressure [bar], restrictor [mm], flow [l/min].
TABLE2 = [("11", 150, 6.0, 80), ("12", 150, 5.4, 66), ("21", 100, 6.0, 59), ("22", 100, 5.4, 50)]


class InputError(Exception):
    pass


def parse_grid(items):
    grid = []
    for g in items:
        if "=" not in g or "." not in g.split("=", 1)[0]:
            raise InputError(f"--grid '{g}': expected COMPONENT.PARAMETER=V1,V2,...")
        name, values = g.split("=", 1)
        vals = [v.strip() for v in values.split(",") if v.strip()]
        for v in vals:
            try:
                if not math.isfinite(float(v)):
                    raise ValueError
            except ValueError:
                raise InputError(f"--grid {name}: '{v}' is not a finite number")
        if not vals:
            raise InputError(f"--grid {name}: no values")
        grid.append((name, vals))
    if not grid:
        raise InputError("no --grid given")
    return grid


def points_of(grid):
    names = [n for n, _ in grid]
    return [dict(zip(names, combo)) for combo in itertools.product(*[v for _, v in grid])]


def run_point(host, model, sets, point, out, index):
    rep = out / f"point_{index}.json"
    cmd = [host, str(model), "--quiet", "--out", str(out / f"point_{index}.h5"), "--report", str(rep)]
    for s in sets:
        cmd += ["--set", s]
    for k, v in point.items():
        cmd += ["--set", f"{k}={v}"]
    r = subprocess.run(cmd, capture_output=True, text=True)
    (out / f"point_{index}.h5").unlink(missing_ok=True)  # the report is what a sweep keeps
    if r.returncode != 0:
        return f"point {index} ({', '.join(f'{k}={v}' for k, v in point.items())}): tlm_host exit {r.returncode}: " + \
               (r.stderr.strip().splitlines() or ["(no message)"])[-1]
    return None


def write_plan(out, model, sets, grid):
    out.mkdir(parents=True, exist_ok=True)
    plan = {"model": str(model), "sets": sets, "grid": grid, "points": points_of(grid)}
    (out / "points.json").write_text(json.dumps(plan, indent=1))
    return plan


def run_all(host, model, sets, grid, out, jobs):
    plan = write_plan(out, model, sets, grid)
    pts = plan["points"]
    t0 = time.monotonic()
    errors = []
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as ex:
        futs = {ex.submit(run_point, host, model, sets, p, out, i): i for i, p in enumerate(pts)}
        for n, f in enumerate(concurrent.futures.as_completed(futs), 1):
            err = f.result()
            if err:
                errors.append(err)
            print(f"sweep: {n}/{len(pts)} points done ({time.monotonic() - t0:.0f} s, {jobs} at a time)", flush=True)
    for e in errors:
        print(f"sweep: {e}", file=sys.stderr)
    collect(out)
    return 4 if errors else 0


def collect(out):
    plan = json.loads((out / "points.json").read_text())
    rows, keys = [], None
    for i, p in enumerate(plan["points"]):
        rep = out / f"point_{i}.json"
        figs = json.loads(rep.read_text()) if rep.exists() else {}
        flat = {k: v for k, v in figs.items() if isinstance(v, (int, float))}
        if keys is None and flat:
            keys = list(flat)
        rows.append((p, flat))
    keys = keys or []
    with open(out / "sweep.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["index"] + [n for n, _ in plan["grid"]] + keys)
        for i, (p, flat) in enumerate(rows):
            w.writerow([i] + [p[n] for n, _ in plan["grid"]] + [repr(flat[k]) if k in flat else "" for k in keys])
    print(f"sweep: {out / 'sweep.csv'}")
    return rows


def slurm_script(args, grid):
    n = len(points_of(grid))
    cmd = [sys.executable, str(pathlib.Path(__file__).resolve()), "point", str(args.model), "--out", str(args.out),
           "--host", args.host]
    for name, vals in grid:
        cmd += ["--grid", f"{name}={','.join(vals)}"]
    for s in args.set:
        cmd += ["--set", s]
    quoted = " ".join("'" + c.replace("'", "'\\''") + "'" for c in cmd)
    return (f"#!/bin/bash\n"
            f"#SBATCH --job-name=hammer_sweep --array=0-{n - 1} --ntasks=1 --cpus-per-task=1 --time={args.time}\n"
            f"# {n} points, one tlm_host run each; afterwards: sweep.py collect {args.out}\n"
            f"set -euo pipefail\n"
            f"{quoted} --index \"$SLURM_ARRAY_TASK_ID\"\n")


def relief_settings(model, pressures):
    """Each operating pressure's relief setting [Pa]: from the calibrated
    conditions.csv beside the model (case, bar, mm, relief.p_crack, ...: the
    mean of the pressure's rows) or, without that file, the pressure itself."""
    table = model.parent / "conditions.csv"
    if not table.exists():
        return {p: p * 1e5 for p in pressures}
    rows = []
    for n, line in enumerate(table.read_text().splitlines(), 1):
        if not line.strip() or line.startswith("#") or line.startswith("case"):
            continue
        cells = line.split(",")
        try:
            bar, crack = float(cells[1]), float(cells[3])
        except (IndexError, ValueError):
            raise InputError(f"{table}:{n}: expected 'case, bar, mm, relief.p_crack, restrictor.A', got '{line}'")
        if not (math.isfinite(bar) and math.isfinite(crack) and crack > 0):
            raise InputError(f"{table}:{n}: the pressure and the relief setting must be finite, the setting positive")
        rows.append((bar, crack))
    out = {}
    for p in pressures:
        vals = [crack for bar, crack in rows if bar == p]
        if not vals:
            raise InputError(f"{table}: no calibrated relief setting for {p:g} bar (its pressures: "
                             f"{sorted({bar for bar, _ in rows})}); sweep at those or recalibrate")
        out[p] = sum(vals) / len(vals)
    return out


def fig16(args):
    diam = [float(d) for d in args.diameters.split(",")]
    pres = [float(p) for p in args.pressures.split(",")]
    if 6.0 not in diam or 150.0 not in pres:
        raise InputError("fig16 normalises to Case 11: the diameters need 6.0 and the pressures 150")
    crack = relief_settings(args.model, pres)
    grid = [("relief.p_crack", [repr(crack[p]) for p in pres]),
            ("restrictor.A", [repr(math.pi / 4 * (d * 1e-3) ** 2) for d in diam])]
    rc = run_all(args.host, args.model, args.set, grid, args.out, args.jobs)
    pressure_of = {repr(crack[p]): p for p in pres}
    plan = json.loads((args.out / "points.json").read_text())
    res = {}
    for i, p in enumerate(plan["points"]):
        rep = args.out / f"point_{i}.json"
        if rep.exists():
            f = json.loads(rep.read_text())
            d = round(math.sqrt(4 * float(p["restrictor.A"]) / math.pi) * 1e3, 3)
            res[(pressure_of[p["relief.p_crack"]], d)] = f
    ref = res.get((150.0, 6.0))
    if ref is None:
        raise InputError("Case 11 (150 bar, 6.0 mm) did not run: nothing to normalise to")
    p11_meas = 150e5 * 80e-3 / 60.0  # the rig's Case 11 input power, gauge pressure x flow [W]
    lines = ["| p [bar] | Ø [mm] | Q_in [l/min] | P_in / P_in,11 measured | W·f / (W·f)_11 | efficiency / eff_11 |",
             "|---|---|---|---|---|---|"]
    for (p, d), f in sorted(res.items()):
        lines.append(f"| {p:g} | {d:g} | {f['inlet_flow_m3_s'] * 6e4:.1f} | {f['input_power_W'] / p11_meas:.3f} | "
                     f"{f['output_power_W'] / ref['output_power_W']:.3f} | {f['efficiency'] / ref['efficiency']:.3f} |")
    (args.out / "fig16.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(12, 3.8))
    for p, color in zip(sorted(pres), ("tab:blue", "tab:red", "tab:green", "tab:orange")):
        ds = sorted(d for (pp, d) in res if pp == p)
        pick = lambda key, norm: [res[(p, d)][key] / norm for d in ds]
        axes[0].plot(ds, pick("input_power_W", p11_meas), "o-", color=color, label=f"simulated, {p:g} bar")
        axes[1].plot(ds, pick("output_power_W", ref["output_power_W"]), "o-", color=color, label=f"{p:g} bar")
        axes[2].plot(ds, pick("efficiency", ref["efficiency"]), "o-", color=color, label=f"{p:g} bar")
        meas = [(d, pm * 1e5 * q * 1e-3 / 60.0 / p11_meas) for _, pm, d, q in TABLE2 if pm == p]
        if meas:
            axes[0].plot(*zip(*meas), "s", mfc="none", ms=9, mew=1.6, color=color, label=f"rig (Table 2), {p:g} bar")
    titles = ("input power p_in·Q_in / Case 11 measured", "output power W·f / Case 11 simulated",
              "efficiency / Case 11 simulated")
    for ax, title in zip(axes, titles):
        ax.set_title(title, fontsize=9)
        ax.set_xlabel("restrictor Ø [mm]")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7, loc="center")
    fig.suptitle(f"Restrictor sweep of {args.model.parent.name}/{args.model.name} (thesis Fig. 16 layout)", fontsize=10)
    fig.tight_layout()
    fig.savefig(args.out / "fig16.png", dpi=110)
    print(f"sweep: {args.out / 'fig16.png'}, {args.out / 'fig16.md'}")
    return rc


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="mode", required=True)
    for name in ("run", "slurm", "point"):
        s = sub.add_parser(name)
        s.add_argument("model", type=pathlib.Path)
        s.add_argument("--grid", action="append", default=[])
        s.add_argument("--set", action="append", default=[])
        s.add_argument("--out", type=pathlib.Path, required=True)
        s.add_argument("--host", default=DEFAULT_HOST)
        if name == "run":
            s.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
        if name == "slurm":
            s.add_argument("--time", default="00:10:00")
        if name == "point":
            s.add_argument("--index", type=int, required=True)
    c = sub.add_parser("collect")
    c.add_argument("out", type=pathlib.Path)
    f = sub.add_parser("fig16")
    f.add_argument("--out", type=pathlib.Path, required=True)
    f.add_argument("--model", type=pathlib.Path, default=HAMMER)
    f.add_argument("--diameters", default="4.8,5.1,5.4,5.7,6.0,6.3,6.6")
    f.add_argument("--pressures", default="100,150")
    f.add_argument("--set", action="append", default=[])
    f.add_argument("--host", default=DEFAULT_HOST)
    f.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    args = ap.parse_args()
    try:
        if args.mode == "collect":
            collect(args.out)
            return 0
        if args.mode == "fig16":
            return fig16(args)
        grid = parse_grid(args.grid)
        if not args.model.is_file():
            raise InputError(f"{args.model}: no such model file")
        if args.mode == "run":
            if args.jobs < 1:
                raise InputError("--jobs: at least 1")
            return run_all(args.host, args.model, args.set, grid, args.out, args.jobs)
        if args.mode == "slurm":
            write_plan(args.out, args.model, args.set, grid)
            sys.stdout.write(slurm_script(args, grid))
            return 0
        pts = points_of(grid)
        if not 0 <= args.index < len(pts):
            raise InputError(f"--index {args.index}: the grid has points 0 to {len(pts) - 1}")
        plan_file = args.out / "points.json"
        if not plan_file.exists():
            write_plan(args.out, args.model, args.set, grid)
        else:
            # A task of another sweep into the same folder would put its report
            # under this plan's labels, and collect would name it wrongly.
            plan = json.loads(plan_file.read_text())
            if plan["points"] != pts or plan["sets"] != args.set or plan["model"] != str(args.model):
                raise InputError(f"{plan_file} plans another sweep (model, --set or --grid differ); "
                                 f"use another --out")
        err = run_point(args.host, args.model, args.set, pts[args.index], args.out, args.index)
        if err:
            print(f"sweep: {err}", file=sys.stderr)
            return 4
        return 0
    except InputError as e:
        print(f"sweep: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
