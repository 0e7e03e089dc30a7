#!/usr/bin/python3
"""scripts/hammer_report.py's primary pulse and per-blow checks on signals
whose answers are known:
- a 110 us plateau of -200 MPa followed, 230 us after its start, by a
  second compressive pulse of -230 MPa (the housing landing on the tool):
  the primary pulse ends with the first, so W is the first pulse's
  (A·c0/E)·σ²·T within 1 % (the sampled edges), not both pulses';
- an exponentially decaying pulse (a rigid piston on a bar) ends where it
  falls below 2 % of its peak;
- the per-blow checks name a blow whose W exceeds 101 % of ½mv² and a
  plateau 12 % off the 1D estimate, and pass figures inside both bounds;
- the scene, and so the geometry, is the one the runs' fe.h5 files name; runs
  of two scenes in one folder, or of an unknown one, are refused;
- the time shift against the reference is found where there is one, and is
  none where the cycles drift apart;
- the fatigue hot spots: each part's most damaged element, per blow, with
  the blows and hours to crack initiation;
- the hourglass energy per cycle (and per part) between the first and last
  impact, and its check against 5 % of ½mv²; the ringing before each blow,
  the rms about its mean of a gauge's stress (a sine of amplitude a: a/√2),
  blind to the blow itself and to a static preload;
- the whole-run figure overlays every blow whose record holds the pulse,
  and the blow's stress picture draws the anvil with piston and tool."""
import pathlib
import sys
import tempfile

import h5py
import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "scripts"))
import hammer_report as h  # noqa: E402

failures = []


def check(ok, what):
    print("ok  " if ok else "FAIL", what)
    if not ok:
        failures.append(what)


h.use_scene("hammer_rig")
dt = 0.5e-6
t = np.arange(0.0, 1.0e-3, dt)
s = np.zeros_like(t)
s[(t >= 20e-6) & (t < 130e-6)] = -200e6
s[(t >= 250e-6) & (t < 360e-6)] = -230e6
end = h.primary_end(s)
check(abs(t[end] - 130e-6) <= dt, f"the primary pulse ends with the first one: {t[end] * 1e6:.1f} us (130 us)")
W = h.AREA * h.C0 / h.E * np.trapz(s[:end] ** 2, t[:end])
W_first = h.AREA * h.C0 / h.E * (200e6) ** 2 * 110e-6
check(abs(W / W_first - 1.0) < 0.01, f"W is the first pulse's: {W:.1f} J against {W_first:.1f} J")

tau = 40e-6
e = np.where(t >= 20e-6, -300e6 * np.exp(-(t - 20e-6) / tau), 0.0)
end = h.primary_end(e)
want = 20e-6 + tau * np.log(50.0)  # exp(-x) = 0.02
check(abs(t[end] - want) <= 2 * dt, f"a decaying pulse ends at 2 % of its peak: {t[end] * 1e6:.1f} us ({want * 1e6:.1f})")

v = [12.0, 12.0, 12.0]
kin = 0.5 * h.M_PISTON * 144.0
level = -12.0 * h.RHO * h.C0 * h.A_STRIKE / (h.A_STRIKE + h.AREA)
pulses = {"blows": {"t": [0.1, 0.14, 0.18], "W": [0.96 * kin, 0.99 * kin, 0.97 * kin],
                    "plateau": [0.97 * level, 1.02 * level, 0.95 * level], "length": [110e-6] * 3,
                    "peak": [1.3 * level] * 3}}
ok = h.blow_checks(h.blow_statistics(pulses, v))
check(all(c[3] for c in ok), f"figures inside the bounds pass: {ok}")
pulses["blows"]["W"][1] = 1.02 * kin
pulses["blows"]["plateau"][2] = 0.88 * level
bad = h.blow_checks(h.blow_statistics(pulses, v))
check(not bad[0][3] and "1.020" in bad[0][1], f"a blow with W at 102 % of ½mv² fails: {bad[0]}")
check(not bad[1][3] and "0.880" in bad[1][1], f"a plateau 12 % under the 1D estimate fails: {bad[1]}")
stats = h.blow_statistics(pulses, v)
check(abs(np.mean(stats["period"]) - 40.0) < 1e-9, "the impact period comes from the blows' times (40 ms)")

