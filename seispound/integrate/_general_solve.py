"""The general driver's linear part and its Newton: A(h)'s factors, the predictor, the condensed Newton per group.

Private to the general driver (``_general.py``, whose docstring gives the method).  A = K + gamma/(beta h) C +
M/(beta h^2) is assembled from the coefficient-vector elements and factored within its envelope, cached per
step-size level (``_cached_factor``); the predictor solves the step with every force of state frozen at
zero (``_predictor``); the active elements' forces are found by Newton per group that shares no building,
on the dense condensed system (``_newton._newton``) or, for a group that holds storeys, through the banded
tangent (``_newton_tangent``).
"""

from __future__ import annotations

import numpy as np
from seispound._jit import njit

from ._elements import (_add_to_band, _deformation, _dot, _scatter, assemble_band, linear_forces, mass_times)
from ._ground import GU1
from ._linear import _dense_solve, _factor_profile, _solve_profile
from ..storey.codes import B_K
from ._newton import _newton, _trial
from ._outputs import S_FACTORIZATIONS

N_LEVELS = 40  # factors kept for h = dt / 2^k, k < N_LEVELS


@njit(cache=True)
def _factor_cache(levels, n, pb, nw):
    """An empty cache for ``_cached_factor``: factors of half bandwidth pb at ``levels`` step sizes and
    one scratch, and gap columns for nw elements of n DOFs."""
    return (np.empty((levels, n, pb + 2)), np.zeros(levels, np.bool_), np.empty((n, pb + 2)), np.zeros((nw, n)),
            np.zeros((nw, n)), np.zeros(nw, np.bool_), np.zeros(nw, np.bool_), np.array([-1], np.int64),
            np.array([-1.0, -1.0]))


@njit(cache=True, inline="always")
def _cached_factor(lv, h, cm, cc, lin, el, elastic, pb, cache, stats):
    """The factor of A(h) (A_el with ``elastic``) and the cache of its gap columns A^-1 b_q, kept per
    step-size level lv (h = dt / 2^lv) and in one scratch slot for any other h (lv < 0).

    cache = (L_lev (levels, n, pb + 2), have (levels,), L_h (n, pb + 2), W_lev, W_scr (nw, n),
    Wok_lev, Wok_scr (nw,), the level whose columns W_lev holds (1,), the h of L_h and of W_scr's
    columns (2,)).  Returns (ok, L, W, W_ok); ok False if A is not positive definite.
    """
    L_lev, have, L_h, W_lev, W_scr, Wok_lev, Wok_scr, lv_W, keys = cache
    if lv >= 0:
        if not have[lv]:
            if not _factor(cm, cc, lin, el, elastic, pb, L_lev[lv]):
                return False, L_h, W_scr, Wok_scr
            have[lv] = True
            stats[S_FACTORIZATIONS] += 1
        if lv != lv_W[0]:
            Wok_lev[:] = False
            lv_W[0] = lv
        return True, L_lev[lv], W_lev, Wok_lev
    if h != keys[0]:
        if not _factor(cm, cc, lin, el, elastic, pb, L_h):
            return False, L_h, W_scr, Wok_scr
        keys[0] = h
        stats[S_FACTORIZATIONS] += 1
    if h != keys[1]:
        Wok_scr[:] = False
        keys[1] = h
    return True, L_h, W_scr, Wok_scr


@njit(cache=True)
def _factor(cm, cc, lin, el, elastic, pb, L):
    """Assemble and factor A = cm M + cc C + K into L (half bandwidth pb); with ``elastic``,
    A_el = A + sum over the storeys of k b b^T (their elastic stiffness: el = (ne_dof, ne_coef, ne_par,
    ne_gap)).  False if not positive definite."""
    assemble_band(cm, cc, 1.0, lin, pb, L)
    if elastic:
        ne_dof, ne_coef, ne_par, ne_gap = el
        for q in range(ne_gap.size):
            if not ne_gap[q]:
                _add_to_band(ne_dof, ne_coef, q, ne_par[q, B_K], L)
    return _factor_profile(L, pb, lin[10], 0, L.shape[0])


