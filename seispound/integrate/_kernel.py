"""Newmark-beta time loop with event-located contact, compiled with numba.

Private: call :func:`seispound.integrate.integrate`, which validates inputs and
allocates the outputs.  Everything here takes arrays and scalars only.

Method
------
Newmark-beta in total form (Newmark 1959; Chopra, Dynamics of Structures,
Sec. 5.4 and Table 5.7.2 for the nonlinear Newton-Raphson version): at every
step the residual

    R(u1) = p1 - M a1(u1) - C v1(u1) - K u1 - B F(u1, v1)

must vanish, B holding b_g = e_left - e_right for each gap and F the contact
forces.  K_hat = K + gamma/(beta h) C + 1/(beta h^2) M is banded (shear
buildings: tridiagonal, factored L D L^T; otherwise banded Cholesky) and
factored once per step size.  The storeys being linear, the step increment is
Du = Du_lin - K_hat^-1 B F with Du_lin = K_hat^-1 R(u) (Sherman-Morrison-
Woodbury), so the Newton-Raphson iteration runs on the m contact forces of
the gaps in contact only: F = F_law(delta_lin - G F, rate_lin - gamma/(beta h)
G F), G = B^T K_hat^-1 B.  Its residual F - F_law is exactly R at the gap DOFs
(R is zero elsewhere) and is tested against rtol times the largest force.
G and K_hat^-1 B F come from Woodbury columns K_hat^-1 b_g cached per factor
of the dt/2^k grid (they serve every substep of that size), and, for a
located step's one-off size, from the semiseparable inverse of the
tridiagonal K_hat (``_inverse_diagonals``): O(n + m^2) instead of m new
columns in O(n m).  K_hat being block diagonal over the buildings, G is block
diagonal over groups of closed gaps that share no building
(``_group_contacts``, regrouped at events); each group gets its own Newton
iteration.  A step costs one banded solve, O(n * bandwidth), plus
O(sum m_c^3) per iteration over the groups' sizes m_c.

Contact events: the set of gaps in contact is frozen during a step.  After a
step, a gap that opened or closed inside it (sign change of the penetration,
or a grazing excursion either way seen by the cubic Hermite interpolant of
delta: a touch of an open gap, a brief separation of a closed one) makes
the step be redone up to the event time, found as the first root of that
interpolant; repeated until the step ends on the event within 1e-7 of the
step's travel.  Gaps whose events fall on the same instant (identical floors,
copies of a pair) switch together, in one attempt.  While any gap is closed the step is cut into substeps of
1/n_sub of the impact duration estimated at onset (``contact_duration``), so
the contact is resolved independently of the analysis step.  At each event
the acceleration is recomputed from equilibrium, because the contact force may
jump there (LVe's dashpot).

Free flight: while every gap is open, the buildings are linear and uncoupled.
When they are also classically damped (``modal.py``), the kernel marches whole
blocks of analysis steps in modal coordinates (``_free_flight``: the same
Newmark recurrence per mode, no solve, Phi q for the physical rows, one matrix
product per chunk of FREE_FLIGHT_CHUNK steps), screens every gap at every step
with the same test as above, chunk by chunk, accepts the steps before the
first one in which a gap may close, and hands that step to the physical path,
starting from the block's own root estimate.  Blocks start at 16 steps after an impact and double up to
``nblk``; the no-pounding twin runs in free flight throughout.

Multi-rate stepping: while some gap is closed, only the buildings its
contact group links (the *stepping* buildings; ``gap_lo``..``gap_hi`` of every
closed gap) take the contact substeps.  Every other building *waits*: at the
start of the analysis step it takes the whole step in one Newmark step of dt
(``_waiting_trial``, the level-0 factor restricted to its rows), committed
when the stepping buildings reach the step's end (``_waiting_commit``).  A
gap between two waiting buildings is screened over that step first (an event
makes its buildings step from the start); a gap between a waiting and a
stepping building is screened at every substep with the waiting side on its
step's own trajectory (``_waiting_state``: exact for average acceleration).
When such a gap may close inside a substep, the substep is redone: the waiting
building first takes a catch-up step from the analysis step's start to the
substep's start (its own factor), then steps with the others (a *join*), so
the event is located with both sides integrated.  Each loop over DOFs,
elements or factor rows runs over the stepping buildings' runs only
(``_runs``), and only the gaps that touch them are screened per substep, so a
row whose pairs pound at different times costs what its pairs cost one by one
plus the substeps that pairs in contact at the same time share.  Waiting
buildings differ from stepping ones by the time discretisation of free flight,
O(dt^2), as in the free-flight blocks.

Energy (relative frame; Uang & Bertero 1990) is accumulated with the
trapezoidal work 0.5 (f0 + f1) . (u1 - u0), which for the average-acceleration
method balances exactly: input = kinetic + strain + damping + contact.
"""


from __future__ import annotations

import numpy as np
from seispound._jit import njit

from ..contact._scalar import NONE, contact_force
from ._borrow import borrow, borrow_all, keep_alive
from ._contact import _begin_impact, _contact_step, _end_impact, _grid_level, _group_contacts, _peak_through
from ._elements import _gap_deformation, _gap_kinematics, _gap_trial
from ._events import LAND_TOL, _event_in_step, _screen_step
from ._free_flight import _block_matvec, _exact_trial, _free_flight
from ._ground import GU0, GU1, GV0, GV1, _gap_ground_accept, _gap_ground_all, _ground_all
from ._linear import (
    SEMISEPARABLE_GAPS,
    _compliance_tridiagonal,
    _factor,
    _factor_range,
    _internal,
    _internal_range,
    _inverse_diagonals_range,
    _strain_energy,
    _subtract_contact,
    _woodbury_columns,
)
from ._material import N_STATE, ST_ZETA
from ._multirate import _gap_state, _join, _runs, _screen_list, _stepping, _waiting_commit, _waiting_step, _who_steps
from ._newmark_step import _accept_rows, _newmark_predictor
from ._newton import _newton
from ._outputs import (  # noqa: F401 (re-exported)
    E_CONTACT,
    E_HYSTERETIC,
    E_DAMPING,
    E_INPUT,
    E_KINETIC,
    E_STRAIN,
    IMPACT_CAPACITY,
    N_STATS,
    NEWTON_FAILED,
    OK,
    S_BLOCKS,
    S_DOF_STEPS,
    S_FACTORIZATIONS,
    S_FREE_FLIGHT,
    S_ITERATIONS,
    S_JOINS,
    S_MAX_ITER,
    S_REJECTED,
    S_STEPS,
    S_WAITING,
)


