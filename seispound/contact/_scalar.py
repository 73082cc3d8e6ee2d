"""Scalar contact-force functions compiled with numba.

These are the only implementation of the force laws: the integrator kernel calls
them inside its time loop and the Python law classes call the same compiled
functions, so what a user evaluates is exactly what the kernel integrates.

Conventions (every law): penetration ``delta`` [m] is positive in contact,
``rate`` = d(delta)/dt [m/s] is positive while the bodies approach, the force
[N] is positive in compression.  ``par`` is one row of the per-gap parameter
table whose columns are named by the ``P_*`` constants below.
"""

from __future__ import annotations

import math

from seispound._jit import njit

from .codes import (E_CONSTANT, E_EXPONENTIAL, E_LINEAR, E_POWER, HC, HD, HERTZ, HERTZDAMP, LHC,  # noqa: F401
                    LVE, MAX_TABLE, MLVE, N_PAR, NIVE, NONE, P_E, P_EA, P_EB, P_EC, P_ED, P_EFORM, P_EXPONENT, P_K,
                    P_MEFF, P_NTAB, P_TAB, P_TENSION, P_XI)


@njit(cache=True)
def hunt_crossley_s(e):
    """Nontrivial root s = zeta*v0/k of the exact Hunt-Crossley relation (seed Eq. 8).

    With x = k / (zeta * v0) = 1/s, Eq. 8 reads ``(1 + e) = x ln|(x + 1)/(x - e)|``.
    s = 0 is always a (trivial, elastic) root; the physical root lies on the
    branch 0 < s < 1/e, i.e. k - zeta*e*v0 > 0, on which k + zeta*rate stays
    positive for the whole impact (the force never becomes tensile).  That
    branch has exactly one root for every 0 < e < 1; e = 1 gives s = 0.

    Solved in t = -ln(1 - e*s) in (0, inf), where the equation
    ``t = (1 + e) s - ln(1 + s)`` stays well conditioned even for small e (the
    root then approaches the branch point 1/e exponentially closely).

    Parameters
    ----------
    e : float
        Coefficient of restitution, 0 < e <= 1.

    Returns
    -------
    float
        s = zeta * v0 / k (dimensionless); zeta = k * s / v0.
    """
    if e >= 1.0:
        return 0.0
    # G(t) = t - (1+e) s(t) + ln(1 + s(t)) with s(t) = (1 - exp(-t)) / e.
    # G < 0 between the trivial root 0 and the physical root, G > 0 beyond.
    hi = (1.0 + e) / e + 1.0
    lo = 0.5 * hi
    for _ in range(200):
        s = -math.expm1(-lo) / e
        if lo - (1.0 + e) * s + math.log1p(s) < 0.0:
            break
        lo *= 0.5
    t = hi
    for _ in range(200):
        s = -math.expm1(-t) / e
        g = t - (1.0 + e) * s + math.log1p(s)
        if g > 0.0:
            hi = t
        else:
            lo = t
        ds = math.exp(-t) / e
        dg = 1.0 - ((1.0 + e) - 1.0 / (1.0 + s)) * ds
        tn = t - g / dg if dg > 0.0 else 0.5 * (lo + hi)
        if not (lo < tn < hi):
            tn = 0.5 * (lo + hi)
        if abs(tn - t) <= 1e-15 * t:
            t = tn
            break
        t = tn
    return -math.expm1(-t) / e


@njit(cache=True)
def restitution_from_s(s):
    """The e whose Hunt-Crossley root is s (the inverse of :func:`hunt_crossley_s`), 0 < e <= 1.

    s = zeta v0 / k falls monotonically from infinity (e -> 0) to 0 (e = 1);
    bisection on e to 1e-15.  This is the exact restitution of any law
    F = delta^n (k + zeta rate) with a fixed zeta (seed Eq. 8 read the other way).
    """
    if s <= 0.0:
        return 1.0
    lo = 0.0
    hi = 1.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if hunt_crossley_s(mid) > s:
            lo = mid
        else:
            hi = mid
        if hi - lo <= 1e-15:
            break
    return 0.5 * (lo + hi)


@njit(cache=True)
def restitution_at(par, v0):
    """The coefficient of restitution of a gap at approach velocity v0 [m/s] (``contact.restitution`` forms).

    Columns P_EFORM (form), P_EA..P_ED (its parameters) and, for a table,
    P_NTAB points at P_TAB (velocities) and P_TAB + MAX_TABLE (e).
    """
    form = int(par[P_EFORM])
    if form == E_CONSTANT:
        return par[P_E]
    v = max(v0, 0.0)
    a = par[P_EA]
    b = par[P_EB]
    c = par[P_EC]
    d = par[P_ED]
    if form == E_LINEAR:  # e0, slope, min, max
        return min(max(a - b * v, c), d)
    if form == E_EXPONENTIAL:  # e0, e_inf, v_c
        return b + (a - b) * math.exp(-v / c)
    if form == E_POWER:  # e_ref, v_ref, exponent, max
        return d if v <= 0.0 else min(d, a * (v / b) ** (-c))
    # table: linear between the points, constant outside
    n = int(par[P_NTAB])
    if v <= par[P_TAB]:
        return par[P_TAB + MAX_TABLE]
    for i in range(1, n):
        v1 = par[P_TAB + i]
        if v <= v1:
            v0_ = par[P_TAB + i - 1]
            e0 = par[P_TAB + MAX_TABLE + i - 1]
            e1 = par[P_TAB + MAX_TABLE + i]
            return e0 + (e1 - e0) * (v - v0_) / (v1 - v0_)
    return par[P_TAB + MAX_TABLE + n - 1]


