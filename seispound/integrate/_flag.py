"""The flag-shaped, self-centring storey law (``storey.codes.FLAG``).

Private: the material protocol (``_material.material_trial`` and ``material_energy``) calls :func:`flag_trial`
and :func:`flag_energy`; the general driver's free flight and elastic predictor call :func:`flag_window` and
:func:`flag_kept_elastic`, and its free flight on a branch :func:`flag_on_branch` and :func:`flag_move`
(through ``_material.flag_path``).

A storey of initial stiffness k [N/m] carries F = alpha k d + h at drift d [m]: a linear spring alpha k (the
post-yield stiffness) and a hysteretic force h [N] that moves at K = (1 - alpha) k between two bounds and
follows them where it reaches one (forces [N], drifts [m]; d >= 0, and the mirror image for d < 0):

* upper bound min(H, K d), H = K dy: loading leaves the origin at k and yields at dy onto the upper branch
  F = alpha k d + H;
* lower bound min(L, K d), L = (1 - beta) H: unloading from the upper branch runs at k until h has dropped by
  beta H, then down the lower branch F = alpha k d + L, and from d = L / K back to the origin at k.

The loop is the flag of self-centring systems (post-tensioned rocking joints, shape-memory-alloy braces) of
Christopoulos, Filiatrault & Folz (2002), "Seismic response of self-centring hysteretic SDOF systems", EESD
31(5), 1131-1150: unloading at k from the upper branch drops the force by beta Fy (Fy = k dy) before the lower
branch, which is the upper one moved by (-beta dy, -beta Fy) along the elastic slope; the branches lie
beta (1 - alpha) Fy apart.  Every beta in [0, 1] returns the storey to zero drift at zero force (beta = 0:
nonlinear elastic, beta = 1: the lower branch ends at the origin).  The formulation in h and its bounds is
written here (derived, not read).

The trial is the return map of h (Simo & Hughes 1998, Computational Inelasticity, Sec. 1.4, with bounds that
depend on d): h moved at K from its committed value, then clipped to the bounds at the trial drift.  The bounds'
slopes never exceed K, so the clip is exact for a drift that moves monotonically within the step; a step that
crosses zero drift restarts from (0, 0), where h is zero on every path (both bounds vanish there).

State columns: h [N] (``ST_FLAG_H``) and the committed drift [m] (``ST_FLAG_DRIFT``).
"""

from __future__ import annotations

from seispound._jit import njit

from ..storey.codes import FL_ALPHA, FL_BETA, FL_DY, FL_K

ST_FLAG_H, ST_FLAG_DRIFT = 0, 1


@njit(cache=True, inline="always")
def _bounds(kh, big, low, d):
    """(lower, upper [N]) bounds of h at drift d [m]; kh = (1 - alpha) k [N/m], big = H, low = L [N]."""
    if d >= 0.0:
        return min(low, kh * d), min(big, kh * d)
    return max(-big, kh * d), max(-low, kh * d)


@njit(cache=True)
def flag_trial(par, committed, trial, q, delta):
    """Force [N] and tangent [N/m] of flag storey q at drift ``delta`` [m] from its committed state; h and the
    drift written to row q of ``trial``.  The tangent is k inside the bounds (and on the origin's line, whose
    slope is K) and alpha k on a branch."""
    k, alpha = par[q, FL_K], par[q, FL_ALPHA]
    kh = (1.0 - alpha) * k
    big = kh * par[q, FL_DY]
    low = (1.0 - par[q, FL_BETA]) * big
    h0, d0 = committed[q, ST_FLAG_H], committed[q, ST_FLAG_DRIFT]
    if (d0 > 0.0 and delta < 0.0) or (d0 < 0.0 and delta > 0.0):
        h0, d0 = 0.0, 0.0  # through zero drift, where h is zero on every path
    h = h0 + kh * (delta - d0)
    lo, hi = _bounds(kh, big, low, delta)
    kt = k
    if h > hi:
        h = hi
        if hi != kh * delta:  # on the upper (or, for delta < 0, the lower) branch
            kt = alpha * k
    elif h < lo:
        h = lo
        if lo != kh * delta:
            kt = alpha * k
    trial[q, ST_FLAG_H] = h
    trial[q, ST_FLAG_DRIFT] = delta
    return alpha * k * delta + h, kt


