"""Flag-shaped self-centring storey hysteresis for the held-out generator (``outside.py``).

Independent of the package (NumPy only).  The law of a storey with post-tensioned, energy-dissipating
rocking connections: Christopoulos, Filiatrault & Folz (2002), "Seismic response of self-centring
hysteretic SDOF systems", Earthquake Engineering and Structural Dynamics 31(5), 1131-1150
(doi:10.1002/eqe.152).  Parameters: initial stiffness ``k0``, yield drift ``dy`` (Fy = k0 dy), post-yield
ratio ``alpha`` (0 < alpha < 1) and the energy-dissipation parameter ``beta_f`` (0 < beta_f < 1: the
flag's height over Fy).  Symmetric.

**Rules** (positive side; the negative side is the mirror image through the origin):

* **Loading**: elastic at ``k0`` through the origin up to (dy, Fy), then the upper line
  ``f = Fy + alpha k0 (d - dy)``.
* **Unloading** from a point of the upper line: elastic at ``k0`` through a force drop of ``beta_f Fy``,
  then the lower line ``f = (1 - beta_f) Fy + alpha k0 (d - (1 - beta_f) dy)`` (the upper line moved by
  (-beta_f dy, -beta_f Fy) along the elastic slope) down to the activation point
  ((1 - beta_f) dy, (1 - beta_f) Fy), which lies on the elastic line through the origin; then elastic
  through the ORIGIN: no residual drift at zero force.
* **Reloading** from the lower line (a partial unloading): elastic at ``k0`` back up to the upper line
  (the flag is crossed at k0 both ways); an unloading that stops inside the flag reloads the same way.

**State formulation.**  The storey force ``f`` and a slip ``p`` (the drift at which the current elastic
line ``f = k0 (d - p)`` would carry no force) are ODE states.  In terms of ``p`` the two lines are force
limits, ``F_up(p) = Fy + H |p|`` and ``F_lo(p) = (1 - beta_f) Fy + H |p|`` with H = alpha k0 / (1 - alpha):
on the positive flag (p > 0) the storey is elastic while ``F_lo(p) < f < F_up(p)``, and the slip moves
only on the lines, ``dp/dt = (1 - alpha) v`` with ``df/dt = alpha k0 v`` (so that f - F_up, or f - F_lo, stays
constant on its line): loading on the upper line (v > 0, f at F_up), re-centring on the lower line (v < 0,
f at F_lo, until p returns to 0).  At p = 0 the storey is elastic between -Fy and Fy.  ``f = k0 (d - p)``
is a linear invariant of the rates (df = kt v, dp = (1 - kt / k0) v), which Runge-Kutta methods keep to
round-off.  A line is reached within ``ENVELOPE_TOL`` Fy (a branch change is a jump of the rate, f and p
stay continuous; on a line the rates keep the distance to it constant, so a storey does not chatter), and
re-centring stops within ``SLIP_TOL`` dy of p = 0 (the residual drift at zero force).
"""

from __future__ import annotations

import numpy as np

ENVELOPE_TOL = 1e-7  # of Fy: a line is reached this close
SLIP_TOL = 1e-7  # of dy: p within this of zero is the origin's elastic range


def _b(x, shape):
    return np.broadcast_to(np.asarray(x, float), shape)


def tangent(v, f, p, k0, dy, alpha, beta_f):
    """(kt, flow): the tangent stiffness and whether the slip moves, for drift rate ``v``, force ``f`` and slip
    ``p``.  Vectorised over storeys (every argument an array of the same shape, or a scalar)."""
    v, f, p = (np.asarray(x, float) for x in (v, f, p))
    k0, dy, alpha, beta_f = (_b(x, v.shape) for x in (k0, dy, alpha, beta_f))
    fy = k0 * dy
    h = alpha * k0 / (1.0 - alpha)
    tol, ptol = ENVELOPE_TOL * fy, SLIP_TOL * dy
    f_up = fy + h * np.abs(p)
    f_lo = (1.0 - beta_f) * fy + h * np.abs(p)
    up = v >= 0.0
    # moving up: loading on the positive upper line (at the origin or on the positive flag), or re-centring on
    # the negative flag's lower line (-F_lo); moving down: the mirror image
    flow_up = np.where(p >= -ptol, f >= f_up - tol, f >= -f_lo - tol)
    flow_dn = np.where(p <= ptol, f <= -f_up + tol, f <= f_lo + tol)
    flow = np.where(up, flow_up, flow_dn) & (v != 0.0)
    return np.where(flow, alpha * k0, k0), flow


def rates(v, f, p, k0, dy, alpha, beta_f):
    """(df/dt, dp/dt) for a storey drift moving at ``v``."""
    kt, flow = tangent(v, f, p, k0, dy, alpha, beta_f)
    v = np.asarray(v, float)
    return kt * v, np.where(flow, (1.0 - np.asarray(alpha, float)) * v, 0.0)


def backbone(d, k0, dy, alpha):
    """The monotonic loading curve (bilinear) at drift ``d``."""
    a = np.abs(d)
    return np.sign(d) * np.where(a <= dy, k0 * a, k0 * dy + alpha * k0 * (a - dy))


def follow(t, d, v, k0, dy, alpha, beta_f, rtol=1e-9, slip=False):
    """The force along a prescribed drift history (callables ``d(t)``, ``v(t)``) at the times ``t`` (with
    ``slip``: also the slip p).

    Integrates the state formulation above with ``solve_ivp`` (RK45: along a prescribed drift the ODE is not
    stiff); the check of the formulation against hand-derived paths in ``tests/diagnose/test_generator_outside.py``."""
    from scipy.integrate import solve_ivp

    def rhs(tt, y):
        df, dp = rates(v(tt), y[0], y[1], k0, dy, alpha, beta_f)
        return [float(df), float(dp)]

    sol = solve_ivp(rhs, (t[0], t[-1]), [0.0, 0.0], method="RK45", t_eval=t, rtol=rtol,
                    atol=[1e-9 * k0 * dy, 1e-12 * dy], max_step=(t[-1] - t[0]) / 2000.0)
    return (sol.y[0], sol.y[1]) if slip else sol.y[0]
