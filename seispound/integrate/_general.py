"""The general driver: Newmark-beta for any element with state, any coupling the band holds.

Private: call :func:`seispound.integrate.integrate`, which chooses this driver
when the model has what the fast one (``_kernel.py``) does not take (storeys
with history, elements on three DOFs, masses on several, gaps against a
storey), or when asked to (``path="general"``, the off switch of every
optimisation the fast driver makes).

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
T = A + B K_t B^T instead of the dense I + K_t G (``_newton_tangent``: the same
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

from ._borrow import borrow, borrow_all, keep_alive
from ._contact import _begin_impact, _contact_step, _end_impact, _grid_level, _group_contacts, _peak_through
from ._elements import (_add_to_band, _dot, _scatter, assemble_band, kinetic_energy, linear_bands, linear_forces,
                        lumped_diagonal, mass_times, strain_energy)
from ._events import LAND_TOL, _event_in_step, _gap_event, _hermite
from ._ground import GU0, GU1, _gap_ground_accept, _gap_ground_all, _ground_all
from ._linear import _dense_solve, _factor_profile, _solve_profile
from ..storey.codes import B_ALPHA, B_FY, B_K, BOUC_WEN, BW_DY
from ._material import (ST_DELTA, ST_EPS, ST_PLASTIC, ST_Z, bouc_wen_path, material_commit,
                        material_energy, material_trial)
from ._newton import _newton, _trial
from ._outputs import (
    E_CONTACT,
    E_DAMPING,
    E_HYSTERETIC,
    E_INPUT,
    E_KINETIC,
    E_STRAIN,
    IMPACT_CAPACITY,
    NEWTON_FAILED,
    OK,
    S_DOF_STEPS,
    S_FACTORIZATIONS,
    S_FREE_FLIGHT,
    S_ITERATIONS,
    S_MAX_ITER,
    S_REJECTED,
    S_STEPS,
)

N_LEVELS = 40  # factors kept for h = dt / 2^k, k < N_LEVELS


# insert-before: general_kernel
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


@njit(cache=True, inline="always")
def _load(dof_load, dof_motion, g, out):
    """The effective earthquake load -M iota a_g [N] for the ground accelerations g (per motion row)."""
    for i in range(out.size):
        out[i] = -dof_load[i] * g[dof_motion[i]]


@njit(cache=True)
def _acceleration(eq, lin, load, g, st, elg, F):
    """Relative acceleration from equilibrium M a = p - K u - C v - B F: a = st[2] [m/s^2].

    eq = (LM, pm): the mass matrix's factor and half bandwidth; load = (dof_load, dof_motion, ...); g the
    ground accelerations per motion row; st the state group (``_general_work``); elg the elements with
    state, F their forces [N].  Also leaves K u + C v in st[8].
    """
    LM, pm = eq
    u, v, a, flin = st[0], st[1], st[2], st[8]
    linear_forces(lin[8], u, v, flin)
    _load(load[0], load[1], g, a)
    for i in range(a.size):
        a[i] -= flin[i]
    for q in range(F.size):
        if F[q] != 0.0:
            _scatter(elg[0], elg[1], q, -F[q], a)
    _solve_profile(LM, pm, lin[10], a, a, 0, a.size)


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
def _solve_groups(grp, elg, stp, frc, fac, band, wrk, opts):
    """Newton on the forces of the active elements, group by group; Du less their share (``general_kernel``).

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
            ok_c, it_c = _newton_tangent((lo_c, hi_c, act), (ne_dof, ne_coef, ne_code, ne_par, ne_gap), (dl, rl, Fm, cc),
                                         (st_c, st_t), (Lf, p, Aband, T, pT, dlo, dhi, lin[10]), twork,
                                         (scale, rtol, max_iter))
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


@njit(cache=True, inline="always")
def _deformation(ne_dof, ne_coef, ne_size, q, u, du, v, c, gk, row):
    """Deformation and rate of element q at u + du, v + c du; gk[row], gk[row + 1]: its ground terms.

    (The rate's increment is c du, Newmark's gamma/(beta h) Du: a scale, not an array, since an
    array argument built per call would be allocated per element and step.)
    """
    bdu = _dot(ne_dof, ne_coef, q, du)
    return (_dot(ne_dof, ne_coef, q, u) + bdu - ne_size[q] + gk[row, q],
            _dot(ne_dof, ne_coef, q, v) + c * bdu + gk[row + 1, q])


@njit(cache=True, inline="always")
def _deformation_at(ne_dof, ne_coef, ne_size, q, u, v, gk, row):
    """Deformation and rate of element q at the state (u, v): ``_deformation`` without an increment."""
    return _dot(ne_dof, ne_coef, q, u) - ne_size[q] + gk[row, q], _dot(ne_dof, ne_coef, q, v) + gk[row + 1, q]