@njit(cache=True)
def integrate_kernel(row, p, init, gaps, motion, settings, modal, multi, outs, cat, stats):
    """Integrate the row of buildings; fill the output arrays; return (status, n_impacts, t_reached).

    The arguments come in named tuples: row = (mass, dof_a0, dof_motion, el_i, el_j, el_k, el_a1); p the
    half bandwidth of K_hat; init = (u_init, v_init); gaps = (gap_i, gap_j, gap_lo, gap_hi, gap_size,
    gap_law, gap_par); motion = (ag, moving, gap_ground); settings = (dt, nsteps, beta, gamma, n_sub, rtol,
    max_iter, store); modal = (use_modal, md_start, md_blocks_t, md_block_off, md_phi_t, md_phi_tm, md_w2,
    md_c, md_gam, nblk, exact, ex_co); multi = (multirate, wait_share, blk_dof, blk_el); outs = (out_u,
    out_v, out_a, out_f, out_e, umax, fmax); cat = (imp_gap, imp_t0, imp_v0, imp_vout, imp_fmax, imp_dur,
    imp_zeta, imp_e); stats.

    Shapes: n DOFs, ne elements, ng gaps, nm base motions, nt = nsteps + 1.
    mass, dof_a0, dof_motion, u_init, v_init : (n,); el_* : (ne,); gap_* : (ng,),
    gap_lo, gap_hi: the DOF range of the blocks (buildings) each gap links,
    gap_par : (ng, N_PAR); ag : (nm, nt) [m/s^2]; out_u, out_v, out_a : (nt, n);
    out_f : (nt, ng); out_e : (nt, 5) (with store False: 1 row, the initial state);
    umax : (n,); fmax : (ng,);
    imp_* : (capacity,); stats : (N_STATS,) int64.
    exact : (with use_modal) every step with every gap open is exact for the
    piecewise-linear ground motion (``_exact.py``): free-flight blocks with the
    coefficients ex_co (8, n) for dt, the physical path's steps around events
    with coefficients computed for their size; False: Newmark throughout.
    use_modal : march the steps with every gap open in blocks of up to nblk
    steps in modal coordinates (``_free_flight``); md_* from ``modal.py``
    (md_start : (nc + 1,) block starts; md_blocks_t, md_block_off: each
    block's Phi^T; md_phi_t, md_phi_tm : (n, n); md_w2, md_c : (n,);
    md_gam : (nm, n)); ignored (may be empty) when False.
    n_sub : (contact substeps per impact duration, longest contact substep [s])
    (``_contact._begin_impact``).
    multirate : while some gap is closed, only the buildings its contact
    group links take contact substeps; the others wait, taking each analysis
    step in one step, and join the stepping ones at the substep in which a gap
    of theirs may close (``Multi-rate stepping`` in the module docstring),
    provided they hold at least ``wait_share`` of the DOFs (WAIT_SHARE).
    blk_dof, blk_el : (nb + 1,) first DOF and first element of each block
    (building); the elements of a block are contiguous.
    moving : some gap's two sides stand on different ground motions;
    gap_ground : (3, ng, nt) the differential ground acceleration, velocity
    and displacement of each gap at the samples (``_ground._gap_ground``);
    (3, ng, 1) and unused when ``moving`` is False.
    """
    # arguments: alive for the whole call, so borrowed (``_borrow``: no reference counting in the loop)
    row, init, gaps, motion, modal, multi, outs, cat = borrow_all((row, init, gaps, motion, modal, multi, outs, cat))
    stats = borrow(stats)
    mass, dof_a0, dof_motion, el_i, el_j, el_k, el_a1 = row
    u_init, v_init = init
    gap_i, gap_j, gap_lo, gap_hi, gap_size, gap_law, gap_par = gaps
    ag, moving, gap_ground = motion
    dt, nsteps, beta, gamma, n_sub, rtol, max_iter, store = settings
    use_modal, md_start, md_blocks_t, md_block_off, md_phi_t, md_phi_tm, md_w2, md_c, md_gam, nblk, exact, ex_co = modal
    multirate, wait_share, blk_dof, blk_el = multi
    out_u, out_v, out_a, out_f, out_e, umax, fmax = outs
    imp_gap, imp_t0, imp_v0, imp_vout, imp_fmax, imp_dur, imp_zeta, imp_e = cat
    n = mass.size
    ng = gap_size.size
    nm = ag.shape[0]
    # -- work arrays (allocated once; the loop allocates nothing) ------------
    # factors of K_hat for h = dt / 2^k (contact substeps stay on this grid,
    # so each level is factored once) plus one scratch factor for odd steps
    n_lev = 40
    L_lev = np.empty((n_lev, n, p + 2))
    have_lev = np.zeros(n_lev, np.bool_)
    h_lev = np.empty(n_lev)
    for k in range(n_lev):
        h_lev[k] = dt / 2.0**k
    L_h = np.empty((n, p + 2))
    u = u_init.copy()
    v = v_init.copy()
    a = np.empty(n)
    fint = np.empty(n)  # storey + damping forces in equilibrium with (u, v)
    fs = np.empty(n)
    fd = np.empty(n)
    Du = np.empty(n)  # u1 - u, kept separately: recomputing it loses digits on short steps
    R0 = np.empty(n)
    Av = np.empty(n)
    Vv = np.empty(n)
    ngw = max(ng, 1)
    # semiseparable ratios and diagonal of the scratch factor's K_hat^-1 (tridiagonal
    # or diagonal K_hat only), computed when a located step with several gaps
    # closed needs them; every other step uses the cached Woodbury columns below
    tri = p <= 1
    sig_h = np.empty(n if tri else 1)
    Sd_h = np.empty(n if tri else 1)
    # Woodbury columns K_hat^-1 b_g for the current factor: nonzero only on the
    # DOFs gap_lo[g]..gap_hi[g]-1 of the two buildings the gap links (zero elsewhere)
    # (two sets: the level factor's, which survive an odd located step in
    # between, and the scratch factor's)
    Wc_level = np.zeros((ngw, n))
    Wc_scratch = np.zeros((ngw, n))
    batch = np.empty(ngw, np.int64)
    Wc_ok_level = np.zeros(ngw, np.bool_)
    Wc_ok_scratch = np.zeros(ngw, np.bool_)
    wc_key = np.array([-2.0, -1.0, 0.0])  # the level and the step the cached columns are for; inverse ok?
    dofs = np.empty(2 * ngw, np.int64)
    order = np.empty(2 * ngw, np.int64)
    pos = np.empty(2 * ngw, np.int64)
    span = np.empty(2 * ngw)
    Kd = np.empty((2 * ngw, 2 * ngw) if tri else (1, 1))
    xs = np.empty(n)
    Sm = np.empty((ngw, ngw))
    Gm = np.empty((ngw, ngw))  # B^T K_hat^-1 B for the gaps in contact
    ym = np.empty(ngw)
    Fm = np.empty(ngw)  # contact forces of the active gaps (Newton unknowns)
    dl = np.empty(ngw)  # their penetration and rate after the linear predictor
    rl = np.empty(ngw)
    resv = np.empty(ngw)
    act_list = np.empty(ngw, np.int64)
    comp_off = np.empty(ngw + 1, np.int64)  # the closed gaps' independent groups (``_group_contacts``)
    toggles = np.empty(ngw, np.int64)  # gaps switched together at one instant
    land_too = np.empty(ngw, np.int64)
    active = np.zeros(ng, np.bool_)
    st_c = np.zeros((ng, N_STATE))  # the laws' committed and trial states (``_material``: zeta, e at onset)
    st_t = np.zeros((ng, N_STATE))
    hsub = np.zeros(ng)
    age = np.zeros(ng, np.int64)  # accepted substeps since the onset of the impact
    cur_imp = -np.ones(ng, np.int64)
    F = np.zeros(ng)  # contact forces in equilibrium with (u, v)
    F1 = np.zeros(ng)
    F_old = np.zeros(ng)  # force and length of each closed gap's last accepted substep
    h_old = np.ones(ng)
    kt = np.zeros(ng)
    d0 = np.empty(ng)  # penetration and rate of every gap at the start of the step
    r0 = np.empty(ng)
    d_end = np.empty(ng)  # ... at the end of the trial step (swapped in on acceptance)
    r_end = np.empty(ng)
    # differential ground displacement and velocity of every gap at t (rows GU0, GV0) and at the end of
    # the trial step (GU1, GV1); zero under one ground motion.  (One array, not four: each live array
    # in the time loop costs registers in its hot loops.)
    gk = np.zeros((4, ng))
    g_t = np.empty(nm)  # ground acceleration at t, per motion row
    # -- multi-rate stepping: buildings that step (in_s) and that wait ------
    nbk = blk_dof.size - 1
    dof_blk = np.empty(n, np.int64)
    for b in range(nbk):
        for i in range(blk_dof[b], blk_dof[b + 1]):
            dof_blk[i] = b
    gb_lo = np.empty(ng, np.int64)  # the buildings each gap links (and any between)
    gb_hi = np.empty(ng, np.int64)
    for g in range(ng):
        gb_lo[g] = dof_blk[gap_lo[g]]
        gb_hi[g] = dof_blk[gap_hi[g] - 1] + 1
    in_s = np.ones(nbk, np.bool_)
    was_s = np.ones(nbk, np.bool_)
    r_lo = np.empty(nbk, np.int64)  # runs of stepping buildings: DOF and element ranges
    r_hi = np.empty(nbk, np.int64)
    r_elo = np.empty(nbk, np.int64)
    r_ehi = np.empty(nbk, np.int64)
    w_lo = np.empty(nbk, np.int64)  # ... of waiting buildings
    w_hi = np.empty(nbk, np.int64)
    w_elo = np.empty(nbk, np.int64)
    w_ehi = np.empty(nbk, np.int64)
    n_run = _runs(in_s, True, blk_dof, blk_el, r_lo, r_hi, r_elo, r_ehi)
    n_wrun = 0
    n_s_dof = n  # DOFs of the stepping buildings
    scr = np.empty(ngw, np.int64)  # gaps screened at every step: those linking a stepping building
    n_ss, n_scr = _screen_list(in_s, gb_lo, gb_hi, scr)
    waiting = False  # some buildings wait in this analysis step
    t_w0 = 0.0  # start of the waiting step, and the ground acceleration there
    g_w0 = np.empty(nm)
    g_w1 = np.empty(nm)
    du_w = np.empty(n)  # the waiting step: increment and end state
    u_w1 = np.empty(n)
    v_w1 = np.empty(n)
    a_w1 = np.empty(n)
    L_w = np.empty((n, p + 2))  # factor of a joining building's catch-up step
    zero_n = np.zeros(n)
    g_1 = np.empty(nm)  # ... at the end of the trial step
    for s in range(stats.size):
        stats[s] = 0
    n_imp = 0
    # free-flight blocks: modal state and block histories (time-contiguous rows)
    nbw = nblk if use_modal else 1
    nq = n if use_modal or exact else 0
    mq = np.empty(nq)
    mqv = np.empty(nq)
    mqa = np.empty(nq)
    Qb = np.empty((nbw, nq))
    QVb = np.empty((nbw, nq))
    QAb = np.empty((nbw, nq))
    DQb = np.empty((nbw, nq))
    Pb = np.empty((nbw + 1, nq))
    Ub = np.empty((nbw, nq))
    Vb = np.empty((nbw, nq))
    f_start = np.empty(nq)
    s_in = np.empty(nbw * nq)  # scratch of the per-block products
    s_out = np.empty(nbw * nq)
    Eb = np.empty((4, nbw))
    md_khinv = np.empty(nq)
    ex_h = np.empty((8, nq if exact else 0))  # exact step coefficients for the last odd step h_ex[0]
    h_ex = np.full(1, -1.0)
    for j in range(nq):
        md_khinv[j] = 1.0 / (md_w2[j] + gamma / (beta * dt) * md_c[j] + 1.0 / (beta * dt * dt))
    modal_current = False  # does (q, qv, qa) hold the current state?
    block_from = 0  # first analysis step that may start a free-flight block
    blk = 16  # current block length: short after an impact, doubling up to nblk
    aim_gap = -1  # a gap whose event the last accepted step stopped just short of
    hint_step = -1  # the step in which a block saw an event, its fraction and gap
    th_hint = 2.0
    g_hint = -1

    # the work arrays: owned by this tuple (kept alive to the end), used through borrowed aliases
    owners = (L_lev, have_lev, h_lev, L_h, u, v, a, fint, fs, fd, Du, R0, Av, Vv, sig_h, Sd_h, Wc_level, Wc_scratch,
              batch, Wc_ok_level, Wc_ok_scratch, dofs, order, pos, span, Kd, xs, Sm, Gm, ym, Fm, dl, rl, resv,
              act_list, comp_off, toggles, land_too, active, st_c, st_t, hsub, age, cur_imp, F, F1, F_old, h_old, kt, d0,
              r0, d_end, r_end, gk, g_t, dof_blk, gb_lo, gb_hi, in_s, was_s, r_lo, r_hi, r_elo, r_ehi,
              w_lo, w_hi, w_elo, w_ehi, scr, g_w0, g_w1, du_w, u_w1, v_w1, a_w1, L_w, zero_n, g_1, mq, mqv, mqa, Qb,
              QVb, QAb, DQb, Pb, Ub, Vb, f_start, s_in, s_out, Eb, md_khinv, wc_key)
    wc_key = borrow(wc_key)
    L_lev, have_lev, h_lev, L_h, u = borrow(L_lev), borrow(have_lev), borrow(h_lev), borrow(L_h), borrow(u)
    v, a, fint, fs, fd, Du, R0 = borrow(v), borrow(a), borrow(fint), borrow(fs), borrow(fd), borrow(Du), borrow(R0)
    Av, Vv, sig_h, Sd_h, Wc_level = borrow(Av), borrow(Vv), borrow(sig_h), borrow(Sd_h), borrow(Wc_level)
    Wc_scratch, batch, Wc_ok_level = borrow(Wc_scratch), borrow(batch), borrow(Wc_ok_level)
    Wc_ok_scratch, dofs, order, pos = borrow(Wc_ok_scratch), borrow(dofs), borrow(order), borrow(pos)
    span, Kd, xs, Sm, Gm, ym = borrow(span), borrow(Kd), borrow(xs), borrow(Sm), borrow(Gm), borrow(ym)
    Fm, dl, rl, resv, act_list = borrow(Fm), borrow(dl), borrow(rl), borrow(resv), borrow(act_list)
    comp_off, toggles, land_too, active = borrow(comp_off), borrow(toggles), borrow(land_too), borrow(active)
    hsub, age, cur_imp, F = borrow(hsub), borrow(age), borrow(cur_imp), borrow(F)
    st_c, st_t = borrow(st_c), borrow(st_t)
    F1, F_old, h_old, kt, d0, r0 = borrow(F1), borrow(F_old), borrow(h_old), borrow(kt), borrow(d0), borrow(r0)
    d_end, r_end, g_t, dof_blk, gb_lo = borrow(d_end), borrow(r_end), borrow(g_t), borrow(dof_blk), borrow(gb_lo)
    gk = borrow(gk)
    gb_hi, in_s, was_s, r_lo, r_hi = borrow(gb_hi), borrow(in_s), borrow(was_s), borrow(r_lo), borrow(r_hi)
    r_elo, r_ehi, w_lo, w_hi, w_elo = borrow(r_elo), borrow(r_ehi), borrow(w_lo), borrow(w_hi), borrow(w_elo)
    w_ehi, scr, g_w0, g_w1, du_w = borrow(w_ehi), borrow(scr), borrow(g_w0), borrow(g_w1), borrow(du_w)
    u_w1, v_w1, a_w1, L_w, zero_n = borrow(u_w1), borrow(v_w1), borrow(a_w1), borrow(L_w), borrow(zero_n)
    g_1, mq, mqv, mqa, Qb, QVb = borrow(g_1), borrow(mq), borrow(mqv), borrow(mqa), borrow(Qb), borrow(QVb)
    QAb, DQb, Pb, Ub, Vb, f_start = borrow(QAb), borrow(DQb), borrow(Pb), borrow(Ub), borrow(Vb), borrow(f_start)
    s_in, s_out, Eb, md_khinv = borrow(s_in), borrow(s_out), borrow(Eb), borrow(md_khinv)
    # the named groups of arrays that the phases take (tuples of the borrowed arrays above)
    cs = (active, st_c, hsub, age, cur_imp)  # each gap's contact state (``_contact._begin_impact``)
    st = (u, v, a, fint, fs, fd)  # the state and the internal forces in equilibrium with it
    runs = (r_lo, r_hi, r_elo, r_ehi, w_lo, w_hi, w_elo, w_ehi)  # stepping and waiting buildings' runs
    mr = (blk_dof, blk_el, dof_blk, gb_lo, gb_hi, in_s, was_s, scr)  # multi-rate: who steps
    ws = (g_w0, g_w1, du_w, u_w1, v_w1, a_w1, L_w, zero_n)  # the waiting buildings' step
    md = (md_start, md_phi_t, md_phi_tm, md_w2, md_c, md_gam)  # the modal basis, for exact steps
    waits = (exact, ex_co, ex_h, h_ex, md, (mq, mqv, mqa), L_lev[0], p, beta, gamma, (Av, Vv, R0))
    wc = (Wc_level, Wc_ok_level, Wc_scratch, Wc_ok_scratch, wc_key, batch)  # Woodbury columns, per factor
    semi = (sig_h, Sd_h, dofs, order, pos, span, Kd, xs)  # the semiseparable inverse of the scratch factor
    nwt = (Gm, dl, rl, Fm, resv, kt, Sm, ym, st_c, st_t)  # the contact Newton's work
    fac = (L_lev, have_lev, L_h)  # K_hat's factors: per dt/2^k level, and a scratch one
    gf = (F, F1, F_old, h_old)  # the closed gaps' forces: at t, trial, and the last accepted substep's
    mdb = (md_start, md_blocks_t, md_block_off, md_phi_t, md_w2, md_c, md_gam, md_khinv)  # ... free flight's
    blocks = (s_in, s_out, mq, mqv, mqa, Qb, QVb, QAb, DQb, Pb, Ub, Vb, f_start, Eb)  # its block work arrays

    if not _factor(dt, beta, gamma, mass, dof_a0, el_i, el_j, el_k, el_a1, p, L_lev[0]):
        return NEWTON_FAILED, 0, 0.0
    have_lev[0] = True
    stats[S_FACTORIZATIONS] += 1
    h_cached = -1.0

    # -- initial state: gaps already closing at t = 0 (touching bodies) start an impact; output row 0
    t = 0.0
    status, n_imp, m_act, n_comp, e_in, es0 = _start(dt, ag, row, gaps, n_sub, st, F, cs, cat, outs, g_t,
                                                     (d0, r0), (act_list, comp_off))
    if status != OK:
        return status, n_imp, t
    w_int = 0.0  # work of storey + damping forces; damping = w_int - (strain - strain0)
    e_cont = 0.0
    pending = -1  # output row still waiting for its strain energy

    hmin = 1e-9 * dt  # events closer than this to the step start switch in place
    step = 0
    while step < nsteps:
        if use_modal and m_act == 0 and step >= block_from:
            # ---- every gap open: march a block of steps in modal coordinates ----
            if not modal_current:
                _block_matvec(md_start, md_phi_tm, u, mq, False)
                _block_matvec(md_start, md_phi_tm, v, mqv, False)
                _block_matvec(md_start, md_phi_tm, a, mqa, False)
                modal_current = True
            if pending >= 0:  # the last physical row still lacks its strain energy
                es = 0.0
                for j in range(n):
                    es += 0.5 * md_w2[j] * mq[j] * mq[j]
                out_e[pending, E_STRAIN] = es
                out_e[pending, E_DAMPING] -= es - es0
                pending = -1
            n_acc, event, th_hint, g_hint, e_in, w_int = _free_flight(
                step, nsteps, min(blk, nblk), store, (dt, beta, gamma), motion, mdb, blocks, row, gaps, (exact, ex_co),
                (d0, r0), st, outs, (e_in, w_int, e_cont, es0))
            stats[S_STEPS] += n_acc
            stats[S_FREE_FLIGHT] += n_acc
            stats[S_DOF_STEPS] += n_acc * n
            stats[S_BLOCKS] += 1
            step += n_acc
            t = step * dt
            _ground_all(ag, t, dt, g_t)
            if moving:
                _gap_ground_all(gap_ground, t, dt, gk, GU0)
            if n_acc > 0:
                for i in range(n):  # storey + damping forces from equilibrium (no contact)
                    fint[i] = -mass[i] * (g_t[dof_motion[i]] + a[i])
            if event:
                block_from = step + 1  # the physical path takes the event's step,
                hint_step = step  # starting on the event the block located
                modal_current = False
                blk = 16
            else:
                blk = min(2 * blk, nblk)
            continue
        modal_current = False
        t_end = (step + 1) * dt
        # ---- who steps: with multi-rate, the buildings of the closed gaps' groups; the others wait, taking
        # the whole analysis step at once (``_multirate``)
        n_wrun = _who_steps(m_act, act_list, multirate, wait_share, mr, runs)
        waiting = False
        if n_wrun > 0:
            t_w0 = t
            n_wrun = _waiting_step((step, t, dt), motion, g_t, n_wrun, mr, runs, ws, waits, row, gaps, st, (d0, r0),
                                   stats)
            waiting = n_wrun > 0
        if waiting:
            stats[S_WAITING] += 1
            if pending >= 0:  # the last output row's strain energy, over the whole row
                es = _strain_energy(el_i, el_j, el_k, u)
                out_e[pending, E_STRAIN] = es
                out_e[pending, E_DAMPING] -= es - es0
                pending = -1
        changed = False
        for b in range(nbk):
            changed = changed or in_s[b] != was_s[b]
        if changed:
            n_run, n_ss, n_scr, n_s_dof = _stepping(mr, runs)
            h_cached = -1.0  # the scratch factor covers the former stepping rows only
        while t_end - t > 1e-9 * dt:
            h, lev = _contact_step(t, t_end, dt, m_act, act_list, gap_law, hsub, age, h_lev, n_lev, 0)
            target = -1
            if aim_gap >= 0:
                ga = aim_gap
                aim_gap = -1
                if d0[ga] * r0[ga] < 0.0:  # still approaching the crossing
                    h_aim = -d0[ga] / r0[ga]
                    if hmin <= h_aim < h:
                        h = h_aim
                        target = ga
            if step == hint_step and t == step * dt and th_hint * h >= hmin:
                h = th_hint * h  # the block's Hermite root: the physical path's first guess too
                target = g_hint
            landed = False
            toggle_now = -1
            n_tog = 0
            n_land = 0
            located = False
            join_gap = -1
            # ======== ATTEMPT LOOP: predictor, contact Newton, event screen; redone up to an event ========
            for attempt in range(200):
                # ---- factor K_hat(h): cached per dt/2^k level, scratch otherwise (none for an
                # exact step with every gap open: the modal step needs no solve)
                modal_step = exact and m_act == 0
                lv, h = _grid_level(h, lev, h_lev, dt)
                ok, Lf, h_cached = _factor_for(lv, h, modal_step, h_cached, fac, row, p, (beta, gamma), runs, n_run,
                                               wc_key, stats)
                if not ok:
                    return NEWTON_FAILED, n_imp, t
                cm = 1.0 / (beta * h * h)
                cc = gamma / (beta * h)
                if h == dt and t == step * dt:  # a whole analysis step: on the record's grid
                    for r in range(nm):
                        g_1[r] = ag[r, step + 1]
                else:
                    _ground_all(ag, t + h, dt, g_1)
                if moving:
                    _gap_ground_all(gap_ground, t + h, dt, gk, GU1)
                # ---- PREDICTOR: the step with every contact force frozen at zero, on the stepping
                # buildings' runs (exact when no gap is closed)
                es = 0.0
                if modal_step:
                    # every gap open (around an event): the exact modal step, as in free flight
                    es = _exact_trial(h, g_t, g_1, beta, gamma, md_start, md_phi_t, md_phi_tm, md_w2, md_c, md_gam,
                                      ex_h, h_ex, u, v, mq, mqv, mqa, Du, Vv, Av)
                    modal_current = False
                else:
                    es = _newmark_predictor(n_run, r_lo, r_hi, r_elo, r_ehi, h, Lf, p, beta, gamma, mass, dof_a0,
                                            dof_motion, el_i, el_j, el_k, el_a1, g_1, u, v, a, Av, Vv, fs, fd, R0, Du)
                if pending >= 0:  # (the whole row steps here: a waiting step settled it already)
                    out_e[pending, E_STRAIN] = 0.5 * es
                    out_e[pending, E_DAMPING] -= 0.5 * es - es0
                    pending = -1
                stats[S_ITERATIONS] += 1
                stats[S_DOF_STEPS] += n_s_dof
                # ---- CONTACT NEWTON on the forces of the closed gaps (condensed through K_hat^-1)
                converged = m_act == 0
                if m_act > 0:
                    converged, it = _contact_newton((lv, h, cc, waiting), (Lf, L_h, p, n_run, runs),
                                                    (m_act, act_list, n_comp, comp_off), wc, semi, gaps,
                                                    (u, Du, Vv, R0, gk), gf, age, nwt,
                                                    (rtol, max_iter), stats)
                    stats[S_ITERATIONS] += it
                    if it > stats[S_MAX_ITER]:
                        stats[S_MAX_ITER] = it
                if not converged:
                    stats[S_REJECTED] += 1
                    h *= 0.25
                    target = -1
                    if h < hmin:
                        return NEWTON_FAILED, n_imp, t
                    continue
                # ---- EVENT SCREEN: does a gap open or close inside the step? (end states from Du)
                landed = False
                if target >= 0:
                    ii = gap_i[target]
                    jj = gap_j[target]
                    dtg, rtg = _gap_trial(u, Du, Vv, cc, ii, jj, gap_size[target], gk[GU1, target], gk[GV1, target])
                    landed = abs(dtg) <= LAND_TOL * max(abs(rtg), abs(r0[target])) * h + 1e-15
                if waiting:  # gaps with a waiting side: it moves along its own step's trajectory
                    _screen_waiting((t + h - t_w0) / dt, dt, cc, mr, n_ss, n_scr, gaps, (u, v, Du, Vv), ws, gk,
                                    (d_end, r_end))
                # screen every gap (or, while some building waits, those in the list scr: the
                # gaps with a stepping side; scr[n_ss:] have a waiting side, computed above)
                theta, g_ev, ev_waits, n_land = _screen_step(
                    waiting, scr, n_ss, n_scr, gap_i, gap_j, gap_size, gap_law, active, u, Du, Vv, cc, h, gk,
                    d0, r0, d_end, r_end, landed, target, land_too)
                if ev_waits:
                    # a waiting building may touch a stepping one in this substep: it
                    # catches up to the substep's start and steps from there (below)
                    stats[S_REJECTED] += 1
                    join_gap = g_ev
                    break
                if g_ev < 0:
                    located = True
                    if target >= 0 and not landed:
                        # the redo stopped just short of its event: aim the next step
                        # at it (linear in delta) instead of finding it again
                        aim_gap = target
                    break
                stats[S_REJECTED] += 1
                if theta * h < hmin:
                    # every gap whose event is at the current time switches now, together
                    # (identical floors touch at once: one attempt, not one per gap)
                    # (a second pass over the gaps' end states: rare, so not kept in the first)
                    n_tog = _at_once(h, hmin, scr, n_ss, n_scr, gaps, cs, (d0, r0, d_end, r_end), landed, target,
                                     toggles)
                    toggle_now = g_ev
                    located = True
                    break
                h = theta * h
                target = g_ev
            if join_gap >= 0:
                # ---- the waiting buildings of gap join_gap catch up to t and step from here
                hw = t - t_w0
                ok, e_in, w_int = _join(join_gap, hw, g_t, mr, ws, waits, row, st, umax, (e_in, w_int), stats)
                if not ok:
                    return NEWTON_FAILED, n_imp, t
                n_run, n_ss, n_scr, n_s_dof = _stepping(mr, runs)
                n_wrun = _runs(in_s, False, blk_dof, blk_el, w_lo, w_hi, w_elo, w_ehi)
                waiting = n_wrun > 0
                h_cached = -1.0  # the scratch factor lacks the joined rows
                aim_gap = -1
                s0 = hw / dt
                for qq in range(n_scr):  # gap states at t: the joined buildings are there now
                    g = scr[qq]
                    d0[g], r0[g] = _gap_state(g, s0, dt, in_s, dof_blk, gap_i, gap_j, gap_size, u, v, u_w1, v_w1,
                                              zero_n, v, 0.0, gk[GU0, g], gk[GV0, g])
                continue
            if not located:
                return NEWTON_FAILED, n_imp, t
            # (toggle_now >= 0: the events are at the current time, switched below without moving)
            if toggle_now < 0:
                # ======== ACCEPT / COMMIT: energy, state, peaks, contact forces ========
                stats[S_STEPS] += 1
                e_in, w_int, e_cont = _accept(h, (cm, cc), (g_t, g_1), (Du, Av, Vv), st, row, gaps, gf, cs, cat,
                                              outs, (m_act, act_list), (waiting, n_run, runs), (e_in, w_int, e_cont))
                if waiting:
                    for qq in range(n_scr):  # (the other gaps link waiting buildings only)
                        g = scr[qq]
                        d0[g] = d_end[g]
                        r0[g] = r_end[g]
                else:  # every gap was screened: swap
                    d0, d_end = d_end, d0
                    r0, r_end = r_end, r0
                t = t + h
                if abs(t - t_end) <= 1e-9 * dt:
                    t = t_end  # no round-off drift of the clock across analysis steps
                for r in range(nm):
                    g_t[r] = g_1[r]
                if moving:
                    _gap_ground_accept(gk)
                if landed:
                    toggles[0] = target
                    n_tog = 1
                    for k_t in range(n_land):  # gaps at their own crossing too (screen)
                        toggles[n_tog] = land_too[k_t]
                        n_tog += 1
            if n_tog > 0:
                # ---- SWITCH: an impact's onset (the law's onset hook) or end at each gap in toggles
                status, n_imp, m_act = _switch(toggles, n_tog, t, n_sub, st, gaps, gk, F, fmax, cs, cat, act_list,
                                               (n_imp, m_act))
                if status != OK:
                    return status, n_imp, t
                n_comp = _group_contacts(m_act, act_list, gap_lo, gap_hi, comp_off)
                _equilibrium(row, st, g_t, gaps, F, runs, n_run)
        if waiting:
            # ---- the waiting buildings' step is accepted with the stepping ones' last
            e_in, w_int = _commit_waiting(n_wrun, mr, runs, ws, row, gaps, gk, st, umax, (d0, r0), (e_in, w_int))
            waiting = False
        # ---- output at the analysis step ---------------------------------------
        step += 1
        if not store:
            continue  # peaks only (the no-pounding twin): no histories to write
        _output_row(step, st, g_t, row, F, outs, (e_in, w_int, e_cont))
        pending = step
    if pending >= 0:
        _internal(mass, dof_a0, el_i, el_j, el_k, el_a1, u, v, fs, fd)
        es = 0.0
        for i in range(n):
            es += 0.5 * fs[i] * u[i]
        out_e[pending, E_STRAIN] = es
        out_e[pending, E_DAMPING] -= es - es0
    keep_alive(owners)
    return OK, n_imp, t


