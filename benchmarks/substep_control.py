"""Fixed contact substeps against error-controlled ones, on one two-body impact per law.

``python -m benchmarks.substep_control``

The kernel cuts an impact into ``contact_substeps`` substeps of its estimated duration
(``contact._scalar.contact_duration``), NIVe's first six graded from 1/64 of a substep up
(``integrate._contact.ONSET_GRADING``).  The alternative studied here sizes each substep from
an embedded estimate of Newmark's local displacement error,

    e_n = (beta - 1/6) h^2 (a_(n+1) - a_n)        (Zienkiewicz & Xie 1991, EESD 20(9):871-887),

holding |e_n| below the error a uniform schedule of N substeps makes on a linear impact,
(beta - 1/6) (pi / N)^3 delta_max (delta_max from the law's closed form), with the usual
controller h_(n+1) = h_n min(2, max(1/2, 0.9 (tol / |e_n|)^(1/3))), starting from 1/8 of a
substep.  Both march the relative coordinate of two free bodies, m_eff delta'' = -F(delta,
delta'), with Newmark's average acceleration, Newton on the step's force and the separation
located on the step's cubic Hermite (as the kernel does); the peak force is the vertex of
the parabola through the samples around the largest (``_contact._peak_through``).  Errors
against the same march with 8192 uniform substeps: restitution vout / v0 and peak force.

What it shows: error control pays only where the force law is rough at onset (NIVe's damping
grows like delta^(1/4)), and the kernel's onset grading already buys most of that; for the
other laws a displacement-error controller spends its steps where the restitution does not
need them.
"""

from __future__ import annotations

import argparse
import math

from scipy.optimize import brentq

from seispound.contact import _scalar as S
from seispound.contact import make_law

BETA = 0.25
M1, M2 = 2.0e5, 3.0e5  # kg: two floors of a pair
MEFF = M1 * M2 / (M1 + M2)
V0 = 0.5  # m/s
STIFFNESS = {"LVe": 9.3e7, "LHC": 9.3e7, "NIVe": 9.3e9, "Hd": 9.3e9}  # N/m or N/m^1.5
GRADING = 6  # the kernel's ONSET_GRADING for NIVe


def _law(name):
    law = make_law(name, stiffness=STIFFNESS[name], restitution=0.65)
    par = law.kernel_params(M1, M2)
    return law.code, par


def _newmark(f, d, r, a, h):
    """One Newmark step of m_eff d'' = -f(d, d'): (d1, r1, a1), Newton on a1 with a numeric slope."""
    a1 = a
    for _ in range(60):
        d1 = d + h * r + h * h * ((0.5 - BETA) * a + BETA * a1)
        r1 = r + 0.5 * h * (a + a1)
        res = MEFF * a1 + f(d1, r1)
        eps = 1e-7 * max(abs(a1), 1.0)
        d1e = d + h * r + h * h * ((0.5 - BETA) * a + BETA * (a1 + eps))
        r1e = r + 0.5 * h * (a + a1 + eps)
        slope = (MEFF * (a1 + eps) + f(d1e, r1e) - res) / eps
        da = -res / slope
        a1 += da
        if abs(da) <= 1e-13 * max(abs(a1), 1.0):
            break
    d1 = d + h * r + h * h * ((0.5 - BETA) * a + BETA * a1)
    return d1, r + 0.5 * h * (a + a1), a1


def _peak(ts, fs):
    k = max(range(len(fs)), key=fs.__getitem__)
    if 0 < k < len(fs) - 1:
        ha, hc = ts[k] - ts[k - 1], ts[k + 1] - ts[k]
        sa, sc = (fs[k - 1] - fs[k]) / ha, (fs[k + 1] - fs[k]) / hc
        c = (sa + sc) / (ha + hc)
        if c < 0:
            b = sc - c * hc
            return fs[k] - b * b / (4 * c)
    return fs[k]


