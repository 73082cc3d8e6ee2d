"""The nonlinear element protocol: what the kernel asks of a force law with state.

After OpenSees's UniaxialMaterial (setTrialStrain / getStress / getTangent /
commitState / revertToLastCommit): a law knows only its deformation, its rate
and its state; the element that links two DOFs computes the deformation
(``_elements._gap_kinematics`` for a gap); the driver knows neither.

* ``material_onset(code, par, v0, state)``: per-event quantities (an impact's
  damping and restitution, from its approach velocity v0), written to the
  committed state;
* ``material_trial(code, par, committed, trial, q, delta, rate)``: force and
  tangents (dF/d delta, dF/d rate) at a trial deformation, the trial state
  written to row q of ``trial`` from row q of ``committed`` (never the other
  way), so a redone step simply calls it again: that is the revert;
* ``material_commit(committed, trial, q)``: the step is accepted.

* ``material_energy(code, par, state, q, delta)``: the recoverable (elastic)
  energy stored at deformation delta [J]; the work done on the law minus this
  is what it dissipated (hysteretic energy, Uang & Bertero 1990).

Parameters and states are whole tables, (nn, N_PAR) and (nn, N_STATE), with the
element's row q: a row view made per call costs numba two atomic reference-count
updates per array, 30 times the bilinear law itself (measured), and the driver
calls the law twice per element and step.

State rows have N_STATE entries.  Contact laws (codes of ``contact.codes``)
keep (zeta, e) set at onset and do not change within an impact.  Hysteretic
storey laws: BILINEAR (kinematic hardening), BOUC_WEN (smooth, Bouc 1967,
Wen 1976), PEAK_ORIENTED (stiffness degrading, ``_peak_oriented``), IWAN
(Masing's rules, ``_iwan``) and FLAG (flag-shaped, self-centring, ``_flag``).  Both drivers call every law through this protocol (``_contact._begin_impact``
for the onset, ``_newton`` for the trials).  Free flight with
Bouc-Wen storeys (``_general_flight._hysteretic_flight``) carries z along a step's path
with ``bouc_wen_path`` and commits the state it reached.
"""

from __future__ import annotations

import numpy as np

from seispound._jit import njit

from ..contact._scalar import law_force, onset_state
from ._events import _hermite
from ..contact.codes import P_EXPONENT, P_K, P_MEFF, P_TENSION

# state columns: contact laws (the fast driver, which holds no other law, keeps only these)
ST_ZETA, ST_E = 0, 1
N_CONTACT_STATE = 2
# state columns: BILINEAR (plastic deformation [m], hysteretic force [N])
ST_PLASTIC, ST_Q = 0, 1
# state columns: BOUC_WEN (hysteretic displacement z [m], the committed deformation [m], the hysteretic
# energy measure eps = integral of z d(delta) / dy^2 [-] that degradation grows with)
ST_Z, ST_DELTA, ST_EPS = 0, 1, 2
# state columns: PEAK_ORIENTED (force [N], drift [m], the largest positive and negative excursions [m]:
# ``_peak_oriented``); IWAN (each slider's offset [m], then the drift [m]: ``_iwan``); FLAG (the hysteretic force
# [N] and the drift [m]: ``_flag``)
N_STATE = 9  # max(4, IWAN_SLIDERS + 1)

# codes of history-carrying laws (beyond the contact codes, which stay below 20) and their parameter columns
from ..storey.codes import (B_ALPHA, B_FY, B_K, BILINEAR, BOUC_WEN, BW_ALPHA, BW_BETA,  # noqa: E402, F401
                            BW_DETA, BW_DNU, BW_DY, BW_GAMMA, BW_K, BW_N, BW_PINCH, BW_PINCH_RATE, BW_PINCH_WIDTH,
                            FL_ALPHA, FL_K, FLAG, IW_ALPHA, IW_K, IWAN, IWAN_SLIDERS, PEAK_ORIENTED, PO_ALPHA,
                            PO_FY, PO_K, PO_PINCH, PO_UNLOAD)
from ._iwan import iwan_energy, iwan_trial, iwan_window  # noqa: E402
from ._flag import ST_FLAG_DRIFT, ST_FLAG_H, flag_energy, flag_move, flag_trial, flag_window  # noqa: E402

assert N_STATE >= IWAN_SLIDERS + 1  # an Iwan storey keeps a slider's offset per column, then its drift
from ._peak_oriented import (ST_D, ST_DNEG, ST_DPOS, ST_F, peak_oriented_energy,  # noqa: E402
                             peak_oriented_move)
# a Bouc-Wen trial integrates z over sub-increments of at most this fraction of dy (trapezoidal rule each)
BW_SUBINCREMENT = 0.02
BW_MAX_SUB = 256




@njit(cache=True)
def material_onset(code, par, v0, state):
    """Set the per-event state of a contact law from the approach velocity v0 [m/s] (``onset_state``)."""
    state[ST_ZETA], state[ST_E] = onset_state(code, par, v0)


