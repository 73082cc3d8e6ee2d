"""Free flight on the general driver: an analysis step with every gap open by each building's state-transition map.

Private to the general driver (``_general.py``).  While every gap is open and every storey has a law with
history (bilinear, Bouc-Wen, peak-oriented, Iwan or flag), each building moves by its own linear map over the
analysis step (``transition.py``: exact for the piecewise-linear ground motion, or the same Newmark substeps
composed), with each storey's offset force c (its force is k delta - c) as an input.  The step is screened for
gap events and for the storeys whose c is held fixed (elastic bilinear, virgin peak-oriented, Iwan and flag
storeys inside their windows) reaching the end of their elastic range (``_events``' cubic bound); the offsets
of the Bouc-Wen storeys, of the bilinear and peak-oriented storeys that have yielded, of flag storeys on a
branch and of Iwan storeys outside their windows (or leaving them within the step) are iterated within the
step (``_hysteretic_flight``).  An accepted step commits the state, the storeys' laws and the energies; one
that is not leaves the state as it was, and the driver takes the step on its physical path.
"""

from __future__ import annotations

import numpy as np
from seispound._jit import njit

from ._elements import _deformation_at, kinetic_energy
from ._events import _event_in_step, _hermite, _screen_elements
from ._ground import GU0, GU1, _gap_ground_accept, _gap_ground_all, _ground_all
from ..storey.codes import B_ALPHA, B_FY, B_K, BOUC_WEN, BW_DY, FL_DY, FLAG, IW_DY, IWAN, PEAK_ORIENTED, PO_FY, PO_K
from ._flag import ST_FLAG_DRIFT, ST_FLAG_H, flag_on_branch
from ._iwan import ST_IWAN_DRIFT
from ._material import (B_ON_SURFACE, ST_DELTA, ST_EPS, ST_PLASTIC, ST_Q, ST_Z, bilinear_dy, bilinear_path,
                        bouc_wen_path, flag_path, iwan_path, material_commit, material_trial, material_window,
                        peak_oriented_path)
from ._peak_oriented import ST_D, ST_DNEG, ST_DPOS, ST_F
from ._outputs import S_DOF_STEPS, S_FREE_FLIGHT, S_ITERATIONS, S_STEPS

# a free-flight step's hysteretic terms: the fixed point stops when the next sweep would move no term's rise
# by more than BW_FLIGHT_TOL (1 - alpha) k dy, and is given up (the physical path takes the step) after
# BW_FLIGHT_ITER sweeps
BW_FLIGHT_TOL = 1e-7
BW_FLIGHT_ITER = 30
# 3-point Gauss-Legendre on [0, 1] (exact for the quartic c(s) delta'(s) of the storey's work)
_GL_T = (0.5 - 0.5 * 0.7745966692414834, 0.5, 0.5 + 0.5 * 0.7745966692414834)
_GL_W = (5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0)


