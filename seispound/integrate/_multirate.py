"""Multi-rate stepping: buildings that wait take a whole analysis step at once while the others take
contact substeps; their trajectory inside the step, the runs of stepping buildings and the gaps screened.
"""

from __future__ import annotations

import numpy as np
from seispound._jit import njit

from ..contact.codes import NONE
from ._elements import _gap_deformation, _gap_kinematics
from ._events import LAND_TOL, _event_in_step
from ._exact import exact_coefficients
from ._free_flight import _exact_waiting
from ._ground import _gap_ground_at
from ._linear import _factor_range
from ._newmark_step import _linear_trial
from ._outputs import S_DOF_STEPS, S_FACTORIZATIONS, S_JOINS

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
def _waiting_trial(rows, h, fac, nb, row, g1, st, scratch, wend):
    """A linear Newmark step of size h [s] for the blocks on DOFs lo..hi-1, none of whose gaps is closed.

    Same recurrence as the kernel's step with every contact force zero; the
    increment and end state go to du_w, u_w1, v_w1, a_w1 (u, v, a stay: the
    step is committed by ``_waiting_commit``).  rows = (lo, hi, elo, ehi); fac = (Lf, p): K_hat(h) factored
    on these rows; nb = (beta, gamma); g1 (nm,): ground acceleration at the step end [m/s^2]; st the
    kernel's state; scratch = (Av, Vv, R0); wend = (du_w, u_w1, v_w1, a_w1).
    """
    beta, gamma = nb
    lo, hi = rows[0], rows[1]
    Av, Vv, R0 = scratch
    du_w, u_w1, v_w1, a_w1 = wend
    u = st[0]
    cm = 1.0 / (beta * h * h)
    cc = gamma / (beta * h)
    _linear_trial(rows, h, fac, nb, row, g1, st, (du_w, R0, Av, Vv))
    for i in range(np.uint64(lo), np.uint64(hi)):
        u_w1[i] = u[i] + du_w[i]
        v_w1[i] = Vv[i] + cc * du_w[i]
        a_w1[i] = Av[i] + cm * du_w[i]


@njit(cache=True, inline="always")
def _waiting_commit(rows, mdm, grd, wend, st, umax, energy):
    """Accept a waiting step on DOFs lo..hi-1 (``_waiting_trial``): state, peaks, energy; return (e_in, w_int).

    The energy terms are the kernel's trapezoidal work over the step, with grd = (g0, g1) (nm,) the ground
    accelerations at its ends [m/s^2].  rows = (lo, hi); mdm = (mass, dof_motion); wend = (du_w, u_w1, v_w1,
    a_w1); st = (u, v, a, fint, ...); energy = (e_in, w_int) [J].
    """
    lo, hi = rows
    mass, dof_motion = mdm
    g0, g1 = grd
    du_w, v_w1, a_w1 = wend[0], wend[2], wend[3]
    u, v, a, fint = st[0], st[1], st[2], st[3]
    e_in, w_int = energy
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
def _gap_state(g, clock, blk, gaps, states, trial, gnd):
    """Penetration [m] and its rate [m/s] of gap g when some building waits.

    A stepping side is at u + Du with velocity Vv + cc Du (the trial step's
    end; Du = 0, Vv = v, cc = 0 for the current state), a waiting side at
    fraction s of its own step (``_waiting_state``).  clock = (s, dt [s]); blk = (in_s, dof_blk); gaps as
    the kernel's; states = (u, v, u_w1, v_w1); trial = (Du, Vv, cc); gnd = (gu, gv): the gap's differential
    ground motion then.
    """
    s, dt = clock
    in_s, dof_blk = blk
    gap_i, gap_j, gap_size = gaps[0], gaps[1], gaps[4]
    u, v, u_w1, v_w1 = states
    Du, Vv, cc = trial
    gu, gv = gnd
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


