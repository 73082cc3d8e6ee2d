"""Degrading storey hysteresis for the held-out generator (``outside.py``): Takeda / Clough with optional pinching.

Independent of the package (NumPy only).  A storey's force-drift law, NOT one of the library's
(bilinear kinematic, Bouc-Wen):

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
(drift at or past ``dpos``, moving on), likewise ``dneg``.  Along a reloading line the tangent is
the slope from the current point to the line's target, ``(F_target - f) / (d_target - d)``, so
that the line needs no stored origin and any drift in ``f`` is steered back onto the target.  A
branch change is a jump of the rate only (``f`` stays continuous), which LSODA's error control
steps through (no events).  The envelope test allows 1e-7 dy, so a storey that reached its peak
does not flicker between the reloading line and the envelope.
"""

from __future__ import annotations

import numpy as np

ENVELOPE_TOL = 1e-7  # of dy


def backbone(d, k0, dy, alpha):
    """The bilinear backbone force at drift ``d`` (array or scalar)."""
    a = np.abs(d)
    return np.sign(d) * np.where(a <= dy, k0 * a, k0 * dy + alpha * k0 * (a - dy))


def tangent(d, v, f, dpos, dneg, k0, dy, alpha, beta, pinch=None):
    """(kt, on_pos, on_neg): the branch's tangent stiffness and whether each envelope moves on.

    Vectorised over storeys (every argument an array of the same shape, or a scalar)."""
    d, v, f, dpos, dneg = (np.asarray(x, float) for x in (d, v, f, dpos, dneg))
    k0, dy, alpha, beta = (np.broadcast_to(np.asarray(x, float), d.shape) for x in (k0, dy, alpha, beta))
    tol = ENVELOPE_TOL * dy
    up = v >= 0.0
    kb = np.where(np.abs(d) < dy, k0, alpha * k0)
    on_pos = up & (d >= dpos - tol)
    on_neg = (~up) & (d <= dneg + tol)
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
    k_re = np.clip(k_re, 0.02 * k0, k0)
    unloading = np.where(up, f < 0.0, f > 0.0)
    kt = np.where(on_pos | on_neg, kb, np.where(unloading, np.where(up, ku_neg, ku_pos), k_re))
    return kt, on_pos, on_neg


def rates(d, v, f, dpos, dneg, k0, dy, alpha, beta, pinch=None):
    """(df/dt, d dpos/dt, d dneg/dt) for drift ``d`` moving at ``v``."""
    kt, on_pos, on_neg = tangent(d, v, f, dpos, dneg, k0, dy, alpha, beta, pinch)
    return kt * v, np.where(on_pos, v, 0.0), np.where(on_neg, v, 0.0)


def follow(t, d, v, k0, dy, alpha, beta, pinch=None, rtol=1e-9):
    """The force along a prescribed drift history (callables ``d(t)``, ``v(t)``) at the times ``t``.

    Integrates the state formulation above with ``solve_ivp`` (the check of the formulation
    against hand-computed paths in ``tests/diagnose/test_generator_outside.py``)."""
    from scipy.integrate import solve_ivp

    def rhs(tt, y):
        df, dp, dn = rates(d(tt), v(tt), y[0], y[1], y[2], k0, dy, alpha, beta, pinch)
        return [float(df), float(dp), float(dn)]

    sol = solve_ivp(rhs, (t[0], t[-1]), [0.0, dy, -dy], method="LSODA", t_eval=t, rtol=rtol, atol=1e-12 * k0 * dy,
                    max_step=(t[-1] - t[0]) / 2000.0)
    return sol.y[0]