@njit(cache=True, inline="always")
def _free_flight(ff, clock, motion, elg, lin, st, elem, ev, fl, peaks, energy, stats):
    """The analysis step ending at t_end in free flight (``_free_flight_trial``), accepted if no gap
    touches, no storey whose term is held fixed reaches the end of its elastic range in it (an Iwan storey
    that does has its term iterated instead, and the step is iterated again) and the hysteretic storeys'
    terms converge (``_hysteretic_flight``).

    clock = (t_end, dt) [s]; the groups as ``_driver.general_kernel`` names them (st, elem, ev, fl: its work
    arrays, ``_general_work``); peaks = (umax, fmax); energy = ((input, linear elements' and dampers' work,
    work on the storeys, contact work) [J], the kinetic energy at the step's start [J] or NaN: computed).
    Returns (accepted, energy, the kinetic energy at the step's end [J]): the elastic bilinear storeys' work
    exactly (their force is linear in their deformation), the iterated storeys' (Bouc-Wen, yielding
    bilinear) along their path, the linear elements' from the balance, input = kinetic + the two, as nothing
    else acts (``transition.py``).  Not accepted, nothing but the trial arrays changed.
    """
    t_end, dt = clock
    energy, ke0 = energy
    ag, moving, ne_ground = motion
    ne_code, ne_par, ne_gap = elg[3], elg[4], elg[5]
    u, v = st[0], st[1]
    st_c, active = elem[0], elem[6]
    d0, r0, d1, r1, land_too, gk, g_t, g_1 = ev[0], ev[1], ev[2], ev[3], ev[5], ev[6], ev[7], ev[8]
    u1, v1, a1, xs, ys, cst, rise, zs, itr, corr, dr = fl
    st_elem = ff[10]
    n_itr = 0
    for j in range(st_elem.size):  # F = k delta - c: c = (1 - alpha) k delta_p, fixed while elastic
        q = st_elem[j]
        if ne_code[q] == BOUC_WEN:  # c = (1 - alpha) k (delta - z) at the step's start
            cst[j] = (1.0 - ne_par[q, B_ALPHA]) * ne_par[q, B_K] * (st_c[q, ST_DELTA] - st_c[q, ST_Z])
            itr[j] = True
        elif ne_code[q] == PEAK_ORIENTED:  # c = k delta - f: fixed while a virgin storey stays within +-dy,
            cst[j] = ne_par[q, B_K] * st_c[q, ST_D] - st_c[q, ST_F]  # iterated once it has yielded
            itr[j] = not _virgin(ne_par, st_c, q)
        elif ne_code[q] == IWAN or ne_code[q] == FLAG:  # c fixed while every spring is elastic; a flag storey
            lo, hi, cj = material_window(ne_code[q], ne_par, st_c, q)  # on a branch iterated, c = K delta - h
            cst[j] = cj
            itr[j] = ne_code[q] == FLAG and ff[16] and flag_on_branch(ne_par, st_c, q)
            if ne_code[q] == IWAN and ff[16] and not _inside(lo, hi, st_c[q, ST_IWAN_DRIFT], ne_par[q, IW_DY]):
                d = st_c[q, ST_IWAN_DRIFT]  # iterated, c = k delta - F
                cst[j] = ne_par[q, B_K] * d - material_trial(IWAN, ne_par, st_c, elem[1], q, d, 0.0)[0]
                itr[j] = True
        else:  # a yielding bilinear storey's c is iterated as a Bouc-Wen storey's (z = q_h / k)
            cst[j] = (1.0 - ne_par[q, B_ALPHA]) * ne_par[q, B_K] * st_c[q, ST_PLASTIC]
            itr[j] = ff[16] and abs(st_c[q, ST_Q]) >= (1.0 - B_ON_SURFACE) * ne_par[q, B_FY]
        if not itr[j]:  # (a term iterated later starts from no rise)
            rise[2 * j], rise[2 * j + 1] = 0.0, 0.0
        n_itr += 1 if itr[j] else 0
    _ground_all(ag, t_end, dt, g_1)
    de = _free_flight_trial(ff, u, v, g_t, g_1, u1, v1, a1, xs, ys, cst)
    if moving:
        _gap_ground_all(ne_ground, t_end, dt, gk, GU1)
    for j in range(st_elem.size):  # each storey's deformation and rate at the step's start, read by every sweep
        dr[4 * j], dr[4 * j + 1] = _deformation_at(elg[0], elg[1], elg[2], st_elem[j], u, v, gk, GU0)
    rise[rise.size - 1] = 0
    de_bw = 0.0
    for attempt in range(3):  # an Iwan storey that leaves its window joins the iterated ones (twice at most)
        dwh = 0.0
        if n_itr > 0:  # Bouc-Wen, yielding bilinear, flag and Iwan storeys: their terms within the step
            ok, de_bw, dwh = _hysteretic_flight(ff, elg[:5], (st_c, cst, elem[1]), (u1, v1, a1),
                                                xs[xs.size - 2 * g_t.size:], gk, dt, (rise, zs, itr, corr, dr),
                                                attempt == 0)
            if not ok:
                return False, energy, ke0
        for q in range(ne_gap.size):
            if ne_gap[q]:
                d1[q], r1[q] = _deformation_at(elg[0], elg[1], elg[2], q, u1, v1, gk, GU1)
        if _screen_elements(ne_gap, active, d0, r0, d1, r1, dt, False, -1, land_too)[1] >= 0:
            return False, energy, ke0
        status, dwh = _elastic_through(ff, elg, st_c, (u1, v1), (d1, r1), gk, dt, cst, (zs, itr, dr), dwh)
        if status == 0:
            break
        if status == 1 or attempt == 2:
            return False, energy, ke0
        n_itr = 1
    if n_itr > 0:
        de += de_bw
    ke1 = kinetic_energy(lin[0], lin[1], lin[2], lin[9], v1)
    dke = ke1 - (ke0 if ke0 == ke0 else kinetic_energy(lin[0], lin[1], lin[2], lin[9], v))
    _flight_commit(ff, elg, st, elem, ev, fl, peaks, moving, dt)
    stats[S_FREE_FLIGHT] += 1
    stats[S_ITERATIONS] += int(rise[rise.size - 1])  # the hysteretic terms' sweeps (0 without)
    stats[S_STEPS] += 1
    stats[S_DOF_STEPS] += u.size
    e_in, w_lin, w_hys, e_cont = energy
    return True, (e_in + de, w_lin + (de - dke - dwh), w_hys + dwh, e_cont), ke1


