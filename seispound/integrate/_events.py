"""Event location: where, inside a step, an open gap touches or a closed one separates.

The penetration over a step is the cubic Hermite interpolant of its values and
rates at both ends; its first root (a touch or a separation, grazing
excursions included) is the event.  A located step ends on its event when
|delta| <= LAND_TOL x the step's travel.
"""

from __future__ import annotations

import math

import numpy as np
from seispound._jit import njit

from ..contact.codes import NONE
from ._elements import _gap_trial
from ._ground import GU1, GV1

# A located step ends on its event when |delta| <= LAND_TOL x the step's travel.
LAND_TOL = 1e-7
# how an attempt at a step ends (each driver's ``_screen_attempt``): redone up to its first event, accepted,
# its events switched in place at its start, a waiting building joins (fast driver), or no step can be taken
REDO, ACCEPT, AT_ONCE, JOIN, FAILED = 0, 1, 2, 3, 4


@njit(cache=True)
def _hermite(s, d0, r0, d1, r1, h):
    """Cubic Hermite interpolant of delta at fraction s of a step of size h."""
    s2 = s * s
    s3 = s2 * s
    return ((2 * s3 - 3 * s2 + 1) * d0 + (s3 - 2 * s2 + s) * h * r0
            + (-2 * s3 + 3 * s2) * d1 + (s3 - s2) * h * r1)


@njit(cache=True, inline="always")  # inlined: per gap and step; as a call it cost the fast driver 9-13 %
def _event_in_step(d0, r0, d1, r1, h, closing, tol):
    """Fraction in (0, 1] of a gap's first event inside a step, or 2.0 if none.

    ``closing`` (an open gap): delta rising above +tol, a touch even if it
    reopens within the step; else (a closed gap) delta falling below -tol, a
    separation even if it closes again within the step.  The cubic Hermite
    interpolant of delta is bounded by max(d0, d1) + (4/27) h (max(r0, 0) +
    max(-r1, 0)) from above and by min(d0, d1) - (4/27) h (max(-r0, 0) +
    max(r1, 0)) from below (its basis functions h10 and -h11 lie in [0, 4/27]),
    so only a gap whose bound reaches the threshold needs the crossing search.
    """
    if closing:
        if max(d0, d1) + (4.0 / 27.0) * h * (max(r0, 0.0) + max(-r1, 0.0)) <= tol:
            return 2.0
    elif min(d0, d1) - (4.0 / 27.0) * h * (max(-r0, 0.0) + max(r1, 0.0)) >= -tol:
        return 2.0
    return _first_crossing(d0, r0, d1, r1, h, closing, tol)


@njit(cache=True)
def _first_crossing(d0, r0, d1, r1, h, closing, tol):
    """Fraction in (0, 1] of the first crossing of delta = 0 inside a step, or 2.0 if none.

    ``closing``: look for delta rising above +tol (onset); else falling below -tol (end).
    """
    sgn = 1.0 if closing else -1.0
    # interior extremum of the cubic (a grazing touch can hide between samples)
    ca = h * (r1 + r0) - 2.0 * (d1 - d0)
    cb = (d1 - d0 - h * r0) - ca
    cc = h * r0
    s_ext = 2.0
    if ca != 0.0:
        disc = 4.0 * cb * cb - 12.0 * ca * cc
        if disc >= 0.0:
            sq = math.sqrt(disc)
            for root in ((-2.0 * cb - sq) / (6.0 * ca), (-2.0 * cb + sq) / (6.0 * ca)):
                if 0.0 < root < 1.0 and sgn * _hermite(root, d0, r0, d1, r1, h) > tol and root < s_ext:
                    s_ext = root
    elif cb != 0.0:
        root = -cc / (2.0 * cb)
        if 0.0 < root < 1.0 and sgn * _hermite(root, d0, r0, d1, r1, h) > tol:
            s_ext = root
    if s_ext > 1.0 and sgn * d1 <= tol and sgn * d0 <= tol:
        return 2.0  # below tol at both ends and at every interior extremum: no crossing
    nsamp = 16
    prev = 0.0
    for k in range(1, nsamp + 1):
        s = k / nsamp
        val = sgn * _hermite(s, d0, r0, d1, r1, h)
        if s_ext < s and s_ext > prev:
            s = s_ext
            val = sgn * _hermite(s, d0, r0, d1, r1, h)
        if val > tol:
            return _crossing_in(prev, s, val, d0, r0, d1, r1, h, sgn)
        prev = s
    return 2.0


@njit(cache=True)
def _crossing_in(lo, hi, f_hi, d0, r0, d1, r1, h, sgn):
    """The fraction at which sgn * delta first exceeds 0 in [lo, hi], where it ends above 0 (f_hi).

    Safeguarded Newton on the cubic Hermite interpolant (Press et al., Numerical
    Recipes, 3rd ed., Sec. 9.4, ``rtsafe``): the bracket [lo, hi] keeps
    sgn * delta <= 0 at lo and > 0 at hi; a Newton step that leaves it, or
    does not halve it, is replaced by bisection; near the root each step is
    pushed at least a few ulps past it so the bracket closes from both sides.
    Returns hi once the bracket is a few ulps wide: the value 60 bisections
    reach (to round-off) in about 5 evaluations instead of 60.  When delta is
    already above 0 at lo there is no bracket, and plain bisection runs.
    """
    f_lo = sgn * _hermite(lo, d0, r0, d1, r1, h)
    if f_lo > 0.0:
        # above 0 (below tol) already at lo, so no bracket: plain bisection, which
        # lands on lo or on a later up-crossing, as the search always has
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            if sgn * _hermite(mid, d0, r0, d1, r1, h) > 0.0:
                hi = mid
            else:
                lo = mid
        return hi
    # start from the secant, a good guess on a short, nearly linear piece
    x = lo + (hi - lo) * (-f_lo / (f_hi - f_lo))
    width_old = hi - lo
    for _ in range(100):
        eps = 4.4e-16 * hi + 1e-300
        if hi - lo <= 2.0 * eps:
            break
        if not lo < x < hi:
            x = 0.5 * (lo + hi)
        f = sgn * _hermite(x, d0, r0, d1, r1, h)
        if f > 0.0:
            hi = x
        else:
            lo = x
        s2 = x * x  # d delta / ds of the cubic
        df = sgn * ((6 * s2 - 6 * x) * (d0 - d1) + (3 * s2 - 4 * x + 1) * h * r0 + (3 * s2 - 2 * x) * h * r1)
        width = hi - lo
        step = f / df if df != 0.0 else 2.0 * width
        if abs(step) < eps:  # overshoot by a few ulps so the far side of the bracket moves too
            step = eps if step > 0.0 else -eps
        if abs(step) > 0.5 * width_old or not lo < x - step < hi:
            x = 0.5 * (lo + hi)  # Newton would leave the bracket or crawl: bisect
        else:
            x = x - step
        width_old = width
    return hi