@njit(cache=True)
def onset_state(code, par, v0):
    """The contact law's onset hook: its per-impact state from the approach velocity v0 [m/s].

    Returns (zeta, e): the damping parameter of :func:`onset_damping` and the
    coefficient of restitution it was set from.  With a constant e (P_EFORM =
    E_CONSTANT) zeta is exactly :func:`onset_damping`'s; a velocity-dependent e
    (``contact.restitution``) is evaluated at v0 and the law's damping set from
    it with the same relations (seed Eqs. 3, 5, 6, 8; Muthukumar & DesRoches
    2006 Eq. 13).  The Hunt-Crossley law HC has a fixed zeta = 3/2 c k, and
    its e = e(s = 3/2 c v0) from seed Eq. 8 (:func:`restitution_from_s`).
    """
    k = par[P_K]
    if code == HC:
        return 1.5 * par[P_XI] * k, restitution_from_s(1.5 * par[P_XI] * max(v0, 0.0))
    if code == HERTZ:
        return 0.0, 1.0
    if int(par[P_EFORM]) == E_CONSTANT:
        return onset_damping(code, par, v0), par[P_E]
    e = restitution_at(par, v0)
    if code == HD or code == LHC:
        return (k * hunt_crossley_s(e) / v0 if v0 > 0.0 else 0.0), e
    if code == HERTZDAMP:
        return (0.75 * k * (1.0 - e * e) / v0 if v0 > 0.0 else 0.0), e
    if code == LVE:
        le = math.log(e)
        xi = -le / math.sqrt(math.pi * math.pi + le * le)  # seed Eq. 3
    elif code == MLVE:
        xi = (1.0 - e * e) / (math.pi * e)  # seed Eq. 5
    elif code == NIVE:
        # Jankowski's xi-bar (seed Eq. 6); NIVe's onset value is the ratio itself
        return 9.0 * math.sqrt(5.0) / 2.0 * (1.0 - e * e) / (e * (e * (9.0 * math.pi - 16.0) + 16.0)), e
    else:
        return 0.0, e
    return 2.0 * xi * math.sqrt(k * par[P_MEFF]), e


@njit(cache=True)
def onset_damping(code, par, v0):
    """Damping parameter fixed at the onset of an impact from its approach velocity.

    Parameters
    ----------
    code : int
        Law code.
    par : ndarray, shape (N_PAR,)
        Gap parameter row.
    v0 : float
        Approach velocity d(delta)/dt at the instant of contact [m/s], > 0.

    Returns
    -------
    float
        zeta [N s/m^(n+1)] for Hd, LHC (exact, seed Eq. 8, solved here at every
        impact) and classic Hertzdamp (zeta = 3 k (1 - e^2) / (4 v0),
        Muthukumar & DesRoches 2006, Eq. 13); the constant damping coefficient
        c = 2 xi sqrt(k m_eff) [N s/m] for LVe and MLVe (seed Eq. 2); the
        damping ratio xi-bar [-] for NIVe (Jankowski 2005); 0 otherwise.
    """
    k = par[P_K]
    if code == HD or code == LHC:
        if v0 <= 0.0:
            return 0.0
        return k * hunt_crossley_s(par[P_E]) / v0
    if code == HERTZDAMP:
        if v0 <= 0.0:
            return 0.0
        e = par[P_E]
        return 0.75 * k * (1.0 - e * e) / v0
    if code == LVE or code == MLVE:
        return 2.0 * par[P_XI] * math.sqrt(k * par[P_MEFF])
    if code == NIVE:
        return par[P_XI]
    return 0.0