# The phases of multi-rate stepping in the fast driver (``_driver.integrate_kernel``).  Their tuples:
# mr = (blk_dof, blk_el, dof_blk, gb_lo, gb_hi, in_s, was_s, scr): each building's first DOF and element
# (nb + 1,), each DOF's building (n,), the buildings each gap links (ng,), who steps now and before (nb,)
# bool, the gaps screened (``_screen_list``); runs = (r_lo, r_hi, r_elo, r_ehi, w_lo, w_hi, w_elo, w_ehi):
# the stepping and the waiting buildings' DOF and element runs (``_runs``); ws = (g_w0, g_w1, du_w, u_w1,
# v_w1, a_w1, L_w, zero_n): the waiting step (ground accelerations at its ends (nm,) [m/s^2], increment
# and end state (n,), the factor of a catch-up step, zeros); waits = (exact, ex_co, ex_h, h_ex, md, mqs,
# L0, p, beta, gamma, scratch): how a waiting building steps (exact modal steps with the coefficients
# ex_co for dt and ex_h for the last other size h_ex[0], md the modal basis, mqs its coordinates; else
# Newmark with the level-0 factor L0 of half bandwidth p; scratch = (Av, Vv, R0) (n,) work arrays).


@njit(cache=True, inline="always")
def _who_steps(m_act, act_list, multirate, wait_share, mr, runs):
    """Which buildings take this analysis step's substeps: with multi-rate stepping and some gap closed,
    the buildings of the closed gaps' groups, provided the others hold at least ``wait_share`` of the
    DOFs; every building otherwise.  Sets in_s (was_s keeps the last), fills the waiting runs and returns
    their number."""
    blk_dof, blk_el, gb_lo, gb_hi, in_s, was_s = mr[0], mr[1], mr[3], mr[4], mr[5], mr[6]
    w_lo, w_hi, w_elo, w_ehi = runs[4], runs[5], runs[6], runs[7]
    nbk = blk_dof.size - 1
    some = multirate and m_act > 0
    for b in range(nbk):
        was_s[b] = in_s[b]
        in_s[b] = not some
    if not some:
        return 0
    for q in range(m_act):
        g = act_list[q]
        for b in range(gb_lo[g], gb_hi[g]):
            in_s[b] = True
    n_wrun = _runs(in_s, False, blk_dof, blk_el, w_lo, w_hi, w_elo, w_ehi)
    n_w_dof = 0
    for w in range(n_wrun):
        n_w_dof += w_hi[w] - w_lo[w]
    if n_w_dof < wait_share * blk_dof[nbk]:  # too few would wait to pay for the bookkeeping: all step
        for b in range(nbk):
            in_s[b] = True
        n_wrun = 0
    return n_wrun


@njit(cache=True)
def _waiting_step(clock, gnd, n_wrun, mr, runs, ws, waits, row, gaps, st, dr, stats):
    """The waiting buildings take the whole analysis step at once (exact modal steps, or Newmark with the
    level-0 factor); a gap between two of them that may close in that step makes its buildings step
    instead.  clock = (step, t, dt); gnd = (ag, moving, gap_ground); dr = (d0, r0, g_t): the gaps' state
    and the ground accelerations at t.  Returns the number of waiting runs left."""
    step, t, dt = clock
    ag, moving, gap_ground = gnd
    blk_dof, blk_el, gb_lo, gb_hi, in_s = mr[0], mr[1], mr[3], mr[4], mr[5]
    w_lo, w_hi, w_elo, w_ehi = runs[4], runs[5], runs[6], runs[7]
    g_w0, g_w1, du_w, u_w1, v_w1, a_w1 = ws[0], ws[1], ws[2], ws[3], ws[4], ws[5]
    exact, ex_co, md, mqs, L0, p, beta, gamma = waits[0], waits[1], waits[4], waits[5], waits[6], waits[7], \
        waits[8], waits[9]
    Av, Vv, R0 = waits[10]
    gap_i, gap_j, gap_size, gap_law = gaps[0], gaps[1], gaps[4], gaps[5]
    u, v = st[0], st[1]
    d0, r0, g_t = dr
    for r in range(ag.shape[0]):
        g_w0[r] = g_t[r]
        g_w1[r] = ag[r, step + 1]
    for w in range(n_wrun):
        if exact:  # exact for the piecewise-linear ground motion, as in free flight
            _exact_waiting((w_lo[w], w_hi[w]), ex_co, (g_w0, g_w1), md, (u, v), (du_w, u_w1, v_w1, a_w1), mqs)
        else:
            _waiting_trial((w_lo[w], w_hi[w], w_elo[w], w_ehi[w]), dt, (L0, p), (beta, gamma), row, g_w1, st,
                           (Av, Vv, R0), (du_w, u_w1, v_w1, a_w1))
        stats[S_DOF_STEPS] += w_hi[w] - w_lo[w]
    # a gap between waiting buildings that may close in this step: its buildings step
    # (a gap between a waiting and a stepping building is screened at every substep)
    for g in range(gap_size.size):
        if gap_law[g] == NONE:
            continue
        apart = True
        for b in range(gb_lo[g], gb_hi[g]):
            apart = apart and not in_s[b]
        if not apart:
            continue
        gu, gv = _gap_ground_at(moving, gap_ground, g, step + 1)
        d1, r1 = _gap_deformation(u_w1, v_w1, gap_i[g], gap_j[g], gap_size[g], gu, gv)
        tol = LAND_TOL * max(abs(r0[g]), abs(r1)) * dt + 1e-15
        if _event_in_step(d0[g], r0[g], d1, r1, dt, True, tol) < 2.0:
            for b in range(gb_lo[g], gb_hi[g]):
                in_s[b] = True
    return _runs(in_s, False, blk_dof, blk_el, w_lo, w_hi, w_elo, w_ehi)