@njit(cache=True, inline="always")
def _virgin(par, st_c, q):
    """Has peak-oriented storey q never passed its yield drift (its excursions at +-dy or unset: its force
    k delta within +-dy, as an elastic bilinear storey's)?"""
    dy = par[q, PO_FY] / par[q, PO_K]
    return st_c[q, ST_DPOS] <= dy and st_c[q, ST_DNEG] >= -dy


@njit(cache=True, inline="always")
def _elastic_through(ff, elg, st_c, x, dr1, gk, dt, cst, terms, dwh):
    """Does each bilinear (or virgin peak-oriented, Iwan or flag) storey whose term is not iterated stay within its
    elastic range over the whole free-flight step (the cubic bound of ``_events``)?  Returns (status, dwh plus
    those storeys' work [J]): status 0 yes, 1 no, 2 no but only Iwan storeys left their windows, each now marked
    iterated in itr (with the hysteretic terms on: the caller iterates the step again).  Fills each storey's end
    deformation and rate, at the end state x = (u1, v1), into dr1 = (d1, r1) (an iterated storey's from its
    path: terms = (zs, itr, dr), ``_hysteretic_flight``; dr holds the start's)."""
    ne_dof, ne_coef, ne_size, ne_code, ne_par = elg[0], elg[1], elg[2], elg[3], elg[4]
    u1, v1 = x
    d1, r1 = dr1
    zs, itr, dr = terms
    st_elem = ff[10]
    status = 0
    for j in range(st_elem.size):
        q = st_elem[j]
        if itr[j]:
            d1[q] = zs[6 * j + 2]
            continue
        k = ne_par[q, B_K]
        ds0, rs0 = dr[4 * j], dr[4 * j + 1]
        if ne_code[q] == IWAN or ne_code[q] == FLAG:  # (one that starts outside its window: a yielding one)
            lo, hi = material_window(ne_code[q], ne_par, st_c, q)[:2]
            if ds0 > hi + 1e-12 * abs(hi) or ds0 < lo - 1e-12 * abs(lo):
                return 1, 0.0
        else:
            centre = 0.0 if ne_code[q] == PEAK_ORIENTED else st_c[q, ST_PLASTIC]  # (a virgin one: f = k delta)
            hi = centre + ne_par[q, B_FY] / k
            lo = centre - ne_par[q, B_FY] / k
        ds1, rs1 = _deformation_at(ne_dof, ne_coef, ne_size, q, u1, v1, gk, GU1)
        tol = 1e-12 * abs(hi - lo)
        if (_event_in_step(ds0 - hi, rs0, ds1 - hi, rs1, dt, True, tol) <= 1.0
                or _event_in_step(lo - ds0, -rs0, lo - ds1, -rs1, dt, True, tol) <= 1.0):
            if not (ff[16] and ne_code[q] == IWAN):
                return 1, 0.0
            itr[j] = True  # its term iterated from no rise: the end state holds its c at the step's start
            status = 2
        d1[q] = ds1
        r1[q] = rs1
        dwh += 0.5 * k * (ds1 * ds1 - ds0 * ds0) - cst[j] * (ds1 - ds0)
    return status, dwh


