"""The phases of the time loop (``_driver.drive``) on the two-node linear part (the fast driver):
Newmark-beta with event-located contact, compiled with numba.

Private: call :func:`seispound.integrate.integrate`, which validates inputs and
allocates the outputs; ``_driver.integrate_kernel`` sets this linear part up and
runs the loop.  Everything here takes arrays and scalars only.

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
from ._contact import _begin_impact, _contact_step, _end_impact, _grid_level, _group_contacts, _peak_through
from ._elements import _gap_deformation, _gap_kinematics, _gap_trial
from ._events import ACCEPT, AT_ONCE, JOIN, LAND_TOL, REDO, _event_in_step, _landed, _screen_step
from ._free_flight import _block_matvec, _exact_trial, _free_flight
from ._ground import GU0, GU1, GV0, GV1, _gap_ground_all, _ground_all, _tick
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
from ._material import N_CONTACT_STATE, ST_ZETA
from ._multirate import _gap_state, _join, _runs, _stepping, _waiting_commit, _waiting_step, _who_steps
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

N_LEV = 40  # K_hat's factors kept for h = dt / 2^k, k < N_LEV


@njit(cache=True)
def _fast_work(n, nm, p, settings, modal, multi, gaps, init):
    """The fast driver's work arrays, allocated once (its loop allocates nothing), in named groups.

    n DOFs, nm motion rows, p the half bandwidth; the other arguments as ``_driver.integrate_kernel`` takes them.
    Returns (fac, st, incr, wc, semi, nwt, lists, cs, gf, ev, mr, runs, ws, blocks, mw):
    fac = (L_lev, have_lev, L_h): K_hat's factors for h = dt / 2^k (contact substeps stay on this grid, so
    each level is factored once) and one scratch factor for odd steps;
    st = (u, v, a, fint, fs, fd): the state and the storey + damping forces in equilibrium with it;
    incr = (Du, R0, Av, Vv): the step's increment (kept apart: recomputing u1 - u loses digits on short
    steps), the predictor's residual and Newmark's terms;
    wc = (Wc_level, Wc_ok_level, Wc_scratch, Wc_ok_scratch, wc_key, batch): the Woodbury columns
    K_hat^-1 b_g of the level and the scratch factor (nonzero only on the DOFs of the two buildings a gap
    links), the level and the step they are for and whether the semiseparable inverse is current;
    semi = (sig_h, Sd_h, dofs, order, pos, span, Kd, xs): the scratch factor's semiseparable inverse
    (tridiagonal or diagonal K_hat only), computed when a located step with several gaps closed needs it;
    nwt = (Gm, dl, rl, Fm, resv, kt, Sm, ym): the contact Newton's work;
    lists = (act_list, comp_off, toggles, land_too): the closed gaps in groups that share no building, the
    gaps switched together;
    cs = (active, st_c, st_t, hsub, age, cur_imp): each gap's contact and law state;
    gf = (F, F1, F_old, h_old): the gaps' forces at t, in the trial and at the last accepted substep;
    ev = (d0, r0, d_end, r_end, gk, g_t, g_1): each gap's penetration and rate at the step's start and
    end, its differential ground terms (rows GU0, GV0 at t, GU1, GV1 at the trial's end: one array, since
    each live array in the loop costs registers), the ground accelerations at t and the trial's end;
    mr = (dof_blk, gb_lo, gb_hi, in_s, was_s, scr): each DOF's building, the buildings each gap links,
    who steps now and before, the gaps screened (``_multirate``); runs: the stepping and waiting runs;
    ws = (g_w0, g_w1, du_w, u_w1, v_w1, a_w1, L_w, zero_n): the waiting step;
    blocks: the free-flight blocks' modal state and histories (``_free_flight``);
    mw = (md_khinv, ex_h, h_ex, h_lev): the modal K_hat^-1, the exact step's coefficients for the last odd
    step h_ex[0], and h per level.
    """
    dt, beta, gamma = settings[0], settings[2], settings[3]
    use_modal, md_w2, md_c, nblk, exact = modal[0], modal[6], modal[7], modal[9], modal[10]
    blk_dof, gap_lo, gap_hi = multi[2], gaps[2], gaps[3]
    ng = gaps[4].size
    ngw = max(ng, 1)
    tri = p <= 1
    h_lev = np.empty(N_LEV)
    for k in range(N_LEV):
        h_lev[k] = dt / 2.0**k
    fac = (np.empty((N_LEV, n, p + 2)), np.zeros(N_LEV, np.bool_), np.empty((n, p + 2)))
    st = (init[0].copy(), init[1].copy(), np.empty(n), np.empty(n), np.empty(n), np.empty(n))
    incr = (np.empty(n), np.empty(n), np.empty(n), np.empty(n))
    wc = (np.zeros((ngw, n)), np.zeros(ngw, np.bool_), np.zeros((ngw, n)), np.zeros(ngw, np.bool_),
          np.array([-2.0, -1.0, 0.0]), np.empty(ngw, np.int64))
    semi = (np.empty(n if tri else 1), np.empty(n if tri else 1), np.empty(2 * ngw, np.int64),
            np.empty(2 * ngw, np.int64), np.empty(2 * ngw, np.int64), np.empty(2 * ngw),
            np.empty((2 * ngw, 2 * ngw) if tri else (1, 1)), np.empty(n))
    nwt = (np.empty((ngw, ngw)), np.empty(ngw), np.empty(ngw), np.empty(ngw), np.empty(ngw), np.zeros(ng),
           np.empty((ngw, ngw)), np.empty(ngw))
    lists = (np.empty(ngw, np.int64), np.empty(ngw + 1, np.int64), np.empty(ngw, np.int64), np.empty(ngw, np.int64))
    cs = (np.zeros(ng, np.bool_), np.zeros((ng, N_CONTACT_STATE)), np.zeros((ng, N_CONTACT_STATE)), np.zeros(ng),
          np.zeros(ng, np.int64), -np.ones(ng, np.int64))
    gf = (np.zeros(ng), np.zeros(ng), np.zeros(ng), np.ones(ng))
    ev = (np.empty(ng), np.empty(ng), np.empty(ng), np.empty(ng), np.zeros((4, ng)), np.empty(nm), np.empty(nm))
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
    mr = (dof_blk, gb_lo, gb_hi, np.ones(nbk, np.bool_), np.ones(nbk, np.bool_), np.empty(ngw, np.int64))
    runs = (np.empty(nbk, np.int64), np.empty(nbk, np.int64), np.empty(nbk, np.int64), np.empty(nbk, np.int64),
            np.empty(nbk, np.int64), np.empty(nbk, np.int64), np.empty(nbk, np.int64), np.empty(nbk, np.int64))
    ws = (np.empty(nm), np.empty(nm), np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty((n, p + 2)),
          np.zeros(n))
    nbw = nblk if use_modal else 1
    nq = n if use_modal or exact else 0
    blocks = (np.empty(nbw * nq), np.empty(nbw * nq), np.empty(nq), np.empty(nq), np.empty(nq), np.empty((nbw, nq)),
              np.empty((nbw, nq)), np.empty((nbw, nq)), np.empty((nbw, nq)), np.empty((nbw + 1, nq)),
              np.empty((nbw, nq)), np.empty((nbw, nq)), np.empty(nq), np.empty((4, nbw)))
    md_khinv = np.empty(nq)
    for j in range(nq):
        md_khinv[j] = 1.0 / (md_w2[j] + gamma / (beta * dt) * md_c[j] + 1.0 / (beta * dt * dt))
    mw = (md_khinv, np.empty((8, nq if exact else 0)), np.full(1, -1.0), h_lev)
    return fac, st, incr, wc, semi, nwt, lists, cs, gf, ev, mr, runs, ws, blocks, mw


@njit(cache=True, inline="always")
def _fly(step, t, cnt, energy, lp, model, work, outs, stats):
    """FREE FLIGHT (``_driver._fly``): with a modal basis (``use_modal``), every gap open and the block's
    start reached, march a block of analysis steps from ``step`` in modal coordinates (``_free_flight``), up
    to the first step in which a gap may close, which the physical path then takes from the block's own
    root estimate.

    lp = (ps, fb, pending, wt) (``_driver.integrate_kernel``): fb = (the first step a block may start, block
    length, the step a block saw an event in, its fraction and gap, whether the modal state is current);
    pending: the output row that still lacks its strain energy.  Blocks start at 16 steps after an impact
    and double up to nblk.  Returns (flew, step, t, energy, lp).
    """
    ps, fb, pending, wt = lp
    if not (model[5][0] and cnt[1] == 0 and step >= fb[0]):
        return False, step, t, energy, (ps, fb[:5] + (False,), pending, wt)
    block_from, blk, hint_step, th_hint, g_hint, modal_current = fb
    row, gaps, motion, settings, modal, es0 = model[0], model[2], model[3], model[4], model[5], model[8]
    dt, nsteps, beta, gamma, store = settings[0], settings[1], settings[2], settings[3], settings[7]
    st, ev, blocks, mw = work[1], work[9], work[13], work[14]
    mq, mqv, mqa = blocks[2], blocks[3], blocks[4]
    md_start, md_phi_tm, md_w2 = modal[1], modal[5], modal[6]
    mass, dof_motion = row[0], row[2]
    u, v, a, fint = st[0], st[1], st[2], st[3]
    g_t = ev[5]
    out_e = outs[4]
    n = mass.size
    if not modal_current:
        _block_matvec(md_start, md_phi_tm, u, mq, False)
        _block_matvec(md_start, md_phi_tm, v, mqv, False)
        _block_matvec(md_start, md_phi_tm, a, mqa, False)
    if pending >= 0:  # the last physical row still lacks its strain energy
        es = 0.0
        for j in range(n):
            es += 0.5 * md_w2[j] * mq[j] * mq[j]
        out_e[pending, E_STRAIN] = es
        out_e[pending, E_DAMPING] -= es - es0
    mdb = (md_start, modal[2], modal[3], modal[4], md_w2, modal[7], modal[8], mw[0])
    n_acc, event, th_hint, g_hint, e_in, w_int = _free_flight(
        (step, nsteps, min(blk, modal[9]), store), (dt, beta, gamma), motion, mdb, blocks, row, gaps,
        (modal[10], modal[11]), (ev[0], ev[1]), st, outs, energy + (es0,))
    stats[S_STEPS] += n_acc
    stats[S_FREE_FLIGHT] += n_acc
    stats[S_DOF_STEPS] += n_acc * n
    stats[S_BLOCKS] += 1
    step += n_acc
    t = step * dt
    _ground_all(motion[0], t, dt, g_t)
    if motion[1]:
        _gap_ground_all(motion[2], t, dt, ev[4], GU0)
    if n_acc > 0:
        for i in range(n):  # storey + damping forces from equilibrium (no contact)
            fint[i] = -mass[i] * (g_t[dof_motion[i]] + a[i])
    energy = (e_in, w_int, energy[2])
    if event:  # the physical path takes the event's step, starting on the event the block located
        return True, step, t, energy, (ps, (step + 1, 16, step, th_hint, g_hint, False), -1, wt)
    return True, step, t, energy, (ps, (block_from, min(2 * blk, modal[9]), hint_step, th_hint, g_hint, True), -1, wt)


@njit(cache=True, inline="always")
def _begin(step, t, cnt, lp, model, work, outs, stats):
    """The analysis step's start on the physical path: who steps (with multi-rate stepping, the buildings of
    the closed gaps' groups; the others wait, taking the whole analysis step at once: ``_multirate``).

    lp = (ps, fb, pending, wt): ps = (the scratch factor's step, a gap aimed at, stepping runs, gaps screened
    with stepping sides only, gaps screened, stepping DOFs); pending: the output row waiting for its strain
    energy; wt = (some building waits, their runs, the waiting step's start).  Returns lp.
    """
    ps, fb, pending = lp[0], lp[1], lp[2]
    m_act = cnt[1]
    row, gaps, motion, multi, es0 = model[0], model[2], model[3], model[6], model[8]
    dt = model[4][0]
    st, lists, ev, mr, runs, ws = work[1], work[6], work[9], work[10], work[11], work[12]
    n_wrun = _who_steps(m_act, lists[0], multi[0], multi[1], mr, runs)
    waiting = False
    if n_wrun > 0:
        n_wrun = _waiting_step((step, t, dt), motion, n_wrun, mr, runs, ws, _waits(model, work), row, gaps, st,
                               (ev[0], ev[1], ev[5]), stats)
        waiting = n_wrun > 0
    if waiting:
        stats[S_WAITING] += 1
        if pending >= 0:  # the last output row's strain energy, over the whole row
            pending = _settle(pending, _strain_energy(row[3], row[4], row[5], st[0]), es0, outs[4])
    changed = False
    for b in range(mr[5].size):
        changed = changed or mr[5][b] != mr[6][b]
    if changed:  # (the scratch factor covers the former stepping rows only)
        ps = (-1.0, ps[1]) + _stepping(mr, runs)
    return ps, fb, pending, (waiting, n_wrun, t)


@njit(cache=True, inline="always")
def _substep(step, t, cnt, lp, model, work):
    """A substep's size from t [s]: the rest of the analysis step or the contact substep grid
    (``_contact._contact_step``), aimed at the event a step stopped just short of (lp's ps[1], linear in
    delta) or at the one a free-flight block located (lp's fb: ``_fly``'s event hint).
    Returns (h [s], its grid level, the gap aimed at or -1)."""
    m_act, aim_gap, fb = cnt[1], lp[0][1], lp[1]
    gaps = model[2]
    dt = model[4][0]
    lists, cs, ev, mw = work[6], work[7], work[9], work[14]
    d0, r0 = ev[0], ev[1]
    hmin = 1e-9 * dt
    h, lev = _contact_step(t, (step + 1) * dt, dt, m_act, lists[0], gaps[5], cs[2], cs[3], mw[3], N_LEV, 0)
    target = -1
    if aim_gap >= 0 and d0[aim_gap] * r0[aim_gap] < 0.0:  # still approaching the crossing
        h_aim = -d0[aim_gap] / r0[aim_gap]
        if hmin <= h_aim < h:
            h = h_aim
            target = aim_gap
    if step == fb[2] and t == step * dt and fb[3] * h >= hmin:
        h = fb[3] * h  # the block's Hermite root: the physical path's first guess too
        target = fb[4]
    return h, lev, target


@njit(cache=True, inline="always")
def _screen(h, coef, t, target, lp, model, work, stats):
    """The EVENT SCREEN of a converged trial step of h [s] from t: does a gap open or close inside it?

    End states from the increments (coef = gamma/(beta h)); a gap with a waiting side moves along its own
    step's trajectory (lp's wt = (some building waits, their runs, the waiting step's start)); target: the gap
    the step aims at.  Returns (outcome, theta, g_ev, landed, n): ACCEPT (no event inside; landed: the
    target's event is at the step's end; n the gaps landed with it, in land_too), REDO (redo up to theta h,
    the first event, at gap g_ev), AT_ONCE (the events are at t: n gaps to switch in place, in toggles) or
    JOIN (a waiting building may touch a stepping one, at gap g_ev).
    """
    cc = coef
    ps, wt = lp[0], lp[3]
    waiting, t_w0 = wt[0], wt[2]
    n_ss, n_scr = ps[3], ps[4]
    gaps = model[2]
    dt = model[4][0]
    st, incr, cs, ev, mr, ws = work[1], work[2], work[7], work[9], work[10], work[12]
    toggles, land_too = work[6][2], work[6][3]
    u, v = st[0], st[1]
    Du, Vv = incr[0], incr[3]
    d0, r0, d_end, r_end, gk = ev[0], ev[1], ev[2], ev[3], ev[4]
    hmin = 1e-9 * dt
    landed = False
    if target >= 0:
        dtg, rtg = _gap_trial(u, Du, Vv, cc, gaps[0][target], gaps[1][target], gaps[4][target], gk[GU1, target],
                              gk[GV1, target])
        landed = abs(dtg) <= LAND_TOL * max(abs(rtg), abs(r0[target])) * h + 1e-15
    if waiting:  # gaps with a waiting side: it moves along its own step's trajectory
        _screen_waiting((t + h - t_w0) / dt, dt, cc, mr, n_ss, n_scr, gaps, (u, v, Du, Vv), ws, gk, (d_end, r_end))
    # screen every gap (or, while some building waits, those in the list scr: the gaps with a stepping side;
    # scr[n_ss:] have a waiting side, computed above)
    theta, g_ev, ev_waits, n_land = _screen_step(waiting, (mr[7], n_ss, n_scr), gaps, cs[0], (u, Du, Vv, cc), h, gk,
                                                 (d0, r0, d_end, r_end), (landed, target), land_too)
    if ev_waits:  # a waiting building may touch a stepping one in this substep: it joins (``_join_now``)
        stats[S_REJECTED] += 1
        return JOIN, theta, g_ev, landed, 0
    if g_ev < 0:
        return ACCEPT, theta, g_ev, landed, n_land
    stats[S_REJECTED] += 1
    if theta * h < hmin:
        # every gap whose event is at the current time switches now, together (identical floors touch at
        # once: one attempt, not one per gap)
        n_tog = _at_once(h, hmin, (mr[7], n_ss, n_scr), gaps, cs, (d0, r0, d_end, r_end), landed, target, toggles)
        return AT_ONCE, theta, g_ev, landed, n_tog
    return REDO, theta, g_ev, landed, 0


@njit(cache=True, inline="always")
def _commit(h, span, aimed, cnt, energy, lp, model, work, outs, cat, stats):
    """ACCEPT / COMMIT the trial step of h [s] (``_accept``) and move the clock on (``_advance``);
    span = (t, the analysis step's end) [s]; aimed = (the gap aimed at, whether its event landed at the
    step's end, the gaps landed with it).  Returns (t, energy, the gaps to switch, in toggles)."""
    t, t_end = span
    m_act, ps, waiting = cnt[1], lp[0], lp[3][0]
    target, landed, n_land = aimed
    settings = model[4]
    lists = work[6]
    stats[S_STEPS] += 1
    cm = 1.0 / (settings[2] * h * h)
    cc = settings[3] / (settings[2] * h)
    energy = _accept(h, (cm, cc), model, work, outs, cat, (waiting, ps[2], m_act), energy)
    t = _advance(t, h, (t_end, settings[0]), waiting, ps[4], work, model[3][1])
    n_tog = _landed(target, n_land, lists[3], lists[2]) if landed else 0
    return t, energy, n_tog


@njit(cache=True, inline="always")
def _switch_at(n_tog, t, cnt, lp, model, work, outs, cat):
    """SWITCH at t [s] the n_tog gaps in toggles (an impact's onset, with the law's onset hook, or its end:
    ``_switch``), regroup the closed gaps and take the accelerations from equilibrium (the contact force may
    jump there), over the stepping runs.  cnt = (impacts, gaps closed, their groups).  Returns (status,
    cnt)."""
    n_run = lp[0][2]
    row, gaps = model[0], model[2]
    n_sub = model[4][4]
    st, lists, cs, gf, ev, runs = work[1], work[6], work[7], work[8], work[9], work[11]
    status, n_imp, m_act = _switch((lists[2], n_tog), t, n_sub, st, gaps, ev[4], gf[0], outs[6], cs, cat, lists[0],
                                   (cnt[0], cnt[1]))
    if status != OK:
        return status, (n_imp, m_act, cnt[2])
    n_comp = _group_contacts(m_act, lists[0], gaps[2], gaps[3], lists[1])
    _equilibrium(row, st, ev[5], gaps, gf[0], runs, n_run)
    return OK, (n_imp, m_act, n_comp)


@njit(cache=True, inline="always")
def _close(step, energy, lp, model, work, outs):
    """The analysis step's END on the physical path: the waiting buildings' step (lp's wt) accepted with the
    stepping ones' last (``_commit_waiting``), and output row ``step`` written (its strain energy is
    pending: it is settled when K u is next formed, ``_settle``).  Returns (energy, lp)."""
    ps, fb, pending, wt = lp
    row, gaps, store = model[0], model[2], model[4][7]
    st, gf, ev, mr, runs, ws = work[1], work[8], work[9], work[10], work[11], work[12]
    if wt[0]:
        e_in, w_int = _commit_waiting(wt[1], mr, runs, ws, row, gaps, ev[4], st, outs[5], (ev[0], ev[1]),
                                      energy[:2])
        energy = (e_in, w_int, energy[2])
    if store:  # (the no-pounding twin keeps its peaks only: no histories to write)
        _output_row(step, st, ev[5], row, gf[0], outs, energy)
        pending = step
    return energy, (ps, fb, pending, wt)


@njit(cache=True, inline="always")
def _finish(lp, model, work, outs):
    """The run's end: the last output row's strain energy (``_last_strain``), if it is still pending."""
    if lp[2] >= 0:
        _last_strain(lp[2], model[0], work[1], model[8], outs[4])


@njit(cache=True, inline="always")
def _aim(outcome, target, landed, lp, model):
    """After a substep's attempts: the gap the next substep aims at (the one an accepted step stopped just
    short of, ``_substep``), none otherwise.  Returns lp."""
    ps = lp[0]
    aim = target if outcome == ACCEPT and target >= 0 and not landed else -1
    return (ps[0], aim) + ps[2:], lp[1], lp[2], lp[3]


@njit(cache=True, inline="always")
def _trial(h, lev, clk, cnt, lp, model, work, outs, stats):
    """One attempt's trial step of h [s]: K_hat(h)'s factor (``_factor_for``), the ground at its end, the
    PREDICTOR with every contact force frozen at zero on the stepping buildings' runs (exact when no gap
    is closed), and the CONTACT NEWTON on the closed gaps' forces (``_contact_newton``).

    clk = (analysis step, t); lp = (ps, fb, pending, wt) (``_begin``).  Returns (factored, converged, h on
    the grid, gamma/(beta h), lp with the scratch factor's step and the output row pending).
    """
    step, t = clk
    ps, pending, waiting = lp[0], lp[2], lp[3][0]
    m_act, n_comp = cnt[1], cnt[2]
    h_cached, n_run, n_s_dof = ps[0], ps[2], ps[5]
    row, p, gaps, motion, settings, modal, md, es0 = (model[0], model[1], model[2], model[3], model[4], model[5],
                                                      model[7], model[8])
    dt, beta, gamma, rtol, max_iter = settings[0], settings[2], settings[3], settings[5], settings[6]
    fac, st, incr, wc, semi, nwt, lists, cs, gf, ev, runs, blocks, mw = (work[0], work[1], work[2], work[3], work[4],
                                                                        work[5], work[6], work[7], work[8], work[9],
                                                                        work[11], work[13], work[14])
    Du, R0, Av, Vv = incr
    ag, g_t, g_1 = motion[0], ev[5], ev[6]
    out_e = outs[4]
    modal_step = modal[10] and m_act == 0  # every gap open (around an event): the exact modal step
    lv, h = _grid_level(h, lev, mw[3], dt)
    ok, Lf, h_cached = _factor_for(lv, h, modal_step, h_cached, fac, row, p, (beta, gamma), runs, n_run, wc[4],
                                   stats)
    if not ok:
        return False, False, h, 0.0, ((h_cached,) + ps[1:], lp[1], pending, lp[3])
    cc = gamma / (beta * h)
    if h == dt and t == step * dt:  # a whole analysis step: on the record's grid
        for r in range(ag.shape[0]):
            g_1[r] = ag[r, step + 1]
    else:
        _ground_all(ag, t + h, dt, g_1)
    if motion[1]:
        _gap_ground_all(motion[2], t + h, dt, ev[4], GU1)
    if modal_step:
        es = _exact_trial(h, (g_t, g_1), (beta, gamma), md, (mw[1], mw[2]), st, blocks[2:5], incr)
    else:
        es = _newmark_predictor((n_run, runs), h, (Lf, p), (beta, gamma), row, g_1, st, incr)
    if pending >= 0:  # (the whole row steps here: a waiting step settled it already)
        pending = _settle(pending, 0.5 * es, es0, out_e)
    stats[S_ITERATIONS] += 1
    stats[S_DOF_STEPS] += n_s_dof
    lp = ((h_cached,) + ps[1:], lp[1], pending, lp[3])
    if m_act == 0:
        return True, True, h, cc, lp
    converged, it = _contact_newton((lv, h, cc, waiting), (Lf, fac[2], p, n_run, runs), (m_act, lists[0], n_comp,
                                    lists[1]), wc, semi, gaps, (st[0], Du, Vv, R0, ev[4]), gf, cs[3], nwt,
                                    (rtol, max_iter), stats)
    stats[S_ITERATIONS] += it
    if it > stats[S_MAX_ITER]:
        stats[S_MAX_ITER] = it
    return True, converged, h, cc, lp


@njit(cache=True, inline="always")
def _join_step(g_ev, t, energy, lp, model, work, outs, stats):
    """JOIN: the waiting buildings of gap g_ev catch up to t and step with the others from here
    (``_join_now``).  Returns (ok, energy, lp)."""
    ok, ps, wt, energy = _join_now(g_ev, t, lp[3], energy, model, work, outs, stats)
    return ok, energy, (ps, lp[1], lp[2], wt)


@njit(cache=True)
def _join_now(join_gap, t, wt, energy, model, work, outs, stats):
    """The waiting buildings of gap join_gap catch up from the waiting step's start to t (``_multirate._join``)
    and step with the others from here: the runs and the screen list follow, and the screened gaps' states
    at t.  wt = (some building waits, their runs, the waiting step's start).  Returns (ok, ps, wt, energy)
    with ps's scratch factor stale (it lacks the joined rows) and no gap aimed at."""
    row, gaps = model[0], model[2]
    dt = model[4][0]
    st, ev, mr, runs, ws = work[1], work[9], work[10], work[11], work[12]
    u, v = st[0], st[1]
    in_s, dof_blk, scr = mr[5], mr[2], mr[7]
    hw = t - wt[2]
    ok, e_in, w_int = _join(join_gap, hw, ev[5], mr, ws, _waits(model, work), row, st, outs[5], energy[:2], stats)
    energy = (e_in, w_int, energy[2])
    ps = (-1.0, -1) + _stepping(mr, runs)
    if not ok:
        return False, ps, wt, energy
    n_wrun = _runs(in_s, False, mr[0], mr[1], runs[4], runs[5], runs[6], runs[7])
    s0 = hw / dt
    for qq in range(ps[4]):  # gap states at t: the joined buildings are there now
        g = scr[qq]
        ev[0][g], ev[1][g] = _gap_state(g, (s0, dt), (in_s, dof_blk), gaps, (u, v, ws[3], ws[4]), (ws[7], v, 0.0),
                                        (ev[4][GU0, g], ev[4][GV0, g]))
    return True, ps, (n_wrun > 0, n_wrun, wt[2]), energy


@njit(cache=True, inline="always")
def _advance(t, h, clock, waiting, n_scr, work, moving):
    """After an accepted step of h [s] from t: each screened gap's penetration and rate at the step's end
    become its start's (while some building waits, the gaps screened, scr[:n_scr]: the others link waiting
    buildings only), and the clock and the ground terms move on (``_ground._tick``; clock = (t_end, dt)).
    Returns the new t."""
    ev, scr = work[9], work[10][7]
    d0, r0, d_end, r_end = ev[0], ev[1], ev[2], ev[3]
    if waiting:
        for qq in range(n_scr):
            g = scr[qq]
            d0[g] = d_end[g]
            r0[g] = r_end[g]
    else:  # every gap was screened (copied, not swapped: a phase cannot rebind its caller's arrays; ng
        # values per accepted step, no measurable cost in the A/B)
        for g in range(d0.size):
            d0[g] = d_end[g]
            r0[g] = r_end[g]
    return _tick(t, h, clock, (ev[5], ev[6]), ev[4], moving)


@njit(cache=True, inline="always")
def _settle(pending, es, es0, out_e):
    """Output row ``pending`` gets its strain energy es [J] (and the damping's share of the storey + damping
    work, which needed it; es0 the strain energy at t = 0).  Returns -1: no row pending."""
    out_e[pending, E_STRAIN] = es
    out_e[pending, E_DAMPING] -= es - es0
    return -1


@njit(cache=True)
def _last_strain(pending, row, st, es0, out_e):
    """The last output row's strain energy, from K u at the end of the run (``_settle``)."""
    mass, dof_a0, dof_motion, el_i, el_j, el_k, el_a1 = row
    u, v, fs, fd = st[0], st[1], st[4], st[5]
    _internal(mass, dof_a0, el_i, el_j, el_k, el_a1, u, v, fs, fd)
    es = 0.0
    for i in range(u.size):
        es += 0.5 * fs[i] * u[i]
    _settle(pending, es, es0, out_e)


@njit(cache=True, inline="always")
def _waits(model, work):
    """How a waiting building steps (``_multirate``): (exact, ex_co, ex_h, h_ex, md, (mq, mqv, mqa), the level-0
    factor, p, beta, gamma, (Av, Vv, R0))."""
    p, settings, modal, md = model[1], model[4], model[5], model[7]
    fac, incr, blocks, mw = work[0], work[2], work[13], work[14]
    return (modal[10], modal[11], mw[1], mw[2], md, (blocks[2], blocks[3], blocks[4]), fac[0][0], p, settings[2],
            settings[3], (incr[2], incr[3], incr[1]))


@njit(cache=True)
def _start(dt, ag, row, gaps, n_sub, st, F, cs, cat, outs, ev, lists):
    """The state at t = 0: gaps already closing (touching bodies) start an impact, the accelerations follow
    from equilibrium, output row 0 is written and the closed gaps are listed and grouped.

    Tuples as in ``_driver.integrate_kernel`` and ``_fast_work``: ev's (d0, r0) each gap's penetration [m] and rate
    [m/s] and g_t filled; lists' (act_list, comp_off) filled.  Returns (status, n_impacts, gaps closed,
    contact groups, energy present at t = 0 [J] (counted as input), strain energy at t = 0 [J])."""
    mass, dof_a0, dof_motion, el_i, el_j, el_k, el_a1 = row
    gap_i, gap_j, gap_lo, gap_hi, gap_size, gap_law, gap_par = gaps
    u, v, a, fint, fs, fd = st
    active, st_c, cur_imp, imp_fmax = cs[0], cs[1], cs[4], cat[4]
    out_u, out_v, out_a, out_f, out_e, umax, fmax = outs
    d0, r0, g_t = ev[0], ev[1], ev[5]
    act_list, comp_off = lists[0], lists[1]
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
def _switch(tog, t, n_sub, st, gaps, gk, F, fmax, cs, cat, act_list, counts):
    """Switch the gaps toggles[:n_tog] at time t (tog = (toggles, n_tog)): an impact's onset (the law's onset
    hook, its force F[g] [N]) where the gap was open, its end where it was closed.  counts = (impacts so far,
    gaps closed); returns (status, impacts, gaps closed)."""
    toggles, n_tog = tog
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
        _internal_range((mass, dof_a0, el_i, el_j, el_k, el_a1), u, v, fs, fd, (r_lo[rr], r_hi[rr], r_elo[rr],
                                                                             r_ehi[rr]))
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
    g_w0, g_w1 = ws[0], ws[1]
    mass, dof_motion = row[0], row[2]
    gap_i, gap_j, gap_size = gaps[0], gaps[1], gaps[4]
    u, v = st[0], st[1]
    d0, r0 = dr
    for w in range(n_wrun):
        e_in, w_int = _waiting_commit((w_lo[w], w_hi[w]), (mass, dof_motion), (g_w0, g_w1), ws[2:6], st, umax,
                                      (e_in, w_int))
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
            _compliance_tridiagonal((comp_off[c], comp_off[c + 1], act_list), gap_i, gap_j, (sig_h, Sd_h), Gm,
                                    (dofs, order, pos, span, Kd))
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
            if not _factor_range(h, (beta, gamma), (mass, dof_a0, el_i, el_j, el_k, el_a1), p, L_h,
                                 (r_lo[rr], r_hi[rr], r_elo[rr], r_ehi[rr])):
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
def _at_once(h, hmin, screened, gaps, cs, states, landed, target, toggles):
    """Every gap whose event is at the current time (within hmin of the step's start): they switch now,
    together (identical floors touch at once: one attempt, not one per gap); a gap with a waiting side is
    found again in the next attempt, and joins then.  screened = (scr, n_ss, n_scr): the gaps screened
    (``_screen_step``); states = (d0, r0, d_end, r_end).  Fills toggles; returns their number."""
    scr, n_ss = screened[0], screened[1]
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
def _accept(h, coef, model, work, outs, cat, rate, energy):
    """Accept the trial step of h [s] on the stepping buildings' rows: state, peaks, each closed gap's force
    and its peak between the last three samples of its impact, and the energies by the trapezoidal work.
    coef = (1/(beta h^2), gamma/(beta h)); rate = (some building waits, stepping runs, gaps closed); energy =
    (e_in, w_int, e_cont) [J], returned updated."""
    cm, cc = coef
    row, gaps = model[0], model[2]
    st, incr, lists, cs, gf, ev, runs = work[1], work[2], work[6], work[7], work[8], work[9], work[11]
    g_t, g_1 = ev[5], ev[6]
    Du = incr[0]
    u, fint = st[0], st[3]
    mass, dof_motion = row[0], row[2]
    gap_i, gap_j = gaps[0], gaps[1]
    F, F1, F_old, h_old = gf
    age, cur_imp = cs[3], cs[4]
    imp_fmax = cat[4]
    umax, fmax = outs[5], outs[6]
    waiting, n_run, m_act = rate
    act_list = lists[0]
    e_in, w_int, e_cont = energy
    if waiting:
        for rr in range(n_run):
            e_in, w_int = _accept_rows((runs[0][rr], runs[1][rr]), (cm, cc), (mass, dof_motion), (g_t, g_1),
                                       incr, st, umax, (e_in, w_int))
    else:
        e_in, w_int = _accept_rows((0, u.size), (cm, cc), (mass, dof_motion), (g_t, g_1), incr, st, umax,
                                   (e_in, w_int))
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
