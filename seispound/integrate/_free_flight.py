"""Free flight: blocks of analysis steps with every gap open, marched in modal coordinates.

The buildings are then linear, uncoupled and (where this is used) classically
damped: each mode follows the same Newmark recurrence as the physical path,
with no solve; Phi q rebuilds the physical rows chunk by chunk, every gap is
screened at every step, and the block stops before the first step in which a
gap may close (handed to the physical path with its root estimate).
"""

from __future__ import annotations

import numpy as np
from seispound._jit import njit

from ..contact._scalar import NONE
from ._elements import _gap_deformation
from ._energy import _block_energy, _block_energy_exact
from ._events import LAND_TOL, _event_in_step
from ._exact import F_QQ, F_QV, F_VQ, F_VV, G0_Q, G0_V, G1_Q, G1_V, exact_coefficients, exact_step
from ._ground import _gap_ground_at
from ._outputs import E_CONTACT, E_DAMPING, E_INPUT, E_KINETIC, E_STRAIN

# Free-flight blocks are marched, rebuilt and screened FREE_FLIGHT_CHUNK steps at a time.
FREE_FLIGHT_CHUNK = 32


# Rows of up to SMALL_ROW DOFs reconstruct free-flight histories with one
# product by the whole block-diagonal Phi^T (cheaper than a call per building).
SMALL_ROW = 64


@njit(cache=True)
def _rows_from_modal(md_start, md_blocks_t, md_block_off, md_phi_t, Q, nb, X, s_in, s_out):
    """Physical rows X[k] = Phi Q[k], k < nb (X C-contiguous, nb rows).

    A small row (n <= SMALL_ROW DOFs) takes one BLAS product with the whole
    block-diagonal Phi^T.  Otherwise each block's columns are gathered into a
    contiguous scratch for one product per block (building), so the cost per
    step is the sum of n_b^2, linear in the number of buildings.
    """
    n = Q.shape[1]
    if n <= SMALL_ROW or md_start.size == 2:
        np.dot(Q[:nb], md_phi_t, X)
        return
    for c in range(md_start.size - 1):
        o = md_start[c]
        m = md_start[c + 1] - o
        A = s_in[:nb * m].reshape((nb, m))
        for k in range(nb):
            for j in range(m):
                A[k, j] = Q[k, o + j]
        B = md_blocks_t[md_block_off[c]:md_block_off[c + 1]].reshape((m, m))
        C = s_out[:nb * m].reshape((nb, m))
        np.dot(A, B, C)
        for k in range(nb):
            for i in range(m):
                X[k, o + i] = C[k, i]


@njit(cache=True)
def _block_matvec(md_start, A, x, y, transposed):
    """y = A x (or A^T x) for a block-diagonal A, block by block.

    With A = md_phi_tm (Phi^T M): modal coordinates of a physical vector; with
    A = md_phi_t (Phi^T) and ``transposed``: the physical vector of modal ones.
    """
    _block_matvec_range(md_start, A, x, y, transposed, 0, x.size)


@njit(cache=True)
def _block_matvec_range(md_start, A, x, y, transposed, lo, hi):
    """:func:`_block_matvec` on the blocks that lie within DOFs lo..hi-1 (whole buildings)."""
    for c in range(md_start.size - 1):
        o = md_start[c]
        e = md_start[c + 1]
        if o < lo or e > hi:
            continue
        for r in range(o, e):
            s = 0.0
            for q in range(o, e):
                s += (A[q, r] if transposed else A[r, q]) * x[q]
            y[r] = s


