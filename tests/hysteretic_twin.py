"""Independent reference ("twin") of a shear building with yielding storeys.

Slow, pure NumPy/SciPy, written apart from the package (it imports nothing
from ``seispound``).  The storey laws are written again from their sources:

* Bouc-Wen (Wen 1976, J. Eng. Mech. Div. 102(2) 249-263, with A = 1):
  F = alpha k d + (1 - alpha) k z, dz/dt = d' (1 - |z/dy|^n (beta sgn(d' z) + gamma)),
  integrated as ODE states next to the floors' displacements and velocities;
* bilinear with kinematic hardening: F = alpha k d + (1 - alpha) q with the
  hysteretic force q obeying dq/dt = k d' while |q| < fy and 0 while
  yielding; the switches (q reaching +-fy, the drift rate changing sign while
  yielding) are terminal events of the integrator, so no step straddles one.

The equations M u'' + C u' + f_s(u, history) = -M 1 a_g(t) (C = a0 M + a1 K0,
Rayleigh from the initial stiffness) are integrated by
:func:`scipy.integrate.solve_ivp` with tight tolerances, restarted at the
record's samples (kinks of the piecewise-linear a_g).  One more state
integrates the work done on the storeys, from which the dissipated
(hysteretic) energy follows exactly: work minus recoverable energy.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp


def storey_force(law, d, h):
    """Storey force [N] for drift d and hysteretic variable h (z or q)."""
    if law["kind"] == "elastic":
        return law["k"] * d
    if law["kind"] == "bouc-wen":
        return law["alpha"] * law["k"] * d + (1 - law["alpha"]) * law["k"] * h
    return law["alpha"] * law["k"] * d + (1 - law["alpha"]) * h


def recoverable(law, d, h):
    """Elastic energy stored in a storey [J]."""
    k, a = law["k"], law.get("alpha", 1.0)
    if law["kind"] == "elastic":
        return 0.5 * k * d * d
    if law["kind"] == "bouc-wen":
        return 0.5 * a * k * d * d + 0.5 * (1 - a) * k * h * h
    return 0.5 * a * k * d * d + 0.5 * (1 - a) * h * h / k


def hysteretic_rate(law, dd, h, regime):
    """dh/dt for drift rate dd: Bouc-Wen's z, or the bilinear law's q in its regime (0 elastic, +-1 yielding)."""
    if law["kind"] == "bouc-wen":
        x = abs(h) / law["dy"]
        return dd * (1.0 - x ** law["n"] * (law["beta"] * np.sign(dd * h) + law["gamma"]))
    if law["kind"] == "bilinear":
        return law["k"] * dd if regime == 0 else 0.0
    return 0.0


def simulate(masses, laws, a0, a1, ag_func, t_end, t_eval, breakpoints=(), drift=None, rtol=1e-10):
    """Integrate a shear building (floors 1..n from the ground up) with storey laws ``laws`` (dicts).

    ``drift``: instead of a building, one storey under the imposed drift d(t)
    (a callable returning (d, d')): the hysteresis loop.  Returns a dict with
    u (nt, n) [m], storey forces f (nt, n) [N], the dissipated energy e_hyst
    (nt,) [J] and, for the building, the damping and input work.
    """
    m = np.asarray(masses, float)
    n = len(laws)
    k0 = np.array([law["k"] for law in laws])
    regime = np.zeros(n, int)

    def drifts(u, v):
        d = u - np.concatenate([[0.0], u[:-1]])
        dd = v - np.concatenate([[0.0], v[:-1]])
        return d, dd

    def unpack(t, y):
        if drift is not None:
            d, dd = drift(t)
            return np.array([d]), np.array([dd]), y[:1], None, None
        u, v, h = y[:n], y[n:2 * n], y[2 * n:3 * n]
        d, dd = drifts(u, v)
        return d, dd, h, u, v

    def rhs(t, y):
        d, dd, h, u, v = unpack(t, y)
        dh = np.array([hysteretic_rate(laws[i], dd[i], h[i], regime[i]) for i in range(n)])
        fs = np.array([storey_force(laws[i], d[i], h[i]) for i in range(n)])
        work = float(np.dot(fs, dd))
        if drift is not None:
            return np.concatenate([dh, [work]])
        shear = fs + a1 * k0 * dd  # storey spring + its Rayleigh dashpot
        f = -m * ag_func(t) - a0 * m * v - shear + np.concatenate([shear[1:], [0.0]])
        damp = float(a0 * np.dot(m * v, v) + np.dot(a1 * k0 * dd, dd))
        inp = float(-np.dot(m * ag_func(t), v))
        return np.concatenate([v, f / m, dh, [work, damp, inp]])

    def events():
        evs = []
        for i, law in enumerate(laws):
            if law["kind"] != "bilinear":
                continue
            if regime[i] == 0:
                for s in (1.0, -1.0):
                    def ev(t, y, i=i, s=s):
                        return unpack(t, y)[2][i] - s * laws[i]["fy"]
                    ev.terminal, ev.direction = True, s
                    evs.append((ev, i, s))
            else:
                def ev(t, y, i=i):
                    return unpack(t, y)[1][i]
                ev.terminal, ev.direction = True, -float(regime[i])
                evs.append((ev, i, 0))
        return evs

    nh = n if drift is not None else 3 * n
    y = np.zeros(nh + (1 if drift is not None else 3))
    bps = np.unique([b for b in breakpoints if 0 < b < t_end] + [t_end])
    t = 0.0
    ys = np.full((len(t_eval), y.size), np.nan)
    done = np.zeros(len(t_eval), bool)
    while t < t_end * (1 - 1e-14):
        t_stop = bps[bps > t * (1 + 1e-14) + 1e-300][0]
        evs = events()
        sol = solve_ivp(rhs, (t, t_stop), y, method="LSODA", rtol=rtol, atol=1e-13, dense_output=True,
                        events=[e[0] for e in evs] or None)
        if sol.status < 0:
            raise RuntimeError(sol.message)
        t_end_seg = sol.t[-1]
        fired = None
        if sol.status == 1:
            hits = [(sol.t_events[k][0], k) for k in range(len(evs)) if sol.t_events[k].size]
            t_end_seg, kf = min(hits)
            fired = evs[kf]
        sel = (~done) & (t_eval >= t) & (t_eval <= t_end_seg)
        if sel.any():
            ys[sel] = sol.sol(t_eval[sel]).T
            done |= sel
        y = sol.sol(t_end_seg)
        t = t_end_seg
        if fired is not None:
            _, i, s = fired
            if s != 0:  # q reached +-fy: yielding
                regime[i] = int(s)
                y[(0 if drift is not None else 2 * n) + i] = s * laws[i]["fy"]
            else:  # the drift turned: elastic again
                regime[i] = 0
    out = {}
    rec = np.zeros(len(t_eval))
    f = np.zeros((len(t_eval), n))
    for k, tk in enumerate(t_eval):
        d, dd, h, u, v = unpack(tk, ys[k])
        f[k] = [storey_force(laws[i], d[i], h[i]) for i in range(n)]
        rec[k] = sum(recoverable(laws[i], d[i], h[i]) for i in range(n))
        if drift is None:
            out.setdefault("u", np.zeros((len(t_eval), n)))[k] = u
    out["f"] = f
    out["e_hyst"] = ys[:, nh] - rec
    if drift is None:
        out["e_damp"] = ys[:, nh + 1]
        out["e_input"] = ys[:, nh + 2]
    return out
