"""Cavitation that conserves oil: tlm_host against an independent continuous
model with a void state.

The circuit (scenes are the model text below, the same for both):

    supply 100 bar ─ orifice (Cd 0.65, 1 mm²) ─ chamber (10 cm³ + A·x) ═ piston

The piston (5 kg, A = 10 cm²) starts at rest with the chamber at supply
pressure, against a return spring preloaded with 1.5 kN (k = 50 kN/m). The
chamber's oil spring (β·A²/V = 1.4e8 N/m) throws the piston out: it
overshoots, the chamber falls to vapour pressure and a void opens while the
piston coasts on; the orifice refills it, and the piston then strokes at the
orifice's flow to its stop at x = 10 mm.

The reference integrates x, v, the chamber's liquid pressure p and its void
volume V_void (scipy's Radau with event switching):
    liquid (V_void = 0, p > p_vap):  dp/dt = β/(V0 + A·x)·(q_in − A·v)
    vapour (V_void > 0):             p = p_vap, dV_void/dt = A·v − q_in
    q_in = Cd·A_o·sqrt(2·|p_s − p|/ρ)·sign(p_s − p)
    m·dv/dt = A·p − F0 − k·x − F_stop(x)
It switches to vapour when p reaches p_vap and back exactly when the void is
refilled. A model that forgets the void (creating oil) reaches the stop early
by V_void,max / (A·v_stroke).

Checks, at host steps of 1 µs and 10 µs: the time the piston reaches its stop
within 0.2 ms (the stroke takes ~100 ms; the created-oil error is ~1 ms), the
chamber pressure during the stroke (mean over 20–80 % of the stroke time)
and after the stop within 1 %, and the largest void within 3·ω·Δt (ω the
oil spring's 5.3 krad/s): the void is the integral of the first swing, and
the TLM chamber answers the piston one step late, an error first order in
ω·Δt (measured: 1.4 % at 1 µs, 13 % at 10 µs). The events are listed, not
judged: the reference's fifth event is a 0.07 ms flicker.

Usage: cavitation_reference.py TLM_HOST_EXE WORK_DIR [--plot PNG]
Exit 0: pass; 1: a check failed; 77: scipy or h5py missing (skipped).
"""
import math
import subprocess
import sys
from pathlib import Path

try:
    import h5py
    import numpy as np
    from scipy.integrate import solve_ivp
except ImportError as e:  # pragma: no cover
    print(f"skipped: {e}")
    sys.exit(77)

P_S, CD, A_O, RHO = 100e5, 0.65, 1e-6, 870.0
V0, BETA, P_VAP = 1e-5, 1.4e9, 5e3
A, M, K, F0 = 1e-3, 5.0, 5e4, 1.5e3
X_MAX, K_STOP, C_STOP = 0.01, 1e8, 2e4
T_END = 0.15
OMEGA = math.sqrt(BETA * A * A / (V0 * M))  # the chamber's oil spring on the piston, rad/s

MODEL = f"""*SIMULATION
timestep, {{dt}}
stoptime, {T_END}
log_every, {{log_every}}
*COMPONENT
supply,  PressureSourceC,            p={P_S}
orifice, HydraulicTurbulentOrificeQ, Cd={CD}, A={A_O}, rho={RHO}
chamber, HydraulicVolumeC,           V={V0}, beta={BETA}, p0={P_S}, p_vap={P_VAP}, dVdx={A}, ports=2
piston,  SpringPistonQ,              A={A}, m={M}, k={K}, F0={F0}, x_max={X_MAX}, k_stop={K_STOP}, c_stop={C_STOP}
*CONNECT
supply.P1,  orifice.P1
orifice.P2, chamber.P1
chamber.P2, piston.P1
piston.x,   chamber.x
"""