@njit(cache=True)
def _march_exact(span, P, co, modes, state, hist):
    """Steps k0..k1-1 of every mode by the exact recurrence (Nigam & Jennings 1969; ``_exact.py``).

    The acceleration follows from each mode's equation, q'' = P - c q' - w2 q.  span = (k0, k1); P the modal
    loads; co the exact coefficients; modes = (md_c, md_w2); state = (mq, mqv, mqa), carried; hist = (Q, QV,
    QA, DQ) the steps' histories.
    """
    k0, k1 = span
    md_c, md_w2 = modes
    mq, mqv, mqa = state
    Q, QV, QA, DQ = hist
    fqq, fqv, fvq, fvv = co[F_QQ], co[F_QV], co[F_VQ], co[F_VV]  # one contiguous row each: vectorised over j
    g0q, g0v, g1q, g1v = co[G0_Q], co[G0_V], co[G1_Q], co[G1_V]
    for k in range(k0, k1):
        for j in range(mq.size):
            p0 = P[k, j]
            p1 = P[k + 1, j]
            q0 = mq[j]
            v0 = mqv[j]
            q1 = fqq[j] * q0 + fqv[j] * v0 + g0q[j] * p0 + g1q[j] * p1
            v1 = fvq[j] * q0 + fvv[j] * v0 + g0v[j] * p0 + g1v[j] * p1
            DQ[k, j] = q1 - q0
            mq[j] = q1
            mqv[j] = v1
            mqa[j] = p1 - md_c[j] * v1 - md_w2[j] * q1
            Q[k, j] = q1
            QV[k, j] = v1
            QA[k, j] = mqa[j]


