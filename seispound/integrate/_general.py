"""The phases of the time loop (``_driver.drive``) on the coefficient-vector linear part (the general
driver): Newmark-beta for any element with state, any coupling the band holds.

Private: call :func:`seispound.integrate.integrate`, which chooses this linear part
when the model has what the two-node one (``_kernel.py``) does not take (storeys
with history, elements on three DOFs, masses on several, gaps against a
storey), or when asked to (``driver="general"``, the off switch of every
optimisation the fast driver makes); ``_driver.general_kernel`` sets it up and
runs the loop.

Method (Newmark 1959; Chopra, Dynamics of Structures, Table 5.7.2; Bathe 1996,
Sec. 9.5): the linear part -- masses, linear springs and dashpots, all as
coefficient vectors (``_elements.py``) -- gives A = K + gamma/(beta h) C +
M/(beta h^2), banded, factored once per step size within its envelope (``_linear._factor_profile``;
a foundation's DOFs are numbered after its floors, ``newmark._profile_numbered``).
The elements with state -- hysteretic storeys (always) and gaps (while closed)
-- are condensed: with their end-of-step forces F frozen the step is
Du = Du_lin - sum_q A^-1 b_q F_q, so the Newton-Raphson iteration runs on the
m forces alone,

    F_q = f_q(delta_lin,q - (G F)_q, rate_lin,q - gamma/(beta h) (G F)_q),
    G = B^T A^-1 B,

with Jacobian I + diag(k_t) G (k_t the law's consistent tangent d f/d delta +
gamma/(beta h) d f/d rate).  That is Newton-Raphson on the full residual
restricted to the only DOFs where it is nonzero, so it converges as the
full iteration does, and the linear part is never refactored for a yield.
A group that holds storeys solves each Newton update through the banded tangent
T = A + B K_t B^T instead of the dense I + K_t G (``_general_solve._newton_tangent``: the same
update by the push-through identity, a few banded solves per iteration; its closed
gaps, which link buildings, by a Woodbury correction); a group of gaps alone uses
G, whose columns A^-1 b_q are cached per factor (``_newton``).

Each law is called through the material protocol (``_material.py``): a
trial from the committed state (a redone step is another trial), committed
when the step is accepted; a gap's onset hook sets its impact's damping.

Events (a gap touching or separating) are located as in the fast driver
(``_events.py``: the first root of the cubic Hermite interpolant of the
penetration); while a gap is closed the step is cut into substeps of
1/n_sub of the impact duration, on the dt/2^k grid.  Yield is not an event:
the return map is exact for a deformation linear in the step.

Energy (relative frame; Uang & Bertero 1990): every force's work by the
trapezoidal rule, which for average acceleration balances exactly: input =
kinetic + strain (linear + recoverable) + damping + contact + hysteretic.
"""

from __future__ import annotations

import numpy as np
from seispound._jit import njit

from ._contact import _begin_impact, _contact_step, _end_impact, _grid_level, _group_contacts, _peak_through
from ._elements import (_deformation, _deformation_at, _dot, _scatter, kinetic_energy, linear_forces, mass_times,
                        strain_energy)
from ._events import ACCEPT, AT_ONCE, FAILED, LAND_TOL, REDO, _event_in_step, _landed, _screen_elements
from ._general_flight import _free_flight
from ._general_solve import N_LEVELS, _acceleration, _cached_factor, _factor_cache, _predictor, _solve_groups
from ._ground import GU0, GU1, _gap_ground_all, _ground_all, _tick
from ..storey.codes import B_FY, B_K, FLAG, IWAN, PEAK_ORIENTED
from ._material import material_commit, material_energy, material_trial
from ._iwan import iwan_kept_elastic
from ._flag import flag_kept_elastic
from ._peak_oriented import BEND, ST_D, ST_F
from ._outputs import (
    E_CONTACT,
    E_DAMPING,
    E_HYSTERETIC,
    E_INPUT,
    E_KINETIC,
    E_STRAIN,
    IMPACT_CAPACITY,
    OK,
    S_DOF_STEPS,
    S_ITERATIONS,
    S_MAX_ITER,
    S_REJECTED,
    S_STEPS,
)