@njit(cache=True, inline="always")
def _inside(lo, hi, d, dy):
    """Does an Iwan storey's committed drift d [m] lie strictly inside its window [lo, hi] (every spring elastic
    around it), by more than 1e-12 of its yield drift dy [m]?"""
    tol = 1e-12 * dy
    return lo + tol < d < hi - tol


@njit(cache=True, inline="always")
def _flight_commit(ff, elg, st, elem, ev, fl, peaks, moving, h):
    """An accepted free-flight step of h [s]'s end becomes the state: (u, v, a), the gaps' and storeys'
    deformations, the storeys' committed laws and forces, the peaks and the ground terms."""
    ne_code, ne_par, ne_gap = elg[3], elg[4], elg[5]
    u, v, a = st[0], st[1], st[2]
    st_c, st_t, F = elem[0], elem[1], elem[2]
    d0, r0, d1, r1, gk, g_t, g_1 = ev[0], ev[1], ev[2], ev[3], ev[6], ev[7], ev[8]
    u1, v1, a1, zs, itr, dr = fl[0], fl[1], fl[2], fl[7], fl[8], fl[10]
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
        if itr[j] and (ne_code[q] == PEAK_ORIENTED or ne_code[q] == FLAG or ne_code[q] == IWAN):  # its law along
            ca, cb, cc = _cubic(dr[4 * j], dr[4 * j + 1], d1[q], dr[4 * j + 3], h)  # the final path (exact)
            if ne_code[q] == IWAN:  # (the path leaves its end state in st_t)
                F[q] = iwan_path(ne_par, q, st_c, st_t, dr[4 * j], ca, cb, cc)[4]
            elif ne_code[q] == FLAG:
                h1 = flag_path(ne_par, q, st_c, dr[4 * j], ca, cb, cc)[5]
                st_t[q, ST_FLAG_H], st_t[q, ST_FLAG_DRIFT] = h1, d1[q]
                F[q] = ne_par[q, B_ALPHA] * ne_par[q, B_K] * d1[q] + h1
            else:
                f1, dpos, dneg = peak_oriented_path(ne_par, q, st_c, dr[4 * j], ca, cb, cc)[5:]
                st_t[q, ST_F], st_t[q, ST_D], st_t[q, ST_DPOS], st_t[q, ST_DNEG] = f1, d1[q], dpos, dneg
                F[q] = f1
        elif itr[j]:  # the state its path reached
            for c in range(st_c.shape[1]):
                st_t[q, c] = st_c[q, c]
            z = zs[6 * j]
            if ne_code[q] == BOUC_WEN:
                st_t[q, ST_Z], st_t[q, ST_EPS], st_t[q, ST_DELTA] = z, zs[6 * j + 1], d1[q]
            else:  # q_h = k z within +-fy, delta_p = delta - z
                dy = bilinear_dy(ne_par, q)
                z = min(max(z, -dy), dy)
                st_t[q, ST_Q], st_t[q, ST_PLASTIC] = ne_par[q, B_K] * z, d1[q] - z
            F[q] = ne_par[q, B_K] * d1[q] - (1.0 - ne_par[q, B_ALPHA]) * ne_par[q, B_K] * (d1[q] - z)
        else:
            F[q] = material_trial(ne_code[q], ne_par, st_c, st_t, q, d1[q], r1[q])[0]
        material_commit(st_c, st_t, q)
        fmax[q] = max(fmax[q], abs(F[q]))
    for r in range(g_t.size):
        g_t[r] = g_1[r]
    if moving:
        _gap_ground_accept(gk)


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
        # the maps are column-major in flat arrays: [u1; v1; a1] is a sum of their columns scaled by x0's
        # entries and the ground's, four columns per pass over the rows (four independent products per
        # row, where a dot product per row was one chain of dependent additions: the product alone 3 times
        # as fast for a building of 11 DOFs, the soil pair's free flight 4-6 % faster), on unsigned
        # subscripts (``_UNSIGNED`` in _linear.py: signed ones made numba's wraparound turn the vectorised
        # loads into gathers)
        n3 = np.uint64(3 * nb)
        unx, unm = np.uint64(nx), np.uint64(nm)
        ox, og = np.uint64(off_x[c]), np.uint64(off_g[c])
        for r in range(n3):
            ys[r] = 0.0
        k = np.uint64(0)
        while k + np.uint64(4) <= unx:
            x0, x1, x2, x3 = xs[k], xs[k + np.uint64(1)], xs[k + np.uint64(2)], xs[k + np.uint64(3)]
            c0 = ox + k * n3
            c1, c2, c3 = c0 + n3, c0 + np.uint64(2) * n3, c0 + np.uint64(3) * n3
            for r in range(n3):
                ys[r] += phi[c0 + r] * x0 + phi[c1 + r] * x1 + phi[c2 + r] * x2 + phi[c3 + r] * x3
            k += np.uint64(4)
        while k < unx:
            xk = xs[k]
            c0 = ox + k * n3
            for r in range(n3):
                ys[r] += phi[c0 + r] * xk
            k += np.uint64(1)
        for m in range(unm):
            g0m, g1m = gs[m], gs[unm + m]
            c0 = og + m * n3
            for r in range(n3):
                ys[r] += G0[c0 + r] * g0m + G1[c0 + r] * g1m
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


