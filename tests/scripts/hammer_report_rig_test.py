#!/usr/bin/python3
"""scripts/hammer_report.py's section against the rig (thesis Table 2): each
flow as % of the committed measured flow, and the three flow ratios, for
made-up figures whose answers are known: flows of exactly 0.9 x Table 2 give
90.0 % everywhere and the measured ratios themselves; a condition missing
gives no section rather than a half table."""
import pathlib
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "scripts"))
import hammer_report as h  # noqa: E402

table2 = {"150bar_6.0mm": 80, "150bar_5.4mm": 66, "100bar_6.0mm": 59, "100bar_5.4mm": 50}
results = [(pathlib.Path(n), {"reference": {"Q_in": 0.9 * q}, "tlm": {"Q_in": 0.9 * q}}) for n, q in table2.items()]
md = "\n".join(h.rig_section(results))
failures = []
for case, q in zip(("11", "12", "21", "22"), table2.values()):
    row = f"| {case} | {q} | {0.9 * q:.1f} (90.0 %) | {0.9 * q:.1f} (90.0 %) |"
    if row not in md:
        failures.append(f"missing row {row}")
for text, ratio in (("Ø5.4 / Ø6.0 at 150 bar", 66 / 80), ("Ø5.4 / Ø6.0 at 100 bar", 50 / 59), ("100 / 150 bar at Ø6.0", 59 / 80)):
    row = f"| {text} | {ratio:.3f} | {ratio:.3f} | {ratio:.3f} |"
    if row not in md:
        failures.append(f"missing ratio row {row}")
if h.rig_section(results[:3]):
    failures.append("three conditions gave a section")
print(md)
for f in failures:
    print("FAIL", f)
sys.exit(1 if failures else 0)