@njit(cache=True)
def _general_work(n, nn, nm, bands, n_ff, dt, state0, init):
    """The general driver's work arrays, allocated once (its loop allocates nothing), in named groups.

    n DOFs, nn elements with state, nm motion rows; bands = (p, pT, el_pred): the half bandwidths of A and
    of the banded tangent, and whether the elastic predictor's factors are kept; n_ff storeys in free
    flight; dt [s] the analysis step; state0 (nn, N_STATE) the elements' initial state; init = (u0, v0).
    Returns (fac, st, lists, nwt, tang, elem, ev, fl):
    fac = (A(h)'s factor cache (``_factor_cache``), the elastic predictor's, h per level, M's factor);
    st = (u, v, a, Vv, Av, R0, Du, work, flin, flin1): the state, Newmark's predictor terms, K u + C v;
    lists = (act, comp_off, actg, compg_off): the active elements (every storey, the closed gaps) and the
    closed gaps alone, each in groups that share no building;
    nwt = (Gm, Sm, ym, Fm, dl, rl, resv, kt): the condensed Newton's work;
    tang = (Aband, T, zt, xt, Wt, gpos): the banded tangent's (``_newton_tangent``);
    elem = (st_c, st_t, F, F1, F_old, h_old, active, hsub, age, cur_imp): each element's committed and trial
    state, its force at t and in the trial, its last accepted substep's, whether it is active, its
    contact substep, the substeps since its impact's onset and the impact's number;
    ev = (d0, r0, d1, r1, toggles, land_too, gk, g_t, g_1): the elements' deformations and rates at the
    step's start and end, the gaps switched together, the ground terms;
    fl = (u1, v1, a1, xs, ys, cst, rise, zs, itr, corr, dr): a free-flight step's trial state and scratch
    (``_general_flight._free_flight``).
    """
    p, pT, el_pred = bands
    nw = max(nn, 1)
    nf = max(n_ff, 1)
    h_lev = np.empty(N_LEVELS)
    for k in range(N_LEVELS):
        h_lev[k] = dt / 2.0**k
    fac = (_factor_cache(N_LEVELS, n, p, nw),
           _factor_cache(N_LEVELS if el_pred else 1, n if el_pred else 1, pT, nw if el_pred else 1),
           h_lev, np.empty((n, p + 2)))
    st = (init[0].copy(), init[1].copy(), np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n),
          np.empty(n), np.empty(n), np.empty(n))
    lists = (np.empty(nw, np.int64), np.empty(nw + 1, np.int64), np.empty(nw, np.int64), np.empty(nw + 1, np.int64))
    nwt = (np.empty((nw, nw)), np.empty((nw, nw)), np.empty(nw), np.empty(nw), np.empty(nw), np.empty(nw),
           np.empty(nw), np.empty(nw))
    tang = (np.zeros((n, pT + 2)), np.empty((n, pT + 2)), np.zeros(n), np.zeros(n), np.zeros((nw, n)),
            np.empty(nw, np.int64))
    elem = (state0.copy(), state0.copy(), np.zeros(nn), np.zeros(nn), np.zeros(nn), np.ones(nn),
            np.zeros(nn, np.bool_), np.full(nn, np.inf), np.zeros(nn, np.int64), -np.ones(nn, np.int64))
    ev = (np.empty(nn), np.empty(nn), np.empty(nn), np.empty(nn), np.empty(nw, np.int64), np.empty(nw, np.int64),
          np.zeros((4, nn)), np.empty(nm), np.empty(nm))
    fl = (np.empty(n), np.empty(n), np.empty(n), np.empty(2 * n + 2 * nm), np.empty(3 * n), np.empty(nf),
          np.zeros(2 * nf + 1), np.zeros(6 * nf), np.zeros(nf, np.bool_), np.zeros(nf), np.zeros(4 * nf))
    return fac, st, lists, nwt, tang, elem, ev, fl