def q_in(p):
    # Turbulent, with a linear zone below 100 Pa so the integrator can pass
    # Δp = 0 (sqrt has no derivative there); the zone holds after the stop only.
    d = P_S - p
    if abs(d) < 100.0:
        return CD * A_O * math.sqrt(2.0 * 100.0 / RHO) * d / 100.0
    return CD * A_O * math.sqrt(2.0 * abs(d) / RHO) * (1.0 if d >= 0 else -1.0)


def stop_force(x, v):
    pen = x - X_MAX
    if pen <= 0:
        return 0.0
    return max(0.0, K_STOP * pen + C_STOP * v)


def reference(conserve=True):
    """Returns arrays t, x, p, void on a fine grid. conserve=False is the
    model that forgets the void (the pressure is held at p_vap only while
    oil flows out faster than it comes in), i.e. creates the missing oil."""
    ts, xs, ps, vs = [], [], [], []
    # state: x, v, p (liquid phase) or x, v, void (vapour phase)
    t, state, vapour = 0.0, [0.0, 0.0, P_S], False
    while t < T_END:
        if not vapour:
            def f(_, y):
                x, v, p = y
                return [v, (A * p - F0 - K * x - stop_force(x, v)) / M, BETA / (V0 + A * x) * (q_in(p) - A * v)]

            def ev(_, y):
                return y[2] - P_VAP
        else:
            def f(_, y):
                x, v, void = y
                return [v, (A * P_VAP - F0 - K * x - stop_force(x, v)) / M, A * v - q_in(P_VAP)]

            if conserve:
                def ev(_, y):
                    return y[2]
            else:
                def ev(_, y):
                    return A * y[1] - q_in(P_VAP)
        ev.terminal, ev.direction = True, -1
        sol = solve_ivp(f, (t, T_END), state, method="Radau", events=ev, rtol=1e-10, atol=[1e-12, 1e-10, 1e-3 if not vapour else 1e-16],
                        max_step=2e-5, dense_output=False)
        ts.append(sol.t)
        xs.append(sol.y[0])
        if vapour:
            ps.append(np.full_like(sol.t, P_VAP))
            vs.append(sol.y[2])
        else:
            ps.append(sol.y[2])
            vs.append(np.zeros_like(sol.t))
        t = sol.t[-1]
        if sol.status == 1:  # an event: switch phase at exactly its state
            x, v = sol.y_events[0][0][0], sol.y_events[0][0][1]
            state = [x, v, 0.0] if not vapour else [x, v, P_VAP]
            vapour = not vapour
        else:
            break
    return np.concatenate(ts), np.concatenate(xs), np.concatenate(ps), np.concatenate(vs)


def stop_time(t, x):
    """First time the piston reaches its stop."""
    i = np.argmax(x >= X_MAX)
    if x[i] < X_MAX:
        return float("nan")
    return t[i - 1] + (X_MAX - x[i - 1]) * (t[i] - t[i - 1]) / (x[i] - x[i - 1])


def events(t, void):
    """Start times of the stretches with vapour."""
    on = void > 0
    return [t[i + 1] for i in range(len(t) - 1) if on[i + 1] and not on[i]]


def stroke_pressure(t, p, t_stop):
    sel = (t > 0.2 * t_stop) & (t < 0.8 * t_stop)
    return float(np.mean(p[sel]))


