"""Tension-only X-braced storey hysteresis for the held-out generator (``outside.py``).

Independent of the package (NumPy only).  A storey of a concentrically braced steel frame whose diagonals are
slender (they buckle at a negligible load, so each carries tension only), in parallel with the frame that
holds them (its columns and beams, elastic).  The behaviour, not the formulas below, is from the literature on
such frames: Tremblay & Filiatrault (1996), "Seismic impact loading in inelastic tension-only concentrically
braced steel frames: myth or reality?", Earthquake Engineering and Structural Dynamics 25(12), 1373-1389, and
Filiatrault & Tremblay (1998), "Design of tension-only concentrically braced steel frames for seismic induced
impact loading", Engineering Structures 20(12), 1087-1096 (a brace that has yielded in tension is slack on the
way back, the storey slips with only the frame's stiffness until the drift takes the slack up, and the brace
then picks up its load at once: pinched, slipping loops that dissipate energy only when an excursion passes the
largest before it); the textbook statement of slender-brace hysteresis, Bruneau, Uang & Sabelli (2011),
*Ductile Design of Steel Structures*, 2nd ed., McGraw-Hill, ch. 9 (concentrically braced frames).  These
references are cited as recalled; their texts were not at hand when this module was written.

**The law** (my own idealisation of the above, stated in drift units; symmetric).  Parameters: the storey's
initial stiffness ``k0``, the yield drift ``dy`` (Fy = k0 dy), the frame's share ``r_f`` (0 < r_f < 1) and the
braces' hardening ratio ``a_h`` (0 <= a_h < 1).

* Frame: elastic, ``k_f = r_f k0``, in parallel with the braces.
* Two braces, one for each sense of drift, each of lateral stiffness ``k_b = (1 - r_f) k0`` (the horizontal
  component of its axial stiffness).  Brace 1 elongates with the drift ``d``, brace 2 with ``-d``; at zero drift
  and no plastic elongation both are just taut (no pre-tension), so for d > 0 brace 1 stretches and brace 2 goes
  slack: the storey's initial stiffness is k_f + k_b = k0 and it yields at dy, both senses.
* Each brace's plastic elongation ``p_i >= 0`` (in drift units: the drift the brace's permanent stretch takes
  up).  Its elongation ``e_1 = d - p_1``, ``e_2 = -d - p_2``; its force (lateral component)
  ``F_i = k_b max(e_i, 0)``: zero in compression (a slender brace buckles at about zero load).
* Yield in tension, linear hardening: a brace flows when it is stretched on at ``F_i = Fb(p_i) = k_b dy + H p_i``
  with H = a_h k_b / (1 - a_h), i.e. at ``e_i = e_y(p_i) = dy + a_h p_i / (1 - a_h)``; while it flows
  ``dp_i/dt = (1 - a_h) de_i/dt`` (with ``de_1/dt = v``, ``de_2/dt = -v``), so that ``dF_i/dt = a_h k_b de/dt`` on
  the line.  First loading to D > dy therefore leaves ``p = (1 - a_h)(D - dy)``, and p depends only on the
  largest excursion on the brace's side: a brace reloaded after slack takes up its load elastically from
  d = p_1 and yields again exactly where it stopped, at D.
* The storey force ``f = k_f d + F_1 - F_2``.  Monotonic loading: k0 d up to Fy, then the storey's post-yield
  stiffness (r_f + a_h (1 - r_f)) k0.  After excursions to D+ and D- both braces are slack for
  ``-p_2 < d < p_1``: there the storey carries the frame's ``k_f d`` alone (the zero-brace-force slip, of length
  p_1 + p_2 = (1 - a_h)(D+ - dy) + (1 - a_h)(D- - dy)).

My own choices: no pre-tension; the braces' buckling load, their compressive stiffness and any post-buckling
strength taken as zero; linear hardening in tension only; the frame elastic; no fracture or low-cycle fatigue;
no impact-load amplification beyond what the stiffness jump at re-tautening gives the dynamics.

**State formulation.**  The plastic elongations ``p_1``, ``p_2`` are the ODE states; the force is algebraic in
the drift and them (above), continuous, with a kink where a brace becomes taut or slack (a jump of the
tangent, as at a contact's onset).  ``dp_1/dt = (1 - a_h) v`` while brace 1 flows (v > 0 and
``e_1 >= e_y(p_1) - YIELD_TOL dy``), else 0; likewise ``dp_2/dt = -(1 - a_h) v`` (v < 0).  On a yield line the
rates keep ``e_i - e_y(p_i)`` constant (``de/dt - dp/dt / (1 - a_h) = 0``), so a storey that reached its line
within ``YIELD_TOL`` dy stays on it and does not chatter; the plastic elongation's rate jumps at yield onset and
goes to zero continuously at a reversal (v = 0).  The storey's tangent stiffness
``kt = k_f + sum over taut braces of k_b (a_h if flowing else 1)``.
"""

