"""The ground motion between its samples: piecewise linear in time (the record's own interpolation)."""

from __future__ import annotations

import math

from numba import njit


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