@njit(cache=True)
def _free_flight(span, nmk, gnd, mdb, blocks, row, gaps, exact_co, dr, st, outs, energy):
    """March up to ``nblk`` analysis steps from step0 with every gap open, in modal coordinates.

    Tuples (``_driver.integrate_kernel``'s): span = (step0, nsteps, nblk, store: the histories are written);
    nmk = (dt [s], beta, gamma); gnd = (ag, moving, gap_ground);
    mdb = (md_start, md_blocks_t, md_block_off, md_phi_t, md_w2, md_c, md_gam, md_khinv) the modal basis;
    blocks = (s_in, s_out, mq, mqv, mqa, Q, QV, QA, DQ, P, U, V, f_start, Eb) the modal state and block work
    arrays; row, gaps, st, outs as the kernel's; exact_co = (exact, ex_co); dr = (d0, r0) the gaps'
    penetration and rate, carried; energy = (e_in, w_int, e_cont, es0) [J].

    The modal state (mq, mqv, mqa) at step0 advances by the Newmark recurrence
    of each mode (``modal.py``: exact Newmark, no solve) or, with ``exact``, by
    the exact step of each mode for the piecewise-linear load (``_exact.py``,
    coefficients ``ex_co`` (8, n) for the step dt), displacements and
    velocities follow as Phi q (one matrix product per block), and every gap is
    screened step by step with the same test as the physical path.  The steps
    before the first one in which a gap may close are accepted (outputs, peaks,
    energy, carried gap states) and the physical state (u, v, a) is left at the
    last of them.  Shapes: Q, QV, QA, DQ, U, V (nblk, n); P (nblk + 1, n).

    Returns (accepted steps, event found, the event's fraction of its step and
    its gap, e_in, w_int).  After an event the modal state is stale (it ran on
    to the block's end).
    """
    step0, nsteps, nblk, store = span
    dt, beta, gamma = nmk
    ag, moving, gap_ground = gnd
    md_start, md_blocks_t, md_block_off, md_phi_t, md_w2, md_c, md_gam, md_khinv = mdb
    s_in, s_out, mq, mqv, mqa, Q, QV, QA, DQ, P, U, V, f_start, Eb = blocks
    dof_motion = row[2]
    gap_i, gap_j, gap_size, gap_law = gaps[0], gaps[1], gaps[4], gaps[5]
    exact, ex_co = exact_co
    d0, r0 = dr
    u, v, a = st[0], st[1], st[2]
    out_u, out_v, out_a, out_f, out_e, umax = outs[0], outs[1], outs[2], outs[3], outs[4], outs[5]
    e_in, w_int, e_cont, es0 = energy
    n = mq.size
    ng = gap_size.size
    nm = ag.shape[0]
    nb = min(nblk, nsteps - step0)
    cm = 1.0 / (beta * dt * dt)
    cc = gamma / (beta * dt)
    c1 = 1.0 / (beta * dt)
    c2 = 0.5 / beta - 1.0
    c3 = 1.0 - gamma / beta
    c4 = dt * (1.0 - 0.5 * gamma / beta)
    # ---- modal loads p = -Gamma a_g at the block's steps -----------------------
    for k in range(nb + 1):
        for j in range(n):
            P[k, j] = 0.0
        for r in range(nm):
            g = ag[r, step0 + k]
            for j in range(n):
                P[k, j] -= md_gam[r, j] * g
    for j in range(n):
        f_start[j] = md_w2[j] * mq[j] + md_c[j] * mqv[j]
    qv_start = mqv.copy() if exact else mqv[:0]  # the exact energy needs the velocity at the block's start
    # ---- march, rebuild and screen chunk by chunk, up to the first event ------
    # (chunks keep the BLAS products large, and an event early in a long block
    # wastes at most one chunk of speculative steps; the twin, with no gap to
    # screen, takes the block in one chunk)
    chunk = nb if ng == 0 else FREE_FLIGHT_CHUNK
    Ub = out_u[step0 + 1:step0 + 1 + nb] if store else U[:nb]  # u = Phi q, straight into the histories
    Vb = out_v[step0 + 1:step0 + 1 + nb] if store else V[:nb]
    n_acc = nb
    th_ev = 2.0  # the event's fraction of its step, and its gap
    g_ev = -1
    k0 = 0
    while k0 < nb and n_acc == nb:
        k1 = min(k0 + chunk, nb)
        if exact:
            _march_exact((k0, k1), P, ex_co, (md_c, md_w2), (mq, mqv, mqa), (Q, QV, QA, DQ))
        for k in range(k0, k1 if not exact else k0):
            for j in range(n):  # every mode at once: vectorised over j
                av = -c1 * mqv[j] - c2 * mqa[j]
                vv = c3 * mqv[j] + c4 * mqa[j]
                dq = (P[k + 1, j] - av - md_c[j] * vv - md_w2[j] * mq[j]) * md_khinv[j]
                mq[j] += dq
                mqv[j] = vv + cc * dq
                mqa[j] = av + cm * dq
                Q[k, j] = mq[j]
                QV[k, j] = mqv[j]
                QA[k, j] = mqa[j]
                DQ[k, j] = dq
        _rows_from_modal(md_start, md_blocks_t, md_block_off, md_phi_t, Q[k0:k1], k1 - k0, Ub[k0:k1], s_in, s_out)
        if ng > 0 or store:
            _rows_from_modal(md_start, md_blocks_t, md_block_off, md_phi_t, QV[k0:k1], k1 - k0, Vb[k0:k1],
                             s_in, s_out)
        # the first step in which any gap may close
        for g in range(ng):
            if gap_law[g] == NONE:
                continue
            ii = np.uint64(gap_i[g])  # unsigned subscripts (``_UNSIGNED``)
            jj = np.uint64(gap_j[g])
            if k0 == 0:
                dp = d0[g]
                rp = r0[g]
            else:
                gu, gv = _gap_ground_at(moving, gap_ground, g, step0 + k0)
                dp, rp = _gap_deformation(Ub[k0 - 1], Vb[k0 - 1], ii, jj, gap_size[g], gu, gv)
            for k in range(k0, min(n_acc + 1, k1)):
                gu, gv = _gap_ground_at(moving, gap_ground, g, step0 + k + 1)
                d1, r1 = _gap_deformation(Ub[k], Vb[k], ii, jj, gap_size[g], gu, gv)
                tol = LAND_TOL * max(abs(rp), abs(r1)) * dt + 1e-15
                th = _event_in_step(dp, rp, d1, r1, dt, True, tol)  # the physical path's test
                if th < 2.0:
                    if k < n_acc or th < th_ev:
                        n_acc = k  # later gaps need only look up to this step
                        th_ev = th
                        g_ev = g
                    break
                dp = d1
                rp = r1
        k0 = k1
    event = n_acc < nb
    if n_acc == 0:
        return 0, event, th_ev, g_ev, e_in, w_int
    # ---- accept steps 0 .. n_acc - 1 ------------------------------------------
    for k in range(n_acc):
        for i in range(n):
            umax[i] = max(umax[i], abs(Ub[k, i]))
    kl = n_acc - 1
    for g in range(ng):
        gu, gv = _gap_ground_at(moving, gap_ground, g, step0 + n_acc)
        d0[g], r0[g] = _gap_deformation(Ub[kl], Vb[kl], gap_i[g], gap_j[g], gap_size[g], gu, gv)
    if store:
        _rows_from_modal(md_start, md_blocks_t, md_block_off, md_phi_t, QA, n_acc,
                         out_a[step0 + 1:step0 + 1 + n_acc], s_in, s_out)
        if exact:
            _block_energy_exact(n_acc, Q, QV, DQ, P, qv_start, md_w2, md_c, dt, Eb)
        else:
            _block_energy(n_acc, Q, QV, DQ, P, f_start, md_w2, md_c, Eb)
        for k in range(n_acc):
            row = step0 + k + 1
            for i in range(n):
                a[i] = out_a[row, i]  # relative; the stored acceleration is absolute
                out_a[row, i] = a[i] + ag[dof_motion[i], row]
            for g in range(ng):
                out_f[row, g] = 0.0
            e_in += Eb[0, k]
            w_int += Eb[1, k]
            out_e[row, E_INPUT] = e_in
            out_e[row, E_KINETIC] = Eb[2, k]
            out_e[row, E_STRAIN] = Eb[3, k]
            out_e[row, E_DAMPING] = w_int - (Eb[3, k] - es0)
            out_e[row, E_CONTACT] = e_cont
    else:
        _block_matvec(md_start, md_phi_t, QA[kl], a, True)
    for i in range(n):
        u[i] = Ub[kl, i]
    if ng > 0 or store:
        for i in range(n):
            v[i] = Vb[kl, i]
    else:
        _block_matvec(md_start, md_phi_t, QV[kl], v, True)
    return n_acc, event, th_ev, g_ev, e_in, w_int