@njit(cache=True, inline="always")
def _fly(step, t, cnt, energy, lp, model, work, outs, stats):
    """FREE FLIGHT (``_driver._fly``): while every gap is open (the storeys are always active) and the row's
    maps allow it (ff's ``on``), the analysis step from ``step`` by each building's map
    (``_general_flight._free_flight``), and its output row.  lp = (the step of A's band, K u + C v stale).
    Returns (flew, step, t, energy, lp); not flown when the screen finds an event in the step."""
    lin, load, elg, motion, settings, ff, e0 = model[0], model[1], model[2], model[3], model[5], model[7], model[9]
    dt = settings[0]
    st, elem, ev = work[1], work[5], work[6]
    if not (ff[0] and cnt[1] == model[8]):
        return False, step, t, energy, lp
    t_end = (step + 1) * dt
    # the kinetic energy at the step's start: the output row written last holds it (stored histories)
    ke0 = outs[4][step, E_KINETIC] if settings[7] else np.nan
    ok, energy, ke1 = _free_flight(ff, (t_end, dt), motion, elg, lin, st, elem, ev, work[7], outs[5:], (energy, ke0),
                                   stats)
    if not ok:
        return False, step, t, energy, lp
    step += 1
    if settings[7]:
        _output(step, False, st, ev[7], load, lin, elg, elem, ev[0], e0, (energy, ke1), outs)
    return True, step, t_end, energy, (lp[0], True)


@njit(cache=True, inline="always")
def _begin(step, t, cnt, lp, model, work, outs, stats):
    """The analysis step's start on the physical path (every building steps): K u + C v at the state free
    flight left, if stale (the corrector's trapezoidal work needs it).  Returns lp."""
    if lp[1]:
        st = work[1]
        linear_forces(model[0][8], st[0], st[1], st[8])
    return lp[0], False


@njit(cache=True, inline="always")
def _substep(step, t, cnt, lp, model, work):
    """A substep's size from t [s]: the rest of the analysis step, or the contact substep grid while a gap is
    closed (``_contact._contact_step``), within dt / 2^lev_free.  Returns (h [s], its grid level, -1: no gap
    aimed at)."""
    cfg, elg = model[6], model[2]
    dt = cfg[0]
    fac, lists, elem = work[0], work[2], work[5]
    h, lev = _contact_step(t, (step + 1) * dt, dt, cnt[1], lists[0], elg[3], elem[7], elem[8], fac[2], N_LEVELS,
                           cfg[8])
    return h, lev, -1


@njit(cache=True, inline="always")
def _aim(outcome, target, landed, lp, model):
    """(No gap is aimed at across substeps on this linear part.)  Returns lp."""
    return lp


@njit(cache=True, inline="always")
def _join_step(g_ev, t, energy, lp, model, work, outs, stats):
    """(Every building steps on this linear part: its screen never asks a waiting one to join.)"""
    return False, energy, lp


@njit(cache=True, inline="always")
def _close(step, energy, lp, model, work, outs):
    """The analysis step's END on the physical path: the storeys' deformation and output row ``step``.
    Returns (energy, lp)."""
    lin, load, elg, e0 = model[0], model[1], model[2], model[9]
    st, elem, ev = work[1], work[5], work[6]
    if model[5][7]:
        ne_gap = elg[5]
        for q in range(ne_gap.size):
            if not ne_gap[q]:
                ev[0][q] = _dot(elg[0], elg[1], q, st[0]) - elg[2][q]
        _output(step, False, st, ev[7], load, lin, elg, elem, ev[0], e0, (energy, np.nan), outs)
    return energy, lp


@njit(cache=True, inline="always")
def _finish(lp, model, work, outs):
    """The run's end: nothing left to settle (every output row is complete when written)."""
    return


