"""Independent reference implementation ("twin") of the pounding problem.

Slow, pure NumPy/SciPy and deliberately written differently from the package:
it imports nothing from ``seispound.integrate`` or ``seispound.contact``.

* The contact laws are coded again from the seed paper (Khatiwada & Chouw,
  "An experimental study on pounding force between reinforced concrete slabs",
  Section 2, Eqs. 1-9) and from Muthukumar & DesRoches (2006) for the classic
  Hertzdamp law.  The implicit Hunt-Crossley relation (seed Eq. 8) is solved for
  x = k / (zeta v0) with :func:`scipy.optimize.brentq` on the branch x > e.
* The equations of motion are written as a first-order ODE in the state
  y = [u, v] and integrated by :func:`scipy.integrate.solve_ivp` (an implicit
  BDF/Adams or Radau method with tight tolerances).  Every opening and closing
  of a gap is a terminal event of the integrator: the integration stops there,
  the contact state is switched, the damping parameter of Hd / LHC / Hertzdamp
  is fixed from the approach velocity at the onset, and the integration
  restarts from the event.  The equations are therefore never integrated across
  a discontinuity of the contact force.

Conventions (same as the package, so that results can be compared): DOFs are
floor displacements relative to the ground; the penetration of a gap between a
left DOF i and a right DOF j is delta = u_i - u_j - size (positive in contact);
its rate d(delta)/dt is positive while the bodies approach; the contact force F
is positive in compression and acts as -F on DOF i and +F on DOF j.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

__all__ = [
    "RefLaw",
    "RefGap",
    "ReferenceResult",
    "hunt_crossley_x",
    "lve_xi",
    "mlve_xi",
    "nive_xi",
    "shear_matrices",
    "simulate_reference",
]


# ---------------------------------------------------------------------------
# Contact laws written from the seed equations
# ---------------------------------------------------------------------------
def lve_xi(e: float) -> float:
    """Damping ratio of the linear viscoelastic law (seed Eq. 3).

    xi = -ln(e) / sqrt(pi^2 + ln(e)^2)  (Anagnostopoulos 1988).
    """
    return -math.log(e) / math.hypot(math.pi, math.log(e))


def mlve_xi(e: float) -> float:
    """Approach-only damping ratio of the modified linear viscoelastic law (seed Eq. 5).

    xi = (1 - e^2) / (pi e)  (Mahmoud 2008).
    """
    return (1.0 - e**2) / (math.pi * e)


def nive_xi(e: float) -> float:
    """Damping ratio xi-bar of the nonlinear viscoelastic law (seed Eq. 6, Jankowski 2005).

    xi-bar = 9 sqrt(5) (1 - e^2) / (2 e (e (9 pi - 16) + 16)).
    """
    return 4.5 * math.sqrt(5.0) * (1.0 - e**2) / (e * (e * (9.0 * math.pi - 16.0) + 16.0))


def hunt_crossley_x(e: float) -> float:
    """Root x = k / (zeta v0) of the exact Hunt-Crossley relation, seed Eq. 8.

    Eq. 8 reads ``1 + e = x ln|(x + 1) / (x - e)|``.  On the branch x > e the
    right-hand side decreases from +inf (x -> e+) to the limit 1 + e reached
    from below as x -> inf, so it has exactly one root for 0 < e < 1; it is
    bracketed and found with :func:`scipy.optimize.brentq`.

    Parameters
    ----------
    e : float
        Coefficient of restitution, 0 < e < 1 (e = 1 returns inf: zeta = 0).

    Returns
    -------
    float
        x = k / (zeta v0) [-]; hence zeta = k / (x v0).
    """
    if e >= 1.0:
        return math.inf

    def f(x):
        return x * math.log((x + 1.0) / (x - e)) - (1.0 + e)

    lo = e * (1.0 + 1e-15) + 1e-300
    while f(lo) <= 0.0:  # pragma: no cover - only for e so small that x ~ e
        lo = e + 0.5 * (lo - e)
    hi = 1.0
    while f(hi) >= 0.0:
        hi *= 2.0
    return brentq(f, lo, hi, xtol=1e-300, rtol=4 * np.finfo(float).eps, maxiter=500)


@dataclass
class RefLaw:
    """A contact law of the seed paper, evaluated from its defining equation.

    Parameters
    ----------
    name : str
        ``LVe`` (Eqs. 1-3), ``MLVe`` (Eqs. 4-5), ``NIVe`` (Eq. 6), ``Hd``
        (Eqs. 7-8), ``LHC`` (Eqs. 8-9), ``Hertz`` (F = k delta^1.5) or
        ``Hertzdamp`` (Muthukumar & DesRoches 2006).
    k : float
        Contact stiffness [N/m] or [N/m^1.5].
    e : float
        Target coefficient of restitution.
    tension : bool
        Whether the force may become tensile (only LVe can produce tension;
        the default of the seed's Eq. 1 is to allow it).
    """

    name: str
    k: float
    e: float = 1.0
    tension: bool = True

    def onset_parameter(self, v0: float, m1: float, m2: float) -> float:
        """Damping parameter fixed at the onset of an impact of approach velocity v0 [m/s].

        Returns c [N s/m] for LVe / MLVe (seed Eq. 2 with Eq. 3 resp. Eq. 5),
        xi-bar for NIVe, zeta = k / (x v0) with x from Eq. 8 for Hd and LHC,
        zeta = 3 k (1 - e^2) / (4 v0) for Hertzdamp (Muthukumar & DesRoches
        2006, Eq. 13) and 0 for Hertz.
        """
        meff = m1 * m2 / (m1 + m2)
        if self.name == "LVe":
            return 2.0 * lve_xi(self.e) * math.sqrt(self.k * meff)
        if self.name == "MLVe":
            return 2.0 * mlve_xi(self.e) * math.sqrt(self.k * meff)
        if self.name == "NIVe":
            return nive_xi(self.e)
        if self.name in ("Hd", "LHC"):
            if self.e >= 1.0:
                return 0.0
            return self.k / (hunt_crossley_x(self.e) * v0)
        if self.name == "Hertzdamp":
            return 3.0 * self.k * (1.0 - self.e**2) / (4.0 * v0)
        if self.name == "Hertz":
            return 0.0
        raise ValueError(f"unknown law {self.name}")

    def force(self, delta: float, rate: float, par: float, m1: float, m2: float) -> float:
        """Contact force [N], compression positive, while the gap is closed.

        Parameters
        ----------
        delta : float
            Penetration [m] (>= 0 up to round-off while in contact).
        rate : float
            d(delta)/dt [m/s], positive on approach.
        par : float
            Value of :meth:`onset_parameter` for this impact.
        m1, m2 : float
            Masses of the two colliding floors [kg] (NIVe's c-bar).
        """
        k = self.k
        d = max(delta, 0.0)
        if self.name == "LVe":  # seed Eq. 1
            F = k * delta + par * rate
            return F if self.tension else max(F, 0.0)
        if self.name == "MLVe":  # seed Eq. 4: dashpot only while approaching
            return k * delta + (par * rate if rate >= 0.0 else 0.0)
        if self.name == "NIVe":  # seed Eq. 6
            F = k * d**1.5
            if rate >= 0.0:
                cbar = 2.0 * par * math.sqrt(k * math.sqrt(d) * m1 * m2 / (m1 + m2))
                F += cbar * rate
            return F
        if self.name in ("Hd", "Hertzdamp"):  # seed Eq. 7 (same form for Hertzdamp)
            return d**1.5 * (k + par * rate)
        if self.name == "LHC":  # seed Eq. 9
            return d * (k + par * rate)
        if self.name == "Hertz":
            return k * d**1.5
        raise ValueError(f"unknown law {self.name}")


@dataclass
class RefGap:
    """A gap element: left DOF i, right DOF j (0-based), at-rest size [m], law."""

    i: int
    j: int
    size: float
    law: RefLaw


@dataclass
class ReferenceResult:
    """Output of :func:`simulate_reference`.

    Attributes
    ----------
    time : (nt,) ndarray
        Output times [s] (``t_eval``).
    displacement, velocity : (nt, n) ndarray
        Relative floor displacements [m] and velocities [m/s].
    force : (nt, ng) ndarray
        Contact force of every gap [N].
    impacts : dict of ndarray
        ``gap``, ``t0`` (onset time), ``v0`` (approach velocity at onset),
        ``vout`` (separation velocity, positive), ``t1`` (end time), ``dur``,
        ``fmax`` (peak force), ``zeta`` (onset parameter).
    peak_displacement : (n,) ndarray
        max |u| over the dense solution [m].
    peak_force : (ng,) ndarray
        Largest contact force of every gap [N].
    nfev : int
        Right-hand-side evaluations (cost).
    """

    time: np.ndarray
    displacement: np.ndarray
    velocity: np.ndarray
    force: np.ndarray
    impacts: dict
    peak_displacement: np.ndarray
    peak_force: np.ndarray
    nfev: int = 0
    segments: list = field(default_factory=list)


def shear_matrices(masses, stiffness, a0=0.0, a1=0.0):
    """Mass vector, stiffness and Rayleigh damping matrices of one shear building.

    Written element by element (each storey spring joins floor i-1 and floor i,
    Chopra, Dynamics of Structures, Eq. 9.2.4); C = a0 M + a1 K.
    """
    m = np.asarray(masses, float)
    k = np.asarray(stiffness, float)
    n = m.size
    K = np.zeros((n, n))
    for s in range(n):
        K[s, s] += k[s]
        if s > 0:
            K[s - 1, s - 1] += k[s]
            K[s - 1, s] -= k[s]
            K[s, s - 1] -= k[s]
    return m, K, a0 * np.diag(m) + a1 * K


def simulate_reference(masses, K, C, gaps, ag_func, t_end, v0, u0=None, t_eval=None,
                       method="LSODA", rtol=1e-10, atol=None, max_step=np.inf,
                       breakpoints=None, dense_points=64, ground_per_dof=False):
    """Integrate M u'' + C u' + K u + B f_c(u, u') = -M 1 a_g(t) with event-located contact.

    The first-order system y' = [v, M^-1 (-M 1 a_g - C v - K u - B f_c)] is
    integrated with :func:`scipy.integrate.solve_ivp`.  A gap that is open
    carries a terminal event on delta(t) = 0 crossed upwards (onset); a closed
    gap carries one on delta(t) = 0 crossed downwards (end of the impact).  At
    every event the integration stops, the approach velocity v0 = d(delta)/dt is
    stored, the law's damping parameter is fixed from it (seed Eq. 8 for Hd and
    LHC, Eq. 2 for LVe/MLVe, Eq. 6 for NIVe), and the integration restarts.

    Parameters
    ----------
    masses : (n,) array_like
        Lumped floor masses [kg].
    K, C : (n, n) array_like
        Stiffness [N/m] and damping [N s/m] matrices of the whole row.
    gaps : list of RefGap
    ag_func : callable
        Ground acceleration a_g(t) [m/s^2].
    t_end : float
        End time [s].
    v0 : (n,) array_like
        Initial velocities relative to the ground [m/s].
    u0 : (n,) array_like, optional
        Initial displacements [m] (default zero).
    t_eval : (nt,) array_like, optional
        Output times (default: 0 and t_end).
    method : str
        ``"LSODA"`` (default) or ``"Radau"``.
    rtol, atol : float
        Tolerances of solve_ivp; atol defaults to 1e-14 m for displacements and
        1e-12 m/s for velocities.
    max_step : float
        Largest integrator step [s] (bounds how long a grazing contact may be).
    breakpoints : array_like, optional
        Times where the integration is restarted (kinks of a piecewise-linear
        a_g), so that no integrator step straddles one.
    dense_points : int
        Dense-output samples per integrator step used for the peaks.
    ground_per_dof : bool
        ``ag_func`` returns one ground acceleration per DOF, shape (n,) (each
        building on its own ground).  The ground displacement and velocity
        under every DOF are then integrated as 2n more states of the same ODE
        (u_g' = v_g, v_g' = a_g), and a gap's penetration is that of the
        absolute positions: u_i + u_g,i - u_j - u_g,j - size.

    Returns
    -------
    ReferenceResult
    """
    m = np.asarray(masses, float)
    n = m.size
    K = np.asarray(K, float)
    C = np.asarray(C, float)
    u_init = np.zeros(n) if u0 is None else np.asarray(u0, float)
    y = np.concatenate([u_init, np.asarray(v0, float) * np.ones(n)])
    if ground_per_dof:
        y = np.concatenate([y, np.zeros(2 * n)])
    ng = len(gaps)
    t_eval = np.array([0.0, t_end]) if t_eval is None else np.asarray(t_eval, float)
    if atol is None:
        atol = np.concatenate([np.full(n, 1e-14), np.full(n, 1e-12)] * (2 if ground_per_dof else 1))
    bps = np.array([] if breakpoints is None else breakpoints, float)
    bps = np.unique(bps[(bps > 0.0) & (bps < t_end)])

    closed = np.zeros(ng, bool)
    par = np.zeros(ng)
    cur = [None] * ng
    impacts = []

    def delta_rate(g, yy):
        gp = gaps[g]
        d, r = yy[gp.i] - yy[gp.j] - gp.size, yy[n + gp.i] - yy[n + gp.j]
        if ground_per_dof:
            d += yy[2 * n + gp.i] - yy[2 * n + gp.j]
            r += yy[3 * n + gp.i] - yy[3 * n + gp.j]
        return d, r

    def gap_force(g, yy):
        if not closed[g]:
            return 0.0
        gp = gaps[g]
        d, r = delta_rate(g, yy)
        return gp.law.force(d, r, par[g], m[gp.i], m[gp.j])

    def open_gap(g, t, yy):
        gp = gaps[g]
        d, r = delta_rate(g, yy)
        closed[g] = True
        par[g] = gp.law.onset_parameter(r, m[gp.i], m[gp.j])
        rec = dict(gap=g, t0=t, v0=r, zeta=par[g], fmax=0.0, t1=np.nan, vout=np.nan)
        rec["fmax"] = max(gap_force(g, yy), 0.0)
        impacts.append(rec)
        cur[g] = rec

    def close_gap(g, t, yy):
        d, r = delta_rate(g, yy)
        rec = cur[g]
        rec["t1"] = t
        rec["vout"] = -r
        closed[g] = False
        cur[g] = None

    # gaps closed (or touching and approaching) at t = 0
    for g in range(ng):
        d, r = delta_rate(g, y)
        if d > 0.0 or (d == 0.0 and r > 0.0):
            open_gap(g, 0.0, y)

    def rhs(t, yy):
        u = yy[:n]
        v = yy[n:2 * n]
        ag = ag_func(t)
        f = -m * ag - C @ v - K @ u
        for g in range(ng):
            if closed[g]:
                F = gap_force(g, yy)
                f[gaps[g].i] -= F
                f[gaps[g].j] += F
        if ground_per_dof:
            return np.concatenate([v, f / m, yy[3 * n:], ag])
        return np.concatenate([v, f / m])

    def make_event(g):
        def ev(t, yy):
            return delta_rate(g, yy)[0]
        ev.terminal = True
        ev.direction = -1.0 if closed[g] else 1.0
        return ev

    out_u = np.full((t_eval.size, n), np.nan)
    out_v = np.full((t_eval.size, n), np.nan)
    out_f = np.zeros((t_eval.size, ng))
    peak_u = np.abs(u_init).copy()
    peak_f = np.zeros(ng)
    t = 0.0
    nfev = 0
    segments = []
    done = np.zeros(t_eval.size, bool)
    while t < t_end:
        nxt = bps[bps > t * (1 + 1e-14) + 1e-300]
        t_stop = min(t_end, nxt[0]) if nxt.size else t_end
        events = [make_event(g) for g in range(ng)]
        sol = solve_ivp(rhs, (t, t_stop), y, method=method, rtol=rtol, atol=atol,
                        events=events or None, dense_output=True, max_step=max_step)
        if sol.status < 0:
            raise RuntimeError(f"solve_ivp failed at t = {t}: {sol.message}")
        nfev += sol.nfev
        t_seg_end = sol.t[-1]
        fired = []
        if sol.status == 1:
            for g in range(ng):
                if sol.t_events[g].size:
                    fired.append((sol.t_events[g][0], g))
            fired.sort()
            t_seg_end = fired[0][0]
        # outputs and peaks on this segment (contact state is constant inside it)
        sel = (~done) & (t_eval >= t) & (t_eval <= t_seg_end)
        if sel.any():
            ys = sol.sol(t_eval[sel])
            out_u[sel] = ys[:n].T
            out_v[sel] = ys[n:2 * n].T
            for g in range(ng):
                out_f[sel, g] = [gap_force(g, ys[:, q]) for q in range(ys.shape[1])]
            done |= sel
        knots = np.concatenate([sol.t[sol.t < t_seg_end], [t_seg_end]])
        fine = np.unique(np.concatenate([np.linspace(a, b, dense_points + 1)
                                         for a, b in zip(knots[:-1], knots[1:])] or [knots]))
        yf = sol.sol(fine)
        peak_u = np.maximum(peak_u, np.abs(yf[:n]).max(axis=1))
        for g in range(ng):
            if closed[g]:
                fg = np.array([gap_force(g, yf[:, q]) for q in range(fine.size)])
                peak_f[g] = max(peak_f[g], fg.max())
                cur[g]["fmax"] = max(cur[g]["fmax"], fg.max())
        segments.append((t, t_seg_end, closed.copy()))
        y = sol.sol(t_seg_end) if sol.status == 1 else sol.y[:, -1]
        t = t_seg_end
        if sol.status == 1:
            t_ev = fired[0][0]
            # switch every gap whose event fired at (numerically) the same instant
            for te, g in fired:
                if te - t_ev <= 1e-12 * max(1.0, t_ev):
                    if closed[g]:
                        close_gap(g, t, y)
                    else:
                        open_gap(g, t, y)
    imp = {key: np.array([rec[key] for rec in impacts], dtype=int if key == "gap" else float)
           for key in ("gap", "t0", "v0", "vout", "t1", "fmax", "zeta")}
    imp["dur"] = imp["t1"] - imp["t0"]
    return ReferenceResult(time=t_eval, displacement=out_u, velocity=out_v, force=out_f,
                           impacts=imp, peak_displacement=peak_u, peak_force=peak_f,
                           nfev=nfev, segments=segments)