@njit(cache=True)
def _hysteretic_flight(ff, elg, mat, x1, gs, gk, h, terms, guess):
    """Iterate the hysteretic storeys' terms over a free-flight step; (converged, input work [J], storeys' work [J]).

    A Bouc-Wen storey's force is k delta - c with c = (1 - alpha) k (delta - z) (``_material``), and so is a
    bilinear storey's with z = q_h / k: the linear part holds k, and c is a load that changes within the
    step.  It is taken as the quadratic through c0 (committed, ``cst``), c0 + dm at the middle and c0 + d1 at
    the end, whose response the maps give (``transition._exact_maps``, columns gq); z follows the end state's
    Hermite cubic of each storey's deformation (``_material.bouc_wen_path``, ``_material.bilinear_path``),
    which gives new dm, d1: a fixed point, swept over the storeys (Gauss-Seidel; the contraction is about
    (1 - alpha) (omega h)^2 / 6 per sweep) from the last step's quadratic extrapolated.  After each sweep
    the change its updates made in every storey's deformation at the middle and the end, times the law's
    slope there, predicts the next sweep's corrections; when none would exceed BW_FLIGHT_TOL (1 - alpha) k dy
    the sweep is not made and z takes that linear correction instead (one path integration per storey and
    sweep saved); a later sweep integrates only the storeys whose own predicted correction exceeds that
    (the others keep the linear correction, accumulated until the step ends).  Not converged, or a
    bilinear storey yielding from inside its elastic range (a kink in c(t) that no quadratic holds): the
    physical path takes the step; so does a peak-oriented or flag storey whose tangent changes inside a
    monotonic piece of its path (``_material.peak_oriented_path``: c = k delta - f, z = delta - c / ((1 - alpha)
    k); ``_material.flag_path``), but not an Iwan storey, whose kinks are one slider's stiffness
    (``_material.iwan_path``).

    elg = (ne_dof, ne_coef, ne_size, ne_code, ne_par): the elements with state; mat = (st_c, cst, st_w), st_w
    the trial state's table, which an Iwan storey's path uses as its scratch row; guess: start from the last
    step's quadratic extrapolated (False: from the rises as they stand, when the step is iterated again); x1 = (u1,
    v1, a1) (in: with c0 held) the step's end with the final terms; gs the ground accelerations at the step's
    start and end (2 nm,); terms = (rise, zs, itr, corr, dr): rise (2 ns + 1) holds dm, d1 and the sweeps
    made; zs (6 ns) per storey z at the end, eps at the end, the deformation at the end and at the middle of
    its last integration, and the law's slopes there; itr (ns,) the storeys whose terms are iterated (the
    others' c stays c0); corr (ns,) each one's predicted next correction; dr (4 ns) per storey its
    deformation and rate at the step's start (set by the caller, fixed over the step) and at the end as the
    last prediction read them.  The storey's work int (k delta - c) d(delta) is exact for the quadratic c and
    cubic delta (3-point Gauss-Legendre; derived here, not read from a source).
    """
    start, st_start, gq = ff[1], ff[11], ff[14]
    rise, itr = terms[0], terms[2]
    o_q = 0
    for c in range(start.size - 1 if guess else 0):  # the first guess: the last step's quadratic, extrapolated
        a = start[c]
        nb = start[c + 1] - a
        for j in range(st_start[c], st_start[c + 1]):
            if not itr[j]:
                continue
            dm, d1 = 2.0 * rise[2 * j + 1] - 3.0 * rise[2 * j], 5.0 * rise[2 * j + 1] - 8.0 * rise[2 * j]
            rise[2 * j], rise[2 * j + 1] = dm, d1
            _add_rise(gq, o_q + (j - st_start[c]) * 6 * nb, nb, a, dm, d1, x1)
        o_q += 6 * nb * (st_start[c + 1] - st_start[c])
    for it in range(BW_FLIGHT_ITER):
        rise[rise.size - 1] = it + 1  # sweeps made (the driver's iteration count)
        if not _hysteretic_sweep(ff, elg, mat, x1, gk, h, terms, it == 0):
            return False, 0.0, 0.0
        if _hysteretic_next(ff, elg, x1, gk, h, terms) <= BW_FLIGHT_TOL:
            de, dwh = _hysteretic_work(ff, elg, mat, gs, h, terms)
            return True, de, dwh
    return False, 0.0, 0.0