@njit(cache=True, inline="always")
def _predictor(h, coef, fac, lin, load, g1, st, storeys):
    """The step with every element force of state frozen at zero: Du = A^-1 R0 (R0 kept).

    R0 = p1 - M Av - C Vv - K u, with Newmark's u1 = u + Du, v1 = Vv + gamma/(beta h) Du,
    a1 = Av + Du/(beta h^2).  coef = (beta, gamma); fac = (A's factor, its half bandwidth); st the
    state group (``_general_work``).  storeys = (on, ne_dof, ne_coef, ne_gap, F): with ``on``, A holds
    the storeys at their elastic stiffness (the elastic predictor) and R0 their committed forces F,
    R0 -= sum b_q F_q: the incremental form of a linear element.
    """
    beta, gamma = coef
    Lf, p = fac
    u, v, a, Vv, Av, R0, Du, work = st[0], st[1], st[2], st[3], st[4], st[5], st[6], st[7]
    for i in range(u.size):
        Vv[i] = (1.0 - gamma / beta) * v[i] + (1.0 - 0.5 * gamma / beta) * h * a[i]
        Av[i] = -v[i] / (beta * h) - (0.5 / beta - 1.0) * a[i]
    linear_forces(lin[8], u, Vv, R0)
    mass_times(lin[0], lin[1], lin[2], lin[9], Av, work)
    _load(load[0], load[1], g1, Du)
    for i in range(u.size):
        R0[i] = Du[i] - work[i] - R0[i]
    if storeys[0]:
        ne_dof, ne_coef, ne_gap, F = storeys[1], storeys[2], storeys[3], storeys[4]
        for q in range(ne_gap.size):
            if not ne_gap[q]:
                _scatter(ne_dof, ne_coef, q, -F[q], R0)
    _solve_profile(Lf, p, lin[10], R0, Du, 0, u.size)


@njit(cache=True)
def _acceleration(eq, lin, load, g, st, elg, F):
    """Relative acceleration from equilibrium M a = p - K u - C v - B F: a = st[2] [m/s^2].

    eq = (LM, pm): the mass matrix's factor and half bandwidth; lin = (K's and C's bands, the envelope);
    load = (dof_load, dof_motion); g the ground accelerations per motion row; st = (u, v, a, flin); elg =
    (ne_dof, ne_coef) the elements with state, F their forces [N].  Also leaves K u + C v in flin.
    (Called with only what it reads: a call copies every array of the groups it takes.)
    """
    LM, pm = eq
    u, v, a, flin = st
    linear_forces(lin[0], u, v, flin)
    _load(load[0], load[1], g, a)
    for i in range(a.size):
        a[i] -= flin[i]
    for q in range(F.size):
        if F[q] != 0.0:
            _scatter(elg[0], elg[1], q, -F[q], a)
    _solve_profile(LM, pm, lin[1], a, a, 0, a.size)


@njit(cache=True, inline="always")
def _load(dof_load, dof_motion, g, out):
    """The effective earthquake load -M iota a_g [N] for the ground accelerations g (per motion row)."""
    for i in range(out.size):
        out[i] = -dof_load[i] * g[dof_motion[i]]