@njit(cache=True, fastmath=True)
def _free_flight_trial(ff, u, v, g0, g1, u1, v1, a1, xs, ys, cst):
    """Every building's state after one analysis step with every gap open, and the step's input work [J].

    ff = (on, start, off_x, off_g, off_e, phi, G0, G1, Egx, Egg): the maps of ``transition.py``,
    [u1; v1; a1] = Phi x0 + G0 g0 + G1 g1 per building (x0 = [u; v] on its DOFs), the input work
    g^T Egx x0 + g^T Egg g with g = [g0; g1] the ground accelerations of the motion rows at the
    step's start and end; each bilinear storey's constant term cst[j] [N] (storey j of ff's st_elem)
    adds its columns Gc and its input work Egc.  xs, ys: scratch (2 n + 2 nm,), (3 n,).  (fastmath: sums may be
    reordered, and so vectorised; round-off only.)
    """
    start, off_x, off_g, off_e, phi, G0, G1, egx, egg = ff[1], ff[2], ff[3], ff[4], ff[5], ff[6], ff[7], ff[8], ff[9]
    st_start, gc, egc = ff[11], ff[12], ff[13]
    o_c = 0
    o_e = 0
    nm = g0.size
    gs = xs[xs.size - 2 * nm:]
    for m in range(nm):
        gs[m] = g0[m]
        gs[nm + m] = g1[m]
    de = 0.0
    for c in range(start.size - 1):
        a = start[c]
        nb = start[c + 1] - a
        nx = 2 * nb
        for k in range(nb):  # x0 = [u; v] of the building, contiguous
            xs[k] = u[a + k]
            xs[nb + k] = v[a + k]
        # the maps are row-major in flat arrays: each row's product is a dot product over unit-stride
        # memory on unsigned subscripts (``_UNSIGNED`` in _linear.py: signed ones made numba's
        # wraparound turn the vectorised loads into gathers)
        unx, unm = np.uint64(nx), np.uint64(nm)
        ox, og = np.uint64(off_x[c]), np.uint64(off_g[c])
        for r in range(np.uint64(3 * nb)):
            s = 0.0
            row = ox + r * unx
            for k in range(unx):
                s += phi[row + k] * xs[k]
            row = og + r * unm
            for m in range(unm):
                s += G0[row + m] * gs[m] + G1[row + m] * gs[unm + m]
            ys[r] = s
        for r in range(nb):
            u1[a + r] = ys[r]
            v1[a + r] = ys[nb + r]
            a1[a + r] = ys[nx + r]
        oe = np.uint64(off_e[c])
        for m in range(np.uint64(2 * nm)):
            if gs[m] == 0.0:
                continue
            s = 0.0
            row = oe + m * unx
            for k in range(unx):
                s += egx[row + k] * xs[k]
            de += gs[m] * s
        for j in range(st_start[c], st_start[c + 1]):  # the bilinear storeys' constant terms
            cj = cst[j]
            jj = j - st_start[c]
            if cj != 0.0:
                base = o_c + jj * 3 * nb
                for r in range(nb):
                    u1[a + r] += gc[base + r] * cj
                    v1[a + r] += gc[base + nb + r] * cj
                    a1[a + r] += gc[base + nx + r] * cj
                for m in range(2 * nm):
                    de += gs[m] * egc[o_e + jj * 2 * nm + m] * cj
        ns_c = st_start[c + 1] - st_start[c]
        o_c += 3 * nb * ns_c
        o_e += 2 * nm * ns_c
    for i in range(2 * nm):
        for j in range(2 * nm):
            de += gs[i] * egg[i, j] * gs[j]
    return de


# a free-flight step's Bouc-Wen terms: the fixed point stops when the next sweep would move no term's rise
# by more than BW_FLIGHT_TOL (1 - alpha) k dy, and is given up (the physical path takes the step) after
# BW_FLIGHT_ITER sweeps
BW_FLIGHT_TOL = 1e-7
BW_FLIGHT_ITER = 30
# 3-point Gauss-Legendre on [0, 1] (exact for the quartic c(s) delta'(s) of the storey's work)
_GL_T = (0.5 - 0.5 * 0.7745966692414834, 0.5, 0.5 + 0.5 * 0.7745966692414834)
_GL_W = (5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0)


@njit(cache=True, inline="always")
def _cubic(ds0, rs0, ds1, rs1, h):
    """(ca, cb, cc) of the deformation's cubic Hermite over a step of h [s]: delta(tau) = ds0 + ca tau + cb tau^2
    + cc tau^3, tau in [0, 1], from its values and rates at both ends."""
    ca, cd = h * rs0, ds1 - ds0
    return ca, 3.0 * cd - 2.0 * ca - h * rs1, ca + h * rs1 - 2.0 * cd


@njit(cache=True, inline="always")
def _add_rise(gq, base, nb, a, dm, d1, x1):
    """Add a storey's rises dm, d1 [N] through its columns (at ``base`` in gq) to building a's end state
    x1 = (u1, v1, a1)."""
    u1, v1, a1 = x1
    for r in range(nb):
        u1[a + r] += gq[base + r] * dm + gq[base + 3 * nb + r] * d1
        v1[a + r] += gq[base + nb + r] * dm + gq[base + 4 * nb + r] * d1
        a1[a + r] += gq[base + 2 * nb + r] * dm + gq[base + 5 * nb + r] * d1