@njit(cache=True, inline="always")  # inlined: a bilinear storey's trial costs half as much (the call, not the law)
def material_trial(code, par, committed, trial, q, delta, rate):
    """Force [N] and tangents (dF/d delta [N/m], dF/d rate [N s/m]) at a trial deformation.

    Contact laws: ``law_force`` with the impact's zeta (committed at onset).
    BILINEAR: kinematic hardening, F = alpha k delta + (1 - alpha) q with the
    hysteretic force q = k (delta - delta_p) limited to |q| <= fy by a return
    map (Simo & Hughes, Computational Inelasticity, 1998, Sec. 1.4: exact for a
    deformation that moves linearly within the step), tangent k inside the
    elastic range and alpha k once it yields.
    """
    for s in range(committed.shape[1]):
        trial[q, s] = committed[q, s]
    if code == BILINEAR:
        k = par[q, B_K]
        fy = par[q, B_FY]
        alpha = par[q, B_ALPHA]
        hq = k * (delta - committed[q, ST_PLASTIC])
        kt = k
        if hq > fy:
            hq = fy
            kt = alpha * k
        elif hq < -fy:
            hq = -fy
            kt = alpha * k
        trial[q, ST_PLASTIC] = delta - hq / k
        trial[q, ST_Q] = hq
        return alpha * k * delta + (1.0 - alpha) * hq, kt, 0.0
    if code == BOUC_WEN:
        return _bouc_wen_trial(par, committed, trial, q, delta)
    if code == PEAK_ORIENTED:
        return _peak_oriented_trial(par, committed, trial, q, delta, rate)
    if code == IWAN or code == FLAG:
        f, kt = (iwan_trial(par, committed, trial, q, delta) if code == IWAN
                 else flag_trial(par, committed, trial, q, delta))
        return f, kt, 0.0
    return law_force(code, par[q, P_K], par[q, P_EXPONENT], par[q, P_MEFF], par[q, P_TENSION], delta, rate,
                     committed[q, ST_ZETA])


@njit(cache=True, inline="always")
def _peak_oriented_par(par, q):
    """(k, fy, alpha, beta_u, pinching) of peak-oriented storey q (``storey.codes`` PO_ columns)."""
    return par[q, PO_K], par[q, PO_FY], par[q, PO_ALPHA], par[q, PO_UNLOAD], par[q, PO_PINCH]


@njit(cache=True)  # not inlined: the driver's trial phase inlines the law protocol, and this law is long
def _peak_oriented_trial(par, committed, trial, q, delta, rate):
    """PEAK_ORIENTED: the committed point moved to delta along the law's branches (``_peak_oriented``); an
    excursion column of 0 is the yield drift (the virgin storey)."""
    pq = _peak_oriented_par(par, q)
    dy = pq[1] / pq[0]
    f, kt, dpos, dneg, _ = peak_oriented_move(pq, committed[q, ST_D], committed[q, ST_F],
                                           max(committed[q, ST_DPOS], dy), min(committed[q, ST_DNEG], -dy),
                                           delta, rate)
    trial[q, ST_F], trial[q, ST_D], trial[q, ST_DPOS], trial[q, ST_DNEG] = f, delta, dpos, dneg
    return f, kt, 0.0


@njit(cache=True, inline="always")
def _bouc_wen_power(z, dy, n):
    """|z / dy|^n [-] and its derivative in z [1/m].

    The one transcendental evaluation of the law, skipped for the common exponents n = 1 and 2,
    where it is a product: in a trial it is evaluated once per Newton iterate of a sub-increment.
    |z / dy|^(n - 1) is exp((n - 1) ln|z / dy|), not ``pow``: LLVM knows that pow(x, n - 1) is x at
    n = 2 and 1 at n = 1, merged the three branches into one ``pow`` call with selected operands,
    and so called libm's pow on every iterate at n = 2 too (16 % of a Bouc-Wen row's samples,
    measured with perf); it knows no such identity of exp and log.
    """
    x = abs(z) / dy
    if x == 0.0:
        return 0.0, 0.0
    if n == 2.0:
        xn1 = x
    elif n == 1.0:
        xn1 = 1.0
    else:
        xn1 = np.exp((n - 1.0) * np.log(x))
    return xn1 * x, n * xn1 / dy * (1.0 if z > 0.0 else -1.0)


# |z / dy|^n is carried from a nearby z by its binomial series where z's relative move is at most this (and n
# times it at most twice this)
BW_SERIES_REACH = 0.05


@njit(cache=True, inline="always")
def _bouc_wen_power_near(z, dy, n, z0, xn0):
    """``_bouc_wen_power`` at z, given xn0 = |z0 / dy|^n at a nearby z0 of the same sign.

    Where |z / z0 - 1| = |r| <= BW_SERIES_REACH and n |r| <= 2 BW_SERIES_REACH, |z/dy|^n = xn0 (1 + r)^n by
    the binomial series
    sum_k C(n, k) r^k, summed until a term is below 1e-17 of the sum: a few products instead of an
    exponential and a logarithm (Newton's iterates within a sub-increment move z by 1e-5 of itself
    and less; one sub-increment moves it by at most BW_SUBINCREMENT dy).  Elsewhere, and at the
    exponents 1 and 2, the power itself.  The series' truncation is below 1e-16 of the power: each
    term is |r (n - k + 1) / k| <= max(n, 1) |r| <= 0.1 times the one before (n >= 1, the law's bound), so
    what follows the last one summed is under 0.12 of it (derived here).
    """
    if n == 2.0 or n == 1.0 or xn0 == 0.0 or z * z0 <= 0.0:
        return _bouc_wen_power(z, dy, n)
    r = (z - z0) / z0
    if abs(r) > BW_SERIES_REACH or abs(r) * n > 2.0 * BW_SERIES_REACH:
        return _bouc_wen_power(z, dy, n)
    term, total = 1.0, 1.0
    for k in range(1, 24):
        term *= r * (n - k + 1.0) / k
        total += term
        if abs(term) <= 1e-17 * total:
            break
    xn = xn0 * total
    return xn, n * xn / z