@njit(cache=True, inline="always")
def _trial(h, lev, clk, cnt, lp, model, work, outs, stats):
    """One attempt at a step of h [s] from t: the step on the factor grid, the ground at its end, A's factor,
    the PREDICTOR and the ITERATIONS.

    Phase 0, the elastic predictor (every storey bilinear or peak-oriented, ``el_pred``): the storeys at
    their elastic stiffness in the linear part, Newton on the closed gaps alone, kept if every storey ends
    the step on that line (``_kept_elastic``).  Phase 1: the predictor with every element force of state
    frozen at zero, then Newton on the active elements' forces, condensed through A^-1 (``_solve_groups``).  clk = (analysis step, t);
    cnt = (impacts, active elements, their groups); lp = (the step of A's band h_A, K u + C v stale).
    Returns (ok: A positive definite, converged, h on the grid, (1/(beta h^2), gamma/(beta h)), lp).
    """
    t = clk[1]
    m_act, n_comp = cnt[1], cnt[2]
    h_A = lp[0]
    cfg = model[6]
    dt, beta, gamma, rtol, max_iter = cfg[0], cfg[1], cfg[2], cfg[4], cfg[5]
    tangent, pT, el_pred, p = cfg[6], cfg[7], cfg[9], cfg[10]
    lin, load, elg, motion = model[0], model[1], model[2], model[3]
    fac, st, lists, nwt, tang, elem, ev = work[0], work[1], work[2], work[3], work[4], work[5], work[6]
    ne_dof, ne_coef, ne_size, ne_code, ne_par, ne_gap, ne_lo, ne_hi = elg
    act, comp_off, actg, compg_off = lists
    Gm, Sm, ym, Fm, dl, rl, resv, kt = nwt
    st_c, st_t, F, F1, F_old, h_old, active, hsub, age, cur_imp = elem
    u, Du, Vv, R0 = st[0], st[6], st[3], st[5]
    gk = ev[6]
    lv, h = _grid_level(h, lev, fac[2], dt)
    cm = 1.0 / (beta * h * h)
    cc = gamma / (beta * h)
    _ground_all(motion[0], t + h, dt, ev[8])
    if motion[1]:
        _gap_ground_all(motion[2], t + h, dt, gk, GU1)
    frc = (F, F1, F_old, h_old, age, Fm, dl, rl, st_c, st_t)
    twork = (tang[2], tang[3], resv, kt, tang[4], Sm, ym, tang[5])
    for phase in range(2):
        if phase == 0 and not el_pred:
            continue
        if phase == 0:
            ok, Lp, Wp, Wp_ok = _cached_factor(lv, h, cm, cc, lin, (ne_dof, ne_coef, ne_par, ne_gap), True, pT,
                                               fac[1], stats)
            if not ok:
                return False, False, h, (cm, cc), lp
            pb = pT
            m_g = 0
            for k in range(m_act):
                if ne_gap[act[k]]:
                    actg[m_g] = act[k]
                    m_g += 1
            grp = (m_g, actg, _group_contacts(m_g, actg, ne_lo, ne_hi, compg_off), compg_off)
        else:  # A(h) is factored only here: a step the elastic predictor keeps never needs it
            ok, Lp, Wp, Wp_ok = _cached_factor(lv, h, cm, cc, lin, (ne_dof, ne_coef, ne_par, ne_gap), False, p,
                                               fac[0], stats)
            if not ok:
                return False, False, h, (cm, cc), lp
            pb = p
            grp = (m_act, act, n_comp, comp_off)
        _predictor(h, (beta, gamma), (Lp, pb), lin, load, ev[8], st, (phase == 0, ne_dof, ne_coef, ne_gap, F))
        stats[S_ITERATIONS] += 1
        stats[S_DOF_STEPS] += u.size
        ok, it, h_A = _solve_groups(grp, elg, (h, cm, cc, u, Du, Vv, R0, gk), frc, (Lp, pb, Wp, Wp_ok, Gm),
                                    (tang[0], tang[1], pT, h_A, lin, tangent and phase == 1),
                                    (resv, kt, Sm, ym, twork), (rtol, max_iter))
        stats[S_ITERATIONS] += it
        if phase == 1:
            stats[S_MAX_ITER] = max(stats[S_MAX_ITER], it)
            return True, ok, h, (cm, cc), (h_A, lp[1])
        elastic = ok
        for q in range(ne_gap.size):
            if elastic and not ne_gap[q]:
                ds, rs = _deformation(ne_dof, ne_coef, ne_size, q, u, Du, Vv, cc, gk, GU1)
                f, dfd, dfv = material_trial(ne_code[q], ne_par, st_c, st_t, q, ds, rs)
                elastic = _kept_elastic(ne_code[q], ne_par, st_c, q, ds, f, dfd)
                F1[q] = f
        if elastic:
            return True, True, h, (cm, cc), (h_A, lp[1])
    return True, True, h, (cm, cc), (h_A, lp[1])  # (not reached: phase 1 returns)


