"""A bare linear Newmark-beta loop: the floor of what a time loop of this size can cost.

Used only by ``python -m benchmarks.canonical`` as the in-process reference.  Same
factor (L D L^T when tridiagonal) and solve as the kernel, no contact, no energy, no events:
incremental average-acceleration Newmark (Chopra Table 5.4.2) on the assembled system.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from seispound.integrate._linear import _factor, _internal, _solve


@njit(cache=True)
def bare_newmark(mass, dof_a0, el_i, el_j, el_k, el_a1, p, ag, dt, nsteps, beta, gamma, out_u):
    """Linear Newmark from rest under ground acceleration ag (nt,); displacements into out_u (nt, n)."""
    n = mass.size
    L = np.empty((n, p + 2))
    _factor(dt, beta, gamma, mass, dof_a0, el_i, el_j, el_k, el_a1, p, L)
    u = np.zeros(n)
    v = np.zeros(n)
    a = np.zeros(n)
    Av = np.empty(n)
    Vv = np.empty(n)
    fs = np.empty(n)
    fd = np.empty(n)
    R = np.empty(n)
    z = np.empty(n)
    cm = 1.0 / (beta * dt * dt)
    cc = gamma / (beta * dt)
    for i in range(n):
        a[i] = -ag[0]
        out_u[0, i] = 0.0
    for k in range(nsteps):
        for i in range(n):
            Av[i] = -v[i] / (beta * dt) - (0.5 / beta - 1.0) * a[i]
            Vv[i] = (1.0 - gamma / beta) * v[i] + dt * (1.0 - 0.5 * gamma / beta) * a[i]
        _internal(mass, dof_a0, el_i, el_j, el_k, el_a1, u, Vv, fs, fd)
        for i in range(n):
            R[i] = -mass[i] * (ag[k + 1] + Av[i]) - fd[i] - fs[i]
        _solve(L, p, R, z)
        for i in range(n):
            u[i] += z[i]
            v[i] = Vv[i] + cc * z[i]
            a[i] = Av[i] + cm * z[i]
            out_u[k + 1, i] = u[i]
    return u
