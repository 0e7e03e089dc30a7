#!/usr/bin/python3
"""scripts/hammer_report.py's section against the rig (thesis Table 2): each
flow as % of the committed measured flow, the three flow ratios and the
acceptance figures, for made-up figures whose answers are known:
- flows of exactly 0.95 x Table 2 at the set pressures and 20 Hz give
  95.0 % everywhere, the measured ratios themselves and no failure;
- a flat flow (the first layout's fault), an inlet pressure 2 % high and a
  frequency of 14 Hz are each named as failing;
- a condition missing gives no section rather than a half table;
- the restrictor sweep (fig16/, written by scripts/sweep.py fig16): its table
  and the input power's slope at 150 bar, (1.000 - 0.700) / 0.6 = 0.500 per
  mm for a made-up table, beside the rig's (80 - 66) / 80 / 0.6 = 0.292; a
  sweep of another model is named and not shown; no sweep, no section."""
import json
import pathlib
import sys
import tempfile

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "scripts"))
import hammer_report as h  # noqa: E402

table2 = {"150bar_6.0mm": 80, "150bar_5.4mm": 66, "100bar_6.0mm": 59, "100bar_5.4mm": 50}
p_set = {"150bar_6.0mm": 151.013, "150bar_5.4mm": 151.013, "100bar_6.0mm": 101.013, "100bar_5.4mm": 101.013}


def col(q, p, f=20.0):
    return {"Q_in": q, "p_in": p, "f": f}


results = [(pathlib.Path(n), {"reference": col(0.95 * q, p_set[n]), "tlm": col(0.95 * q, p_set[n])})
           for n, q in table2.items()]
md, failed = h.rig_section(results)
md = "\n".join(md)
failures = []
for case, q in zip(("11", "12", "21", "22"), table2.values()):
    row = f"| {case} | {q} | {0.95 * q:.1f} (95.0 %) | {0.95 * q:.1f} (95.0 %) |"
    if row not in md:
        failures.append(f"missing row {row}")
for text, a, b in (("Ø5.4 / Ø6.0 at 150 bar", 66, 80), ("Ø5.4 / Ø6.0 at 100 bar", 50, 59), ("100 / 150 bar at Ø6.0", 59, 80)):
    ours = f"{0.95 * a / (0.95 * b):.3f}"  # the same division the report makes
    row = f"| {text} | {a / b:.3f} | {ours} | {ours} |"
    if row not in md:
        failures.append(f"missing ratio row {row}")
if failed:
    failures.append(f"figures inside every band were reported failing: {failed}")

# The co-simulation column wrong in three ways; the reference stays right.
bad = [(pathlib.Path(n), {"reference": col(0.95 * q, p_set[n]),
                          "tlm": col(60.0, 1.02 * p_set[n] if n == "150bar_5.4mm" else p_set[n],
                                     14.0 if n == "100bar_5.4mm" else 20.0)})
       for n, q in table2.items()]
_, failed = h.rig_section(bad)
print("\n".join(failed))
for want in ("flow ratio Ø5.4 / Ø6.0 at 150 bar (TLM, 1 µs): 1.000", "flow ratio Ø5.4 / Ø6.0 at 100 bar (TLM, 1 µs)",
             "flow ratio 100 / 150 bar at Ø6.0 (TLM, 1 µs)", "case 12 (TLM, 1 µs): p_in ±1 %",
             "case 22 (TLM, 1 µs): f 15–30 Hz", "case 11 (TLM, 1 µs): Q ±10 %"):
    if not any(f.startswith(want) for f in failed):
        failures.append(f"not reported: {want}")
if any("reference" in f for f in failed):
    failures.append("the right reference column was reported failing")
if h.rig_section(results[:3]) != ([], []):
    failures.append("three conditions gave a section")

# The restrictor sweep section.
h.use_scene("hammer_rig")
with tempfile.TemporaryDirectory() as tmp:
    out = pathlib.Path(tmp)
    if h.sweep_section(out) != []:
        failures.append("a section without a sweep")
    (out / "fig16").mkdir()
    ours = pathlib.Path(h.__file__).resolve().parents[1] / "scenes/hammer_rig/model.tlm"
    (out / "fig16/points.json").write_text(json.dumps({"model": str(ours), "points": []}))
    (out / "fig16/fig16.md").write_text(
        "| p [bar] | Ø [mm] | Q_in [l/min] | P_in / P_in,11 measured | W·f / (W·f)_11 | efficiency / eff_11 |\n"
        "|---|---|---|---|---|---|\n| 150 | 5.4 | 60.0 | 0.700 | 0.9 | 1.0 |\n| 150 | 6.0 | 80.0 | 1.000 | 1.0 | 1.0 |\n")
    sweep = "\n".join(h.sweep_section(out))
    print(sweep)
    if "0.500 of Case 11 per mm (the rig: 0.292)" not in sweep:
        failures.append("the sweep's slope at 150 bar is not 0.500 against the rig's 0.292")
    if "| 150 | 5.4 | 60.0 | 0.700 |" not in sweep or "fig16/fig16.png" not in sweep:
        failures.append("the sweep's table or picture is missing")
    (out / "fig16/points.json").write_text(json.dumps({"model": "/elsewhere/model.tlm", "points": []}))
    other = "\n".join(h.sweep_section(out))
    if "not shown" not in other or "0.700" in other:
        failures.append("a sweep of another model was shown as this scene's")

print(md)
for f in failures:
    print("FAIL", f)
sys.exit(1 if failures else 0)