@njit(cache=True, inline="always")
def _kept_elastic(code, par, st_c, q, ds, f, dfd):
    """Did storey q's trial at deformation ds [m] (force f [N], tangent dfd [N/m]) stay on the line of slope k
    through its committed point, as the elastic predictor took it?  Bilinear: tangent k.  Iwan, flag: both
    ends in the window (``iwan_kept_elastic``, ``flag_kept_elastic``).  Peak-oriented: the committed force
    moved along k, to round-off (the virgin storey's unloading and reloading lines are one), and tangent k."""
    k = par[q, B_K]
    if code == IWAN or code == FLAG:
        return iwan_kept_elastic(par, st_c, q, dfd) if code == IWAN else flag_kept_elastic(par, st_c, q, ds, dfd)
    if code == PEAK_ORIENTED:
        return (abs(dfd - k) <= BEND * k
                and abs(f - st_c[q, ST_F] - k * (ds - st_c[q, ST_D])) <= 1e-12 * par[q, B_FY])
    return dfd == k


@njit(cache=True, inline="always")
def _screen(h, coef, t, target, lp, model, work, stats):
    """The EVENT SCREEN of a converged trial step of h [s] from t: does a gap touch or separate inside it?

    coef = (1/(beta h^2), gamma/(beta h)); target: the gap the step aims at.  Each gap's deformation and
    rate at the step's end go to ev's (d1, r1).  Returns (outcome, theta, g_ev, landed, n): ACCEPT (no event
    inside; landed: the target's event is at the step's end; n the gaps landed with it, in land_too), REDO
    (redo up to theta h, the first event, at gap g_ev), AT_ONCE (the events are at the step's start: n gaps
    to switch in place, in toggles) or FAILED (an event at the start that no gap owns).
    """
    cc = coef[1]
    hmin = 1e-9 * model[6][0]
    elg, st, elem, ev = model[2], work[1], work[5], work[6]
    ne_gap, active = elg[5], elem[6]
    d0, r0, d1, r1, toggles, land_too, gk = ev[0], ev[1], ev[2], ev[3], ev[4], ev[5], ev[6]
    for q in range(ne_gap.size):
        if ne_gap[q]:
            d1[q], r1[q] = _deformation(elg[0], elg[1], elg[2], q, st[0], st[6], st[3], cc, gk, GU1)
    landed = False
    if target >= 0:
        landed = abs(d1[target]) <= LAND_TOL * max(abs(r1[target]), abs(r0[target])) * h + 1e-15
    theta, g_ev, n_land = _screen_elements(ne_gap, active, d0, r0, d1, r1, h, landed, target, land_too)
    if g_ev < 0:
        return ACCEPT, theta, g_ev, landed, n_land
    stats[S_REJECTED] += 1
    if theta * h < hmin:  # events at the current time: switch them in place, then step
        n_tog = _at_once(h, hmin, ne_gap, active, (d0, r0, d1, r1), landed, target, toggles)
        return AT_ONCE if n_tog > 0 else FAILED, theta, g_ev, landed, n_tog
    return REDO, theta, g_ev, landed, 0