# insert-before: _accept
@njit(cache=True)
def _bouc_wen_flight(ff, elg, mat, x0, x1, gs, gk, h, bw):
    """Iterate the Bouc-Wen storeys' terms over a free-flight step; (converged, input work [J], storeys' work [J]).

    A Bouc-Wen storey's force is k delta - c with c = (1 - alpha) k (delta - z) (``_material``): the
    linear part holds k, and c is a load that changes within the step.  It is taken as the quadratic
    through c0 (committed, ``cst``), c0 + dm at the middle and c0 + d1 at the end, whose response the
    maps give (``transition._exact_maps``, columns gq); z follows the end state's Hermite cubic of each
    storey's deformation (``_material.bouc_wen_path``), which gives new dm, d1: a fixed point, swept over the
    storeys (Gauss-Seidel; the contraction is about (1 - alpha) (omega h)^2 / 6 per sweep) from the
    last step's quadratic extrapolated.  After each sweep the change its updates made in every
    storey's deformation at the middle and the end, times the law's slope there, predicts the next
    sweep's corrections; when none would exceed BW_FLIGHT_TOL (1 - alpha) k dy the sweep is not made
    and z takes that linear correction instead (one path integration per storey and sweep saved).

    elg: the elements with state (``general_kernel``); mat = (st_c, cst); x0 = (u, v) the step's start;
    x1 = (u1, v1, a1) (in: with c0 held) end with the final terms; gs the ground accelerations at the
    step's start and end (2 nm,); bw = (rise, zs): rise (2 ns + 1) holds dm, d1 and the sweeps made; zs
    (6 ns) per storey z at the end, eps at the end, the deformation at the end and at the middle of its
    last integration, and the law's slopes there.  The storey's work int (k delta - c) d(delta) is exact
    for the quadratic c and cubic delta (3-point Gauss-Legendre; derived here, not read from a source).
    """
    start, st_elem, st_start, gq = ff[1], ff[10], ff[11], ff[14]
    ne_code = elg[3]
    rise, zs = bw
    o_q = 0
    for c in range(start.size - 1):  # the first guess: the last step's quadratic, extrapolated
        a = start[c]
        nb = start[c + 1] - a
        for j in range(st_start[c], st_start[c + 1]):
            if ne_code[st_elem[j]] != BOUC_WEN:
                continue
            dm, d1 = 2.0 * rise[2 * j + 1] - 3.0 * rise[2 * j], 5.0 * rise[2 * j + 1] - 8.0 * rise[2 * j]
            rise[2 * j], rise[2 * j + 1] = dm, d1
            _add_rise(gq, o_q + (j - st_start[c]) * 6 * nb, nb, a, dm, d1, x1)
        o_q += 6 * nb * (st_start[c + 1] - st_start[c])
    for it in range(BW_FLIGHT_ITER):
        rise[rise.size - 1] = it + 1  # sweeps made (the driver's iteration count)
        _bouc_wen_sweep(ff, elg, mat, x0, x1, gk, h, bw)
        if _bouc_wen_next(ff, elg, x0, x1, gk, h, zs) <= BW_FLIGHT_TOL:
            de, dwh = _bouc_wen_work(ff, elg, mat, x0, x1, gs, gk, h, bw)
            return True, de, dwh
    return False, 0.0, 0.0


@njit(cache=True, inline="always")
def _screen(ne_gap, active, d0, r0, d1, r1, h, landed, target, land_too):
    """The first event of any gap in a trial step: (theta, gap, n_land) (theta 2: none).

    An open gap may touch, a closed one separate, even within the step
    (``_events._event_in_step``).  When the step ``landed`` on the event of
    ``target``, the gaps at their own crossing within the landing tolerance
    are listed in land_too: they switch together.
    """
    theta = 2.0
    g_ev = -1
    n_land = 0
    for q in range(ne_gap.size):
        if not ne_gap[q] or (landed and q == target):
            continue
        th, lands = _gap_event(d0[q], r0[q], d1[q], r1[q], h, active[q], landed)
        if lands:
            land_too[n_land] = q
            n_land += 1
        if th < theta:
            theta = th
            g_ev = q
    return theta, g_ev, n_land


@njit(cache=True, inline="always")
def _free_flight(ff, clock, motion, elg, lin, st, elem, ev, fl, peaks, energy, stats):
    """The analysis step ending at t_end in free flight (``_free_flight_trial``), accepted if no gap
    touches, no bilinear storey leaves its elastic range in it and the Bouc-Wen storeys' terms
    converge (``_bouc_wen_flight``).

    clock = (t_end, dt) [s]; the groups as ``general_kernel`` names them (st, elem, ev, fl: its work
    arrays, ``_general_work``); peaks = (umax, fmax); energy = (input, linear elements' and dampers' work,
    work on the storeys, contact work) [J].  Returns (accepted, energy): the bilinear storeys' work
    exactly (an elastic storey's force is linear in its deformation), the Bouc-Wen storeys' along their
    path, the linear elements' from the balance, input = kinetic + the two, as nothing else acts
    (``transition.py``).  Not accepted, nothing but the trial arrays changed.
    """
    t_end, dt = clock
    ag, moving, ne_ground = motion
    ne_code, ne_par, ne_gap = elg[3], elg[4], elg[5]
    u, v = st[0], st[1]
    st_c, active = elem[0], elem[6]
    d0, r0, d1, r1, land_too, gk, g_t, g_1 = ev[0], ev[1], ev[2], ev[3], ev[5], ev[6], ev[7], ev[8]
    u1, v1, a1, xs, ys, cst, rise, zs = fl
    st_elem = ff[10]
    for j in range(st_elem.size):  # F = k delta - c: c = (1 - alpha) k delta_p, fixed while elastic
        q = st_elem[j]
        if ne_code[q] == BOUC_WEN:  # c = (1 - alpha) k (delta - z) at the step's start
            cst[j] = (1.0 - ne_par[q, B_ALPHA]) * ne_par[q, B_K] * (st_c[q, ST_DELTA] - st_c[q, ST_Z])
        else:
            cst[j] = (1.0 - ne_par[q, B_ALPHA]) * ne_par[q, B_K] * st_c[q, ST_PLASTIC]
    _ground_all(ag, t_end, dt, g_1)
    de = _free_flight_trial(ff, u, v, g_t, g_1, u1, v1, a1, xs, ys, cst)
    if moving:
        _gap_ground_all(ne_ground, t_end, dt, gk, GU1)
    dwh = 0.0
    if ff[16]:  # Bouc-Wen storeys: their terms within the step
        ok, de_bw, dwh = _bouc_wen_flight(ff, elg, (st_c, cst), (u, v), (u1, v1, a1), xs[xs.size - 2 * g_t.size:],
                                          gk, dt, (rise, zs))
        if not ok:
            return False, energy
        de += de_bw
    for q in range(ne_gap.size):
        if ne_gap[q]:
            d1[q], r1[q] = _deformation_at(elg[0], elg[1], elg[2], q, u1, v1, gk, GU1)
    if _screen(ne_gap, active, d0, r0, d1, r1, dt, False, -1, land_too)[1] >= 0:
        return False, energy
    ok, dwh = _elastic_through(ff, elg, st_c, (u, v, u1, v1), (d1, r1), gk, dt, cst, zs, dwh)
    if not ok:
        return False, energy
    dke = kinetic_energy(lin[0], lin[1], lin[2], lin[9], v1) - kinetic_energy(lin[0], lin[1], lin[2], lin[9], v)
    _flight_commit(ff, elg, st, elem, ev, fl, peaks, moving)
    stats[S_FREE_FLIGHT] += 1
    stats[S_ITERATIONS] += int(rise[rise.size - 1])  # the Bouc-Wen terms' sweeps (0 without)
    stats[S_STEPS] += 1
    stats[S_DOF_STEPS] += u.size
    e_in, w_lin, w_hys, e_cont = energy
    return True, (e_in + de, w_lin + (de - dke - dwh), w_hys + dwh, e_cont)


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