@njit(cache=True, inline="always")
def _solve_groups(grp, elg, stp, frc, fac, band, wrk, opts):
    """Newton on the forces of the active elements, group by group; Du less their share (``_driver.general_kernel``).

    grp = (m_act, act, n_comp, comp_off): the active elements in groups that share no building;
    elg = (ne_dof, ne_coef, ne_size, ne_code, ne_par, ne_gap, ne_lo, ne_hi); stp = (h, cm, cc, u, Du,
    Vv, R0, gk): the step and its linear trial; frc = (F, F1, F_old, h_old, age, Fm, dl, rl, st_c,
    st_t); fac = (Lf, p, W, W_ok, Gm): A's factor and the columns A^-1 b_q under it; band = (Aband,
    T, pT, h_A, lin, tangent): the banded tangent's storage (``_newton_tangent``); wrk = (resv, kt,
    Sm, ym, twork); opts = (rtol, max_iter).  Returns (converged, iterations, h_A).
    """
    m_act, act, n_comp, comp_off = grp
    ne_dof, ne_coef, ne_size, ne_code, ne_par, ne_gap, ne_lo, ne_hi = elg
    h, cm, cc, u, Du, Vv, R0, gk = stp
    F, F1, F_old, h_old, age, Fm, dl, rl, st_c, st_t = frc
    Lf, p, W, W_ok, Gm = fac
    Aband, T, pT, h_A, lin, tangent = band
    resv, kt, Sm, ym, twork = wrk
    rtol, max_iter = opts
    zt = twork[0]
    n = u.size
    if m_act == 0:
        return True, 0, h_A
    scale = 0.0
    for i in range(n):
        scale = max(scale, abs(R0[i]))
    it = 0
    for c in range(n_comp):  # G is block diagonal over the groups
        lo_c, hi_c = comp_off[c], comp_off[c + 1]
        banded = False
        dlo, dhi = n, 0
        for k in range(lo_c, hi_c):
            q = act[k]
            banded = banded or (tangent and not ne_gap[q])
            dlo, dhi = min(dlo, ne_lo[q]), max(dhi, ne_hi[q])
            dl[k], rl[k] = _deformation(ne_dof, ne_coef, ne_size, q, u, Du, Vv, cc, gk, GU1)
            Fm[k] = F[q]
            if ne_gap[q] and age[q] >= 1:  # along the impact's last substep
                Fm[k] += (F[q] - F_old[q]) * (h / h_old[q])
        if banded:
            if h != h_A:  # A's band at this step size, the tangent's starting point
                assemble_band(cm, cc, 1.0, lin, pT, Aband)
                h_A = h
            ok_c, it_c = _newton_tangent((lo_c, hi_c, act), (ne_dof, ne_coef, ne_code, ne_par, ne_gap),
                                         (dl, rl, Fm, cc), (st_c, st_t), (Lf, p, Aband, T, pT, dlo, dhi, lin[10]),
                                         twork, (scale, rtol, max_iter))
        else:
            _columns(Lf, p, lin[10], ne_dof, ne_coef, ne_lo, ne_hi, act[lo_c:hi_c], hi_c - lo_c, W, W_ok)
            for k in range(lo_c, hi_c):
                for r in range(lo_c, hi_c):
                    Gm[k, r] = _dot(ne_dof, ne_coef, act[k], W[act[r]])
            ok_c, it_c = _newton((lo_c, hi_c, act), Gm, (dl, rl, Fm, cc), ne_code, ne_par, (st_c, st_t),
                                 (scale, rtol, max_iter), (resv, kt, Sm, ym))
        it = max(it, it_c)
        if not ok_c:
            return False, it, h_A
        # the step with the group's forces: Du -= A^-1 B F (zt holds it after _newton_tangent)
        for k in range(lo_c, hi_c):
            q = act[k]
            F1[q] = Fm[k]
            if not banded and Fm[k] != 0.0:
                for i in range(ne_lo[q], ne_hi[q]):
                    Du[i] -= Fm[k] * W[q, i]
        if banded:
            for i in range(dlo, dhi):
                Du[i] -= zt[i]
    return True, it, h_A


@njit(cache=True)
def _columns(Lf, p, first, ne_dof, ne_coef, ne_lo, ne_hi, act, m, W, W_ok):
    """W[q] = A^-1 b_q for the active elements that lack it under the current factor.

    A is block diagonal over the buildings, so the column is nonzero only on the DOFs
    ne_lo[q]..ne_hi[q]-1 of the buildings element q links (zero elsewhere from the start).
    """
    for k in range(m):
        q = act[k]
        if W_ok[q]:
            continue
        for i in range(ne_lo[q], ne_hi[q]):
            W[q, i] = 0.0
        _scatter(ne_dof, ne_coef, q, 1.0, W[q])
        _solve_profile(Lf, p, first, W[q], W[q], ne_lo[q], ne_hi[q])
        W_ok[q] = True