@njit(cache=True, inline="always")
def _commit(h, span, aimed, cnt, energy, lp, model, work, outs, cat, stats):
    """ACCEPT / COMMIT the trial step of h [s] (``_accept``) and move the clock on (``_advance``).
    span = (t, the analysis step's end) [s]; aimed = (the gap aimed at, whether its event landed at the
    step's end, the gaps landed with it).  Returns (t, energy, the gaps to switch, in toggles)."""
    t, t_end = span
    dt, beta, gamma = model[6][0], model[6][1], model[6][2]
    cm = 1.0 / (beta * h * h)  # (as the trial formed them)
    cc = gamma / (beta * h)
    m_act = cnt[1]
    target, landed, n_land = aimed
    lin, load, elg, motion = model[0], model[1], model[2], model[3]
    st, lists, elem, ev = work[1], work[2], work[5], work[6]
    energy = _accept(h, (cm, cc), lin, load, elg, (lists[0], m_act), (ev[7], ev[8]), st, elem,
                     (outs[5], outs[6], cat[4]), energy)
    stats[S_STEPS] += 1
    t = _advance(t, h, (t_end, dt), elg[5], ev, motion[1])
    n_tog = _landed(target, n_land, ev[5], ev[4]) if landed else 0
    return t, energy, n_tog


@njit(cache=True, inline="always")
def _switch_at(n_tog, t, cnt, lp, model, work, outs, cat):
    """SWITCH at t [s] the n_tog gaps in toggles (``_switch``), regroup the active elements and take the
    accelerations from equilibrium at fixed (u, v) (a contact force may jump at an event: LVe's dashpot).
    cnt = (impacts, active elements, their groups).  Returns (status, cnt)."""
    n_sub, p = model[6][3], model[6][10]
    lin, load, elg, cs = model[0], model[1], model[2], model[4]
    fac, st, lists, elem, ev = work[0], work[1], work[2], work[5], work[6]
    status, n_imp, m_act = _switch(ev[4], n_tog, t, n_sub, elg, (ev[0], ev[1]), elem[2], outs[6], cs, cat,
                                   lists[0], (cnt[0], cnt[1]))
    if status != OK:
        return status, (n_imp, m_act, cnt[2])
    n_comp = _group_contacts(m_act, lists[0], elg[6], elg[7], lists[1])
    _acceleration((fac[3], p), (lin[8], lin[10]), load[:2], ev[7], (st[0], st[1], st[2], st[8]), elg[:2], elem[2])
    return OK, (n_imp, m_act, n_comp)


@njit(cache=True, inline="always")
def _advance(t, h, clock, ne_gap, ev, moving):
    """After an accepted step of h [s] from t: each gap's deformation and rate at the step's end become its
    start's, and the clock and the ground terms move on (``_ground._tick``; clock = (t_end, dt)).  Returns
    the new t."""
    d0, r0, d1, r1 = ev[0], ev[1], ev[2], ev[3]
    for q in range(ne_gap.size):
        if ne_gap[q]:
            d0[q] = d1[q]
            r0[q] = r1[q]
    return _tick(t, h, clock, (ev[7], ev[8]), ev[6], moving)


@njit(cache=True, inline="always")
def _accept(h, coef, lin, load, elg, acts, grd, st, elem, peaks, energy):
    """Accept the trial step: state, committed laws, peaks and every force's trapezoidal work.

    coef = (1/(beta h^2), gamma/(beta h)); acts = (act, m_act) the active elements; grd = (g at the step's
    start, at its end) per motion row; peaks = (umax, fmax, imp_fmax); energy = (input, linear work,
    storeys' work, contact work) [J].  Returns the energy after the step.
    """
    cm, cc = coef
    dof_load, dof_motion = load[0], load[1]
    ne_dof, ne_coef, ne_gap = elg[0], elg[1], elg[5]
    act, m_act = acts
    g0, g1 = grd
    u, v, a, Vv, Av, R0, Du, work, flin, flin1 = st
    st_c, st_t, F, F1, F_old, h_old, active, hsub, age, cur_imp = elem
    umax, fmax, imp_fmax = peaks
    e_in, w_lin, w_hys, e_cont = energy
    for i in range(u.size):
        e_in -= 0.5 * dof_load[i] * (g0[dof_motion[i]] + g1[dof_motion[i]]) * Du[i]
        u[i] += Du[i]
        v[i] = Vv[i] + cc * Du[i]
        a[i] = Av[i] + cm * Du[i]
        umax[i] = max(umax[i], abs(u[i]))
    # K u1 + C v1 (read only by the energy) from equilibrium at the step's end, M a1 + K u1 + C v1 + B F1 = p1,
    # which the solve holds to round-off: products with M and the active elements instead of with K and C
    mass_times(lin[0], lin[1], lin[2], lin[9], a, flin1)
    for i in range(u.size):
        flin1[i] = -dof_load[i] * g1[dof_motion[i]] - flin1[i]
    for k in range(m_act):
        _scatter(ne_dof, ne_coef, act[k], -F1[act[k]], flin1)
    for i in range(u.size):
        w_lin += 0.5 * (flin[i] + flin1[i]) * Du[i]
        flin[i] = flin1[i]
    for k in range(m_act):
        q = act[k]
        work = 0.5 * (F[q] + F1[q]) * _dot(ne_dof, ne_coef, q, Du)
        if ne_gap[q]:
            e_cont += work
            age[q] += 1
            # the force's peak between the last three samples of this impact
            fpk = _peak_through(F_old[q], F[q], F1[q], h_old[q], h) if age[q] >= 2 else F1[q]
            fpk = max(fpk, F1[q])
            F_old[q] = F[q]
            h_old[q] = h
            fmax[q] = max(fmax[q], fpk)
            imp_fmax[cur_imp[q]] = max(imp_fmax[cur_imp[q]], fpk)
        else:
            w_hys += work
            fmax[q] = max(fmax[q], abs(F1[q]))
        F[q] = F1[q]
        material_commit(st_c, st_t, q)
    return e_in, w_lin, w_hys, e_cont