@njit(cache=True)
def _exact_trial(h, grd, nb, md, coef, st, mqs, incr):
    """A step of size h [s] of the whole row with every gap open, exact for the piecewise-linear ground motion.

    The physical path's step around events (the rest of a step after an impact,
    the part of a step before one), in modal coordinates like a free-flight
    block (``_exact.py``; coefficients for h in ``co`` (8, n), recomputed when
    h differs from h_co[0]).  The result is returned in the Newmark form the
    rest of the step expects: u1 = u + Du, v1 = Vv + cc Du, a1 = Av + cm Du
    (cc = gamma / (beta h), cm = 1 / (beta h^2)), so screening, events and
    acceptance run unchanged.  grd = (g_t, g_1) (nm,): ground accelerations at the
    step's ends; nb = (beta, gamma); md = (md_start, md_phi_t, md_phi_tm, md_w2, md_c,
    md_gam) the modal basis; coef = (co, h_co); st = (u, v, ...); mqs = (q, qv, qa) (n,)
    scratch; incr = (Du, R0, Av, Vv).  Returns sum (K u)_i u_i at the start (twice the
    strain energy), as the Newmark predictor does.
    """
    g_t, g_1 = grd
    beta, gamma = nb
    md_start, md_phi_t, md_phi_tm, md_w2, md_c, md_gam = md
    co, h_co = coef
    u, v = st[0], st[1]
    q, qv, qa = mqs
    Du, Av, Vv = incr[0], incr[2], incr[3]
    n = u.size
    if h != h_co[0]:
        exact_coefficients(md_w2, md_c, h, co)
        h_co[0] = h
    _block_matvec(md_start, md_phi_tm, u, q, False)
    _block_matvec(md_start, md_phi_tm, v, qv, False)
    es = 0.0
    for j in range(n):
        es += md_w2[j] * q[j] * q[j]
    _modal_steps(co, g_t, g_1, md_w2, md_c, md_gam, q, qv, qa, 0, n)
    _block_matvec(md_start, md_phi_t, q, Du, True)
    _block_matvec(md_start, md_phi_t, qv, Vv, True)
    _block_matvec(md_start, md_phi_t, qa, Av, True)
    cc = gamma / (beta * h)
    cm = 1.0 / (beta * h * h)
    for i in range(n):
        Du[i] -= u[i]
        Vv[i] -= cc * Du[i]
        Av[i] -= cm * Du[i]
    return es


