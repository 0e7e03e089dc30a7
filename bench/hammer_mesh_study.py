"""Speed against error for the elastic hammer's meshes (issue 14): the
scene's stepped piston (shared/scenes/hammer.md) strikes the Ø65 mm tool at
8 m/s, both axisymmetric, meshed by fe_mesh at several radial and axial cell
sizes; fe_server runs each standalone. The tool is 2 m long here so that the
primary pulse passes the gauge (0.2 m below the top) before anything comes
back from the far end; the quantities are those of issue 14's pulse check:
plateau level, pulse length, W = (A·c0/E)∫σ²dt, peak; each against the
finest mesh and against 1D theory.

    /usr/bin/python3 bench/hammer_mesh_study.py [--quick] [--out DIR]

Writes DIR/mesh_study.json and DIR/mesh_study.png (default bench/results).
"""
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import h5py
import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "scripts"))
from hammer_report import plateau_and_length  # noqa: E402
BUILD = Path(os.environ.get("PCS_BUILD_DIR", ROOT / "build"))
FE_MESH = BUILD / "fe_server" / "fe_mesh"
FE_SERVER = BUILD / "fe_server" / "fe_server"

RHO, E = 7850.0, 2.1e11
C0 = (E / RHO) ** 0.5
V0 = 8.0
PISTON = "0.33,0.0305/0.11,0.0328/0.2,0.028"
L_PISTON = 0.64
R_TOOL, L_TOOL, GAUGE = 0.0325, 2.0, -0.2
A_STEM, A_TOOL = np.pi * 0.0305**2, np.pi * R_TOOL**2
# 1D theory (equal material): the striking stem against the tool,
# sigma = -v0·rho·c0·A_p/(A_p + A_t) while the piston's first reflection is on its way.
PLATEAU_1D = -V0 * RHO * C0 * A_STEM / (A_STEM + A_TOOL)
LENGTH_1D = 2.0 * L_PISTON / C0


def deck(dirpath, radial, axial):
    run = lambda *a: subprocess.run([str(FE_MESH), *a], check=True, capture_output=True, text=True)
    run("--axisymmetric", "--sections", PISTON, "--size", str(radial), "--axial-size", str(axial),
        "--z0", "1e-4", "--part", "1", "--title", "piston", "-o", str(dirpath / "piston_mesh.k"))
    run("--axisymmetric", "--sections", f"{L_TOOL},{R_TOOL}", "--size", str(radial), "--axial-size", str(axial),
        "--z0", str(-L_TOOL), "--gauge", str(GAUGE), "--part", "2", "--title", "tool", "--node-offset", "200000",
        "--element-offset", "200000", "--set-offset", "10", "-o", str(dirpath / "tool_mesh.k"))
    (dirpath / "deck.k").write_text(f"""*KEYWORD
*INCLUDE
piston_mesh.k
*INCLUDE
tool_mesh.k
*PART
piston
1,1,1
*PART
tool
2,1,1
*SECTION_SHELL
1,15
0,0,0,0
*MAT_ELASTIC
1,{RHO},{E},0.3
*SET_PART_LIST
1
1
*SET_PART_LIST
2
2
*CONTACT_2D_AUTOMATIC_SURFACE_TO_SURFACE
1,2,1.0
0,1e20
0,20
*INITIAL_VELOCITY_GENERATION
1,2,0,0,{-V0},0
0,0,0,0,0,0
*CONTROL_TIMESTEP
0,0.9
*CONTROL_TERMINATION
4.0e-4
*DATABASE_ELOUT
2.0e-7
*END
""")


def gauge_stress(dirpath, h5):
    """Ring-area-weighted mean axial stress of the gauge layer against time."""
    text = (dirpath / "tool_mesh.k").read_text().splitlines()
    nodes, elems, ids, mode = {}, {}, [], None
    for line in text:
        if line.startswith("*"):
            mode = line.strip()
            continue
        if line.startswith("$") or not line.strip():
            continue
        f = line.split(",")
        if mode == "*NODE":
            nodes[int(f[0])] = float(f[1])
        elif mode == "*ELEMENT_SHELL":
            elems[int(f[0])] = [int(x) for x in f[2:6]]
        elif mode == "*DATABASE_HISTORY_SHELL":
            ids += [int(x) for x in f]
    with h5py.File(h5, "r") as f:
        t = f["time_elements"][:]
        num, den = 0.0, 0.0
        for e in ids:
            r = [nodes[n] for n in elems[e]]
            w = max(r) ** 2 - min(r) ** 2
            num = num + w * f[f"axisymmetric/{e}/axial"][:]
            den += w
    return t, num / den