@njit(cache=True, inline="always")
def _output(k, first, st, g, load, lin, elg, elem, delta, e0, energy, outs):
    """Write output row k (``delta`` holds the storeys' deformations); the first call also starts the peaks.

    g: the ground accelerations per motion row; e0 = (the linear elements' strain energy, the storeys'
    recoverable energy) at t = 0 [J]; energy = ((input, linear work, storeys' work, contact work) [J], the
    kinetic energy at the state [J] where the caller has it, else NaN).
    """
    u, v, a = st[0], st[1], st[2]
    dof_motion, dof_infl = load[1], load[2]
    ne_code, ne_par, ne_gap = elg[3], elg[4], elg[5]
    st_c, F = elem[0], elem[2]
    es_lin0, rec0 = e0
    (e_in, w_lin, w_hys, e_cont), ke = energy
    out_u, out_v, out_a, out_f, out_e, umax, fmax = outs
    if first:
        for i in range(u.size):
            umax[i] = abs(u[i])
        for q in range(F.size):
            fmax[q] = max(F[q], 0.0) if ne_gap[q] else abs(F[q])
    col = lin[11]  # the output column of each DOF
    for i in range(u.size):
        c = col[i]
        out_u[k, c] = u[i]
        out_v[k, c] = v[i]
        out_a[k, c] = a[i] + dof_infl[i] * g[dof_motion[i]]
    rec = 0.0
    for q in range(F.size):
        out_f[k, q] = F[q]
        if not ne_gap[q]:
            rec += material_energy(ne_code[q], ne_par, st_c, q, delta[q])
    es_lin = strain_energy(lin[4], lin[5], lin[6], u)
    out_e[k, E_INPUT] = e_in
    out_e[k, E_KINETIC] = ke if ke == ke else kinetic_energy(lin[0], lin[1], lin[2], lin[9], v)
    out_e[k, E_STRAIN] = es_lin + rec
    out_e[k, E_DAMPING] = w_lin - (es_lin - es_lin0)
    out_e[k, E_CONTACT] = e_cont
    out_e[k, E_HYSTERETIC] = w_hys - (rec - rec0)