@njit(cache=True)
def flag_energy(par, state, q, delta):
    """Recoverable energy [J] of flag storey q in ``state`` at drift ``delta`` [m]: alpha k delta^2 / 2 and
    h^2 / (2 K) + L |h - K delta| / K, the work the hysteretic force returns along the law's path back to zero
    drift (derived here: an elastic drop to the lower branch, along it, and down the origin's line).  Moves
    inside the bounds and along the lower branch towards zero change it by their work; only a move outwards on
    the upper branch dissipates, (H - L) per unit drift."""
    k, alpha = par[q, FL_K], par[q, FL_ALPHA]
    kh = (1.0 - alpha) * k
    low = (1.0 - par[q, FL_BETA]) * kh * par[q, FL_DY]
    h = state[q, ST_FLAG_H]
    return 0.5 * alpha * k * delta * delta + 0.5 * h * h / kh + low * abs(h - kh * delta) / kh


@njit(cache=True)
def flag_window(par, state, q):
    """(lo, hi [m], c [N]) of flag storey q in ``state``: the drifts between which h moves at K from its committed
    point without reaching a branch, and the storey's force k delta - c there, c = K d_c - h_c (derived here: on
    the origin's line, c = 0 and the window is +-dy; above or below it, the window lies on one side of zero drift,
    between the drifts at which h would reach the lower and the upper branch)."""
    k, alpha = par[q, FL_K], par[q, FL_ALPHA]
    kh = (1.0 - alpha) * k
    big = kh * par[q, FL_DY]
    low = (1.0 - par[q, FL_BETA]) * big
    off = state[q, ST_FLAG_H] - kh * state[q, ST_FLAG_DRIFT]  # h = K delta + off while it moves at K
    if abs(off) <= 1e-12 * big:
        return -par[q, FL_DY], par[q, FL_DY], 0.0
    if off < 0.0:  # right of the origin's line: between the lower and the upper branch
        return (low - off) / kh, (big - off) / kh, -off
    return (-big - off) / kh, (-low - off) / kh, -off


@njit(cache=True)
def flag_kept_elastic(par, state, q, delta, kt):
    """Did flag storey q move at k from its committed point (``state``) to a trial drift ``delta`` [m] of tangent
    ``kt`` [N/m]?  Both lie inside the window of :func:`flag_window` (an interval, so the move between them is
    elastic throughout): the tangent alone does not tell, since the origin's line is also of slope k."""
    if kt != par[q, FL_K]:
        return False
    lo, hi, _ = flag_window(par, state, q)
    tol = 1e-12 * par[q, FL_DY]
    d = state[q, ST_FLAG_DRIFT]
    return lo - tol <= d <= hi + tol and lo - tol <= delta <= hi + tol


@njit(cache=True)
def flag_on_branch(par, state, q):
    """Is flag storey q in ``state`` at a bound of its hysteretic force off the origin's line (on a branch, or at
    the edge of its window where one begins), so that its force is not k delta - c over a window around its
    drift?  Within 1e-12 H of the bound."""
    kh = (1.0 - par[q, FL_ALPHA]) * par[q, FL_K]
    big = kh * par[q, FL_DY]
    low = (1.0 - par[q, FL_BETA]) * big
    h, d = state[q, ST_FLAG_H], state[q, ST_FLAG_DRIFT]
    tol = 1e-12 * big
    if abs(h - kh * d) <= tol:
        return False
    lo, hi = _bounds(kh, big, low, d)
    return h >= hi - tol or h <= lo + tol


@njit(cache=True)
def flag_move(par, q, d, h, delta):
    """The hysteretic force h [N] after flag storey q's drift moves monotonically from (d, h) to ``delta`` [m],
    the slope dh/d(delta) / K [-] it ends on (1 inside its bounds or on the origin's line, 0 on a branch), and
    whether that slope differs from the move's first (the force is then not linear in the drift along it).

    The end is :func:`flag_trial`'s return map (exact for a monotone move); the first slope is the branch's
    where h starts at the bound the move pushes it against (within 1e-12 H), else 1 (derived here)."""
    kh = (1.0 - par[q, FL_ALPHA]) * par[q, FL_K]
    big = kh * par[q, FL_DY]
    low = (1.0 - par[q, FL_BETA]) * big
    tol = 1e-12 * big
    lo, hi = _bounds(kh, big, low, d)
    up = delta > d
    first = 1.0
    if abs(h - kh * d) > tol and ((up and h >= hi - tol) or (not up and h <= lo + tol)):
        first = 0.0
    if (d > 0.0 and delta < 0.0) or (d < 0.0 and delta > 0.0):
        d, h = 0.0, 0.0  # through zero drift, where h is zero on every path
    h1 = h + kh * (delta - d)
    lo, hi = _bounds(kh, big, low, delta)
    slope = 1.0
    if h1 > hi:
        h1 = hi
        slope = 0.0 if hi != kh * delta else 1.0
    elif h1 < lo:
        h1 = lo
        slope = 0.0 if lo != kh * delta else 1.0
    return h1, slope, slope != first