@njit(cache=True, inline="always")
def _gauss_near(z, width, z0, e0):
    """exp(-(z / width)^2) [-], given e0, its value at a nearby z0: e0 exp(-a), a = (z - z0)(z + z0) / width^2,
    by the exponential series where |a| <= BW_SERIES_REACH (summed until a term is below 1e-17 of the sum;
    the pinching function's Gaussian, carried between Newton's iterates as ``_bouc_wen_power_near`` carries the
    power); elsewhere the exponential itself."""
    a = (z - z0) * (z + z0) / (width * width)
    if e0 == 0.0 or abs(a) > BW_SERIES_REACH:
        return np.exp(-(z / width) ** 2)
    term, total = 1.0, 1.0
    for k in range(1, 24):
        term *= -a / k
        total += term
        if abs(term) <= 1e-17 * total:
            break
    return e0 * total


@njit(cache=True, inline="always")
def _bouc_wen_phi(z, d, xn, dxn, beta, gamma, nu, eta, pinch, width, gauss):
    """dz/d(delta) of the Bouc-Wen model with A = 1 and its derivative in z, for a step of sign d.

    Phi = h(z) (1 - nu |z/dy|^n (beta sgn(d z) + gamma)) / eta (Wen 1976, J. Eng. Mech. Div.
    102(2) 249-263, Eq. 2 divided by d(delta)/dt: the model is rate independent; nu and eta,
    1 without degradation, are Baber & Wen's (1981) strength and stiffness degradation factors);
    xn, dxn: |z/dy|^n and its derivative (``_bouc_wen_power``).  h(z) = 1 - zeta_1 exp(-(z / w)^2)
    is Baber & Noori's (1985, J. Eng. Mech. 111(8) 1010-1026) pinching function in Foliente's (1995,
    J. Struct. Eng. 121(6) 1013-1022) form with q = 0 (the pinch centred at z = 0); pinch = zeta_1 [-],
    width = w [m]; pinch 0: no pinching; gauss: exp(-(z / w)^2) [-] (unused without pinching).
    """
    c = beta * (1.0 if d * z >= 0.0 else -1.0) + gamma
    phi, dphi = (1.0 - nu * xn * c) / eta, -nu * c * dxn / eta
    if pinch == 0.0:
        return phi, dphi
    g = pinch * gauss
    return (1.0 - g) * phi, (1.0 - g) * dphi + 2.0 * g * z / (width * width) * phi


@njit(cache=True, inline="always")
def _pinching(par, q, eps):
    """(zeta_1 [-], w [m]) of Bouc-Wen storey q at energy measure eps: zeta_1 = zeta_s (1 - exp(-p eps))
    grows with the dissipated energy (Foliente 1995, Eq. 10), w = psi dy a constant width (Foliente's
    (psi + delta_psi eps)(lambda + zeta_1) with delta_psi = 0 and lambda + zeta_1 taken into the fitted
    psi: a simplification made here)."""
    zs = par[q, BW_PINCH]
    if zs == 0.0:
        return 0.0, 1.0
    return zs * (1.0 - np.exp(-par[q, BW_PINCH_RATE] * max(eps, 0.0))), par[q, BW_PINCH_WIDTH] * par[q, BW_DY]


@njit(cache=True)
def _bouc_wen_trial(par, committed, trial, q, delta):
    """Force and tangent of a Bouc-Wen storey at a trial deformation ``delta`` [m].

    F = alpha k delta + (1 - alpha) k z (the issue's form of Wen 1976 with
    A = 1: z is a displacement bounded by dy for beta + gamma = 1); z carried
    from the committed deformation by :func:`bouc_wen_advance`, whose tangent
    dz/d(delta) makes the driver's Newton converge quadratically.
    """
    k = par[q, BW_K]
    alpha = par[q, BW_ALPHA]
    z, eps, dz = bouc_wen_advance(par, q, committed[q, ST_Z], committed[q, ST_EPS], delta - committed[q, ST_DELTA])[:3]
    trial[q, ST_Z] = z
    trial[q, ST_DELTA] = delta
    trial[q, ST_EPS] = eps
    return alpha * k * delta + (1.0 - alpha) * k * z, alpha * k + (1.0 - alpha) * k * dz, 0.0