@njit(cache=True)
def _start(dt, ag, row, gaps, n_sub, st, F, cs, cat, outs, g_t, dr, lists):
    """The state at t = 0: gaps already closing (touching bodies) start an impact, the accelerations follow
    from equilibrium, output row 0 is written and the closed gaps are listed and grouped.

    Tuples as in ``integrate_kernel``; dr = (d0, r0) each gap's penetration [m] and rate [m/s], filled;
    lists = (act_list, comp_off), filled.  Returns (status, n_impacts, gaps closed, contact groups, energy
    present at t = 0 [J] (counted as input), strain energy at t = 0 [J])."""
    mass, dof_a0, dof_motion, el_i, el_j, el_k, el_a1 = row
    gap_i, gap_j, gap_lo, gap_hi, gap_size, gap_law, gap_par = gaps
    u, v, a, fint, fs, fd = st
    active, st_c, cur_imp, imp_fmax = cs[0], cs[1], cs[4], cat[4]
    out_u, out_v, out_a, out_f, out_e, umax, fmax = outs
    d0, r0 = dr
    act_list, comp_off = lists
    n = mass.size
    ng = gap_size.size
    n_imp = 0
    for g in range(ng):
        if gap_law[g] == NONE:
            continue
        dg, rg = _gap_deformation(u, v, gap_i[g], gap_j[g], gap_size[g], 0.0, 0.0)
        if dg > 0.0 or (dg == 0.0 and rg > 0.0):
            if n_imp >= imp_fmax.size:
                return IMPACT_CAPACITY, n_imp, 0, 0, 0.0, 0.0
            _begin_impact(g, 0.0, dg, rg, gap_law[g], gap_par[g], n_sub, cs, cat, n_imp)
            n_imp += 1
    _internal(mass, dof_a0, el_i, el_j, el_k, el_a1, u, v, fs, fd)
    _ground_all(ag, 0.0, dt, g_t)
    es0 = 0.0
    ek = 0.0
    for i in range(n):
        fint[i] = fs[i] + fd[i]
        a[i] = -g_t[dof_motion[i]] - fint[i] / mass[i]
        es0 += 0.5 * fs[i] * u[i]
        ek += 0.5 * mass[i] * v[i] * v[i]
    for g in range(ng):
        F[g] = 0.0
        if active[g]:
            dg, rg = _gap_deformation(u, v, gap_i[g], gap_j[g], gap_size[g], 0.0, 0.0)
            F[g] = contact_force(gap_law[g], gap_par[g], dg, rg, st_c[g, ST_ZETA])[0]
            a[gap_i[g]] -= F[g] / mass[gap_i[g]]
            a[gap_j[g]] += F[g] / mass[gap_j[g]]
            imp_fmax[cur_imp[g]] = max(F[g], 0.0)
    e_in = ek + es0
    for i in range(n):
        out_u[0, i] = u[i]
        out_v[0, i] = v[i]
        out_a[0, i] = a[i] + g_t[dof_motion[i]]
        umax[i] = abs(u[i])
    for g in range(ng):
        out_f[0, g] = F[g]
        fmax[g] = max(F[g], 0.0)
    out_e[0, E_INPUT] = e_in
    out_e[0, E_KINETIC] = ek
    out_e[0, E_STRAIN] = es0
    out_e[0, E_DAMPING] = 0.0
    out_e[0, E_CONTACT] = 0.0
    m_act = 0  # gaps in contact, listed in act_list (kept up to date at events)
    for g in range(ng):
        d0[g], r0[g] = _gap_deformation(u, v, gap_i[g], gap_j[g], gap_size[g], 0.0, 0.0)
        if active[g]:
            act_list[m_act] = g
            m_act += 1
    # the closed gaps in groups that share no building (updated at every event)
    return OK, n_imp, m_act, _group_contacts(m_act, act_list, gap_lo, gap_hi, comp_off), e_in, es0


