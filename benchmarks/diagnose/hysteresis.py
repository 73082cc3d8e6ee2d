"""Degrading storey hysteresis for the held-out generator (``outside.py``): Takeda / Clough with optional pinching.

Independent of the package (NumPy only).  The package's hypothesis library now holds a peak-oriented law of
this kind (Clough / Takeda, optional pinching), so the outside suite's default draw conceals yielding
storeys with the other laws of the generator, ``braced.py`` (tension-only X-braced storeys) and ``masing.py``
(Ramberg-Osgood with Masing's rules; ``flag.py``, flag-shaped and self-centring, is held by the library too
since it gained a flag-shaped law); the forms "takeda", "clough-pinched", "rocking-cone+takeda" and
"stratum+clough-pinched" that use this law are still made with ``--forms``.  The law:

* **Backbone**: bilinear, elastic stiffness ``k0`` up to the yield drift ``dy`` (force Fy = k0 dy),
  then ``alpha * k0``; symmetric.
* **Unloading** (force and drift rate of opposite signs): a straight line of stiffness
  ``k0 * (dy / dm) ** beta`` where ``dm`` is the largest excursion so far on the side the force
  is on (at least dy): Takeda et al. (1970) with Otani's exponent (``beta`` 0.3-0.5); ``beta = 0``
  is Clough's model (unloading at the elastic stiffness).
* **Reloading** (past zero force, towards the other side): peak-oriented, a straight line aimed at
  the point of largest excursion on that side, on the backbone (the yield point while that side
  has not yielded).  With ``pinch = p`` (0 < p < 1) the line is first aimed at the pinch point,
  where the target side's last unloading line carries p times the target force, then at the
  target: the loop is pinched near zero force.
* A partial reversal (a reversal before the force reaches zero) unloads with the unloading
  stiffness and reloads straight back towards the same peak, which is the point the unloading line
  left (the simplified Takeda rule).

**Integration: a smooth state formulation.**  The storey force ``f`` and the two largest
excursions ``dpos >= dy``, ``dneg <= -dy`` are ODE states; ``df/dt = kt * dd/dt``, with the tangent
``kt`` of the branch chosen from the signs of the drift rate and the force and from the drift's
position against the excursions; ``d dpos/dt = dd/dt`` while the storey is on the positive envelope
(drift at or past ``dpos``, moving on; through a continuous ramp, ``rates``), likewise ``dneg``.  Along a reloading line the tangent is
the slope from the current point to the line's target, ``(F_target - f) / (d_target - d)``, so
that the line needs no stored origin and any drift in ``f`` is steered back onto the target.  A
branch change is a jump of the rate only (``f`` stays continuous), which LSODA's error control
steps through (no events).  The envelope test allows 2e-7 dy and the excursions follow the
drift 1e-7 dy behind it, so that a storey on its envelope does not chatter between the reloading
line and the envelope (a sliding mode that stalled LSODA at 1e-9 s steps).
"""

from __future__ import annotations

import numpy as np

ENVELOPE_TOL = 1e-7  # of dy


def backbone(d, k0, dy, alpha):
    """The bilinear backbone force at drift ``d`` (array or scalar)."""
    a = np.abs(d)
    return np.sign(d) * np.where(a <= dy, k0 * a, k0 * dy + alpha * k0 * (a - dy))