def main():
    host, work = sys.argv[1], Path(sys.argv[2])
    plot = sys.argv[sys.argv.index("--plot") + 1] if "--plot" in sys.argv else None
    work.mkdir(parents=True, exist_ok=True)
    t, x, p, void = reference()
    t_ref = stop_time(t, x)
    p_ref = stroke_pressure(t, p, t_ref)
    void_ref = float(void.max())
    p_end_ref = float(p[-1])
    print(f"reference: stop at {t_ref*1e3:.3f} ms, stroke pressure {p_ref/1e5:.3f} bar, "
          f"final {p_end_ref/1e5:.3f} bar, largest void {void_ref*1e6:.4f} cm³")
    ok = True
    runs = {}
    for dt in (1e-6, 1e-5):
        model = work / f"cav_{dt:g}.tlm"
        model.write_text(MODEL.format(dt=dt, log_every=max(1, round(1e-5 / dt))))
        out = work / f"cav_{dt:g}.h5"
        r = subprocess.run([host, str(model), "--out", str(out)], capture_output=True, text=True, timeout=300)
        if r.returncode != 0:
            print(f"tlm_host failed at dt = {dt:g}:\n{r.stderr}")
            return 1
        with h5py.File(out) as f:
            th, xh = f["time"][:], f["components/piston/x"][:]
            ph, vh = f["components/chamber/p_mean"][:], f["components/chamber/V_void"][:]
        t_h = stop_time(th, xh)
        p_h = stroke_pressure(th, ph, t_h)
        runs[dt] = (th, xh, vh, t_h)
        checks = [
            ("stop time [ms]", t_h * 1e3, t_ref * 1e3, abs(t_h - t_ref) <= 2e-4),
            ("stroke pressure [bar]", p_h / 1e5, p_ref / 1e5, abs(p_h / p_ref - 1) <= 0.01),
            ("final pressure [bar]", ph[-1] / 1e5, p_end_ref / 1e5, abs(ph[-1] / p_end_ref - 1) <= 0.01),
            ("largest void [cm³]", vh.max() * 1e6, void_ref * 1e6, abs(vh.max() / void_ref - 1) <= 3 * OMEGA * dt),
            ("cavitation events", len(events(th, vh)), len(events(t, void)), True),  # shown, not judged
        ]
        for name, got, want, good in checks:
            print(f"  dt = {dt:g} s: {name}: {got:.4f} (reference {want:.4f}) {'ok' if good else 'FAILED'}")
            ok &= good
        cav = [line for line in r.stderr.splitlines() if "cavitation" in line]
        print("  " + (cav[0] if cav else "no cavitation reported"))
        ok &= bool(cav)
    if plot:
        draw(plot, (t, x, void, t_ref), runs)
    return 0 if ok else 1


def draw(path, ref, runs):
    """Piston travel and vapour volume: the conserving reference, the
    oil-creating one, and tlm_host; the stop times in the legend."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    tf, xf, vf, _ = reference(conserve=False)
    t_forget = stop_time(tf, xf)
    t, x, void, t_ref = ref
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 3.8))
    a1.plot(t * 1e3, x * 1e3, "k-", lw=2, label=f"continuous, void kept: stop {t_ref*1e3:.2f} ms")
    a1.plot(tf * 1e3, xf * 1e3, "C3--", label=f"continuous, void forgotten: stop {t_forget*1e3:.2f} ms")
    for (dt, (th, xh, vh, t_h)), style in zip(sorted(runs.items()), ("C0:", "C2-.")):
        a1.plot(th * 1e3, xh * 1e3, style, label=f"tlm_host {dt*1e6:g} µs: stop {t_h*1e3:.2f} ms")
        a2.plot(th * 1e3, vh * 1e6, style, label=f"tlm_host {dt*1e6:g} µs")
    a2.plot(t * 1e3, void * 1e6, "k-", lw=2, alpha=0.6, label="continuous, void kept")
    a1.set_xlim(t_ref * 1e3 - 3, t_ref * 1e3 + 1)
    a1.set_ylim(9.6, 10.05)
    a1.set_xlabel("t [ms]")
    a1.set_ylabel("piston x [mm]")
    a1.set_title("End of stroke", fontsize=10)
    a1.legend(fontsize=7)
    a2.set_xlim(0, 10)
    a2.set_xlabel("t [ms]")
    a2.set_ylabel("vapour volume [cm³]")
    a2.set_title("Cavitation after the launch", fontsize=10)
    a2.legend(fontsize=7)
    for a in (a1, a2):
        a.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    print(f"oil-creating model: stop at {t_forget*1e3:.3f} ms ({(t_forget - t_ref)*1e3:+.3f} ms); plot {path}")


if __name__ == "__main__":
    sys.exit(main())