@njit(cache=True, inline="always")
def bouc_wen_advance(par, q, z, eps, total):
    """(z, eps, dz/d(total), dz/d(delta) at the start, |z/dy|^n and its derivative at the end) of Bouc-Wen storey
    q after its deformation moves monotonically by ``total`` [m].

    At the exponents 1 and 2, without degradation or pinching, z comes from the law's closed form along the
    move (``_bouc_wen_exact``).  Otherwise z [m] is carried over sub-increments of at most BW_SUBINCREMENT dy, each by the implicit
    trapezoidal rule z1 = z0 + d/2 (Phi(z0) + Phi(z1)), solved by Newton; the tangent is the
    derivative of that map (chain rule over the sub-increments).  Phi and its derivative at the
    end of a sub-increment are those of Newton's last iterate, which the last correction moved
    by at most 1e-15 dy; they serve the tangent and the next sub-increment's start (one power
    per iterate, none recomputed, each carried from the one before by its binomial series where z
    moved little: ``_bouc_wen_power_near``); the slope at the start and the power at the end are
    returned for the slopes a path needs (``bouc_wen_path``), so that they cost no further power.

    Degradation (Baber & Wen 1981, J. Eng. Mech. Div. 107(6) 1069-1087, Eqs. 5-6):
    nu = 1 + delta_nu eps and eta = 1 + delta_eta eps grow with the hysteretic
    energy measure eps = integral of z d(delta) / dy^2 (Baber & Wen's integral of
    z u' dt, made dimensionless by dy^2 here), and so does the pinching's severity
    (``_pinching``).  They are held at their values at
    the start of each sub-increment, eps advanced by the trapezoidal rule after
    it; the tangent leaves out eps's own dependence on the step (a first-order
    term of one sub-increment), so with degradation Newton converges linearly.
    The law is rate independent: only the path of the deformation matters.
    """
    dy = par[q, BW_DY]
    n = par[q, BW_N]
    beta = par[q, BW_BETA]
    gamma = par[q, BW_GAMMA]
    dnu = par[q, BW_DNU]
    deta = par[q, BW_DETA]
    if (n == 2.0 or n == 1.0) and dnu == 0.0 and deta == 0.0 and par[q, BW_PINCH] == 0.0:
        out = _bouc_wen_exact(z, eps, total, dy, n, beta, gamma)
        if out[0] == out[0]:  # (NaN: a state outside the law's range, taken by the sub-increments below)
            return out
    n_sub = min(BW_MAX_SUB, 1 + int(abs(total) / (BW_SUBINCREMENT * dy)))
    d = total / n_sub
    dz = 0.0  # dz/d(total)
    xn, dxn = _bouc_wen_power(z, dy, n)
    pinched = par[q, BW_PINCH] != 0.0
    gauss = np.exp(-(z / (par[q, BW_PINCH_WIDTH] * dy)) ** 2) if pinched else 0.0
    zp = z  # where xn and gauss were taken: each is carried from the one before (``_bouc_wen_power_near``)
    p_start = 0.0
    for i in range(n_sub):
        nu = 1.0 + dnu * eps
        eta = 1.0 + deta * eps
        pinch, width = _pinching(par, q, eps)
        phi0, dphi0 = _bouc_wen_phi(z, d, xn, dxn, beta, gamma, nu, eta, pinch, width, gauss)
        if i == 0:
            p_start = phi0
        z1 = z + d * phi0 * (1.0 + 0.5 * d * dphi0)  # second-order Taylor start, closer for Newton
        phi1, dphi1 = phi0, dphi0
        for _ in range(50):
            xn, dxn = _bouc_wen_power_near(z1, dy, n, zp, xn)
            if pinched:
                gauss = _gauss_near(z1, width, zp, gauss)
            zp = z1
            phi1, dphi1 = _bouc_wen_phi(z1, d, xn, dxn, beta, gamma, nu, eta, pinch, width, gauss)
            step = (z1 - z - 0.5 * d * (phi0 + phi1)) / (1.0 - 0.5 * d * dphi1)
            z1 -= step
            if abs(step) <= 1e-15 * dy:
                break
        dz = (dz * (1.0 + 0.5 * d * dphi0) + 0.5 * (phi0 + phi1) / n_sub) / (1.0 - 0.5 * d * dphi1)
        eps += 0.5 * (z + z1) * d / (dy * dy)
        z = z1
    return z, eps, dz, p_start, xn, dxn


@njit(cache=True)
def _bouc_wen_exact(z, eps, total, dy, n, beta, gamma):
    """``bouc_wen_advance`` in closed form for n = 1 or 2, without degradation or pinching.

    Along a monotonic move the law is the autonomous equation dX/dU = 1 - c |X|^n in X = s z / dy and
    U = s delta / dy (s the move's sign, so U grows), with c = beta + gamma where X >= 0 and gamma - beta
    where X < 0 (Wen 1976, Eq. 2, with A = 1).  For n = 2, X(U) = tanh(a U + atanh(a X0)) / a (c = a^2 > 0;
    coth above saturation), tan(b U + atan(b X0)) / b (c = -b^2) or X0 + U (c = 0); for n = 1 and k = c
    sign(X), X(U) = X0 e^(-k U) - expm1(-k U) / k.  A move that starts at X0 < 0 runs to X = 0 first (U* from
    the same forms) and on with the other c.  The slopes are 1 - c |X|^n at both ends, and dz/d(total) is the
    slope at the end (an autonomous equation's solution moves with its end's rate).  Derived here, not read;
    verified against SciPy's ``solve_ivp`` (``tests/verification/test_bouc_wen_closed_form.py``).  eps, which only
    degradation and pinching read, is advanced by the trapezoidal rule over each part.  An unloading state
    whose slope is not positive (it would move away from zero), or a tan past its pole, returns NaN: the
    caller's sub-increments take it.  Returns as ``bouc_wen_advance``.
    """
    s = 1.0 if total >= 0.0 else -1.0
    x = s * z / dy
    u = s * total / dy
    cn, cp = gamma - beta, gamma + beta  # c where X < 0 (unloading) and where X >= 0 (loading)
    p_start = _bw_slope(x, cn, cp, n)
    if x < 0.0 and u > 0.0:
        if not p_start > 0.0:  # unloading away from zero: outside the law's range
            return np.nan, eps, 0.0, 0.0, 0.0, 0.0
        u0 = _bw_to_zero(x, cn, n)  # the move that brings X to 0
        if u0 < u:
            eps += 0.5 * x * u0
            u -= u0
            x = 0.0
        else:
            x1 = _bw_run(x, u, cn, n)
            eps += 0.5 * (x + x1) * u
            x, u = x1, 0.0
    if u > 0.0:
        x1 = _bw_run(x, u, cp, n)
        eps += 0.5 * (x + x1) * u
        x = x1
    if x != x:
        return np.nan, eps, 0.0, 0.0, 0.0, 0.0
    z1 = s * x * dy
    xn, dxn = _bouc_wen_power(z1, dy, n)
    return z1, eps, _bw_slope(x, cn, cp, n), p_start, xn, dxn


