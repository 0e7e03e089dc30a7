"""A linear model of one coupling loop, to compare ways of solving the FE
side's TLM port (no processes; prints a table for bench/RESULTS.md).

The loop: a two-port host volume (HydraulicVolumeC: Zc = β·T/V, one port
shut) joined to a piston of mass m on a spring k_s (central difference, one
FE step per coupling step T). Its state after one step is a linear map of
the state before; the spectral radius ρ of that map says whether the loop
grows (ρ > 1). Variants of the FE port p = c + Zc·q:

  explicit   q from v_{n-1/2}: an explicit damper Zc·A² (the first implementation)
  end        q from v_{n+1/2}, solved implicitly
  mid        q from v_n = ½(v_{n-1/2} + v_{n+1/2}), solved implicitly, and the
             host receives that same q (what fe_server does now)

Usage: /usr/bin/python3 bench/coupling_loop_model.py
"""
import numpy as np

BETA, AREA, SPRING = 1.4e9, 1e-3, 1e6


def spectral_radius(m, V, T, variant):
    Z = BETA * T / V

    def step(s):
        c1, c2, v, x, q_last = s
        pm = 0.5 * (c1 + c2 + 2 * Z * q_last)
        c1, c2 = 2 * pm - c1, 2 * pm - c2 - 2 * Z * q_last
        d = T * Z * AREA ** 2 / m
        f = T * (-AREA * c2 - SPRING * x) / m
        if variant == "explicit":
            vn = v - d * v + f
            q = AREA * vn
        elif variant == "end":
            vn = (v + f) / (1 + d)
            q = AREA * vn
        else:  # mid
            vn = (v * (1 - d / 2) + f) / (1 + d / 2)
            q = AREA * 0.5 * (v + vn)
        return np.array([c1, c2, vn, x + T * vn, q])

    M = np.column_stack([step(e) for e in np.eye(5)])
    return max(abs(np.linalg.eigvals(M)))


def main():
    print("| variant | m [kg] | V [cm³] | largest ρ over ω·T = 0.01–100 (ω_s·T ≤ 1.3) | largest ρ at ω_s·T = 1.8 (TSSFAC 0.9) |")
    print("|---|---|---|---|---|")
    for variant in ("explicit", "end", "mid"):
        for m, V in ((0.5, 1e-6), (5.0, 1e-4)):
            w = np.sqrt(BETA * AREA ** 2 / (V * m))
            ws = np.sqrt(SPRING / m)
            steps = [x / w for x in np.logspace(-2, 2, 200) if x / w * ws <= 1.3]
            r1 = max(spectral_radius(m, V, T, variant) for T in steps)
            r2 = spectral_radius(m, V, 1.8 / ws, variant)
            print(f"| {variant} | {m:g} | {V*1e6:g} | {r1:.6f} | {r2:.6f} |")


if __name__ == "__main__":
    main()