# insert-before: _accept
@njit(cache=True)
def general_kernel(linear, p, numbering, elements, state0, motion, init, settings, opts, outs, cat, stats):
    """Integrate; fill the outputs; return (status, n_impacts, t_reached).

    The arguments come in named tuples: linear = (ms_dof, ms_coef, ms_val, ms_a0, le_dof, le_coef, le_k,
    le_c); p; numbering = (first, out_col); elements = (dof_load, dof_motion, dof_infl, ne_dof, ne_coef,
    ne_size, ne_code, ne_par, ne_gap, ne_lo, ne_hi); state0; motion = (ag, moving, ne_ground); init = (u_init,
    v_init); settings = (dt, nsteps, beta, gamma, n_sub, rtol, max_iter, store) as the fast driver's; opts =
    (tangent, pT, lev_free, ff, el_pred); outs = (out_u, out_v, out_a, out_f, out_e, umax, fmax); cat =
    (imp_gap, imp_t0, imp_v0, imp_vout, imp_fmax, imp_dur, imp_zeta, imp_e); stats.

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
    outputs as ``_kernel.integrate_kernel`` (out_f (nt, nn): every element's
    force; out_e (nt, 6) with the hysteretic energy).
    n_sub : (contact substeps per impact duration, longest contact substep [s]) (``_contact._begin_impact``).
    lev_free : no step longer than dt / 2^lev_free (substeps that make Newmark accurate at the
    analysis step: ``simulation.newmark_substeps``).
    tangent : a group of active elements that holds a storey iterates on the banded tangent
    (``_newton_tangent``, half bandwidth pT with the storeys); False: every group on the dense
    condensed system (``_newton``), the off switch the tests compare against.
    el_pred: every storey is bilinear, and a physical step first tries them at their elastic stiffness in
    the linear part (Newton on the closed gaps alone), kept if every storey ends the step elastic.
    ff = (on, start, off_x, off_g, off_e, phi, G0, G1, Egx, Egg, st_elem, st_start, Gc, Egc, Gq, Egq, bw):
    while every gap is open (and every storey, if any, is bilinear or, with ``bw``, Bouc-Wen: ``on``
    says so) an analysis step is one map per building (``transition.py``: exact, or the same Newmark
    substeps composed), screened for gap events and for bilinear storeys leaving their elastic
    range, the Bouc-Wen storeys' terms iterated within it (``_bouc_wen_flight``); on False, or when
    the screen finds an event, the step is taken on the physical path (``_physical_step``).
    """
    # arguments: alive for the whole call, so borrowed (``_borrow``: no reference counting in the loop)
    linear, numbering, elements, motion, init, opts, outs, cat = borrow_all(
        (linear, numbering, elements, motion, init, opts, outs, cat))
    stats = borrow(stats)
    dt, nsteps, beta, gamma, n_sub, rtol, max_iter, store = settings
    tangent, pT, lev_free, ff, el_pred = opts
    load, elg = elements[:3], elements[3:]
    ne_gap = elg[5]
    n, nn = init[0].size, ne_gap.size
    # the linear part as elements (assembly), as the bands of K and C (its forces), M's diagonal if lumped
    # and the envelope every factor keeps to
    lin = linear + (linear_bands(linear, p, n), lumped_diagonal(linear[0], linear[1], linear[2], n)) + numbering
    # the work arrays: owned by this tuple (kept alive to the end), used through borrowed aliases
    owners = _general_work(n, nn, motion[0].shape[0], (p, pT, el_pred), ff[10].size, dt, state0, init)
    work = borrow_all(owners)
    fac, st, lists, elem, ev = work[0], work[1], work[2], work[5], work[6]
    cs = (elem[6], elem[0], elem[7], elem[8], elem[9])  # each element's contact state (``_contact._begin_impact``)
    cfg = (dt, beta, gamma, n_sub, rtol, max_iter, tangent, pT, lev_free, el_pred, p)
    model = (lin, load, elg, motion, cs)
    for s in range(stats.size):
        stats[s] = 0
    assemble_band(1.0, 0.0, 0.0, linear, p, fac[3])
    if not _factor_profile(fac[3], p, lin[10], 0, n):
        return NEWTON_FAILED, 0, 0.0  # a DOF without mass (the front end refuses it first)
    # -- initial state: storeys active, gaps closing at t = 0 start an impact ------
    status, n_imp, m_act, n_comp, es_lin0, rec0, e_in = _start(dt, n_sub, motion, elg, elem, cs, cat, lists, st, ev,
                                                               (fac[3], p, lin, load))
    if status != OK:
        return status, n_imp, 0.0
    energy = (e_in, 0.0, 0.0, 0.0)  # input, linear elements' and dampers' work, work on the storeys, contact [J]
    _output(0, True, st, ev[7], load, lin, elg, elem, ev[0], (es_lin0, rec0), energy, outs)
    n_storeys = 0
    for q in range(nn):
        n_storeys += 0 if ne_gap[q] else 1
    ls = (0.0, n_imp, m_act, n_comp, -1.0)  # t, impacts, active elements, their groups, h of A's band
    flin_stale = False
    step = 0
    while step < nsteps:
        t_end = (step + 1) * dt
        ok = False
        if ff[0] and ls[2] == n_storeys:  # every gap open (the storeys are always active): FREE FLIGHT
            ok, energy = _free_flight(ff, (t_end, dt), motion, elg, lin, st, elem, ev, work[7], outs[5:], energy,
                                      stats)
        if ok:
            ls = (t_end,) + ls[1:]
            flin_stale = True
        else:  # the PHYSICAL PATH: Newmark steps, contact substeps, events
            if flin_stale:  # K u + C v at the state free flight left (the corrector's trapezoidal work needs it)
                linear_forces(lin[8], st[0], st[1], st[8])
                flin_stale = False
            status, ls, energy = _physical_step(t_end, ls, energy, cfg, model, work, outs, cat, stats)
            if status != OK:
                return status, ls[1], ls[0]
            if store:
                for q in range(nn):
                    if not ne_gap[q]:
                        ev[0][q] = _dot(elg[0], elg[1], q, st[0]) - elg[2][q]
        step += 1
        if store:
            _output(step, False, st, ev[7], load, lin, elg, elem, ev[0], (es_lin0, rec0), energy, outs)
    keep_alive(owners)
    return OK, ls[1], ls[0]