@njit(cache=True, inline="always")
def _bw_slope(x, cn, cp, n):
    """dX/dU = 1 - c |X|^n at X (``_bouc_wen_exact``; n = 1 or 2, written as products)."""
    ax = abs(x)
    return 1.0 - (cp if x >= 0.0 else cn) * (ax * ax if n == 2.0 else ax)


@njit(cache=True, inline="always")
def _bw_to_zero(x, c, n):
    """The move U* [-] that brings X < 0 to 0 under dX/dU = 1 - c |X|^n (``_bouc_wen_exact``)."""
    if c == 0.0:
        return -x
    if n == 1.0:
        return np.log1p(c * x) / -c  # X0 e^(cU) + expm1(cU) / c = 0
    if c > 0.0:
        a = np.sqrt(c)
        return -np.arctanh(a * x) / a
    b = np.sqrt(-c)
    return -np.arctan(b * x) / b


@njit(cache=True, inline="always")
def _bw_run(x, u, c, n):
    """X after a move U >= 0 under dX/dU = 1 - c |X|^n, X keeping its sign (``_bouc_wen_exact``); NaN past a
    pole."""
    if c == 0.0:
        return x + u
    if n == 1.0:
        k = c if x >= 0.0 else -c
        return x * np.exp(-k * u) - np.expm1(-k * u) / k
    if c > 0.0:
        a = np.sqrt(c)
        w = a * x
        if abs(w) < 1.0:
            return np.tanh(a * u + np.arctanh(w)) / a
        if w == 1.0:
            return x
        return 1.0 / (a * np.tanh(a * u + np.arctanh(1.0 / w)))  # above saturation: coth, decaying to 1 / a
    b = np.sqrt(-c)
    arg = b * u + np.arctan(b * x)
    return np.tan(arg) / b if arg < 0.5 * np.pi else np.nan


@njit(cache=True, inline="always")
def _slope_at(par, q, z, eps, d, xn, dxn):
    """dz/d(delta) [-] of Bouc-Wen storey q at z [m] and energy measure eps, moving in the direction of sign d, with
    |z/dy|^n and its derivative given (``_bouc_wen_power``; the law: ``_bouc_wen_phi``, Wen 1976 with Baber &
    Wen's 1981 degradation and Baber & Noori's 1985 pinching)."""
    pinch, width = _pinching(par, q, eps)
    gauss = np.exp(-(z / width) ** 2) if pinch != 0.0 else 0.0
    return _bouc_wen_phi(z, d, xn, dxn, par[q, BW_BETA], par[q, BW_GAMMA], 1.0 + par[q, BW_DNU] * eps,
                         1.0 + par[q, BW_DETA] * eps, pinch, width, gauss)[0]


@njit(cache=True)
def _bouc_wen_piece(par, q, z, eps, total):
    """``bouc_wen_advance`` compiled once, not inlined: a path calls it from two places, and inlining it in
    both cost seconds of compilation for nothing measurable in run time."""
    return bouc_wen_advance(par, q, z, eps, total)


@njit(cache=True, inline="always")
def _turning_points(ca, cb, cc):
    """The turning points (delta'(tau) = 0) of delta(tau) = d0 + ca tau + cb tau^2 + cc tau^3 inside (0, 1),
    sorted; 2.0 where there is none."""
    t_a, t_b = 2.0, 2.0
    qa, qb, qc = 3.0 * cc, 2.0 * cb, ca
    if qa != 0.0:
        disc = qb * qb - 4.0 * qa * qc
        if disc > 0.0:
            sq = np.sqrt(disc)
            r1 = (-qb - sq) / (2.0 * qa)
            r2 = (-qb + sq) / (2.0 * qa)
            t_a, t_b = min(r1, r2), max(r1, r2)
    elif qb != 0.0:
        t_a = -qc / qb
    if not 1e-9 < t_a < 1.0 - 1e-9:
        t_a = 2.0
    if not 1e-9 < t_b < 1.0 - 1e-9:
        t_b = 2.0
    if t_a > t_b:
        t_a, t_b = t_b, t_a
    return t_a, t_b


# a bilinear storey whose hysteretic force is within this fraction of fy of its yield force is yielding
B_ON_SURFACE = 1e-9