@njit(cache=True, inline="always")
def _newton_tangent(grp, el, trial, states, fac, work, tol):
    """Newton-Raphson on the forces Fm[lo:hi] of a group that holds storeys with state, on the banded tangent.

    The same iteration as ``_newton`` (module docstring), Delta F = -(I + K_t G)^-1 res with
    G = B^T A^-1 B, solved without G: by the push-through (Woodbury) identity

        (I + K_t B^T A^-1 B)^-1 = I - K_t B^T (A + B K_t B^T)^-1 B,

    so Delta F = -res + K_t B^T T^-1 B res, where T = A + B K_t B^T is banded as long as the
    elements in it (the storeys) link DOFs within the band; the group's closed gaps, which
    link buildings, enter by the Woodbury correction of T (m_g columns T^-1 b_g, an m_g x m_g
    system).  Each iteration costs a few banded solves over the group's buildings instead of
    a dense m x m factorisation and m^2 column products (derived here from the identity;
    Golub & Van Loan 2013, Sec. 2.1.4).  The trial forces' deformations use
    G F = B^T A^-1 (B F), one solve with A's factor.

    grp = (lo, hi, act): the group's slots in the active list; el = (ne_dof, ne_coef, ne_code, ne_par,
    ne_gap); trial = (dl, rl, Fm, cc): the linear trial's deformations [m] and rates [m/s], the forces
    [N] iterated, gamma/(beta h) [1/s]; states = (st_c, st_t); fac = (Lf, p, Aband, T, pT, dlo, dhi,
    first): A's factor (half bandwidth p), A's unfactored band and the tangent's storage, (n, pT + 2),
    the group's DOF range and the envelope both factors keep to; work = (z, x, resv, kt, Wt, Sg, yg,
    gpos); tol = (scale [N], rtol, max_iter).  Returns (converged, iterations beyond the first
    evaluation); a tangent that is not positive definite ends the iteration unconverged (the driver
    then shortens the step).
    """
    lo, hi, act = grp
    ne_dof, ne_coef, ne_code, ne_par, ne_gap = el
    dl, rl, Fm, cc = trial
    st_c, st_t = states
    Lf, p, Aband, T, pT, dlo, dhi, first = fac
    z, x, resv, kt, Wt, Sg, yg, gpos = work
    scale, rtol, max_iter = tol
    it = 0
    while True:
        # the trial forces' deformations: dl - b^T A^-1 B Fm
        for i in range(dlo, dhi):
            z[i] = 0.0
        for k in range(lo, hi):
            _scatter(ne_dof, ne_coef, act[k], Fm[k], z)
        _solve_profile(Lf, p, first, z, z, dlo, dhi)
        rn = 0.0
        sc = scale
        for k in range(lo, hi):
            q = act[k]
            f = _trial(ne_code, ne_par, (st_c, st_t), q, k, _dot(ne_dof, ne_coef, q, z), (dl, rl, cc), Fm, resv, kt)
            rn = max(rn, abs(resv[k]))
            sc = max(sc, abs(f))
        if rn <= rtol * sc:
            return True, it
        if it >= max_iter:
            return False, it
        it += 1
        # T = A + sum over the storeys of k_t b b^T, on the group's rows
        for i in range(dlo, dhi):
            for d in range(pT + 2):
                T[i, d] = Aband[i, d]
        m_g = 0
        for k in range(lo, hi):
            q = act[k]
            if ne_gap[q]:
                gpos[m_g] = k
                m_g += 1
            else:
                _add_to_band(ne_dof, ne_coef, q, kt[k], T)
        if not _factor_profile(T, pT, first, dlo, dhi):
            return False, it
        # x = (A + B K_t B^T)^-1 B res: T^-1, then the gaps' Woodbury correction
        for i in range(dlo, dhi):
            x[i] = 0.0
        for k in range(lo, hi):
            _scatter(ne_dof, ne_coef, act[k], resv[k], x)
        _solve_profile(T, pT, first, x, x, dlo, dhi)
        if m_g > 0:
            _woodbury(m_g, (lo, act, gpos), el, kt, (T, pT, first, dlo, dhi), (Wt, Sg, yg), x)
        for k in range(lo, hi):
            Fm[k] += -resv[k] + kt[k] * _dot(ne_dof, ne_coef, act[k], x)


@njit(cache=True, inline="always")
def _woodbury(m_g, gaps, el, kt, fac, work, x):
    """x -= T^-1 B_g (I + K_g B_g^T T^-1 B_g)^-1 K_g B_g^T x: the closed gaps' Woodbury correction of the
    banded tangent's solve (``_newton_tangent``; Golub & Van Loan 2013, Sec. 2.1.4).

    gaps = (lo, act, gpos): the m_g gaps' slots act[gpos[j]]; el as ``_newton_tangent``'s; kt their
    consistent tangents [N/m]; fac = (T, pT, first, dlo, dhi) the tangent's factor; work = (Wt, Sg, yg).
    """
    lo, act, gpos = gaps
    ne_dof, ne_coef = el[0], el[1]
    T, pT, first, dlo, dhi = fac
    Wt, Sg, yg = work
    for j in range(m_g):
        w = Wt[j]
        for i in range(dlo, dhi):
            w[i] = 0.0
        _scatter(ne_dof, ne_coef, act[gpos[j]], 1.0, w)
        _solve_profile(T, pT, first, w, w, dlo, dhi)
    for a in range(m_g):
        qa = act[gpos[a]]
        ka = kt[gpos[a]]
        for b in range(m_g):
            Sg[a, b] = ka * _dot(ne_dof, ne_coef, qa, Wt[b])
        Sg[a, a] += 1.0
        yg[a] = ka * _dot(ne_dof, ne_coef, qa, x)
    _dense_solve(m_g, Sg, yg)
    for j in range(m_g):
        for i in range(dlo, dhi):
            x[i] -= yg[j] * Wt[j, i]