@njit(cache=True, inline="always")
def _bouc_wen_sweep(ff, elg, mat, x0, x1, gk, h, bw):
    """One Gauss-Seidel sweep of ``_bouc_wen_flight`` over the Bouc-Wen storeys: each storey's z along its
    end state's cubic, its rises dm, d1 [N] corrected and added to the end state x1."""
    start, st_elem, st_start, gq = ff[1], ff[10], ff[11], ff[14]
    ne_dof, ne_coef, ne_size, ne_code, ne_par = elg[0], elg[1], elg[2], elg[3], elg[4]
    st_c, cst = mat
    u, v = x0
    u1, v1 = x1[0], x1[1]
    rise, zs = bw
    o_q = 0
    for c in range(start.size - 1):
        a = start[c]
        nb = start[c + 1] - a
        for j in range(st_start[c], st_start[c + 1]):
            q = st_elem[j]
            if ne_code[q] != BOUC_WEN:
                continue
            ds0, rs0 = _deformation_at(ne_dof, ne_coef, ne_size, q, u, v, gk, GU0)
            ds1, rs1 = _deformation_at(ne_dof, ne_coef, ne_size, q, u1, v1, gk, GU1)
            ca, cb, cc = _cubic(ds0, rs0, ds1, rs1, h)
            zm, z1, eps1, pm, p1 = bouc_wen_path(ne_par, q, st_c[q, ST_Z], st_c[q, ST_EPS], ds0, ca, cb, cc)
            dm_ = _hermite(0.5, ds0, rs0, ds1, rs1, h)
            scale = (1.0 - ne_par[q, B_ALPHA]) * ne_par[q, B_K]
            ddm = scale * (dm_ - zm) - cst[j] - rise[2 * j]
            dd1 = scale * (ds1 - z1) - cst[j] - rise[2 * j + 1]
            zs[6 * j], zs[6 * j + 1], zs[6 * j + 2], zs[6 * j + 3] = z1, eps1, ds1, dm_
            zs[6 * j + 4], zs[6 * j + 5] = pm, p1
            if ddm == 0.0 and dd1 == 0.0:
                continue
            rise[2 * j] += ddm
            rise[2 * j + 1] += dd1
            _add_rise(gq, o_q + (j - st_start[c]) * 6 * nb, nb, a, ddm, dd1, x1)
        o_q += 6 * nb * (st_start[c + 1] - st_start[c])


@njit(cache=True, inline="always")
def _bouc_wen_next(ff, elg, x0, x1, gk, h, zs):
    """The next sweep's largest correction, predicted from how far the last sweep's updates moved each
    Bouc-Wen storey's deformation at the step's middle and end times the law's slope there, relative
    to its yield displacement (``_bouc_wen_flight``)."""
    st_elem = ff[10]
    ne_dof, ne_coef, ne_size, ne_code, ne_par = elg[0], elg[1], elg[2], elg[3], elg[4]
    u, v = x0
    u1, v1 = x1[0], x1[1]
    pred = 0.0
    for j in range(st_elem.size):
        q = st_elem[j]
        if ne_code[q] != BOUC_WEN:
            continue
        ds0, rs0 = _deformation_at(ne_dof, ne_coef, ne_size, q, u, v, gk, GU0)
        ds1, rs1 = _deformation_at(ne_dof, ne_coef, ne_size, q, u1, v1, gk, GU1)
        dm_ = _hermite(0.5, ds0, rs0, ds1, rs1, h)
        step1, stepm = ds1 - zs[6 * j + 2], dm_ - zs[6 * j + 3]
        pred = max(pred, (abs((1.0 - zs[6 * j + 4]) * stepm) + abs((1.0 - zs[6 * j + 5]) * step1))
                   / ne_par[q, BW_DY])
    return pred