@njit(cache=True)
def contact_force(code, par, delta, rate, zeta):
    """Contact force and its partial derivatives for one gap.

    Parameters
    ----------
    code : int
        Law code (``LVE`` ... ``HERTZDAMP``).
    par : ndarray, shape (N_PAR,)
        Gap parameter row.
    delta : float
        Penetration [m], positive in contact.  Slightly negative values occur
        only inside a step that ends an impact; power laws use max(delta, 0)
        and linear laws extend continuously.
    rate : float
        d(delta)/dt [m/s], positive on approach.
    zeta : float
        Value returned by :func:`onset_damping` for this impact.

    Returns
    -------
    F, dF_ddelta, dF_drate : float
        Force [N] (compression positive) and its partials [N/m], [N s/m].
        For NIVe the derivative of c-bar with respect to delta (singular at
        delta = 0) is left out of dF_ddelta: the Newton iteration then is a
        quasi-Newton, its residual test is unchanged.

    Notes
    -----
    Seed paper (Khatiwada & Chouw, "An experimental study on pounding force
    between reinforced concrete slabs"), Section 2:

    * LVe, Eq. 1:  F = k delta + c rate  (Anagnostopoulos 1988)
    * MLVe, Eq. 4: F = k delta + c rate if rate >= 0 else k delta (Mahmoud 2008)
    * NIVe, Eq. 6: F = k delta^1.5 + c-bar rate if rate >= 0 else k delta^1.5,
      c-bar = 2 xi-bar sqrt(k sqrt(delta) m1 m2 / (m1 + m2)) (Jankowski 2005)
    * Hd, Eq. 7:   F = k delta^1.5 + zeta delta^1.5 rate
    * LHC, Eq. 9:  F = k delta + zeta delta rate
    * Hertz:       F = k delta^1.5
    * Hertzdamp:   F = k delta^1.5 + zeta delta^1.5 rate (Muthukumar & DesRoches 2006)
    * HC:          F = k delta^n (1 + 3/2 c rate) = delta^n (k + zeta rate), zeta = 3/2 c k
      (Hunt & Crossley 1975)
    """
    return law_force(code, par[P_K], par[P_EXPONENT], par[P_MEFF], par[P_TENSION], delta, rate, zeta)


@njit(cache=True)
def law_force(code, k, exponent, meff, tension, delta, rate, zeta):
    """:func:`contact_force` on the parameters as scalars (the kernel's form).

    ``k``, ``exponent``, ``meff`` and ``tension`` are the columns P_K, P_EXPONENT,
    P_MEFF and P_TENSION of a gap's parameter row.  Taking scalars rather than
    the row lets the kernel call it without making a view of its parameter
    table: each view costs two atomic reference-count updates in numba.
    """
    F = 0.0
    dFd = 0.0
    dFv = 0.0
    if code == LVE:
        F = k * delta + zeta * rate
        dFd = k
        dFv = zeta
    elif code == MLVE:
        F = k * delta
        dFd = k
        if rate >= 0.0:
            F += zeta * rate
            dFv = zeta
    elif code == LHC:
        d = max(delta, 0.0)
        F = d * (k + zeta * rate)
        dFd = (k + zeta * rate) if delta > 0.0 else 0.0
        dFv = zeta * d
    else:
        d = max(delta, 0.0)
        n = exponent
        if n == 1.5:  # the Hertz exponent: sqrt is much cheaper than pow
            sd = math.sqrt(d)
            dn = d * sd
            dn1 = 1.5 * sd
        else:
            dn = d**n
            dn1 = n * d ** (n - 1.0) if d > 0.0 else 0.0
        if code == HERTZ:
            F = k * dn
            dFd = k * dn1
        elif code == HD or code == HERTZDAMP or code == HC:
            F = dn * (k + zeta * rate)
            dFd = dn1 * (k + zeta * rate)
            dFv = zeta * dn
        elif code == NIVE:
            F = k * dn
            dFd = k * dn1
            if rate >= 0.0:
                cbar = 2.0 * zeta * math.sqrt(k * math.sqrt(d) * meff)
                F += cbar * rate
                dFv = cbar
    if tension == 0.0 and F < 0.0:
        return 0.0, 0.0, 0.0
    return F, dFd, dFv


@njit(cache=True)
def contact_duration(code, par, v0):
    """Estimate of an impact's duration [s], used only to size contact substeps.

    Linear laws: half the undamped contact period, pi sqrt(m_eff / k).
    Power laws (exponent n): the Hertz closed form for the elastic impact,
    t_c = C_n * delta_max / v0 with delta_max = ((n + 1) m_eff v0^2 / (2 k))^(1/(n+1))
    and C_n = 2 sqrt(pi) Gamma(1/(n+1)) / ((n+1) Gamma(1/(n+1) + 1/2))
    (Johnson, Contact Mechanics, 1985, Sec. 11.4; C_1.5 = 2.94).
    """
    k = par[P_K]
    m = par[P_MEFF]
    n = par[P_EXPONENT]
    if n == 1.0:
        return math.pi * math.sqrt(m / k)
    v = max(v0, 1e-6)
    dmax = ((n + 1.0) * m * v * v / (2.0 * k)) ** (1.0 / (n + 1.0))
    a = 1.0 / (n + 1.0)
    cn = 2.0 * math.sqrt(math.pi) * math.gamma(a) / ((n + 1.0) * math.gamma(a + 0.5))
    return cn * dmax / v
