"""The time loop: one driver for every row, over either linear part.

Private: call :func:`seispound.integrate.integrate`, which validates inputs, allocates the outputs and
chooses the linear part.  Everything here takes arrays, scalars and tuples of them only.

One loop (``drive``) reads as the phases of an analysis step (OpenSees' transient analysis: predictor,
iterations, accept/commit), and knows neither the elements nor their laws:

* **free flight** while every gap is open and the row allows it (``_fly``): a block of steps in modal
  coordinates, or one step by each building's state-transition map;
* the **physical path** otherwise: who steps (``_begin``), then substeps (``_substep``: the rest of the
  analysis step, or the contact substep grid aimed at a located event), each taken in *attempts* --
  the trial (``_trial``: factor, predictor, the Newton iterations on the elements with state), the event
  screen (``_screen``), redone up to the first event -- and accepted (``_commit``: commit every law's
  trial state, peaks, work) or followed by a switch of the gaps that opened or closed (``_switch``);
* the analysis step's end (``_close``: the waiting buildings' step, the output row) and the run's end
  (``_finish``).

Each phase has two implementations with one signature, one per linear part.  ``drive`` is written once
and compiled once per linear part (``drive_two_node``, ``drive_coupled``: its phase names bound to that
part's implementations, ``_bind``), each phase inlined; no branch on the part is taken at run time:

* the **two-node** linear part (``_kernel.py``, model ``TwoNode``): lumped masses and two-node storeys,
  K_hat tridiagonal or banded by DOF pairs, the Woodbury columns of the closed gaps, free flight in modal
  blocks, multi-rate stepping (buildings away from a contact wait) and the exact scheme between impacts;
* the **coefficient-vector** linear part (``_general.py``, model ``Coupled``): masses on several DOFs,
  elements on three, storeys with history and gaps against storeys, A's profile factor, Newton on the
  condensed forces or the banded tangent, free flight by each building's state-transition map.

What the two share is written once below the phases (``_contact``, ``_events``, ``_newton``, ``_ground``,
``_material``).  ``integrate_kernel`` and ``general_kernel`` set each linear part up (work arrays, the
first factor, the state at t = 0) and run the loop.

(Choosing the phases through ``numba.extending.overload`` instead, by the model's type, was tried: with
the numba in use, phases inlined that way lost their stores into the energy history and the storeys'
deformations while every other history was right.  ``tests/integrate/test_driver.py`` compares every
history of the compiled loop with the same loop run by Python.)
"""

from __future__ import annotations

import inspect
from collections import namedtuple
from types import FunctionType

import numpy as np
from seispound._jit import njit

from . import _general as G
from . import _kernel as K
from ._borrow import borrow, borrow_all, keep_alive
from ._events import ACCEPT, FAILED, JOIN, REDO
from ._linear import _factor, _factor_profile
from ._multirate import _runs, _screen_list
from ._elements import assemble_band, linear_bands, lumped_diagonal
from ._outputs import NEWTON_FAILED, OK, S_FACTORIZATIONS, S_REJECTED

#: the model of a row whose linear part is two-node (``_kernel.py``'s phases read it by position)
TwoNode = namedtuple("TwoNode", ["row", "p", "gaps", "motion", "settings", "modal", "multi", "md", "es0"])
#: the model of a row whose linear part is coefficient vectors (``_general.py``'s phases read it by position)
Coupled = namedtuple("Coupled", ["lin", "load", "elg", "motion", "cs", "settings", "cfg", "ff", "n_storeys", "e0"])


def _unbound(*args):
    raise NotImplementedError("the loop's phases are bound per linear part: drive_two_node, drive_coupled")


# the phases, as ``drive``'s source names them; each ``drive_*`` binds them to its linear part's
_fly = _begin = _substep = _trial = _screen = _aim = _join = _commit = _switch = _close = _finish = _unbound