@njit(cache=True, inline="always")
def _bouc_wen_work(ff, elg, mat, x0, x1, gs, gk, h, bw):
    """The converged step's input work of the rises [J], z's linear correction, and the Bouc-Wen storeys'
    work along the final path [J] (``_bouc_wen_flight``)."""
    start, st_elem, st_start, egq = ff[1], ff[10], ff[11], ff[15]
    ne_dof, ne_coef, ne_size, ne_code, ne_par = elg[0], elg[1], elg[2], elg[3], elg[4]
    cst = mat[1]
    u, v = x0
    u1, v1 = x1[0], x1[1]
    rise, zs = bw
    nm = gs.size // 2
    de = 0.0
    dwh = 0.0
    o_e = 0
    for c in range(start.size - 1):
        for j in range(st_start[c], st_start[c + 1]):
            q = st_elem[j]
            if ne_code[q] != BOUC_WEN:
                continue
            dm, d1 = rise[2 * j], rise[2 * j + 1]
            base = o_e + (j - st_start[c]) * 4 * nm
            for m in range(2 * nm):
                de += gs[m] * (egq[base + m] * dm + egq[base + 2 * nm + m] * d1)
            ds0, rs0 = _deformation_at(ne_dof, ne_coef, ne_size, q, u, v, gk, GU0)
            ds1, rs1 = _deformation_at(ne_dof, ne_coef, ne_size, q, u1, v1, gk, GU1)
            step1 = ds1 - zs[6 * j + 2]
            zs[6 * j] += zs[6 * j + 5] * step1
            zs[6 * j + 1] += zs[6 * j] * step1 / (ne_par[q, BW_DY] * ne_par[q, BW_DY])
            zs[6 * j + 2] = ds1
            ca, cb, cc = _cubic(ds0, rs0, ds1, rs1, h)
            work_c = 0.0  # int c d(delta) = int_0^1 c(tau) delta'(tau) d tau
            for g in range(3):
                tau = _GL_T[g]
                ct = cst[j] + (4.0 * dm - d1) * tau + (2.0 * d1 - 4.0 * dm) * tau * tau
                work_c += _GL_W[g] * ct * (ca + tau * (2.0 * cb + 3.0 * cc * tau))
            dwh += 0.5 * ne_par[q, B_K] * (ds1 * ds1 - ds0 * ds0) - work_c
        o_e += 4 * nm * (st_start[c + 1] - st_start[c])
    return de, dwh


@njit(cache=True, inline="always")
def _elastic_through(ff, elg, st_c, x, dr1, gk, dt, cst, zs, dwh):
    """Does each bilinear storey stay within its elastic range over the whole free-flight step (the
    cubic bound of ``_events``)?  Returns (ok, dwh plus the bilinear storeys' work [J]); fills each storey's end
    deformation and rate into dr1 = (d1, r1) (a Bouc-Wen storey's from its path, zs)."""
    ne_dof, ne_coef, ne_size, ne_code, ne_par = elg[0], elg[1], elg[2], elg[3], elg[4]
    u, v, u1, v1 = x
    d1, r1 = dr1
    st_elem = ff[10]
    for j in range(st_elem.size):
        q = st_elem[j]
        if ne_code[q] == BOUC_WEN:
            d1[q] = zs[6 * j + 2]
            continue
        k = ne_par[q, B_K]
        hi = st_c[q, ST_PLASTIC] + ne_par[q, B_FY] / k
        lo = st_c[q, ST_PLASTIC] - ne_par[q, B_FY] / k
        ds0, rs0 = _deformation_at(ne_dof, ne_coef, ne_size, q, u, v, gk, GU0)
        ds1, rs1 = _deformation_at(ne_dof, ne_coef, ne_size, q, u1, v1, gk, GU1)
        tol = 1e-12 * (hi - lo)
        if (_event_in_step(ds0 - hi, rs0, ds1 - hi, rs1, dt, True, tol) <= 1.0
                or _event_in_step(lo - ds0, -rs0, lo - ds1, -rs1, dt, True, tol) <= 1.0):
            return False, 0.0
        d1[q] = ds1
        r1[q] = rs1
        dwh += 0.5 * k * (ds1 * ds1 - ds0 * ds0) - cst[j] * (ds1 - ds0)
    return True, dwh


@njit(cache=True, inline="always")
def _flight_commit(ff, elg, st, elem, ev, fl, peaks, moving):
    """An accepted free-flight step's end becomes the state: (u, v, a), the gaps' and storeys'
    deformations, the storeys' committed laws and forces, the peaks and the ground terms."""
    ne_code, ne_par, ne_gap = elg[3], elg[4], elg[5]
    u, v, a = st[0], st[1], st[2]
    st_c, st_t, F = elem[0], elem[1], elem[2]
    d0, r0, d1, r1, gk, g_t, g_1 = ev[0], ev[1], ev[2], ev[3], ev[6], ev[7], ev[8]
    u1, v1, a1, zs = fl[0], fl[1], fl[2], fl[7]
    umax, fmax = peaks
    st_elem = ff[10]
    for i in range(u.size):
        u[i] = u1[i]
        v[i] = v1[i]
        a[i] = a1[i]
        umax[i] = max(umax[i], abs(u[i]))
    for q in range(ne_gap.size):
        if ne_gap[q]:
            d0[q] = d1[q]
            r0[q] = r1[q]
    for j in range(st_elem.size):  # the storeys' state at the step's end (elastic: delta_p kept)
        q = st_elem[j]
        d0[q] = d1[q]  # (the output's recoverable energy reads the storeys' deformations here)
        if ne_code[q] == BOUC_WEN:  # the state its path reached
            for c in range(st_c.shape[1]):
                st_t[q, c] = st_c[q, c]
            st_t[q, ST_Z], st_t[q, ST_EPS], st_t[q, ST_DELTA] = zs[6 * j], zs[6 * j + 1], d1[q]
            F[q] = ne_par[q, B_K] * d1[q] - (1.0 - ne_par[q, B_ALPHA]) * ne_par[q, B_K] * (d1[q] - zs[6 * j])
        else:
            F[q] = material_trial(ne_code[q], ne_par, st_c, st_t, q, d1[q], r1[q])[0]
        material_commit(st_c, st_t, q)
        fmax[q] = max(fmax[q], abs(F[q]))
    for r in range(g_t.size):
        g_t[r] = g_1[r]
    if moving:
        _gap_ground_accept(gk)


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
    fl = (u1, v1, a1, xs, ys, cst, rise, zs): a free-flight step's trial state and scratch.
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
          np.zeros(2 * nf + 1), np.zeros(6 * nf))
    return fac, st, lists, nwt, tang, elem, ev, fl