with tempfile.TemporaryDirectory() as tmp:
    def run_of(cond, scene):
        d = pathlib.Path(tmp) / cond / "tlm10"
        d.mkdir(parents=True, exist_ok=True)
        with h5py.File(d / "fe.h5", "w") as f:
            f.attrs["port_table"] = np.bytes_(f"/somewhere/scenes/{scene}/ports.cfg")
        return pathlib.Path(tmp) / cond
    a, b = run_of("150bar_6.0mm", "hammer_rig"), run_of("150bar_5.4mm", "hammer_rig")
    check(h.scene_of([a, b]) == "hammer_rig", "the scene is the runs' own")
    c = run_of("100bar_6.0mm", "hammer_elastic")
    for conds, what in (([a, c], "runs of two scenes"), ([run_of("100bar_5.4mm", "my_hammer")], "an unknown scene")):
        try:
            h.scene_of(conds)
            check(False, f"refused: {what}")
        except SystemExit as e:
            check("expected one of" in str(e), f"refused: {what}: {e}")
# The time shift: a lift 2 ms late is found as +2000 us; a lift whose cycle
# is 3 % longer drifts by whole cycles over the run, and its best lag lies on
# the window's edge: no shift, "—" (the main job once printed -8000 us).
tt = np.arange(0.0, 1.6, 20e-6)
lift = lambda t_, period: np.maximum(0.0, np.sin(2 * np.pi * t_ / period)) ** 3
ref = {"time": tt, "components/piston/x": lift(tt, 0.04)}
late = {"time": tt, "components/mech/x": lift(tt - 2e-3, 0.04)}
check(abs(h.time_shift(ref, late) - 2e-3) < 20e-6, f"a lift 2 ms late: {1e6 * h.time_shift(ref, late):.0f} us")
slow = {"time": tt, "components/mech/x": lift(tt, 0.0412)}
check(np.isnan(h.time_shift(ref, slow)), f"a lift 3 % slower drifts: {h.time_shift(ref, slow)} (nan)")
# The fatigue hot spots: per part the element with the most damage, per
# blow over the run's blows, and the blows and hours to initiation at f.
with tempfile.TemporaryDirectory() as tmp:
    p = pathlib.Path(tmp) / "fe_fatigue.csv"
    p.write_text("element,part,x,y,z,cycles,largest_range,damage,time_to_initiation_s\n"
                 "1,1,0.004,0.005,0,100,5e8,2e-6,1\n2,1,0.01,0.1,0,100,3e8,1e-6,1\n"
                 "200240,2,0.032,-0.005,0,90,2.6e8,4e-7,1\n500066,5,0.031,0.009,0,80,5.4e8,0,inf\n")
    spots = {b["part"]: b for b in h.fatigue_hot_spots(p, 20, 25.0)}
    check(spots[1]["element"] == 1 and abs(spots[1]["per_blow"] - 1e-7) < 1e-20,
          f"the piston's hot spot is its most damaged element, 2e-6 over 20 blows: {spots[1]}")
    check(abs(spots[1]["blows_to_initiation"] - 1e7) < 1e-3 and abs(spots[1]["hours"] - 1e7 / 25 / 3600) < 1e-9,
          f"1e7 blows to initiation, {1e7 / 25 / 3600:.1f} h at 25 Hz: {spots[1]['hours']}")
    check(spots[5]["blows_to_initiation"] == float("inf"), "no damage: no initiation")
    check(abs(spots[2]["r_mm"] - 32.0) < 1e-9 and abs(spots[2]["range_MPa"] - 260.0) < 1e-9, "position in mm, range in MPa")
