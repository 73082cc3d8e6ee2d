"""Multi-rate stepping: buildings that wait take a whole analysis step at once while the others take
contact substeps; their trajectory inside the step, the runs of stepping buildings and the gaps screened.
"""

from __future__ import annotations

import numpy as np
from seispound._jit import njit

from ._elements import _gap_kinematics
from ._newmark_step import _linear_trial

# Buildings wait (multi-rate stepping) by default only when they hold at least this share
# of the row's DOFs: waiting costs a step, a commit and a screen of the waiting
# buildings per analysis step plus a catch-up step per join, and the
# stepping buildings' loops run over ranges.  Measured in same-process A/B
# runs: waiting a third of the row (canonical row of three) made the run
# 20 % slower, waiting most of it (16 pairs, one or two pounding) 1.8 times faster.
WAIT_SHARE = 0.5


@njit(cache=True)
def _waiting_state(i, s, dt, u, v, u_w1, v_w1):
    """Displacement [m] and velocity [m/s] of waiting DOF i at fraction s of its analysis step dt.

    The cubic Hermite interpolant of the step from (u, v) to (u_w1, v_w1), and
    its derivative.  For the average-acceleration method it is the step's own
    trajectory: the acceleration is (a0 + a1) / 2 throughout the step, so u is
    the quadratic through both ends with both end slopes (Chopra, Dynamics of
    Structures, Sec. 5.4.1), which the Hermite cubic reproduces exactly.
    """
    s2 = s * s
    s3 = s2 * s
    x = ((2 * s3 - 3 * s2 + 1) * u[i] + (s3 - 2 * s2 + s) * dt * v[i]
         + (-2 * s3 + 3 * s2) * u_w1[i] + (s3 - s2) * dt * v_w1[i])
    xd = ((6 * s2 - 6 * s) * (u[i] - u_w1[i]) / dt + (3 * s2 - 4 * s + 1) * v[i]
          + (3 * s2 - 2 * s) * v_w1[i])
    return x, xd


@njit(cache=True, inline="always")
def _waiting_trial(lo, hi, elo, ehi, h, Lf, p, beta, gamma, mass, dof_a0, dof_motion, el_i, el_j, el_k, el_a1,
                   g1, u, v, a, Av, Vv, fs, fd, R0, du_w, u_w1, v_w1, a_w1):
    """A linear Newmark step of size h [s] for the blocks on DOFs lo..hi-1, none of whose gaps is closed.

    Same recurrence as the kernel's step with every contact force zero; the
    increment and end state go to du_w, u_w1, v_w1, a_w1 (u, v, a stay: the
    step is committed by ``_waiting_commit``).  Lf: K_hat(h) factored on these
    rows; g1 (nm,): ground acceleration at the step end [m/s^2].
    """
    cm = 1.0 / (beta * h * h)
    cc = gamma / (beta * h)
    _linear_trial(lo, hi, elo, ehi, h, Lf, p, beta, gamma, mass, dof_a0, dof_motion, el_i, el_j, el_k, el_a1,
                  g1, u, v, a, Av, Vv, fs, fd, R0, du_w)
    for i in range(np.uint64(lo), np.uint64(hi)):
        u_w1[i] = u[i] + du_w[i]
        v_w1[i] = Vv[i] + cc * du_w[i]
        a_w1[i] = Av[i] + cm * du_w[i]


@njit(cache=True, inline="always")
def _waiting_commit(lo, hi, mass, dof_motion, g0, g1, du_w, v_w1, a_w1, u, v, a, fint, umax, e_in, w_int):
    """Accept a waiting step on DOFs lo..hi-1 (``_waiting_trial``): state, peaks, energy; return (e_in, w_int).

    The energy terms are the kernel's trapezoidal work over the step, with g0
    and g1 (nm,) the ground accelerations at its ends [m/s^2].
    """
    for i in range(np.uint64(lo), np.uint64(hi)):
        du = du_w[i]
        ai = a_w1[i]
        gi1 = g1[dof_motion[i]]
        f1 = -mass[i] * (gi1 + ai)  # no gap closed: equilibrium gives the storey + damping forces
        e_in -= 0.5 * mass[i] * (g0[dof_motion[i]] + gi1) * du
        w_int += 0.5 * (fint[i] + f1) * du
        fint[i] = f1
        u[i] += du
        v[i] = v_w1[i]
        a[i] = ai
        if abs(u[i]) > umax[i]:
            umax[i] = abs(u[i])
    return e_in, w_int


@njit(cache=True)
def _gap_state(g, s, dt, in_s, dof_blk, gap_i, gap_j, gap_size, u, v, u_w1, v_w1, Du, Vv, cc, gu, gv):
    """Penetration [m] and its rate [m/s] of gap g when some building waits.

    A stepping side is at u + Du with velocity Vv + cc Du (the trial step's
    end; Du = 0, Vv = v, cc = 0 for the current state), a waiting side at
    fraction s of its own step (``_waiting_state``); gu, gv: the gap's differential ground motion then.
    """
    ii = gap_i[g]
    jj = gap_j[g]
    if in_s[dof_blk[ii]]:
        xi = u[ii] + Du[ii]
        vi = Vv[ii] + cc * Du[ii]
    else:
        xi, vi = _waiting_state(ii, s, dt, u, v, u_w1, v_w1)
    if in_s[dof_blk[jj]]:
        xj = u[jj] + Du[jj]
        vj = Vv[jj] + cc * Du[jj]
    else:
        xj, vj = _waiting_state(jj, s, dt, u, v, u_w1, v_w1)
    return _gap_kinematics(xi, 0.0, xj, 0.0, vi, 0.0, vj, 0.0, gap_size[g], gu, gv)


@njit(cache=True)
def _runs(in_s, want, blk_dof, blk_el, r_lo, r_hi, r_elo, r_ehi):
    """DOF and element ranges of the maximal runs of consecutive buildings b with in_s[b] == want; their number."""
    nr = 0
    b = 0
    nb = in_s.size
    while b < nb:
        if in_s[b] != want:
            b += 1
            continue
        b0 = b
        while b < nb and in_s[b] == want:
            b += 1
        r_lo[nr] = blk_dof[b0]
        r_hi[nr] = blk_dof[b]
        r_elo[nr] = blk_el[b0]
        r_ehi[nr] = blk_el[b]
        nr += 1
    return nr


@njit(cache=True)
def _screen_list(in_s, gb_lo, gb_hi, scr):
    """The gaps that link at least one stepping building (in_s) into scr; return (n_ss, n_scr).

    scr[:n_ss] link stepping buildings only, scr[n_ss:n_scr] a stepping and a
    waiting one (screened against the waiting step's trajectory).
    """
    n_scr = 0
    n_ss = 0
    for both in (True, False):
        for g in range(gb_lo.size):
            n_in = 0
            for b in range(gb_lo[g], gb_hi[g]):
                if in_s[b]:
                    n_in += 1
            if (n_in == gb_hi[g] - gb_lo[g]) if both else (0 < n_in < gb_hi[g] - gb_lo[g]):
                scr[n_scr] = g
                n_scr += 1
        if both:
            n_ss = n_scr
    return n_ss, n_scr