from __future__ import annotations

import numpy as np

YIELD_TOL = 1e-7  # of dy: a brace's yield line is reached this close (in elongation)


def _b(x, shape):
    return np.broadcast_to(np.asarray(x, float), shape)


def elongation_at_yield(p, dy, a_h):
    """``e_y(p) = dy + a_h p / (1 - a_h)``: the elongation at which a brace of plastic elongation ``p`` flows."""
    return dy + a_h * np.asarray(p, float) / (1.0 - a_h)


def brace_forces(d, p1, p2, k0, dy, r_f, a_h):
    """(F_1, F_2): the braces' tension (lateral components, >= 0) at drift ``d``."""
    kb = (1.0 - np.asarray(r_f, float)) * np.asarray(k0, float)
    d = np.asarray(d, float)
    return kb * np.maximum(d - p1, 0.0), kb * np.maximum(-d - p2, 0.0)


def force(d, p1, p2, k0, dy, r_f, a_h):
    """The storey force ``k_f d + F_1 - F_2`` at drift ``d`` with plastic elongations ``p1``, ``p2`` (vectorised)."""
    f1, f2 = brace_forces(d, p1, p2, k0, dy, r_f, a_h)
    return np.asarray(r_f, float) * np.asarray(k0, float) * np.asarray(d, float) + f1 - f2


def tangent(d, v, p1, p2, k0, dy, r_f, a_h, partials=False):
    """(kt, flow1, flow2): the storey's tangent stiffness along the motion and whether each brace flows, for drift
    ``d`` moving at ``v``; with ``partials`` also the force's partial derivatives (df/dd, df/dp1, df/dp2) at fixed
    states (for an implicit integrator's Jacobian: the force is algebraic in the drift and the states).

    Vectorised over storeys (every argument an array of the same shape, or a scalar)."""
    d, v, p1, p2 = (np.asarray(x, float) for x in (d, v, p1, p2))
    k0, dy, r_f, a_h = (_b(x, d.shape) for x in (k0, dy, r_f, a_h))
    kf, kb = r_f * k0, (1.0 - r_f) * k0
    e1, e2 = d - p1, -d - p2
    tol = YIELD_TOL * dy
    flow1 = (v > 0.0) & (e1 >= elongation_at_yield(p1, dy, a_h) - tol)
    flow2 = (v < 0.0) & (e2 >= elongation_at_yield(p2, dy, a_h) - tol)
    taut1, taut2 = e1 > 0.0, e2 > 0.0
    kt = kf + kb * (taut1 * np.where(flow1, a_h, 1.0) + taut2 * np.where(flow2, a_h, 1.0))
    if not partials:
        return kt, flow1, flow2
    return kt, flow1, flow2, kf + kb * (taut1 + taut2), -kb * taut1, kb * taut2


def rates(d, v, p1, p2, k0, dy, r_f, a_h):
    """(dp1/dt, dp2/dt) for a storey drift ``d`` moving at ``v``."""
    _kt, flow1, flow2 = tangent(d, v, p1, p2, k0, dy, r_f, a_h)
    v, a_h = np.asarray(v, float), np.asarray(a_h, float)
    return np.where(flow1, (1.0 - a_h) * v, 0.0), np.where(flow2, -(1.0 - a_h) * v, 0.0)


def backbone(d, k0, dy, r_f, a_h):
    """The monotonic loading curve at drift ``d``: k0 d to Fy, then (r_f + a_h (1 - r_f)) k0 on."""
    a = np.abs(d)
    kp = (r_f + a_h * (1.0 - r_f)) * k0
    return np.sign(d) * np.where(a <= dy, k0 * a, k0 * dy + kp * (a - dy))


def follow(t, d, v, k0, dy, r_f, a_h, rtol=1e-9, elongations=False):
    """The force along a prescribed drift history (callables ``d(t)``, ``v(t)``) at the times ``t`` (with
    ``elongations``: also the plastic elongations p1, p2).

    Integrates the state formulation above with ``solve_ivp`` (RK45: along a prescribed drift the ODE is not
    stiff); the check of the formulation against hand-derived paths in ``tests/diagnose/test_generator_outside.py``."""
    from scipy.integrate import solve_ivp

    def rhs(tt, y):
        d1, d2 = rates(d(tt), v(tt), y[0], y[1], k0, dy, r_f, a_h)
        return [float(d1), float(d2)]

    sol = solve_ivp(rhs, (t[0], t[-1]), [0.0, 0.0], method="RK45", t_eval=t, rtol=rtol,
                    atol=[1e-12 * dy, 1e-12 * dy], max_step=(t[-1] - t[0]) / 2000.0)
    dd = np.array([d(s) for s in t])
    f = force(dd, sol.y[0], sol.y[1], k0, dy, r_f, a_h)
    return (f, sol.y[0], sol.y[1]) if elongations else f