@njit(cache=True)
def _exact_waiting(rows, co, grd, md, x0, wend, mqs):
    """A waiting step of the buildings on DOFs lo..hi-1, exact for the piecewise-linear ground motion.

    Multi-rate stepping's one step per analysis step (``_multirate._waiting_trial``)
    under the exact scheme: each of the buildings' modes advances by its exact
    recurrence (coefficients ``co`` (8, n) for the step's length; ``_exact.py``),
    with g0, g1 (nm,) the ground accelerations at the step's ends.  The end
    state goes to u_w1, v_w1, a_w1 and the increment to du_w, as
    ``_waiting_trial`` leaves them (u, v stay until ``_waiting_commit``).  rows = (lo, hi);
    grd = (g0, g1); md the modal basis (``_exact_trial``); x0 = (u, v); wend = (du_w, u_w1,
    v_w1, a_w1); mqs = (q, qv, qa) (n,): scratch (the caller's modal state, stale on the
    physical path).
    """
    lo, hi = rows
    g0, g1 = grd
    md_start, md_phi_t, md_phi_tm, md_w2, md_c, md_gam = md
    u, v = x0
    du_w, u_w1, v_w1, a_w1 = wend
    q, qv, qa = mqs
    _block_matvec_range(md_start, md_phi_tm, u, q, False, lo, hi)
    _block_matvec_range(md_start, md_phi_tm, v, qv, False, lo, hi)
    _modal_steps(co, g0, g1, md_w2, md_c, md_gam, q, qv, qa, lo, hi)
    _block_matvec_range(md_start, md_phi_t, q, u_w1, True, lo, hi)
    _block_matvec_range(md_start, md_phi_t, qv, v_w1, True, lo, hi)
    _block_matvec_range(md_start, md_phi_t, qa, a_w1, True, lo, hi)
    for i in range(lo, hi):
        du_w[i] = u_w1[i] - u[i]


@njit(cache=True)
def _modal_steps(co, g0, g1, md_w2, md_c, md_gam, q, qv, qa, lo, hi):
    """Modes lo..hi-1 one exact step on (q, qv) in place, their accelerations into qa.

    The modal load is -sum_r Gamma[r, j] a_g,r at both ends (g0, g1 (nm,)); the
    acceleration follows from the mode's equation.  Shared by the physical
    path's exact trial and the waiting buildings' exact step.
    """
    for j in range(lo, hi):
        p0 = 0.0
        p1 = 0.0
        for r in range(g0.size):
            p0 -= md_gam[r, j] * g0[r]
            p1 -= md_gam[r, j] * g1[r]
        q1, v1 = exact_step(co, j, q[j], qv[j], p0, p1)
        q[j] = q1
        qv[j] = v1
        qa[j] = p1 - md_c[j] * v1 - md_w2[j] * q1