@njit(cache=True, inline="always")
def _physical_step(t_end, ls, energy, cfg, model, work, outs, cat, stats):
    """The rest of the analysis step ending at t_end [s] on the physical path: Newmark steps (contact
    substeps while a gap is closed), each by attempts of factor, predictor and Newton (``_iterate``) and
    the event screen, redone up to the first event; then ACCEPT / COMMIT, and a SWITCH at each event.

    ls = (t, impacts, active elements, their groups, h of the banded tangent's A); energy = (input,
    linear work, storeys' work, contact work) [J]; cfg = (dt, beta, gamma, n_sub, rtol, max_iter,
    tangent, pT, lev_free, el_pred, p); model = (lin, load, elg, motion, cs); work: ``_general_work``'s
    groups.  Returns (status, ls, energy).
    """
    t, n_imp, m_act, n_comp, h_A = ls
    dt, n_sub, lev_free, p = cfg[0], cfg[3], cfg[8], cfg[10]
    lin, load, elg, motion, cs = model
    fac, st, lists, elem, ev = work[0], work[1], work[2], work[5], work[6]
    ne_code, ne_gap, ne_lo, ne_hi = elg[3], elg[5], elg[6], elg[7]
    act, comp_off = lists[0], lists[1]
    F, active, hsub, age = elem[2], elem[6], elem[7], elem[8]
    d0, r0, d1, r1, toggles, land_too, gk, g_t, g_1 = ev
    hmin = 1e-9 * dt  # events closer than this to the step's start switch in place
    while t_end - t > 1e-9 * dt:
        # ---- step size: the rest of the analysis step, or the contact substep grid
        h, lev = _contact_step(t, t_end, dt, m_act, act, ne_code, hsub, age, fac[2], N_LEVELS, lev_free)
        target = -1
        landed = False
        located = False
        n_tog = 0
        n_land = 0
        cc = 0.0
        cm = 0.0
        for attempt in range(200):
            lv, h = _grid_level(h, lev, fac[2], dt)
            cm = 1.0 / (cfg[1] * h * h)
            cc = cfg[2] / (cfg[1] * h)
            _ground_all(motion[0], t + h, dt, g_1)
            if motion[1]:
                _gap_ground_all(motion[2], t + h, dt, gk, GU1)
            ok, converged, h_A = _iterate(lv, (h, cm, cc), (m_act, n_comp), cfg, model, work, h_A, stats)
            if not ok:
                return NEWTON_FAILED, (t, n_imp, m_act, n_comp, h_A), energy
            if not converged:
                stats[S_REJECTED] += 1
                h *= 0.25
                target = -1
                if h < hmin:
                    return NEWTON_FAILED, (t, n_imp, m_act, n_comp, h_A), energy
                continue
            # ---- EVENT SCREEN: does a gap touch or separate inside the step?
            for q in range(ne_gap.size):
                if ne_gap[q]:
                    d1[q], r1[q] = _deformation(elg[0], elg[1], elg[2], q, st[0], st[6], st[3], cc, gk, GU1)
            landed = False
            if target >= 0:
                landed = abs(d1[target]) <= LAND_TOL * max(abs(r1[target]), abs(r0[target])) * h + 1e-15
            theta, g_ev, n_land = _screen(ne_gap, active, d0, r0, d1, r1, h, landed, target, land_too)
            if g_ev < 0:
                located = True
                break
            stats[S_REJECTED] += 1
            if theta * h < hmin:  # events at the current time: switch them in place, then step
                n_tog = _at_once(h, hmin, ne_gap, active, (d0, r0, d1, r1), landed, target, toggles)
                break
            h = theta * h
            target = g_ev
        if not located and n_tog == 0:
            return NEWTON_FAILED, (t, n_imp, m_act, n_comp, h_A), energy
        if located:
            # ---- ACCEPT / COMMIT
            energy = _accept(h, (cm, cc), lin, load, elg, (act, m_act), (g_t, g_1), st, elem,
                             (outs[5], outs[6], cat[4]), energy)
            stats[S_STEPS] += 1
            t = _advance(t, h, (t_end, dt), ne_gap, ev, motion[1])
            if landed:
                n_tog = _landed(target, n_land, land_too, toggles)
        if n_tog > 0:
            # ---- SWITCH: an impact's onset (the law's onset hook) or end at each gap in toggles
            status, n_imp, m_act = _switch(toggles, n_tog, t, n_sub, elg, (d0, r0), F, outs[6], cs, cat, act,
                                           (n_imp, m_act))
            if status != OK:
                return status, (t, n_imp, m_act, n_comp, h_A), energy
            n_comp = _group_contacts(m_act, act, ne_lo, ne_hi, comp_off)
            # a contact force may jump at an event (LVe's dashpot): equilibrium at fixed (u, v)
            _acceleration((fac[3], p), lin, load, g_t, st, elg, F)
    return OK, (t, n_imp, m_act, n_comp, h_A), energy