# Hourglass per cycle and ringing: impacts every 40 ms; the hourglass energy
# grows by 30 J a cycle (piston 10, anvil 20); the tool's gauge carries a
# -50 MPa preload, a 4 kHz ring of 2 MPa and, at each impact, a -200 MPa
# pulse of 110 us that the window before the next impact leaves out.
with tempfile.TemporaryDirectory() as tmp:
    impacts = [0.30, 0.34, 0.38, 0.42]
    path = pathlib.Path(tmp) / "fe.h5"
    with h5py.File(path, "w") as f:
        tg = np.arange(0.25, 0.45, 1e-4)
        f["time"] = tg
        f["energy/hourglass"] = 750.0 * tg
        f["part_energy/hourglass/1"] = 250.0 * tg
        f["part_energy/hourglass/4"] = 500.0 * tg
        f["part_energy/hourglass/3"] = 0.0 * tg
        te = np.arange(0.25, 0.45, 4e-6)
        f["time_elements"] = te
        stress = -50e6 + 2e6 * np.sin(2 * np.pi * 4000.0 * te)
        for ti in impacts:
            stress[(te >= ti) & (te < ti + 110e-6)] = -200e6
        f[f"sections/{h.SECTION}/fy"] = stress * h.AREA
        f[f"sections/{h.SECTION}/vy"] = 0.0 * te
    with h5py.File(path) as f:
        hg, parts = h.hourglass_per_cycle(f, impacts)
        check(abs(hg - 30.0) < 1e-6 and abs(parts[1] - 10.0) < 1e-6 and abs(parts[4] - 20.0) < 1e-6 and 3 not in parts,
              f"30 J a cycle, piston 10, anvil 20, the spool none: {hg}, {parts}")
        ring = h.ringing(f, impacts, h.SECTION, h.AREA)
        check(abs(ring - 2.0 / np.sqrt(2.0)) < 0.01, f"a 2 MPa ring is 1.414 MPa rms, preload and pulses left out: {ring}")
        check(h.ringing(f, impacts, "999", h.AREA) is None, "no such gauge: no figure")
    rows = h.hourglass_check({"hg": 30.0, "hg_parts": parts, "W_kin": 400.0})
    check(rows[0][3] is False and "7.5 %" in rows[0][1] and rows[0][1].index("anvil") < rows[0][1].index("piston"),
          f"7.5 % of 400 J fails, the anvil named first: {rows}")
    check(h.hourglass_check({"hg": 19.0, "hg_parts": {}, "W_kin": 400.0})[0][3] is True, "4.75 % holds")

# The runs' scene. A study's port table (run_hammer.sh --ports) lies outside
# every scene, so run_hammer.sh names the scene (--scene); a run whose table
# is another scene's must still be refused, not read with the given scene's
# gauges and areas.
def scene_or_exit(tables, given):
    with tempfile.TemporaryDirectory() as d:
        conds = []
        for i, table in enumerate(tables):
            cond = pathlib.Path(d) / f"150bar_{i}.0mm"
            (cond / "tlm10").mkdir(parents=True)
            with h5py.File(cond / "tlm10" / "fe.h5", "w") as f:
                f.attrs["port_table"] = table
            conds.append(cond)
        try:
            return h.scene_of(conds, given)
        except SystemExit as e:
            return f"exit: {e}"


rig, elastic, study = "/r/scenes/hammer_rig/ports.cfg", "/r/scenes/hammer_elastic/ports.cfg", "/tmp/study/ports_s80.cfg"
check(scene_or_exit([rig, rig], None) == "hammer_rig", "the scene from the port tables")
check(scene_or_exit([study], "hammer_rig") == "hammer_rig", "a study's table: the scene given")
check(scene_or_exit([study, rig], "hammer_rig") == "hammer_rig", "a study's run beside the scene's own")
got = scene_or_exit([rig], "hammer_elastic")
check(got.startswith("exit") and "--scene hammer_elastic" in got, f"another scene's run is refused: {got}")
got = scene_or_exit([rig, elastic], None)
check(got.startswith("exit"), f"runs of two scenes are refused: {got}")
got = scene_or_exit([study], None)
check(got.startswith("exit"), f"a study's table without --scene is refused: {got}")