def impact(name: str, n_sub: int, schedule: str) -> dict:
    """One impact at V0 with ``schedule`` 'uniform', 'graded' (the kernel's: NIVe graded) or 'controlled'."""
    code, par = _law(name)
    zeta = S.onset_state(code, par, V0)[0]
    tc = S.contact_duration(code, par, V0)
    n = par[S.P_EXPONENT]
    dmax = ((n + 1.0) * MEFF * V0 * V0 / (2.0 * par[S.P_K])) ** (1.0 / (n + 1.0))
    tol = (BETA - 1.0 / 6.0) * (math.pi / n_sub) ** 3 * dmax

    def f(d, r):
        return S.contact_force(code, par, max(d, 0.0), r, zeta)[0]

    hsub = tc / n_sub
    d, r, a, t = 0.0, V0, -f(0.0, V0) / MEFF, 0.0
    ts, fs = [0.0], [f(0.0, V0)]
    h = hsub / 8 if schedule == "controlled" else hsub
    age = 0
    while True:
        if schedule == "graded" and code == S.NIVE and age < GRADING:
            h = hsub / 2 ** (GRADING - age)
        elif schedule == "graded":
            h = hsub
        d1, r1, a1 = _newmark(f, d, r, a, h)
        if d1 < 0.0:  # separation inside the step: its cubic Hermite's root, and the step redone to it
            def herm(s, d=d, r=r, d1=d1, r1=r1, h=h):
                return ((2 * s**3 - 3 * s**2 + 1) * d + (s**3 - 2 * s**2 + s) * h * r
                        + (-2 * s**3 + 3 * s**2) * d1 + (s**3 - s**2) * h * r1)
            h *= brentq(herm, 1e-14, 1.0)
            d1, r1, a1 = _newmark(f, d, r, a, h)
            ts.append(t + h)
            fs.append(f(d1, r1))
            return dict(steps=age + 1, e=-r1 / V0, fmax=_peak(ts, fs))
        err = abs(BETA - 1.0 / 6.0) * h * h * abs(a1 - a)
        d, r, a, t = d1, r1, a1, t + h
        ts.append(t)
        fs.append(f(d, r))
        age += 1
        if schedule == "controlled":
            h *= min(2.0, max(0.5, 0.9 * (tol / max(err, 1e-300)) ** (1.0 / 3.0)))


def run(laws=("LVe", "LHC", "NIVe", "Hd"), counts=(4, 8, 16, 32)) -> list[dict]:
    rows = []
    for name in laws:
        ref = impact(name, 8192, "uniform")
        for n_sub in counts:
            for schedule in ("graded", "controlled"):
                r = impact(name, n_sub, schedule)
                rows.append(dict(law=name, substeps=n_sub, schedule=schedule, steps=r["steps"],
                                 e_err=r["e"] / ref["e"] - 1.0, f_err=r["fmax"] / ref["fmax"] - 1.0))
    return rows


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.substep_control", description=__doc__.splitlines()[0])
    ap.parse_args(argv)
    print(f"two bodies {M1:.0f} + {M2:.0f} kg at {V0} m/s, e = 0.65; errors against 8192 uniform substeps")
    print(f"{'law':5s} {'N':>3s}  {'fixed (kernel)':>34s}  {'error-controlled':>34s}")
    print(f"{'':5s} {'':>3s}  {'steps':>6s} {'restitution':>13s} {'peak force':>12s}  "
          f"{'steps':>6s} {'restitution':>13s} {'peak force':>12s}")
    rows = run()
    for k in range(0, len(rows), 2):
        g, c = rows[k], rows[k + 1]
        print(f"{g['law']:5s} {g['substeps']:3d}  {g['steps']:6d} {g['e_err']:+13.2e} {g['f_err']:+12.2e}  "
              f"{c['steps']:6d} {c['e_err']:+13.2e} {c['f_err']:+12.2e}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