def pulse(t, s):
    """Plateau and length of the first compressive pulse (the report's own
    definition, scripts/hammer_report.py), W over the whole record (nothing
    comes back within it) and the peak."""
    plateau, length = plateau_and_length(t, s)
    W = A_TOOL * C0 / E * np.trapz(np.minimum(s, 0.0) ** 2, t)
    return {"plateau_MPa": plateau / 1e6, "length_us": length * 1e6, "W_J": float(W), "peak_MPa": float(s.min() / 1e6)}


def study(out, quick=False):
    """Runs the meshes; writes out/mesh_study.json and .png; returns the result."""
    out.mkdir(parents=True, exist_ok=True)
    # (radial, axial) cell sizes in m; the first is the reference.
    meshes = [(0.0025, 0.0025), (0.005, 0.005), (0.009, 0.005), (0.005, 0.01), (0.009, 0.01), (0.016, 0.01),
              (0.009, 0.02)]
    if quick:
        meshes = [(0.005, 0.005), (0.009, 0.01)]
    rows = []
    with tempfile.TemporaryDirectory(prefix="pcs_mesh_study_") as tmp:
        for radial, axial in meshes:
            d = Path(tmp) / f"r{radial}_a{axial}"
            d.mkdir()
            deck(d, radial, axial)
            t0 = time.perf_counter()
            r = subprocess.run([str(FE_SERVER), "--model", "deck.k", "--out", "fe.h5", "--threads", "1"], cwd=d,
                               capture_output=True, text=True, timeout=1200)
            wall = time.perf_counter() - t0
            if r.returncode != 0:
                raise SystemExit(f"fe_server failed on {d.name}: {r.stdout}{r.stderr}")
            line = r.stdout.strip().splitlines()[-1]
            steps, dt = int(line.split("run, ")[1].split(" steps")[0]), float(line.split("steps of ")[1].split(" s")[0])
            elements = sum(1 for f in ("piston_mesh.k", "tool_mesh.k")
                           for ln in (d / f).read_text().split("*ELEMENT_SHELL\n")[1].split("*")[0].splitlines()
                           if ln and not ln.startswith("$"))
            t, s = gauge_stress(d, d / "fe.h5")
            row = {"radial_mm": radial * 1e3, "axial_mm": axial * 1e3, "elements": elements, "dt_us": dt * 1e6,
                   "wall_s": wall, "steps": steps, "us_per_step": wall / steps * 1e6, **pulse(t, s)}
            rows.append(row)
            print(json.dumps(row), flush=True)
            np.save(d.parent / f"{d.name}.npy", np.vstack([t, s]))
        ref = rows[0]
        for row in rows:
            for k in ("plateau", "length", "W", "peak"):
                key = next(x for x in row if x.startswith(k + "_"))
                row[k + "_vs_ref_pct"] = 100.0 * (row[key] / ref[key] - 1.0)
            row["plateau_vs_1D_pct"] = 100.0 * (row["plateau_MPa"] * 1e6 / PLATEAU_1D - 1.0)
            row["length_vs_1D_pct"] = 100.0 * (row["length_us"] * 1e-6 / LENGTH_1D - 1.0)
        result = {"plateau_1D_MPa": PLATEAU_1D / 1e6, "length_1D_us": LENGTH_1D * 1e6,
                  "kinetic_J": 0.5 * 14.36 * V0**2, "rows": rows}
        (out / "mesh_study.json").write_text(json.dumps(result, indent=1))
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(8, 4.5))
        for radial, axial in meshes:
            t, s = np.load(Path(tmp) / f"r{radial}_a{axial}.npy")
            ax.plot(t * 1e6, s / 1e6, label=f"radial {radial*1e3:g} mm, axial {axial*1e3:g} mm")
        ax.axhline(PLATEAU_1D / 1e6, color="k", ls=":", label="1D impedance estimate")
        ax.set_xlabel("time [µs]")
        ax.set_ylabel("tool stress 0.2 m below the top [MPa]")
        ax.set_title("Elastic hammer: tool pulse against mesh size (8 m/s)")
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(out / "mesh_study.png", dpi=110)
    return result


def main():
    quick = "--quick" in sys.argv
    out = Path(sys.argv[sys.argv.index("--out") + 1]) if "--out" in sys.argv else ROOT / "bench" / "results"
    rows = study(out, quick)["rows"]
    for row in rows:
        print(f"{row['radial_mm']:4.1f}/{row['axial_mm']:4.1f} mm  {row['elements']:6d} el  dt {row['dt_us']:.3f} us  "
              f"{row['us_per_step']:6.1f} us/step  plateau {row['plateau_MPa']:7.2f} ({row['plateau_vs_ref_pct']:+.2f} %)"
              f"  length {row['length_us']:6.1f} ({row['length_vs_ref_pct']:+.2f} %)  W {row['W_J']:6.1f}"
              f" ({row['W_vs_ref_pct']:+.2f} %)  peak {row['peak_MPa']:7.1f}")


if __name__ == "__main__":
    main()