@njit(cache=True)
def _switch(toggles, n_tog, t, n_sub, st, gaps, gk, F, fmax, cs, cat, act_list, counts):
    """Switch the gaps toggles[:n_tog] at time t: an impact's onset (the law's onset hook, its force F[g]
    [N]) where the gap was open, its end where it was closed.  counts = (impacts so far, gaps closed);
    returns (status, impacts, gaps closed)."""
    u, v = st[0], st[1]
    gap_i, gap_j, gap_size, gap_law, gap_par = gaps[0], gaps[1], gaps[4], gaps[5], gaps[6]
    active = cs[0]
    n_imp, m_act = counts
    for k_t in range(n_tog):
        g = toggles[k_t]
        dg, rg = _gap_deformation(u, v, gap_i[g], gap_j[g], gap_size[g], gk[GU0, g], gk[GV0, g])
        if not active[g]:
            if n_imp >= cat[0].size:
                return IMPACT_CAPACITY, n_imp, m_act
            F[g] = _begin_impact(g, t, dg, rg, gap_law[g], gap_par[g], n_sub, cs, cat, n_imp)
            if F[g] > fmax[g]:
                fmax[g] = F[g]
            n_imp += 1
            act_list[m_act] = g
            m_act += 1
        else:
            m_act = _end_impact(g, t, rg, m_act, act_list, cs, cat)
            F[g] = 0.0
    return OK, n_imp, m_act