def tangent(d, v, f, dpos, dneg, k0, dy, alpha, beta, pinch=None, partials=False):
    """(kt, on_pos, on_neg): the branch's tangent stiffness and whether each envelope moves on; with
    ``partials`` also the derivatives of the force rate kt v in the drift and in the force (nonzero on a
    reloading line only, whose slope depends on the current point: a stiff attractor near the target,
    which an implicit integrator's Jacobian must hold).

    Vectorised over storeys (every argument an array of the same shape, or a scalar)."""
    d, v, f, dpos, dneg = (np.asarray(x, float) for x in (d, v, f, dpos, dneg))
    k0, dy, alpha, beta = (np.broadcast_to(np.asarray(x, float), d.shape) for x in (k0, dy, alpha, beta))
    tol = ENVELOPE_TOL * dy
    up = v >= 0.0
    kb = np.where(np.abs(d) < dy, k0, alpha * k0)
    on_pos = up & (d >= dpos - 2.0 * tol)
    on_neg = (~up) & (d <= dneg + 2.0 * tol)
    ku_pos = k0 * (dy / np.maximum(dpos, dy)) ** beta  # unloading from the positive side
    ku_neg = k0 * (dy / np.maximum(-dneg, dy)) ** beta
    # the reloading targets
    d_t = np.where(up, dpos, dneg)
    f_t = backbone(d_t, k0, dy, alpha)
    ku_t = np.where(up, ku_pos, ku_neg)
    if pinch is not None:
        p = np.broadcast_to(np.asarray(pinch, float), d.shape)
        # the pinch point: on the target side's last unloading line, at p times the target force
        d_p = d_t - (1.0 - p) * f_t / ku_t
        f_p = p * f_t
        before = (p < 1.0) & np.where(up, (f < f_p) & (d < d_p), (f > f_p) & (d > d_p))
        d_t = np.where(before, d_p, d_t)
        f_t = np.where(before, f_p, f_t)
    den = d_t - d
    with np.errstate(divide="ignore", invalid="ignore"):
        k_re = np.where(np.abs(den) > tol, (f_t - f) / den, k0)
    free = (k_re > 0.02 * k0) & (k_re < k0) & (np.abs(den) > tol)  # the slope is not clipped
    k_re = np.clip(k_re, 0.02 * k0, k0)
    unloading = np.where(up, f < 0.0, f > 0.0)
    reloading = ~(on_pos | on_neg) & ~unloading
    kt = np.where(on_pos | on_neg, kb, np.where(unloading, np.where(up, ku_neg, ku_pos), k_re))
    if partials:
        # d(kt v)/dd and d(kt v)/df on an unclipped reloading line, kt = (f_t - f) / (d_t - d)
        live = reloading & free
        with np.errstate(divide="ignore", invalid="ignore"):
            dd = np.where(live, v * k_re / den, 0.0)
            dfv = np.where(live, -v / den, 0.0)
        return kt, on_pos, on_neg, dd, dfv
    return kt, on_pos, on_neg


def rates(d, v, f, dpos, dneg, k0, dy, alpha, beta, pinch=None):
    """(df/dt, d dpos/dt, d dneg/dt) for drift ``d`` moving at ``v``."""
    kt, on_pos, on_neg = tangent(d, v, f, dpos, dneg, k0, dy, alpha, beta, pinch)
    tol = ENVELOPE_TOL * np.asarray(dy, float)
    # the excursions move with the drift through a ramp over (2 tol, tol) behind it, continuous in the state,
    # so that a storey on its envelope settles at tol behind it, inside the envelope test (2 tol) and without
    # chattering across a switching surface
    ramp_p = np.clip((np.asarray(d) - dpos + 2.0 * tol) / tol, 0.0, 1.0)
    ramp_n = np.clip((dneg - np.asarray(d) + 2.0 * tol) / tol, 0.0, 1.0)
    v = np.asarray(v, float)
    return kt * v, np.where(v >= 0.0, v * ramp_p, 0.0), np.where(v < 0.0, v * ramp_n, 0.0)


def follow(t, d, v, k0, dy, alpha, beta, pinch=None, rtol=1e-9):
    """The force along a prescribed drift history (callables ``d(t)``, ``v(t)``) at the times ``t``.

    Integrates the state formulation above with ``solve_ivp`` (the check of the formulation
    against hand-computed paths in ``tests/diagnose/test_generator_outside.py``)."""
    from scipy.integrate import solve_ivp

    def rhs(tt, y):
        df, dp, dn = rates(d(tt), v(tt), y[0], y[1], y[2], k0, dy, alpha, beta, pinch)
        return [float(df), float(dp), float(dn)]

    # RK45 here: along a prescribed drift the ODE is not stiff, and LSODA crawled through the kink of the rate
    # at a pinched loop's zero-force crossing (steps of 1e-10 s); the force's absolute tolerance is relative to Fy
    sol = solve_ivp(rhs, (t[0], t[-1]), [0.0, dy, -dy], method="RK45", t_eval=t, rtol=rtol,
                    atol=[1e-9 * k0 * dy, 1e-12 * dy, 1e-12 * dy], max_step=(t[-1] - t[0]) / 2000.0)
    return sol.y[0]
