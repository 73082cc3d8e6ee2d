"""The Newmark step of the linear part: predictor with the contact forces frozen, and the corrector
that accepts a step (state, peaks and the energy balance).

Newmark 1959; Chopra, Dynamics of Structures, Sec. 5.4 and Table 5.7.2 (total form).
Energy in the relative frame (Uang & Bertero 1990) by the trapezoidal rule on
each force's work, which for average acceleration balances exactly.
"""

from __future__ import annotations

import numpy as np
from seispound._jit import njit

from ._linear import _internal, _internal_range, _solve, _solve_range


@njit(cache=True, inline="always")
def _accept_rows(rows, coef, mdm, grd, incr, st, umax, energy):
    """Accept a step of increment Du on DOFs lo..hi-1: state, peaks, energy; return (e_in, w_int).

    rows = (lo, hi); coef = (cm, cc); mdm = (mass, dof_motion); grd = (g0, g1); incr = (Du, R0, Av, Vv);
    st = (u, v, a, fint, ...); energy = (e_in, w_int) [J].

    Newmark (Chopra Table 5.7.2): a1 = cm Du + Av, v1 = cc Du + Vv.  The
    storey + damping forces at the step end follow from equilibrium without
    the contact terms (the caller adds those), and the input and internal
    work are the trapezoidal rule over the step (module docstring), with g0
    and g1 (nm,) the ground accelerations at its ends [m/s^2].
    """
    lo, hi = rows
    cm, cc = coef
    mass, dof_motion = mdm
    g0, g1 = grd
    Du, Av, Vv = incr[0], incr[2], incr[3]
    u, v, a, fint = st[0], st[1], st[2], st[3]
    e_in, w_int = energy
    for i in range(np.uint64(lo), np.uint64(hi)):  # unsigned subscripts (``_UNSIGNED``)
        du = Du[i]
        ai = Av[i] + cm * du
        gi1 = g1[dof_motion[i]]
        f1 = -mass[i] * (gi1 + ai)
        e_in -= 0.5 * mass[i] * (g0[dof_motion[i]] + gi1) * du
        w_int += 0.5 * (fint[i] + f1) * du
        fint[i] = f1
        u[i] += du
        v[i] = Vv[i] + cc * du
        a[i] = ai
        if abs(u[i]) > umax[i]:
            umax[i] = abs(u[i])
    return e_in, w_int


@njit(cache=True, inline="always")
def _linear_trial(rows, h, fac, nb, row, g1, st, incr):
    """Newmark predictor and linear increment of a step of size h [s] on DOFs lo..hi-1 (whole blocks).

    Newmark (Chopra Table 5.7.2, total form): a1 = cm Du + Av, v1 = cc Du + Vv with
    Av = -v / (beta h) - (1 / (2 beta) - 1) a and Vv = (1 - gamma / beta) v + h (1 - gamma / (2 beta)) a;
    one element loop gives K u and C Vv, hence the residual R0 at Du = 0, and
    Du = K_hat^-1 R0 is the step with every contact force zero.  rows = (lo, hi, elo, ehi): the DOFs and
    elements; fac = (Lf, p): K_hat(h) factored on these rows; nb = (beta, gamma); row as the kernel's;
    g1 (nm,): ground acceleration at the step end; st = (u, v, a, fint, fs, fd); incr = (Du, R0, Av, Vv).
    Returns sum (K u)_i u_i over the rows [J x 2] (twice the strain energy).
    """
    lo, hi, elo, ehi = rows
    Lf, p = fac
    beta, gamma = nb
    mass, dof_a0, dof_motion, el_i, el_j, el_k, el_a1 = row
    u, v, a, fs, fd = st[0], st[1], st[2], st[4], st[5]
    Du, R0, Av, Vv = incr
    for i in range(np.uint64(lo), np.uint64(hi)):
        Av[i] = -v[i] / (beta * h) - (0.5 / beta - 1.0) * a[i]
        Vv[i] = (1.0 - gamma / beta) * v[i] + h * (1.0 - 0.5 * gamma / beta) * a[i]
    _internal_range((mass, dof_a0, el_i, el_j, el_k, el_a1), u, Vv, fs, fd, rows)
    es = 0.0
    for i in range(np.uint64(lo), np.uint64(hi)):
        R0[i] = -mass[i] * (g1[dof_motion[i]] + Av[i]) - fd[i] - fs[i]
        es += fs[i] * u[i]
    _solve_range(Lf, p, R0, Du, lo, hi)
    return es


@njit(cache=True, inline="always")
def _newmark_predictor(rs, h, fac, nb, row, g1, st, incr):
    """The predictor of a trial step of size h on the stepping buildings' runs: :func:`_linear_trial` on each.

    When the whole row steps (single-rate, or nobody waits) the same loops run
    over 0..n-1, which LLVM optimises better than the range version (measured
    11-13 % per attempt).  rs = (stepping runs, runs); the rest as :func:`_linear_trial`'s.  Returns
    sum (K u)_i u_i over the rows stepped.  (Inlined at numba IR level, as the driver's other hot parts.)
    """
    n_run, runs = rs
    r_lo, r_hi, r_elo, r_ehi = runs[0], runs[1], runs[2], runs[3]
    Lf, p = fac
    beta, gamma = nb
    mass, dof_a0, dof_motion, el_i, el_j, el_k, el_a1 = row
    u, v, a, fs, fd = st[0], st[1], st[2], st[4], st[5]
    Du, R0, Av, Vv = incr
    n = mass.size
    es = 0.0
    if n_run == 1 and r_hi[0] - r_lo[0] == n:
        for i in range(n):
            Av[i] = -v[i] / (beta * h) - (0.5 / beta - 1.0) * a[i]
            Vv[i] = (1.0 - gamma / beta) * v[i] + h * (1.0 - 0.5 * gamma / beta) * a[i]
        _internal(mass, dof_a0, el_i, el_j, el_k, el_a1, u, Vv, fs, fd)
        for i in range(n):
            R0[i] = -mass[i] * (g1[dof_motion[i]] + Av[i]) - fd[i] - fs[i]
            es += fs[i] * u[i]
        _solve(Lf, p, R0, Du)
        return es
    for rr in range(n_run):
        es += _linear_trial((r_lo[rr], r_hi[rr], r_elo[rr], r_ehi[rr]), h, fac, nb, row, g1, st, incr)
    return es