@njit(cache=True)
def _equilibrium(row, st, g_t, gaps, F, runs, n_run):
    """The accelerations from equilibrium at fixed (u, v) on the stepping buildings' runs (the waiting ones
    are still at their step's start): a contact force may jump at an event (LVe's dashpot), and the jump
    does no work."""
    mass, dof_a0, dof_motion, el_i, el_j, el_k, el_a1 = row
    u, v, a, fint, fs, fd = st
    r_lo, r_hi, r_elo, r_ehi = runs[0], runs[1], runs[2], runs[3]
    gap_i, gap_j = gaps[0], gaps[1]
    for rr in range(n_run):
        _internal_range(mass, dof_a0, el_i, el_j, el_k, el_a1, u, v, fs, fd, r_lo[rr], r_hi[rr],
                        r_elo[rr], r_ehi[rr])
        for i in range(np.uint64(r_lo[rr]), np.uint64(r_hi[rr])):
            fint[i] = fs[i] + fd[i]
            a[i] = -g_t[dof_motion[i]] - fint[i] / mass[i]
    for q in range(F.size):
        if F[q] != 0.0:
            a[gap_i[q]] -= F[q] / mass[gap_i[q]]
            a[gap_j[q]] += F[q] / mass[gap_j[q]]


@njit(cache=True)
def _commit_waiting(n_wrun, mr, runs, ws, row, gaps, gk, st, umax, dr, energy):
    """Accept the waiting buildings' analysis step with the stepping ones' last substep, and set the
    penetration and rate (dr = (d0, r0)) of every gap with a waiting side.  energy = (e_in, w_int) [J];
    returns them updated."""
    e_in, w_int = energy
    in_s, dof_blk = mr[5], mr[2]
    w_lo, w_hi = runs[4], runs[5]
    g_w0, g_w1, du_w, v_w1, a_w1 = ws[0], ws[1], ws[2], ws[4], ws[5]
    mass, dof_motion = row[0], row[2]
    gap_i, gap_j, gap_size = gaps[0], gaps[1], gaps[4]
    u, v, a, fint = st[0], st[1], st[2], st[3]
    d0, r0 = dr
    for w in range(n_wrun):
        e_in, w_int = _waiting_commit(w_lo[w], w_hi[w], mass, dof_motion, g_w0, g_w1, du_w, v_w1, a_w1,
                                      u, v, a, fint, umax, e_in, w_int)
    for g in range(gap_size.size):
        if not (in_s[dof_blk[gap_i[g]]] and in_s[dof_blk[gap_j[g]]]):
            d0[g], r0[g] = _gap_deformation(u, v, gap_i[g], gap_j[g], gap_size[g], gk[GU0, g], gk[GV0, g])
    return e_in, w_int