@njit(cache=True)
def _start(dt, n_sub, motion, elg, elem, cs, cat, lists, st, ev, eq):
    """The state at t = 0: every storey active, gaps already closing (touching bodies) start an impact, each
    active element's force from its law, the closed gaps listed and grouped, the accelerations from
    equilibrium.  The groups as ``_driver.general_kernel`` names them (``_general_work``): lists (act, comp_off)
    filled, ev's (d0, r0) each element's deformation [m] and rate [m/s], g_t; eq = (LM, p, lin, load).
    Returns (status, impacts, active elements, groups, the linear elements' strain energy [J], the storeys'
    recoverable energy [J], the energy present at t = 0 [J], counted as input)."""
    ag, moving, ne_ground = motion
    ne_dof, ne_coef, ne_size, ne_code, ne_par, ne_gap, ne_lo, ne_hi = elg
    st_c, st_t, F, active = elem[0], elem[1], elem[2], elem[6]
    act, comp_off = lists[0], lists[1]
    u, v = st[0], st[1]
    d0, r0, gk, g_t = ev[0], ev[1], ev[6], ev[7]
    LM, p, lin, load = eq
    n_imp = 0
    if moving:
        _gap_ground_all(ne_ground, 0.0, dt, gk, GU0)
    m_act = 0
    for q in range(ne_size.size):
        d0[q], r0[q] = _deformation_at(ne_dof, ne_coef, ne_size, q, u, v, gk, GU0)
        if not ne_gap[q]:
            active[q] = True
        elif d0[q] > 0.0 or (d0[q] == 0.0 and r0[q] > 0.0):
            if n_imp >= cat[0].size:
                return IMPACT_CAPACITY, n_imp, 0, 0, 0.0, 0.0, 0.0
            _begin_impact(q, 0.0, d0[q], r0[q], ne_code[q], ne_par[q], n_sub, cs, cat, n_imp)
            n_imp += 1
        if active[q]:
            act[m_act] = q
            m_act += 1
            F[q] = material_trial(ne_code[q], ne_par, st_c, st_t, q, d0[q], r0[q])[0]
            material_commit(st_c, st_t, q)
    n_comp = _group_contacts(m_act, act, ne_lo, ne_hi, comp_off)
    _ground_all(ag, 0.0, dt, g_t)
    _acceleration((LM, p), (lin[8], lin[10]), load[:2], g_t, (st[0], st[1], st[2], st[8]), elg[:2], F)
    es_lin0 = strain_energy(lin[4], lin[5], lin[6], u)
    rec0 = 0.0
    for q in range(ne_size.size):
        rec0 += material_energy(ne_code[q], ne_par, st_c, q, d0[q])
    e_in = kinetic_energy(lin[0], lin[1], lin[2], lin[9], v) + es_lin0 + rec0
    return OK, n_imp, m_act, n_comp, es_lin0, rec0, e_in


@njit(cache=True)
def _at_once(h, hmin, ne_gap, active, states, landed, target, toggles):
    """Every gap whose event is at the current time (within hmin of the step's start): they switch now,
    together.  states = (d0, r0, d1, r1).  Fills toggles; returns their number."""
    d0, r0, d1, r1 = states
    n_tog = 0
    for q in range(ne_gap.size):
        if not ne_gap[q] or (landed and q == target):
            continue
        tol = LAND_TOL * max(abs(r0[q]), abs(r1[q])) * h + 1e-15
        if _event_in_step(d0[q], r0[q], d1[q], r1[q], h, not active[q], tol) * h < hmin:
            toggles[n_tog] = q
            n_tog += 1
    return n_tog


@njit(cache=True)
def _switch(toggles, n_tog, t, n_sub, elg, dr, F, fmax, cs, cat, act, counts):
    """Switch the gaps toggles[:n_tog] at time t: an impact's onset (the law's onset hook, its force F[q]
    [N]) where the gap was open, its end where it was closed.  dr = (d0, r0); counts = (impacts so far,
    active elements); returns (status, impacts, active elements)."""
    ne_code, ne_par = elg[3], elg[4]
    d0, r0 = dr
    active = cs[0]
    n_imp, m_act = counts
    for k in range(n_tog):
        q = toggles[k]
        if not active[q]:
            if n_imp >= cat[0].size:
                return IMPACT_CAPACITY, n_imp, m_act
            F[q] = _begin_impact(q, t, d0[q], r0[q], ne_code[q], ne_par[q], n_sub, cs, cat, n_imp)
            fmax[q] = max(fmax[q], F[q])
            n_imp += 1
            act[m_act] = q
            m_act += 1
        else:
            m_act = _end_impact(q, t, r0[q], m_act, act, cs, cat)
            F[q] = 0.0
    return OK, n_imp, m_act