@njit(cache=True, inline="always")
def _gap_event(d0, r0, d1, r1, h, closed, landed):
    """One gap's event in a trial step of length h [s]: (theta, lands) (theta 2: none).

    d0, r0 and d1, r1: its penetration [m] and rate [m/s] at the step's start and end; an open
    gap may touch, a closed one separate, even within the step (``_event_in_step``).  After a
    step that ``landed`` on another gap's event, ``lands`` says that this gap is at its own
    crossing as well within the landing tolerance (identical floors): it switches with that
    gap, not one attempt later.  Both drivers' screens call it.
    """
    tol = LAND_TOL * max(abs(r0), abs(r1)) * h + 1e-15
    th = _event_in_step(d0, r0, d1, r1, h, not closed, tol)
    lands = landed and ((d1 >= -tol and r1 > 0.0 and not closed) or (d1 <= tol and r1 < 0.0 and closed))
    return th, lands


@njit(cache=True, inline="always")
def _screen_step(waiting, screened, gaps, active, trial, h, gk, states, aim, land_too):
    """The event screen of a trial step of length h: the first event of any gap; (theta, gap, waits, n_land).

    Every gap, or while some building waits the gaps listed in ``scr`` (those
    with a stepping side; ``scr[n_ss:n_scr]`` have a waiting side whose end
    state is already in d_end, r_end).  The end states go to d_end, r_end.
    theta: the earliest event's fraction of the step (2 if none), its gap, and
    whether that gap has a waiting side.  When the step ``landed`` on the event
    of gap ``target``, gaps at their own crossing within the landing tolerance
    are listed in ``land_too`` (n_land of them): they switch together.
    screened = (scr, n_ss, n_scr); gaps as the kernel's; trial = (u, Du, Vv, cc); states = (d0, r0,
    d_end, r_end); aim = (landed, target).
    (Inlined at numba IR level: as a called function it cost 17 % per run.)
    """
    scr, n_ss, n_scr = screened
    gap_i, gap_j, gap_size, gap_law = gaps[0], gaps[1], gaps[4], gaps[5]
    u, Du, Vv, cc = trial
    d0, r0, d_end, r_end = states
    landed, target = aim
    theta = 2.0
    g_ev = -1
    ev_waits = False
    n_land = 0
    for qq in range(n_scr if waiting else gap_size.size):
        g = scr[qq] if waiting else qq
        waits = waiting and qq >= n_ss
        if waits:
            d1 = d_end[g]
            r1 = r_end[g]
        else:
            ii = np.uint64(gap_i[g])  # unsigned subscripts (``_UNSIGNED`` in _linear.py)
            jj = np.uint64(gap_j[g])
            d1, r1 = _gap_trial(u, Du, Vv, cc, ii, jj, gap_size[g], gk[GU1, g], gk[GV1, g])
        d_end[g] = d1
        r_end[g] = r1
        if gap_law[g] == NONE or (landed and g == target):
            continue
        th, lands = _gap_event(d0[g], r0[g], d1, r1, h, active[g], landed and not waits)
        if lands:
            land_too[n_land] = g
            n_land += 1
        if th < theta:
            theta = th
            g_ev = g
            ev_waits = waits
    return theta, g_ev, ev_waits, n_land


@njit(cache=True, inline="always")
def _landed(target, n_land, land_too, toggles):
    """The gaps a step that landed on target's event switches: target and the n_land gaps at their own crossing
    within the landing tolerance (land_too, from the screen).  Fills toggles; returns their number."""
    toggles[0] = target
    n_tog = 1
    for k in range(n_land):
        toggles[n_tog] = land_too[k]
        n_tog += 1
    return n_tog


@njit(cache=True, inline="always")
def _screen_elements(ne_gap, active, d0, r0, d1, r1, h, landed, target, land_too):
    """The first event of any gap in a trial step: (theta, gap, n_land) (theta 2: none).

    An open gap may touch, a closed one separate, even within the step
    (``_events._event_in_step``).  When the step ``landed`` on the event of
    ``target``, the gaps at their own crossing within the landing tolerance
    are listed in land_too: they switch together.
    """
    theta = 2.0
    g_ev = -1
    n_land = 0
    for q in range(ne_gap.size):
        if not ne_gap[q] or (landed and q == target):
            continue
        th, lands = _gap_event(d0[q], r0[q], d1[q], r1[q], h, active[q], landed)
        if lands:
            land_too[n_land] = q
            n_land += 1
        if th < theta:
            theta = th
            g_ev = q
    return theta, g_ev, n_land
