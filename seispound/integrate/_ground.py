"""The ground motion between its samples: piecewise linear in time (the record's own interpolation)."""

from __future__ import annotations

import math

from seispound._jit import njit


@njit(cache=True)
def _ground(ag, row, t, dt):
    """Ground acceleration of motion ``row`` at time t [m/s^2], linear between samples."""
    nt = ag.shape[1]
    x = t / dt
    k = int(math.floor(x))
    if k >= nt - 1:
        return ag[row, nt - 1]
    if k < 0:
        return ag[row, 0]
    f = x - k
    return (1.0 - f) * ag[row, k] + f * ag[row, k + 1]


@njit(cache=True, inline="always")
def _ground_all(ag, t, dt, out):
    """Ground acceleration of every motion row at time t into ``out`` (nm,)."""
    for r in range(out.size):
        out[r] = _ground(ag, r, t, dt)


# rows of the kernel's per-gap ground state ``gk`` (4, ng)
GU0, GV0, GU1, GV1 = 0, 1, 2, 3


@njit(cache=True)
def _gap_ground(gap_ground, g, t, dt):
    """Differential ground displacement [m] and velocity [m/s] of gap g at time t: (u_g,i - u_g,j, v_g,i - v_g,j).

    The ground under each side moves with its own record; between samples the
    acceleration is linear (as everywhere in the kernel), so the velocity is
    quadratic and the displacement cubic in tau = t - k dt:
    u = u_k + v_k tau + a_k tau^2 / 2 + (a_k+1 - a_k) tau^3 / (6 dt).
    ``gap_ground`` (3, ng, nt) holds the differences of acceleration, velocity
    and displacement at the samples (:func:`seispound.integrate.newmark.gap_ground_motion`).
    """
    nt = gap_ground.shape[2]
    k = min(max(int(math.floor(t / dt)), 0), nt - 2)
    tau = t - k * dt
    a0 = gap_ground[0, g, k]
    da = (gap_ground[0, g, k + 1] - a0) / dt
    v0 = gap_ground[1, g, k]
    gv = v0 + a0 * tau + 0.5 * da * tau * tau
    gu = gap_ground[2, g, k] + v0 * tau + 0.5 * a0 * tau * tau + da * tau * tau * tau / 6.0
    return gu, gv


@njit(cache=True)
def _gap_ground_all(gap_ground, t, dt, gk, row):
    """:func:`_gap_ground` of every gap at time t into gk[row] (displacement) and gk[row + 1] (velocity).

    (A call of its own: the same loop written in the driver made the whole
    driver 7 % slower in same-process A/B runs, even where it never ran.)
    """
    for g in range(gk.shape[1]):
        gk[row, g], gk[row + 1, g] = _gap_ground(gap_ground, g, t, dt)


@njit(cache=True)
def _gap_ground_accept(gk):
    """The trial step's end becomes the current state: gk[GU0:GV0 + 1] = gk[GU1:GV1 + 1]."""
    for g in range(gk.shape[1]):
        gk[GU0, g] = gk[GU1, g]
        gk[GV0, g] = gk[GV1, g]


@njit(cache=True, inline="always")
def _gap_ground_at(moving, gap_ground, g, k):
    """The differential ground motion of gap g at sample k (an analysis step's end); (0, 0) if not ``moving``."""
    if not moving:
        return 0.0, 0.0
    return gap_ground[2, g, k], gap_ground[1, g, k]


@njit(cache=True, inline="always")
def _tick(t, h, clock, grd, gk, moving):
    """After an accepted step of h [s] from t: the ground accelerations at its end (grd = (g_t, g_1), per motion
    row) and each gap's ground terms (gk, when ``moving``) become its start's, and the clock moves on, to t_end
    exactly where it lands within round-off of it (no drift across analysis steps; clock = (t_end, dt)).
    Returns the new t [s]."""
    t_end, dt = clock
    g_t, g_1 = grd
    t = t + h
    if abs(t - t_end) <= 1e-9 * dt:
        t = t_end
    for r in range(g_t.size):
        g_t[r] = g_1[r]
    if moving:
        _gap_ground_accept(gk)
    return t