@njit(cache=True, inline="always")
def _output_row(k, st, g_t, row, F, outs, energy):
    """Write output row k: the state (absolute accelerations), the gaps' forces and the energies
    (energy = (e_in, w_int, e_cont) [J]; the strain energy, and the damping's share of w_int, follow when
    K u is next formed)."""
    u, v, a = st[0], st[1], st[2]
    mass, dof_motion = row[0], row[2]
    out_u, out_v, out_a, out_f, out_e = outs[0], outs[1], outs[2], outs[3], outs[4]
    e_in, w_int, e_cont = energy
    ek = 0.0
    for i in range(u.size):
        out_u[k, i] = u[i]
        out_v[k, i] = v[i]
        out_a[k, i] = a[i] + g_t[dof_motion[i]]
        ek += 0.5 * mass[i] * v[i] * v[i]
    for g in range(F.size):
        out_f[k, g] = F[g]
    out_e[k, E_INPUT] = e_in
    out_e[k, E_KINETIC] = ek
    out_e[k, E_DAMPING] = w_int  # strain energy subtracted when K u is next formed
    out_e[k, E_CONTACT] = e_cont


@njit(cache=True, inline="always")
def _contact_newton(kind, lin, act, wc, semi, gaps, trial, gf, age, nwt, opts, stats):
    """Newton-Raphson on the closed gaps' forces, condensed through K_hat^-1 (module docstring), one
    iteration per independent group; the increment Du then loses the contact forces' share.

    G = B^T K_hat^-1 B on the gaps in contact: a level factor (or a wider band) keeps Woodbury columns
    K_hat^-1 b_g, cached per factor, that serve every step of that size; a located step's one-off factor,
    with several gaps closed, takes G from the semiseparable inverse in O(n + m^2) instead of m new
    columns in O(n m).

    kind = (grid level or -1, h [s], gamma/(beta h) [1/s], some building waits); lin = (the factor Lf, the
    scratch factor L_h, half bandwidth, stepping runs, runs); act = (gaps closed, their list, groups, group
    offsets); wc = (columns and their flags for the level and the scratch factor, key (3,): the level and
    the step they are for and whether the semiseparable inverse is current, batch); semi = (sig_h, Sd_h,
    dofs, order, pos, span, Kd, xs); trial = (u, Du, Vv, R0, gk); gf = (F, F1, F_old, h_old); nwt = (Gm, dl,
    rl, Fm, resv, kt, Sm, ym, st_c, st_t); opts = (rtol, max_iter).
    Returns (converged, iterations); F1 holds the forces [N]."""
    lv, h, cc, waiting = kind
    Lf, L_h, p, n_run, runs = lin
    m_act, act_list, n_comp, comp_off = act
    Wc_level, Wc_ok_level, Wc_scratch, Wc_ok_scratch, wc_key, batch = wc
    sig_h, Sd_h, dofs, order, pos, span, Kd, xs = semi
    gap_i, gap_j, gap_lo, gap_hi, gap_size, gap_law, gap_par = gaps
    u, Du, Vv, R0, gk = trial
    F, F1, F_old, h_old = gf
    Gm, dl, rl, Fm, resv, kt, Sm, ym, st_c, st_t = nwt
    rtol, max_iter = opts
    r_lo, r_hi = runs[0], runs[1]
    ngw = batch.size
    columns = lv >= 0 or p > 1 or m_act < SEMISEPARABLE_GAPS
    Wc = Wc_level
    Wc_ok = Wc_ok_level
    if not columns:  # the scratch factor L_h
        if wc_key[2] == 0.0:
            for rr in range(n_run):
                _inverse_diagonals_range(L_h, p, sig_h, Sd_h, r_lo[rr], r_hi[rr])
            wc_key[2] = 1.0
        for c in range(n_comp):  # G's diagonal blocks, one group at a time
            _compliance_tridiagonal(comp_off[c], comp_off[c + 1], act_list, gap_i, gap_j, sig_h, Sd_h,
                                    Gm, dofs, order, pos, span, Kd)
    elif lv >= 0:
        if lv != wc_key[0]:
            for g in range(ngw):
                Wc_ok_level[g] = False
            wc_key[0] = lv
    else:
        if h != wc_key[1]:
            for g in range(ngw):
                Wc_ok_scratch[g] = False
            wc_key[1] = h
        Wc = Wc_scratch
        Wc_ok = Wc_ok_scratch
    for q in range(m_act if columns else 0):
        g = act_list[q]
        if not Wc_ok[g]:
            # every missing column on the same blocks, solved together
            nr = 0
            for q2 in range(q, m_act):
                g2 = act_list[q2]
                if not Wc_ok[g2] and gap_lo[g2] == gap_lo[g] and gap_hi[g2] == gap_hi[g]:
                    batch[nr] = g2
                    nr += 1
                    Wc_ok[g2] = True
            _woodbury_columns(Lf, p, Wc, batch, nr, gap_lo[g], gap_hi[g], gap_i, gap_j)
    # Newton on the closed gaps' forces alone, scaled by the largest residual of the predictor
    scale = 0.0
    if waiting:
        for rr in range(n_run):
            for i in range(np.uint64(r_lo[rr]), np.uint64(r_hi[rr])):
                scale = max(scale, abs(R0[i]))
    else:
        for i in range(u.size):
            scale = max(scale, abs(R0[i]))
    for q in range(m_act):
        g = act_list[q]
        dl[q], rl[q] = _gap_trial(u, Du, Vv, cc, gap_i[g], gap_j[g], gap_size[g], gk[GU1, g], gk[GV1, g])
        Fm[q] = F[g]  # start from the force at the start of the step,
        if age[g] >= 1:  # extrapolated along the last accepted substep
            Fm[q] += (F[g] - F_old[g]) * (h / h_old[g])
    if columns:  # G is block diagonal over the groups: fill the blocks only
        for c in range(n_comp):
            for q in range(comp_off[c], comp_off[c + 1]):
                g = act_list[q]
                ii = gap_i[g]
                jj = gap_j[g]
                for r in range(comp_off[c], comp_off[c + 1]):
                    gr = act_list[r]
                    Gm[q, r] = Wc[gr, ii] - Wc[gr, jj]
    # one Newton iteration per independent group: O(sum m_c^3), not O(m^3)
    converged = True
    it = 0
    for c in range(n_comp):
        ok_c, it_c = _newton((comp_off[c], comp_off[c + 1], act_list), Gm, (dl, rl, Fm, cc), gap_law, gap_par,
                             (st_c, st_t), (scale, rtol, max_iter), (resv, kt, Sm, ym))
        converged = converged and ok_c
        it = max(it, it_c)
        if not ok_c:
            break
    for q in range(m_act):
        g = act_list[q]
        F1[g] = Fm[q]
        if columns and Fm[q] != 0.0:
            for i in range(np.uint64(gap_lo[g]), np.uint64(gap_hi[g])):
                Du[i] -= Fm[q] * Wc[g, i]
    if not columns:
        _subtract_contact(L_h, p, m_act, act_list, gap_i, gap_j, gap_lo, gap_hi, Fm, xs, Du)
    return converged, it