# The whole-run figure: four impacts, the fe.h5 record ending 0.3 ms after
# the last: three pulses are overlaid, the cut one is left out; without an
# elastic co-simulation there is no figure.
with tempfile.TemporaryDirectory() as tmp:
    cond = pathlib.Path(tmp) / "150bar_6.0mm"
    run = cond / "tlm10"
    run.mkdir(parents=True)
    impacts = [0.30, 0.34, 0.38, 0.42]
    tt = np.arange(0.0, 0.4203, 1e-5)
    (cond / "reference.json").write_text('{"impact_times_s": [0.30, 0.34, 0.38, 0.42]}')
    (run / "host.json").write_text('{"impact_times_s": [0.30, 0.34, 0.38, 0.42]}')
    with h5py.File(cond / "reference.h5", "w") as f:
        f["time"] = tt
        f["components/piston/v"] = -12.0 + 0.0 * tt
    with h5py.File(run / "host.h5", "w") as f:
        f["time"] = tt
        f["components/mech/v"] = -11.9 + 0.0 * tt
    with h5py.File(run / "fe.h5", "w") as f:
        f["time"] = tt
        f["ports/housing.x"] = 1e-3 * np.sin(2 * np.pi * 25.0 * tt)
        for name in ("kinetic", "internal", "external_work", "balance_error"):
            f[f"energy/{name}"] = 0.0 * tt
        te = np.arange(0.25, 0.4203, 4e-6)
        f["time_elements"] = te
        stress = 0.0 * te
        for ti in impacts:
            stress[(te >= ti) & (te < ti + 110e-6)] = -200e6
        f[f"sections/{h.SECTION}/fy"] = stress * h.AREA
        f[f"sections/{h.SECTION}/vy"] = 0.0 * te
    drawn = h.blows_plot(cond, {"reference": {}, "tlm10": {"elastic": True, "v": 11.9}})
    check(drawn == 3 and (cond / "blows.png").exists(), f"three whole pulses overlaid, the cut one left out: {drawn}")
    check(h.blows_plot(cond, {"reference": {}, "tlm10": {"elastic": False}}) is None, "a 1D tool: no such figure")
# The blow's stress picture draws every part of the field file, the anvil too.
with tempfile.TemporaryDirectory() as tmp:
    out = pathlib.Path(tmp)
    (out / "impact").mkdir()
    xml = "".join(f'<Time Value="{1e-5 * k}"/>' for k in range(16))
    (out / "impact/impact_fields.xdmf").write_text(f"<Xdmf>{xml}</Xdmf>")
    with h5py.File(out / "impact/impact_fields.h5", "w") as f:
        corners = [[0, 0], [0.03, 0], [0.03, 0.1], [0, 0.1]]
        f["mesh/coordinates"] = np.array([[x, y - 0.1 * b, 0.0] for b in range(3) for x, y in corners])
        f["mesh/topology"] = np.array([[4 * b, 4 * b + 1, 4 * b + 2, 4 * b + 3] for b in range(3)])
        f["mesh/part"] = np.array([1, 2, 4])
        for k in range(16):
            f[f"fields/{k:06d}/stress_axial"] = np.array([-1e8, -2e8, -5e7])
    parts = h.stress_field_picture(out)
    check(parts == [1, 2, 4] and (out / "stress_field.png").exists(), f"piston, tool and anvil drawn: {parts}")
    check(h.stress_field_picture(pathlib.Path(tmp) / "none") is None, "no blow run: no picture")
sys.exit(1 if failures else 0)