#: name in ``drive`` -> (the two-node part's implementation, the coefficient-vector part's)
PHASES = {
    "_fly": (K._fly, G._fly),
    "_begin": (K._begin, G._begin),
    "_substep": (K._substep, G._substep),
    "_trial": (K._trial, G._trial),
    "_screen": (K._screen, G._screen),
    "_aim": (K._aim, G._aim),
    "_join": (K._join_step, G._join_step),
    "_commit": (K._commit, G._commit),
    "_switch": (K._switch_at, G._switch_at),
    "_close": (K._close, G._close),
    "_finish": (K._finish, G._finish),
}


def _bind(loop, name, part):
    """``loop`` compiled with each phase name bound to linear part ``part``'s implementation (0: two-node,
    1: coefficient vectors): one source, one compiled loop per linear part, each phase inlined as numba
    inlines any ``inline="always"`` function (a template instantiated twice, as C++ would).

    The two implementations of a phase must share one signature (TypeError otherwise).  Under
    ``NUMBA_DISABLE_JIT`` the bound loop runs as Python.
    """
    phases = {}
    for phase, impls in PHASES.items():
        sigs = {inspect.signature(getattr(f, "py_func", f)) for f in impls}
        if len(sigs) != 1:
            raise TypeError(f"{phase}: {impls[0].__name__} and {impls[1].__name__}: one phase, two signatures")
        phases[phase] = impls[part]
    py = getattr(loop, "py_func", loop)
    bound = FunctionType(py.__code__, {**py.__globals__, **phases}, name, py.__defaults__, py.__closure__)
    bound.__qualname__ = name  # (numba's cache file is named by it: one per linear part)
    bound.__doc__ = py.__doc__
    return njit(cache=True)(bound)


def drive(model, work, lp, cnt, energy, outs, cat, stats):
    """Run the analysis steps from t = 0; return (status, impacts, t reached [s]).

    model: ``TwoNode`` or ``Coupled`` (its ``settings`` = (dt, nsteps, beta, gamma, n_sub, rtol, max_iter,
    store)); work: the linear part's work arrays in named groups (``_kernel._fast_work``,
    ``_general._general_work``); lp: the loop's state that only the linear part's phases read (the
    two-node part: the scratch factor and who steps, the free-flight blocks, the output row pending, the
    waiting step; the coefficient-vector part: the step of A's band, whether K u + C v is stale);
    cnt = (impacts, elements active, their groups); energy: the work accumulated [J] (the linear part's
    tuple); outs, cat, stats as the entry points take them.
    """
    # borrowed here as well as by the caller: arguments' reference counts are unknown to LLVM, borrowed ones
    # are null in this function's own code, so that it drops every reference-count operation in the loop
    model, work, outs, cat = borrow_all((model, work, outs, cat))
    stats = borrow(stats)
    dt, nsteps = model.settings[0], model.settings[1]
    hmin = 1e-9 * dt  # events closer than this to a step's start switch in place
    t = 0.0
    step = 0
    while step < nsteps:
        # ---- FREE FLIGHT while every gap is open (and the row allows it): one step or a block, then on
        flew, step, t, energy, lp = _fly(step, t, cnt, energy, lp, model, work, outs, stats)
        if flew:
            continue
        # ---- the PHYSICAL PATH: who steps (the others wait a whole step), then its substeps
        t_end = (step + 1) * dt
        lp = _begin(step, t, cnt, lp, model, work, outs, stats)
        while t_end - t > hmin:
            # ---- a SUBSTEP: its size, then ATTEMPTS up to the first event
            h, lev, target = _substep(step, t, cnt, lp, model, work)
            outcome, landed, g_ev, n_tog = FAILED, False, -1, 0
            for attempt in range(200):
                # TRIAL: factor, PREDICTOR, the ITERATIONS on the elements with state
                ok, converged, h, coef, lp = _trial(h, lev, (step, t), cnt, lp, model, work, outs, stats)
                if not ok:
                    break
                if not converged:  # a quarter of the step
                    stats[S_REJECTED] += 1
                    h *= 0.25
                    target = -1
                    if h < hmin:
                        break
                    continue
                # EVENT SCREEN: does a gap open or close inside the step?
                outcome, theta, g_ev, landed, n_tog = _screen(h, coef, t, target, lp, model, work, stats)
                if outcome != REDO:
                    break
                h = theta * h  # up to the event
                target = g_ev
                outcome = FAILED  # (unless a later attempt ends otherwise)
            if outcome == FAILED:
                return NEWTON_FAILED, cnt[0], t
            lp = _aim(outcome, target, landed, lp, model)
            if outcome == JOIN:
                # ---- a waiting building catches up to t and steps from here
                ok, energy, lp = _join(g_ev, t, energy, lp, model, work, outs, stats)
                if not ok:
                    return NEWTON_FAILED, cnt[0], t
                continue
            if outcome == ACCEPT:
                # ---- ACCEPT / COMMIT: state, committed laws, peaks, work; the clock moves on
                t, energy, n_tog = _commit(h, (t, t_end), (target, landed, n_tog), cnt, energy, lp, model, work,
                                           outs, cat, stats)
            if n_tog > 0:
                # ---- SWITCH: an impact's onset (the law's onset hook) or end at each gap toggled
                status, cnt = _switch(n_tog, t, cnt, lp, model, work, outs, cat)
                if status != OK:
                    return status, cnt[0], t
        step += 1
        # ---- the analysis step's END: the waiting buildings' step, the output row
        energy, lp = _close(step, energy, lp, model, work, outs)
    _finish(lp, model, work, outs)
    return OK, cnt[0], t