@njit(cache=True, inline="always")
def _factor_for(lv, h, modal_step, h_cached, fac, row, p, nb, runs, n_run, wc_key, stats):
    """K_hat(h)'s factor for a step of h [s]: the level's (lv >= 0: h = dt / 2^lv, factored once), the scratch
    factor otherwise, refactored on the stepping buildings' runs when h changed; none for an exact step with
    every gap open (``modal_step``: the modal step needs no solve).  fac = (L_lev, have_lev, L_h); nb = (beta,
    gamma); h_cached: the step the scratch factor holds.  Returns (ok, the factor, the scratch factor's step)."""
    L_lev, have_lev, L_h = fac
    mass, dof_a0, dof_motion, el_i, el_j, el_k, el_a1 = row
    beta, gamma = nb
    r_lo, r_hi, r_elo, r_ehi = runs[0], runs[1], runs[2], runs[3]
    if lv >= 0:
        if not have_lev[lv] and not modal_step:
            if not _factor(h, beta, gamma, mass, dof_a0, el_i, el_j, el_k, el_a1, p, L_lev[lv]):
                return False, L_h, h_cached
            have_lev[lv] = True
            stats[S_FACTORIZATIONS] += 1
        return True, L_lev[lv], h_cached
    if not modal_step and abs(h - h_cached) > 1e-14 * h:
        for rr in range(n_run):  # the stepping buildings' rows
            if not _factor_range(h, beta, gamma, mass, dof_a0, el_i, el_j, el_k, el_a1, p, L_h,
                                 r_lo[rr], r_hi[rr], r_elo[rr], r_ehi[rr]):
                return False, L_h, h_cached
        stats[S_FACTORIZATIONS] += 1
        h_cached = h
        wc_key[2] = 0.0  # its semiseparable inverse is stale
    return True, L_h, h_cached