@njit(cache=True, inline="always")
def _breakpoints(t_a, t_b):
    """The ends of a path's pieces in (0, 1]: its turning points t_a <= t_b (``_turning_points``) and the
    middle 0.5, sorted, then 1.0 (a turning point absent: 2.0, skipped by the caller)."""
    s0, s1, s2 = t_a, t_b, 0.5  # sorted with the middle: s0 <= s1 <= s2
    if s1 > 0.5:
        s1, s2 = 0.5, s1
        if s0 > 0.5:
            s0, s1 = 0.5, s0
    return s0, s1, s2


@njit(cache=True, inline="always")
def bilinear_dy(par, q):
    """The deformation [m] a bilinear storey's hysteretic force reaches fy at from its elastic state: fy / k."""
    return par[q, B_FY] / par[q, B_K]


@njit(cache=True)
def bilinear_path(par, q, z, d0, ca, cb, cc):
    """(z at the step's middle, z at its end, dz/d(delta) there, whether it yields from inside its elastic range)
    of bilinear storey q along delta(tau) = d0 + ca tau + cb tau^2 + cc tau^3, tau in [0, 1].

    z = q_h / k [m] is the hysteretic force over the elastic stiffness, bounded by dy = fy / k, so that the
    storey's force is alpha k delta + (1 - alpha) k z, Bouc-Wen's form (``bouc_wen_path``).  On a monotonic
    piece the return map is exact: z moves with delta and stops at +-dy (``material_trial``'s; Simo & Hughes
    1998, Sec. 1.4), so the path is cut at its turning points and at the middle.  A storey that reaches dy
    from inside its elastic range within the step makes its force's slope in time jump there, which the
    free-flight step's quadratic load does not hold: the caller takes that step on the physical path.
    (At a turning point the slope in time is continuous: delta' = 0 there.)
    """
    dy = bilinear_dy(par, q)
    inner = dy * (1.0 - B_ON_SURFACE)
    t_a, t_b = _turning_points(ca, cb, cc)
    s0, s1, s2 = _breakpoints(t_a, t_b)
    zm, pm, p1, tp, dp, onset = z, 1.0, 1.0, 0.0, d0, False
    for i in range(4):
        tb = s0 if i == 0 else (s1 if i == 1 else (s2 if i == 2 else 1.0))
        if tb > 1.0 or tb <= tp:
            continue
        db = d0 + tb * (ca + tb * (cb + tb * cc))
        d = db - dp
        z0 = z
        z += d
        slope = 1.0
        if z >= dy:
            onset = onset or z0 < inner
            z, slope = dy, (0.0 if d > 0.0 else 1.0)
        elif z <= -dy:
            onset = onset or z0 > -inner
            z, slope = -dy, (0.0 if d < 0.0 else 1.0)
        if tb == 0.5:
            zm, pm = z, slope
        p1 = slope
        dp, tp = db, tb
    return zm, z, pm, p1, onset


@njit(cache=True, inline="always")
def _piece_end(i, t_a, t_b, tp, d0, ca, cb, cc):
    """(tau, delta [m]) at the end of a path's monotonic piece i (0, 1: at the turning points t_a, t_b; 2: at the
    step's end) along delta(tau) = d0 + ca tau + cb tau^2 + cc tau^3, and whether the piece is empty (its end
    outside (tp, 1], tp the last piece's end)."""
    tb = t_a if i == 0 else (t_b if i == 1 else 1.0)
    return tb, d0 + tb * (ca + tb * (cb + tb * cc)), tb > 1.0 or tb <= tp


@njit(cache=True)
def peak_oriented_path(par, q, state, d0, ca, cb, cc):
    """A peak-oriented storey along delta(tau) = d0 + ca tau + cb tau^2 + cc tau^3, tau in [0, 1], from its
    committed ``state``: (z at the middle [m], z at the end [m], dz/d(delta) there [-], whether its slope
    changes inside a monotonic piece, and the end's force [N] and excursions [m]).

    Written as Bouc-Wen's form (``bouc_wen_path``): the force k delta - c with c = (1 - alpha) k (delta - z),
    so z = delta - (k delta - f) / ((1 - alpha) k) and dz/d(delta) = 1 - (k - k_t) / ((1 - alpha) k) on a
    segment of slope k_t (derived here).  The law is rate independent and piecewise linear: each monotonic
    piece (cut at the turning points) is followed exactly (``peak_oriented_move``), and where no piece bends
    the middle lies on its piece's line.  A slope that changes inside a piece (yield, zero force, a pinch
    point, the target) makes the force's slope in time jump, which the free-flight step's quadratic load does
    not hold: the caller takes that step on the physical path.  At a turning point the slope in time is
    continuous (delta' = 0 there).
    """
    pq = _peak_oriented_par(par, q)
    k, alpha = pq[0], pq[2]
    dy = pq[1] / k
    scale = (1.0 - alpha) * k
    f, d = state[q, ST_F], state[q, ST_D]
    dpos, dneg = max(state[q, ST_DPOS], dy), min(state[q, ST_DNEG], -dy)
    t_a, t_b = _turning_points(ca, cb, cc)
    dm = d0 + 0.5 * (ca + 0.5 * (cb + 0.5 * cc))
    zm, pm, kt, tp, bent = 0.0, 1.0, k, 0.0, False
    for i in range(3):
        tb, db, empty = _piece_end(i, t_a, t_b, tp, d0, ca, cb, cc)
        if empty:
            continue
        f_a, d_a = f, d
        f, kt, dpos, dneg, b = peak_oriented_move(pq, d, f, dpos, dneg, db, db - d)
        bent = bent or b  # (the move stays exact: the commit reads the end state of a path that bends)
        if tp < 0.5 <= tb:  # the middle, on this piece's line
            fm = f_a + kt * (dm - d_a)
            zm, pm = dm - (k * dm - fm) / scale, 1.0 - (k - kt) / scale
        d, tp = db, tb
    return zm, d - (k * d - f) / scale, pm, 1.0 - (k - kt) / scale, bent, f, dpos, dneg