@njit(cache=True)
def _stepping(mr, runs):
    """The stepping buildings' runs and the gaps screened, after in_s changed: returns (stepping runs,
    gaps linking stepping buildings only, gaps screened, stepping DOFs)."""
    blk_dof, blk_el, gb_lo, gb_hi, in_s, scr = mr[0], mr[1], mr[3], mr[4], mr[5], mr[7]
    r_lo, r_hi, r_elo, r_ehi = runs[0], runs[1], runs[2], runs[3]
    n_run = _runs(in_s, True, blk_dof, blk_el, r_lo, r_hi, r_elo, r_ehi)
    n_ss, n_scr = _screen_list(in_s, gb_lo, gb_hi, scr)
    n_s_dof = 0
    for rr in range(n_run):
        n_s_dof += r_hi[rr] - r_lo[rr]
    return n_run, n_ss, n_scr, n_s_dof


@njit(cache=True)
def _join(join_gap, hw, g_t, mr, ws, waits, row, st, umax, energy, stats):
    """The waiting buildings of gap join_gap catch up from the waiting step's start to now (a step of hw
    [s], exact or Newmark with its own factor) and step with the others from here.  energy = (e_in, w_int)
    [J]; returns (factored, e_in, w_int)."""
    e_in, w_int = energy
    blk_dof, blk_el, gb_lo, gb_hi, in_s = mr[0], mr[1], mr[3], mr[4], mr[5]
    g_w0, du_w, u_w1, v_w1, a_w1, L_w = ws[0], ws[2], ws[3], ws[4], ws[5], ws[6]
    exact, ex_h, h_ex, md, mqs, p, beta, gamma = waits[0], waits[2], waits[3], waits[4], waits[5], waits[7], \
        waits[8], waits[9]
    Av, Vv, R0 = waits[10]
    md_start, md_phi_t, md_phi_tm, md_w2, md_c, md_gam = md
    mass, dof_a0, dof_motion, el_i, el_j, el_k, el_a1 = row
    u, v, a, fint, fs, fd = st
    for b in range(gb_lo[join_gap], gb_hi[join_gap]):
        if in_s[b]:
            continue
        lo = blk_dof[b]
        hi = blk_dof[b + 1]
        if hw > 0.0 and exact:  # the catch-up step, exact too (coefficients for its length)
            if hw != h_ex[0]:
                exact_coefficients(md_w2, md_c, hw, ex_h)
                h_ex[0] = hw
            _exact_waiting((lo, hi), ex_h, (g_w0, g_t), md, (u, v), (du_w, u_w1, v_w1, a_w1), mqs)
        elif hw > 0.0:
            if not _factor_range(hw, (beta, gamma), (mass, dof_a0, el_i, el_j, el_k, el_a1), p, L_w,
                                 (lo, hi, blk_el[b], blk_el[b + 1])):
                return False, e_in, w_int
            stats[S_FACTORIZATIONS] += 1
            _waiting_trial((lo, hi, blk_el[b], blk_el[b + 1]), hw, (L_w, p), (beta, gamma), row, g_t, st,
                           (Av, Vv, R0), (du_w, u_w1, v_w1, a_w1))
        if hw > 0.0:
            e_in, w_int = _waiting_commit((lo, hi), (mass, dof_motion), (g_w0, g_t), (du_w, u_w1, v_w1, a_w1), st,
                                          umax, (e_in, w_int))
            stats[S_DOF_STEPS] += hi - lo
        in_s[b] = True
    stats[S_JOINS] += 1
    return True, e_in, w_int