@njit(cache=True, inline="always")
def _screen_waiting(s1, dt, cc, mr, n_ss, n_scr, gaps, trial, ws, gk, ends):
    """The end state of each gap with a waiting side (scr[n_ss:n_scr]) at the end of a substep: the stepping
    side at u + Du, the waiting side on its own step's cubic Hermite trajectory (``_waiting_state``) at the
    fraction s1 of the analysis step.  trial = (u, v, Du, Vv); ends = (d_end, r_end), filled.

    The Hermite weights are computed once per attempt, in a loop of their own: calling _gap_state per gap
    instead, even inlined, made 4 x 10 storeys 12 % slower in same-process A/B (it recomputes them per
    side)."""
    dof_blk, in_s, scr = mr[2], mr[5], mr[7]
    gap_i, gap_j, gap_size = gaps[0], gaps[1], gaps[4]
    u, v, Du, Vv = trial
    u_w1, v_w1 = ws[3], ws[4]
    d_end, r_end = ends
    s2 = s1 * s1
    s3 = s2 * s1
    wu0 = 2 * s3 - 3 * s2 + 1
    wv0 = (s3 - 2 * s2 + s1) * dt
    wu1 = -2 * s3 + 3 * s2
    wv1 = (s3 - s2) * dt
    xu = (6 * s2 - 6 * s1) / dt  # derivative: xd = xu (u0 - u1) + xv0 v0 + xv1 v1
    xv0 = 3 * s2 - 4 * s1 + 1
    xv1 = 3 * s2 - 2 * s1
    for qq in range(n_ss, n_scr):
        g = scr[qq]
        ii = np.uint64(gap_i[g])
        jj = np.uint64(gap_j[g])
        if in_s[dof_blk[ii]]:
            xi = u[ii] + Du[ii]
            vi = Vv[ii] + cc * Du[ii]
        else:
            xi = wu0 * u[ii] + wv0 * v[ii] + wu1 * u_w1[ii] + wv1 * v_w1[ii]
            vi = xu * (u[ii] - u_w1[ii]) + xv0 * v[ii] + xv1 * v_w1[ii]
        if in_s[dof_blk[jj]]:
            xj = u[jj] + Du[jj]
            vj = Vv[jj] + cc * Du[jj]
        else:
            xj = wu0 * u[jj] + wv0 * v[jj] + wu1 * u_w1[jj] + wv1 * v_w1[jj]
            vj = xu * (u[jj] - u_w1[jj]) + xv0 * v[jj] + xv1 * v_w1[jj]
        d_end[g], r_end[g] = _gap_kinematics(xi, 0.0, xj, 0.0, vi, 0.0, vj, 0.0, gap_size[g], gk[GU1, g], gk[GV1, g])


@njit(cache=True, inline="always")
def _at_once(h, hmin, scr, n_ss, n_scr, gaps, cs, states, landed, target, toggles):
    """Every gap whose event is at the current time (within hmin of the step's start): they switch now,
    together (identical floors touch at once: one attempt, not one per gap); a gap with a waiting side is
    found again in the next attempt, and joins then.  states = (d0, r0, d_end, r_end).  Fills toggles;
    returns their number."""
    gap_law = gaps[5]
    active = cs[0]
    d0, r0, d_end, r_end = states
    n_tog = 0
    for qq in range(n_ss):
        g = scr[qq]
        if gap_law[g] == NONE or (landed and g == target):
            continue
        tol = LAND_TOL * max(abs(r0[g]), abs(r_end[g])) * h + 1e-15
        if _event_in_step(d0[g], r0[g], d_end[g], r_end[g], h, not active[g], tol) * h < hmin:
            toggles[n_tog] = g
            n_tog += 1
    return n_tog


@njit(cache=True, inline="always")
def _accept(h, coef, grd, incr, st, row, gaps, gf, cs, cat, outs, act, rate, energy):
    """Accept the trial step of h [s] on the stepping buildings' rows: state, peaks, each closed gap's force
    and its peak between the last three samples of its impact, and the energies by the trapezoidal work.
    coef = (1/(beta h^2), gamma/(beta h)); grd = (g_t, g_1) the ground accelerations at its ends; incr =
    (Du, Av, Vv); act = (gaps closed, their list); rate = (some building waits, stepping runs, runs); energy =
    (e_in, w_int, e_cont) [J], returned updated."""
    cm, cc = coef
    g_t, g_1 = grd
    Du, Av, Vv = incr
    u, v, a, fint = st[0], st[1], st[2], st[3]
    mass, dof_motion = row[0], row[2]
    gap_i, gap_j = gaps[0], gaps[1]
    F, F1, F_old, h_old = gf
    age, cur_imp = cs[3], cs[4]
    imp_fmax = cat[4]
    umax, fmax = outs[5], outs[6]
    m_act, act_list = act
    waiting, n_run, runs = rate
    e_in, w_int, e_cont = energy
    if waiting:
        for rr in range(n_run):
            e_in, w_int = _accept_rows(runs[0][rr], runs[1][rr], cm, cc, mass, dof_motion, g_t, g_1, Du, Av, Vv,
                                       fint, u, v, a, umax, e_in, w_int)
    else:
        e_in, w_int = _accept_rows(0, u.size, cm, cc, mass, dof_motion, g_t, g_1, Du, Av, Vv,
                                   fint, u, v, a, umax, e_in, w_int)
    for q in range(m_act):
        gq = act_list[q]
        ii = gap_i[gq]
        jj = gap_j[gq]
        age[gq] += 1
        w_int -= 0.5 * F1[gq] * (Du[ii] - Du[jj])
        fint[ii] -= F1[gq]
        fint[jj] += F1[gq]
        e_cont += 0.5 * (F[gq] + F1[gq]) * (Du[ii] - Du[jj])
        # the force's peak between the last three samples of this impact
        fpk = _peak_through(F_old[gq], F[gq], F1[gq], h_old[gq], h) if age[gq] >= 2 else F1[gq]
        fpk = max(fpk, F1[gq])
        F_old[gq] = F[gq]
        h_old[gq] = h
        F[gq] = F1[gq]
        if fpk > fmax[gq]:
            fmax[gq] = fpk
        if fpk > imp_fmax[cur_imp[gq]]:
            imp_fmax[cur_imp[gq]] = fpk
    return e_in, w_int, e_cont