@njit(cache=True, inline="always")
def _hysteretic_sweep(ff, elg, mat, x1, gk, h, terms, first):
    """One Gauss-Seidel sweep of ``_hysteretic_flight`` over the iterated storeys (after the ``first``, those
    whose predicted correction exceeds the tolerance): each storey's z along its end state's cubic, its
    rises dm, d1 [N] corrected and added to the end state x1.  False: a bilinear storey yields from inside
    its elastic range within the step."""
    start, st_elem, st_start, gq = ff[1], ff[10], ff[11], ff[14]
    ne_dof, ne_coef, ne_size, ne_code, ne_par = elg[0], elg[1], elg[2], elg[3], elg[4]
    st_c, cst, st_w = mat
    u1, v1 = x1[0], x1[1]
    rise, zs, itr, corr, dr = terms
    o_q = 0
    for c in range(start.size - 1):
        a = start[c]
        nb = start[c + 1] - a
        for j in range(st_start[c], st_start[c + 1]):
            q = st_elem[j]
            if not itr[j] or (not first and corr[j] <= BW_FLIGHT_TOL):
                continue
            ds0, rs0 = dr[4 * j], dr[4 * j + 1]
            ds1, rs1 = _deformation_at(ne_dof, ne_coef, ne_size, q, u1, v1, gk, GU1)
            ca, cb, cc = _cubic(ds0, rs0, ds1, rs1, h)
            if ne_code[q] == BOUC_WEN:
                zm, z1, eps1, pm, p1 = bouc_wen_path(ne_par, q, st_c[q, ST_Z], st_c[q, ST_EPS], ds0, ca, cb, cc)
            elif ne_code[q] == IWAN:
                zm, z1, pm, p1 = iwan_path(ne_par, q, st_c, st_w, ds0, ca, cb, cc)[:4]
                eps1 = 0.0
            elif ne_code[q] == PEAK_ORIENTED or ne_code[q] == FLAG:
                zm, z1, pm, p1, kink = (peak_oriented_path(ne_par, q, st_c, ds0, ca, cb, cc)[:5]
                                        if ne_code[q] == PEAK_ORIENTED else
                                        flag_path(ne_par, q, st_c, ds0, ca, cb, cc)[:5])
                if kink:
                    return False
                eps1 = 0.0
            else:
                zm, z1, pm, p1, onset = bilinear_path(ne_par, q, st_c[q, ST_Q] / ne_par[q, B_K], ds0, ca, cb, cc)
                if onset:
                    return False
                eps1 = 0.0
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
    return True


