"""The event test of every step: a touch of an open gap and a separation of a closed one,
even when the gap closes again (or reopens) before the step ends.

The kernel interpolates delta over a step by the cubic Hermite of its end values
and rates; ``_event_in_step`` screens with a rigorous bound and then finds the
first crossing.  Checked against the cubic sampled densely.
"""

import numpy as np
import pytest

from seispound.integrate._events import LAND_TOL, _event_in_step


def cubic(d0, r0, d1, r1, h, s):
    s = np.asarray(s)
    return ((2 * s**3 - 3 * s**2 + 1) * d0 + (s**3 - 2 * s**2 + s) * h * r0
            + (-2 * s**3 + 3 * s**2) * d1 + (s**3 - s**2) * h * r1)


def tol_of(r0, r1, h):
    return LAND_TOL * max(abs(r0), abs(r1)) * h + 1e-15


@pytest.mark.parametrize("closing", [False, True])
def test_an_excursion_inside_one_step_is_found(closing):
    """Both ends on the same side, the middle across: delta(1/2) = d - h (|r0| + |r1|) / 8 < 0.

    A closed gap that separates for part of a step and closes again (closing=False),
    or an open gap that touches and reopens (closing=True).
    """
    sgn = 1.0 if not closing else -1.0  # closed: delta > 0 at both ends; open: < 0
    d0 = d1 = sgn * 1e-6
    r0, r1, h = -sgn * 0.02, sgn * 0.02, 1e-3
    mid = cubic(d0, r0, d1, r1, h, 0.5)
    assert sgn * mid < 0  # the excursion: -4e-6 m for the closed gap
    th = _event_in_step(d0, r0, d1, r1, h, closing, tol_of(r0, r1, h))
    assert 0.0 < th < 0.5
    assert abs(cubic(d0, r0, d1, r1, h, th)) <= 1e-9 * 1e-6 + 1e-15  # on the crossing
    s = np.linspace(0.0, th, 200, endpoint=False)
    assert np.all(sgn * cubic(d0, r0, d1, r1, h, s) > 0)  # and the first one


def test_the_screen_never_misses_an_event_and_finds_the_first_crossing():
    """Random steps: wherever the sampled cubic clearly crosses the threshold the screen
    reports an event at its first crossing; where it clearly stays on its side, none."""
    rng = np.random.default_rng(7)
    s = np.linspace(0.0, 1.0, 4001)
    found = clear = 0
    for _ in range(4000):
        closing = bool(rng.integers(2))
        sgn = 1.0 if closing else -1.0  # the side an event crosses to
        h = 10 ** rng.uniform(-4, -2)
        d0 = -sgn * rng.uniform(0.0, 1e-4)  # on the current side at the start
        d1 = rng.uniform(-1e-4, 1e-4)
        r0, r1 = rng.uniform(-0.2, 0.2, size=2)
        tol = tol_of(r0, r1, h)
        vals = sgn * cubic(d0, r0, d1, r1, h, s)
        th = _event_in_step(d0, r0, d1, r1, h, closing, tol)
        if vals.max() > 2 * tol + 1e-12:
            found += 1
            assert th < 2.0
            first = s[np.argmax(vals > tol)]  # first sample past the threshold
            assert th <= first + 1e-9
            assert sgn * cubic(d0, r0, d1, r1, h, th) >= -1e-12  # at or past the crossing
        elif vals.max() < 0.5 * tol:
            clear += 1
            assert th == 2.0
    assert found > 1000 and clear > 1000


def _bisect(lo, hi, d0, r0, d1, r1, h, sgn, iters=200):
    """The reference: plain bisection to the last representable bracket, on the kernel's
    own evaluation of the cubic (the sign of delta next to the root is round-off)."""
    from seispound.integrate._events import _hermite

    for _ in range(iters):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        if sgn * _hermite(mid, d0, r0, d1, r1, h) > 0.0:
            hi = mid
        else:
            lo = mid
    return hi


def test_the_crossing_refinement_lands_where_bisection_does():
    """``_crossing_in`` (safeguarded Newton) against bisection run to round-off on the
    same bracket: the same crossing to a few ulps, on brackets of every width and
    position inside the step, with gentle and with steep cubics."""
    from seispound.integrate._events import _crossing_in, _hermite

    rng = np.random.default_rng(11)
    checked = 0
    worst = 0.0
    for _ in range(40000):
        closing = bool(rng.integers(2))
        sgn = 1.0 if closing else -1.0
        h = 10 ** rng.uniform(-5, -2)
        d0, d1 = rng.normal(size=2) * 10 ** rng.uniform(-7, -3)
        r0, r1 = rng.normal(size=2) * 10 ** rng.uniform(-3, 0.5)
        lo, hi = np.sort(rng.uniform(0.0, 1.0, size=2))
        f_lo = sgn * _hermite(lo, d0, r0, d1, r1, h)
        f_hi = sgn * _hermite(hi, d0, r0, d1, r1, h)
        if not (f_lo <= 0.0 < f_hi):
            continue  # not a bracket: the sampler hands _crossing_in brackets only
        got = _crossing_in(lo, hi, f_hi, d0, r0, d1, r1, h, sgn)
        assert lo < got <= hi
        assert sgn * _hermite(got, d0, r0, d1, r1, h) > 0.0  # past the crossing, as bisection's hi
        ref = _bisect(lo, hi, d0, r0, d1, r1, h, sgn)
        # the same crossing (a bracket may hold three; then either is an up-crossing)
        if np.sum(np.diff(np.sign(sgn * cubic(d0, r0, d1, r1, h, np.linspace(lo, hi, 2001)))) != 0) == 1:
            worst = max(worst, abs(got - ref) / ref)
            checked += 1
    assert checked > 3000
    assert worst <= 8 * np.finfo(float).eps, worst


def test_the_crossing_refinement_keeps_the_old_answer_without_a_bracket():
    """delta already above 0 (but below tol) at the bracket's start: plain bisection, as before."""
    from seispound.integrate._events import _crossing_in, _hermite

    d0, r0, d1, r1, h = 2.08e-7, -0.0995, 0.00019, -1.16, 0.00146  # dips below 0, then rises past it
    lo, hi = 0.0, 1.0 / 16.0
    f_hi = _hermite(hi, d0, r0, d1, r1, h)
    assert _hermite(lo, d0, r0, d1, r1, h) > 0.0 and f_hi > 0.0
    got = _crossing_in(lo, hi, f_hi, d0, r0, d1, r1, h, 1.0)
    ref = lo
    hi_ = hi
    for _ in range(60):
        mid = 0.5 * (ref + hi_)
        if _hermite(mid, d0, r0, d1, r1, h) > 0.0:
            hi_ = mid
        else:
            ref = mid
    assert got == hi_