@njit(cache=True)
def flag_path(par, q, state, d0, ca, cb, cc):
    """A flag storey along delta(tau) = d0 + ca tau + cb tau^2 + cc tau^3, tau in [0, 1], from its committed
    ``state``: (z at the middle [m], z at the end [m], dz/d(delta) there [-], whether its slope changes inside
    a monotonic piece, and h at the end [N]).

    Written as Bouc-Wen's form (``bouc_wen_path``): F = alpha k delta + h = k delta - c with c = K delta - h,
    K = (1 - alpha) k, so z = h / K, and dz/d(delta) is 1 where h moves at K and 0 on a branch (derived here).
    The law is rate independent and piecewise linear: each monotonic piece (cut at the turning points) is
    followed exactly (``_flag.flag_move``), as ``peak_oriented_path`` follows its law; a slope that changes
    inside a piece (a branch reached, the lower branch meeting the origin's line) makes the force's slope in
    time jump, which the free-flight step's quadratic load does not hold: the caller takes that step on the
    physical path.
    """
    kh = (1.0 - par[q, FL_ALPHA]) * par[q, FL_K]
    h, d = state[q, ST_FLAG_H], state[q, ST_FLAG_DRIFT]
    t_a, t_b = _turning_points(ca, cb, cc)
    dm = d0 + 0.5 * (ca + 0.5 * (cb + 0.5 * cc))
    zm, pm, p1, tp, bent = 0.0, 1.0, 1.0, 0.0, False
    for i in range(3):
        tb, db, empty = _piece_end(i, t_a, t_b, tp, d0, ca, cb, cc)
        if empty:
            continue
        h_a, d_a = h, d
        h, p1, b = flag_move(par, q, d, h, db)
        bent = bent or b
        if tp < 0.5 <= tb:  # the middle, on this piece's line
            zm, pm = (h_a + p1 * kh * (dm - d_a)) / kh, p1
        d, tp = db, tb
    return zm, h / kh, pm, p1, bent, h


@njit(cache=True)
def iwan_path(par, q, state, work, d0, ca, cb, cc):
    """An Iwan storey along delta(tau) = d0 + ca tau + cb tau^2 + cc tau^3, tau in [0, 1], from its committed
    ``state``: (z at the middle [m], z at the end [m], dz/d(delta) at the middle and at the end [-], the end's
    force [N]); row q of ``work`` holds the end's state.

    Written as Bouc-Wen's form (``bouc_wen_path``): c = k delta - F, z = delta - c / ((1 - alpha) k) and
    dz/d(delta) = 1 - (k - k_t) / ((1 - alpha) k) (derived here, as ``peak_oriented_path``).  Each monotonic
    piece of the path, cut at the turning points and the middle, is the sliders' return map (``_iwan``:
    exact for a monotone move), so z is exact at the middle and the end.  Unlike the other piecewise-linear
    laws the path is not refused where a slider starts to slip inside a piece: the kink it puts in the force's
    slope in time (one slider's stiffness, (1 - c)(1 - alpha) k / 8, or the self-centring spring's) is what the
    free-flight step's quadratic load then misses (measured against the solve_ivp twin:
    ``tests/verification/test_iwan_storeys``).
    """
    k, alpha = par[q, IW_K], par[q, IW_ALPHA]
    scale = (1.0 - alpha) * k
    for c in range(state.shape[1]):
        work[q, c] = state[q, c]
    t_a, t_b = _turning_points(ca, cb, cc)
    s0, s1, s2 = _breakpoints(t_a, t_b)
    zm, pm, f, kt, tp, db = 0.0, 1.0, 0.0, k, 0.0, d0
    for i in range(4):
        tb = s0 if i == 0 else (s1 if i == 1 else (s2 if i == 2 else 1.0))
        if tb > 1.0 or tb <= tp:
            continue
        db = d0 + tb * (ca + tb * (cb + tb * cc))
        f, kt = iwan_trial(par, work, work, q, db)  # (in place: each slider reads its offset, then writes it)
        if tb == 0.5:
            zm, pm = db - (k * db - f) / scale, 1.0 - (k - kt) / scale
        tp = tb
    return zm, db - (k * db - f) / scale, pm, 1.0 - (k - kt) / scale, f