@njit(cache=True, inline="always")
def _yield_scale(code, par, q):
    """The displacement [m] z is bounded by: a Bouc-Wen or flag storey's dy, a bilinear storey's fy / k."""
    if code == FLAG or code == IWAN:
        return par[q, FL_DY] if code == FLAG else par[q, IW_DY]
    return par[q, BW_DY] if code == BOUC_WEN else bilinear_dy(par, q)


@njit(cache=True, inline="always")
def _hysteretic_next(ff, elg, x1, gk, h, terms):
    """The next sweep's largest correction, predicted from how far the last sweep's updates moved each
    iterated storey's deformation at the step's middle and end times the law's slope there, relative
    to its yield displacement, each storey's kept in corr (``_hysteretic_flight``)."""
    st_elem = ff[10]
    ne_dof, ne_coef, ne_size, ne_code, ne_par = elg[0], elg[1], elg[2], elg[3], elg[4]
    u1, v1 = x1[0], x1[1]
    zs, itr, corr, dr = terms[1], terms[2], terms[3], terms[4]
    pred = 0.0
    for j in range(st_elem.size):
        q = st_elem[j]
        if not itr[j]:
            continue
        ds0, rs0 = dr[4 * j], dr[4 * j + 1]
        ds1, rs1 = _deformation_at(ne_dof, ne_coef, ne_size, q, u1, v1, gk, GU1)
        dr[4 * j + 2], dr[4 * j + 3] = ds1, rs1  # (read by ``_hysteretic_work`` if no sweep follows)
        dm_ = _hermite(0.5, ds0, rs0, ds1, rs1, h)
        step1, stepm = ds1 - zs[6 * j + 2], dm_ - zs[6 * j + 3]
        corr[j] = (abs((1.0 - zs[6 * j + 4]) * stepm) + abs((1.0 - zs[6 * j + 5]) * step1)) / _yield_scale(
            ne_code[q], ne_par, q)
        pred = max(pred, corr[j])
    return pred


@njit(cache=True, inline="always")
def _hysteretic_work(ff, elg, mat, gs, h, terms):
    """The converged step's input work of the rises [J], z's linear correction, and the iterated storeys'
    work along the final path [J] (``_hysteretic_flight``)."""
    start, st_elem, st_start, egq = ff[1], ff[10], ff[11], ff[15]
    ne_code, ne_par = elg[3], elg[4]
    cst = mat[1]
    rise, zs, itr, dr = terms[0], terms[1], terms[2], terms[4]
    nm = gs.size // 2
    de = 0.0
    dwh = 0.0
    o_e = 0
    for c in range(start.size - 1):
        for j in range(st_start[c], st_start[c + 1]):
            q = st_elem[j]
            if not itr[j]:
                continue
            dm, d1 = rise[2 * j], rise[2 * j + 1]
            base = o_e + (j - st_start[c]) * 4 * nm
            for m in range(2 * nm):
                de += gs[m] * (egq[base + m] * dm + egq[base + 2 * nm + m] * d1)
            ds0, rs0, ds1, rs1 = dr[4 * j], dr[4 * j + 1], dr[4 * j + 2], dr[4 * j + 3]  # (``_hysteretic_next``'s)
            step1 = ds1 - zs[6 * j + 2]
            zs[6 * j] += zs[6 * j + 5] * step1
            if ne_code[q] == BOUC_WEN:
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