drive_two_node = _bind(drive, "drive_two_node", 0)
drive_coupled = _bind(drive, "drive_coupled", 1)


@njit(cache=True)
def integrate_kernel(row, p, init, gaps, motion, settings, modal, multi, outs, cat, stats):
    """Integrate a row whose linear part is two-node; fill the outputs; return (status, n_impacts, t_reached).

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
    of theirs may close (``Multi-rate stepping`` in ``_kernel.py``'s docstring),
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
    dt = settings[0]
    n = row[0].size
    # the work arrays (``_fast_work``): owned by this tuple (kept alive to the end), used through borrowed aliases
    owners = K._fast_work(n, motion[0].shape[0], p, settings, modal, multi, gaps, init)
    fac, st, incr, wc, semi, nwt0, lists, csa, gf, ev, mr6, runs, ws, blocks, mw = borrow_all(owners)
    cs = (csa[0], csa[1], csa[3], csa[4], csa[5])  # each gap's contact state (``_contact._begin_impact``)
    mr = (multi[2], multi[3]) + mr6  # multi-rate: who steps
    md = (modal[1], modal[4], modal[5], modal[6], modal[7], modal[8])  # the modal basis, for exact steps
    work = (fac, st, incr, wc, semi, nwt0 + (csa[1], csa[2]), lists, cs, gf, ev, mr, runs, ws, blocks, mw)
    for s in range(stats.size):
        stats[s] = 0
    if not _factor(dt, settings[2], settings[3], row[0], row[1], row[3], row[4], row[5], row[6], p, fac[0][0]):
        return NEWTON_FAILED, 0, 0.0
    fac[1][0] = True
    stats[S_FACTORIZATIONS] += 1
    # -- initial state: gaps already closing at t = 0 (touching bodies) start an impact; output row 0
    status, n_imp, m_act, n_comp, e_in, es0 = K._start(dt, motion[0], row, gaps, settings[4], st, gf[0], cs, cat,
                                                       outs, ev, lists)
    if status != OK:
        return status, n_imp, 0.0
    n_run = _runs(mr[5], True, mr[0], mr[1], runs[0], runs[1], runs[2], runs[3])
    n_ss, n_scr = _screen_list(mr[5], mr[3], mr[4], mr[7])
    model = TwoNode(row, p, gaps, motion, settings, modal, multi, md, es0)
    ps = (-1.0, -1, n_run, n_ss, n_scr, n)  # the scratch factor's step, a gap aimed at, who steps (``_stepping``)
    fb = (0, 16, -1, 2.0, -1, False)  # free-flight blocks: first step, length, event hint, modal state current
    wt = (False, 0, 0.0)  # some building waits, their runs, the waiting step's start
    out = drive_two_node(model, work, (ps, fb, -1, wt), (n_imp, m_act, n_comp), (e_in, 0.0, 0.0), outs, cat, stats)
    keep_alive(owners)
    return out


@njit(cache=True)
def general_kernel(linear, p, numbering, elements, state0, motion, init, settings, opts, outs, cat, stats):
    """Integrate a row whose linear part is coefficient vectors; fill the outputs; return (status, n_impacts,
    t_reached).

    The arguments come in named tuples: linear = (ms_dof, ms_coef, ms_val, ms_a0, le_dof, le_coef, le_k,
    le_c); p; numbering = (first, out_col); elements = (dof_load, dof_motion, dof_infl, ne_dof, ne_coef,
    ne_size, ne_code, ne_par, ne_gap, ne_lo, ne_hi); state0; motion = (ag, moving, ne_ground); init = (u_init,
    v_init); settings = (dt, nsteps, beta, gamma, n_sub, rtol, max_iter, store) as ``integrate_kernel``'s;
    opts = (tangent, pT, lev_free, ff, el_pred); outs = (out_u, out_v, out_a, out_f, out_e, umax, fmax);
    cat = (imp_gap, imp_t0, imp_v0, imp_vout, imp_fmax, imp_dur, imp_zeta, imp_e); stats.

    Shapes: n DOFs, nn elements with state, nm motion rows, nt = nsteps + 1.
    ms_* : masses (nms, 3) / (nms,) [kg], ms_a0 [1/s] their proportional damping;
    le_* : linear elements (nle, 3) / (nle,), le_k [N/m], le_c [N s/m];
    p : half bandwidth of M, C and K; numbering = (first, out_col), (n,) int64 each: the first column of
    each row's lower envelope in M, C, K and the storeys' elastic stiffness (``structure.band.envelope``;
    every factor is a profile factor, ``_linear._factor_profile``, within max(first[i], i - its half
    bandwidth)), and the output column of each DOF (the row's own numbering, where the driver's is
    another: ``newmark._profile_numbered``); dof_load (n,) [kg]: M iota, the load per
    unit ground acceleration of row dof_motion (n,); dof_infl (n,): iota;
    ne_* : elements with state (nn, 4) / (nn,) / (nn, N_PAR), ne_gap (nn,)
    True for a gap (events, active only while closed), False for a storey
    (always active); ne_lo, ne_hi (nn,): the DOF range of the buildings each
    element links (A is block diagonal over buildings: elements whose ranges do
    not overlap are uncoupled, and Newton runs per group, ``_group_contacts``);
    state0 (nn, N_STATE) their initial committed state;
    ag (nm, nt) [m/s^2]; ne_ground (3, nn, nt): each element's differential
    ground acceleration, velocity and displacement (used when ``moving``);
    outputs as ``integrate_kernel`` (out_f (nt, nn): every element's
    force; out_e (nt, 6) with the hysteretic energy).
    n_sub : (contact substeps per impact duration, longest contact substep [s]) (``_contact._begin_impact``).
    lev_free : no step longer than dt / 2^lev_free (substeps that make Newmark accurate at the
    analysis step: ``simulation.newmark_substeps``).
    tangent : a group of active elements that holds a storey iterates on the banded tangent
    (``_general_solve._newton_tangent``, half bandwidth pT with the storeys); False: every group on the dense
    condensed system (``_newton``), the off switch the tests compare against.
    el_pred: every storey is bilinear, peak-oriented, Iwan or flag, and a physical step first tries them at their
    elastic stiffness in the linear part (Newton on the closed gaps alone), kept if every storey ends the
    step on that line.
    ff = (on, start, off_x, off_g, off_e, phi, G0, G1, Egx, Egg, st_elem, st_start, Gc, Egc, Gq, Egq, bw):
    while every gap is open (and every storey, if any, is bilinear or, with ``bw``, Bouc-Wen or
    peak-oriented: ``on`` says so) an analysis step is one map per building (``transition.py``: exact, or the same Newmark
    substeps composed), screened for gap events and for elastic bilinear storeys reaching yield, the
    terms of the Bouc-Wen storeys and, with ``bw``, of the yielding bilinear ones iterated within it
    (``_general_flight``); on False, or when the screen finds an event, the step is taken on the physical
    path.
    """
    # arguments: alive for the whole call, so borrowed (``_borrow``: no reference counting in the loop)
    linear, numbering, elements, motion, init, opts, outs, cat = borrow_all(
        (linear, numbering, elements, motion, init, opts, outs, cat))
    stats = borrow(stats)
    dt, beta, gamma, n_sub, rtol, max_iter = settings[0], settings[2], settings[3], settings[4], settings[5], settings[6]
    tangent, pT, lev_free, ff, el_pred = opts
    load, elg = elements[:3], elements[3:]
    ne_gap = elg[5]
    n, nn = init[0].size, ne_gap.size
    # the linear part as elements (assembly), as the bands of K and C (its forces), M's diagonal if lumped
    # and the envelope every factor keeps to
    lin = linear + (linear_bands(linear, p, n), lumped_diagonal(linear[0], linear[1], linear[2], n)) + numbering
    # the work arrays: owned by this tuple (kept alive to the end), used through borrowed aliases
    owners = G._general_work(n, nn, motion[0].shape[0], (p, pT, el_pred), ff[10].size, dt, state0, init)
    work = borrow_all(owners)
    fac, st, lists, elem, ev = work[0], work[1], work[2], work[5], work[6]
    cs = (elem[6], elem[0], elem[7], elem[8], elem[9])  # each element's contact state (``_contact._begin_impact``)
    for s in range(stats.size):
        stats[s] = 0
    assemble_band(1.0, 0.0, 0.0, linear, p, fac[3])
    if not _factor_profile(fac[3], p, lin[10], 0, n):
        return NEWTON_FAILED, 0, 0.0  # a DOF without mass (the front end refuses it first)
    # -- initial state: storeys active, gaps closing at t = 0 start an impact ------
    status, n_imp, m_act, n_comp, es_lin0, rec0, e_in = G._start(dt, n_sub, motion, elg, elem, cs, cat, lists, st,
                                                                 ev, (fac[3], p, lin, load))
    if status != OK:
        return status, n_imp, 0.0
    n_storeys = 0
    for q in range(nn):
        n_storeys += 0 if ne_gap[q] else 1
    cfg = (dt, beta, gamma, n_sub, rtol, max_iter, tangent, pT, lev_free, el_pred, p)
    model = Coupled(lin, load, elg, motion, cs, settings, cfg, ff, n_storeys, (es_lin0, rec0))
    energy = (e_in, 0.0, 0.0, 0.0)  # input, linear elements' and dampers' work, work on the storeys, contact [J]
    G._output(0, True, st, ev[7], load, lin, elg, elem, ev[0], (es_lin0, rec0), (energy, np.nan), outs)
    # lp: the step of A's band (none yet), K u + C v stale after free flight
    out = drive_coupled(model, work, (-1.0, False), (n_imp, m_act, n_comp), energy, outs, cat, stats)
    keep_alive(owners)
    return out