@njit(cache=True)
def bouc_wen_path(par, q, z, eps, d0, ca, cb, cc):
    """(z at the step's middle, z and eps at its end, dz/d(delta) at the middle and at the end) of Bouc-Wen
    storey q along the deformation delta(tau) = d0 + ca tau + cb tau^2 + cc tau^3, tau in [0, 1] (the
    step's Hermite cubic).

    The law is rate independent, so z follows the path: ``bouc_wen_advance`` over its monotonic
    pieces, split at the turning points (delta'(tau) = 0).  On a monotonic step one piece, and z at
    the middle from the cubic Hermite of z in delta through both ends, with the law's slopes there
    (error of order (delta1 - delta0)^4; derived here); otherwise split at the middle too.
    """
    t_a, t_b = _turning_points(ca, cb, cc)
    d1 = d0 + ca + cb + cc
    dm = d0 + 0.5 * ca + 0.25 * cb + 0.125 * cc
    if t_a > 1.0:  # monotonic: one piece, the middle by Hermite interpolation in delta
        span = d1 - d0
        z1, eps1, _, p0, xn1, dxn1 = _bouc_wen_piece(par, q, z, eps, span)
        p1 = _slope_at(par, q, z1, eps1, span, xn1, dxn1)  # the power of Newton's last iterate (1e-15 dy off)
        th = (dm - d0) / span if span != 0.0 else 0.5
        zm = _hermite(th, z, p0, z1, p1, span)  # z as a cubic in delta, its slopes the law's
        xm, dxm = _bouc_wen_power_near(zm, par[q, BW_DY], par[q, BW_N], z1, xn1)
        return zm, z1, eps1, _slope_at(par, q, zm, eps, span, xm, dxm), p1
    s0, s1, s2 = _breakpoints(t_a, t_b)
    zm = z
    pm = 1.0
    tp = 0.0
    dp = d0
    for i in range(4):
        tb = s0 if i == 0 else (s1 if i == 1 else (s2 if i == 2 else 1.0))
        if tb > 1.0 or tb <= tp:
            continue
        db = d0 + tb * (ca + tb * (cb + tb * cc))
        z, eps, _, _, xn, dxn = _bouc_wen_piece(par, q, z, eps, db - dp)
        last = db - dp
        if tb == 0.5:
            zm = z
            pm = _slope_at(par, q, z, eps, last, xn, dxn)
        dp = db
        tp = tb
    return zm, z, eps, pm, _slope_at(par, q, z, eps, last, xn, dxn)


@njit(cache=True, inline="always")  # inlined: per storey and output step (``_elements.kinetic_energy``)
def material_energy(code, par, state, q, delta):
    """Recoverable energy [J] of a storey law in ``state`` at deformation ``delta`` [m] (0 for contact laws).

    BILINEAR: alpha k delta^2 / 2 + (1 - alpha) q^2 / (2 k); BOUC_WEN:
    alpha k delta^2 / 2 + (1 - alpha) k eta z^2 / 2 (the elastic energy of the
    linear and hysteretic springs in parallel: an unloading hysteretic spring
    follows dz/d(delta) = 1 / eta, so releasing z returns (1 - alpha) k eta z^2 / 2,
    derived here; eta = 1 without degradation; what the law absorbed beyond
    it is dissipated).  With pinching the unloading slope is h(z) / eta, and
    (1 - alpha) k eta int_0^z s / h(s) ds = (1 - alpha) k eta (w^2 / 2) (U + ln(1 - zeta_1 e^-U)
    - ln(1 - zeta_1)), U = z^2 / w^2 (the substitution u = s^2 / w^2 and
    int du / (1 - zeta_1 e^-u) = ln(e^u - zeta_1); derived here), which is eta z^2 / 2 at zeta_1 = 0.
    """
    if code == BILINEAR:
        k = par[q, B_K]
        return 0.5 * par[q, B_ALPHA] * k * delta * delta + 0.5 * (1.0 - par[q, B_ALPHA]) * state[q, ST_Q] ** 2 / k
    if code == BOUC_WEN:
        k = par[q, BW_K]
        eta = 1.0 + par[q, BW_DETA] * state[q, ST_EPS]
        z = state[q, ST_Z]
        pinch, width = _pinching(par, q, state[q, ST_EPS])
        z2 = z * z
        if pinch > 0.0:
            u = z2 / (width * width)
            z2 = width * width * (u + np.log1p(-pinch * np.exp(-u)) - np.log1p(-pinch))
        return 0.5 * par[q, BW_ALPHA] * k * delta * delta + 0.5 * (1.0 - par[q, BW_ALPHA]) * k * eta * z2
    if code == PEAK_ORIENTED:
        pq = _peak_oriented_par(par, q)
        dy = pq[1] / pq[0]
        return peak_oriented_energy(pq, state[q, ST_F], max(state[q, ST_DPOS], dy), min(state[q, ST_DNEG], -dy))
    if code == IWAN:
        return iwan_energy(par, state, q, delta)
    if code == FLAG:
        return flag_energy(par, state, q, delta)
    return 0.0


@njit(cache=True)
def material_window(code, par, state, q):
    """(lo, hi [m], c [N]) of a storey whose law is linear in pieces with a window (IWAN, FLAG): the drifts
    between which it moves at its initial stiffness k from its committed point, and its force k delta - c there
    (``_iwan.iwan_window``, ``_flag.flag_window``); what free flight holds fixed while the storey stays inside."""
    if code == FLAG:
        return flag_window(par, state, q)
    return iwan_window(par, state, q)


@njit(cache=True, inline="always")
def material_commit(committed, trial, q):
    """Accept the trial state of row q."""
    for s in range(committed.shape[1]):
        committed[q, s] = trial[q, s]