@njit(cache=True, inline="always")
def _iterate(lv, step, counts, cfg, model, work, h_A, stats):
    """One attempt at a step of h [s] (``_physical_step``): factor, PREDICTOR, and the ITERATIONS.

    Phase 0, the elastic predictor (every storey bilinear, ``el_pred``): the storeys at their elastic
    stiffness in the linear part, Newton on the closed gaps alone, kept if every storey ends the step
    elastic.  Phase 1: the predictor with every element force of state frozen at zero, then Newton on
    the active elements' forces, condensed through A^-1 (``_solve_groups``).  step = (h, cm, cc); counts
    = (active elements, their groups).  Returns (ok: A positive definite, converged, h_A).
    """
    h, cm, cc = step
    m_act, n_comp = counts
    beta, gamma, rtol, max_iter, tangent, pT, el_pred, p = cfg[1], cfg[2], cfg[4], cfg[5], cfg[6], cfg[7], cfg[9], cfg[10]
    lin, load, elg = model[0], model[1], model[2]
    fac, st, lists, nwt, tang, elem, ev = work[0], work[1], work[2], work[3], work[4], work[5], work[6]
    ne_dof, ne_coef, ne_size, ne_code, ne_par, ne_gap, ne_lo, ne_hi = elg
    act, comp_off, actg, compg_off = lists
    Gm, Sm, ym, Fm, dl, rl, resv, kt = nwt
    st_c, st_t, F, F1, F_old, h_old, active, hsub, age, cur_imp = elem
    u, Du, Vv, R0 = st[0], st[6], st[3], st[5]
    gk = ev[6]
    frc = (F, F1, F_old, h_old, age, Fm, dl, rl, st_c, st_t)
    twork = (tang[2], tang[3], resv, kt, tang[4], Sm, ym, tang[5])
    for phase in range(2):
        if phase == 0 and not el_pred:
            continue
        if phase == 0:
            ok, Lp, Wp, Wp_ok = _cached_factor(lv, h, cm, cc, lin, (ne_dof, ne_coef, ne_par, ne_gap), True, pT,
                                               fac[1], stats)
            if not ok:
                return False, False, h_A
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
                return False, False, h_A
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
            return True, ok, h_A
        elastic = ok
        for q in range(ne_gap.size):
            if elastic and not ne_gap[q]:
                ds, rs = _deformation(ne_dof, ne_coef, ne_size, q, u, Du, Vv, cc, gk, GU1)
                f, dfd, dfv = material_trial(ne_code[q], ne_par, st_c, st_t, q, ds, rs)
                elastic = dfd == ne_par[q, B_K]
                F1[q] = f
        if elastic:
            return True, True, h_A
    return True, True, h_A


@njit(cache=True, inline="always")
def _advance(t, h, clock, ne_gap, ev, moving):
    """After an accepted step of h [s] from t: each gap's deformation and rate at the step's end become its
    start's, the ground terms move on, and the clock too (to t_end exactly where it lands within round-off
    of it: no drift across analysis steps).  clock = (t_end, dt).  Returns the new t."""
    t_end, dt = clock
    d0, r0, d1, r1, gk, g_t, g_1 = ev[0], ev[1], ev[2], ev[3], ev[6], ev[7], ev[8]
    for q in range(ne_gap.size):
        if ne_gap[q]:
            d0[q] = d1[q]
            r0[q] = r1[q]
    t = t + h
    if abs(t - t_end) <= 1e-9 * dt:
        t = t_end
    for r in range(g_t.size):
        g_t[r] = g_1[r]
    if moving:
        _gap_ground_accept(gk)
    return t


@njit(cache=True, inline="always")
def _landed(target, n_land, land_too, toggles):
    """The gaps a step that landed on target's event switches: target and those at their own crossing
    within the landing tolerance (``_screen``).  Fills toggles; returns their number."""
    toggles[0] = target
    n_tog = 1
    for k in range(n_land):
        toggles[n_tog] = land_too[k]
        n_tog += 1
    return n_tog


@njit(cache=True)
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
    linear_forces(lin[8], u, v, flin1)
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
    recoverable energy) at t = 0 [J]; energy = (input, linear work, storeys' work, contact work) [J].
    """
    u, v, a = st[0], st[1], st[2]
    dof_motion, dof_infl = load[1], load[2]
    ne_code, ne_par, ne_gap = elg[3], elg[4], elg[5]
    st_c, F = elem[0], elem[2]
    es_lin0, rec0 = e0
    e_in, w_lin, w_hys, e_cont = energy
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
    out_e[k, E_KINETIC] = kinetic_energy(lin[0], lin[1], lin[2], lin[9], v)
    out_e[k, E_STRAIN] = es_lin + rec
    out_e[k, E_DAMPING] = w_lin - (es_lin - es_lin0)
    out_e[k, E_CONTACT] = e_cont
    out_e[k, E_HYSTERETIC] = w_hys - (rec - rec0)


@njit(cache=True)
def _start(dt, n_sub, motion, elg, elem, cs, cat, lists, st, ev, eq):
    """The state at t = 0: every storey active, gaps already closing (touching bodies) start an impact, each
    active element's force from its law, the closed gaps listed and grouped, the accelerations from
    equilibrium.  The groups as ``general_kernel`` names them (``_general_work``): lists (act, comp_off)
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
    _acceleration((LM, p), lin, load, g_t, st, elg, F)
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
