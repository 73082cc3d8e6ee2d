"""Elements as coefficient vectors: the linear part and the elements with state of the general driver.

Every element acts through one deformation that is linear in the DOFs,

    delta = sum_k coef[e, k] u[dof[e, k]]     (dof < 0: an unused slot),

so b_e = (coef[e, k] at dof[e, k]) is the element's row of the compatibility
matrix and its force f enters the equations as b_e f (Bathe 1996, Sec. 4.2:
K = sum b_e k_e b_e^T).  A storey spring has b = e_i - e_(i-1); a storey
above a rocking foundation b = e_i - e_(i-1) - (h_i - h_(i-1)) e_theta; a
gap b = e_left - e_right, or against a storey, with the struck side
interpolated between its two floors.  Masses are elements too (m b b^T):
a lumped mass has one entry, a coupled block (a rigid body seen from several
DOFs) more, so the mass matrix may have small coupled blocks.

Slots: 3 for masses and linear elements, 4 for elements with state (a gap
between two interpolated sides).
"""

from __future__ import annotations

import numpy as np
from seispound._jit import njit


@njit(cache=True, inline="always")
def _dot(dof, coef, e, x):
    """b_e . x."""
    s = 0.0
    for k in range(dof.shape[1]):
        if dof[e, k] >= 0:
            s += coef[e, k] * x[dof[e, k]]
    return s


@njit(cache=True, inline="always")
def _scatter(dof, coef, e, f, y):
    """y += b_e f."""
    for k in range(dof.shape[1]):
        if dof[e, k] >= 0:
            y[dof[e, k]] += coef[e, k] * f


@njit(cache=True)
def _add_to_band(dof, coef, e, c, L):
    """Lower band of A += c b_e b_e^T: L[i, i - j] = A(i, j), i >= j."""
    for k1 in range(dof.shape[1]):
        i = dof[e, k1]
        if i < 0:
            continue
        for k2 in range(dof.shape[1]):
            j = dof[e, k2]
            if j < 0 or j > i:
                continue
            L[i, i - j] += c * coef[e, k1] * coef[e, k2]


@njit(cache=True)
def assemble_band(cm, cc, ck, linear, p, L):
    """L (n, p + 2): the lower band of A = cm M + cc C + ck K, with C = sum a0 m b b^T + sum c b b^T.

    linear = (ms_dof, ms_coef, ms_val, ms_a0, le_dof, le_coef, le_k, le_c): the masses and the linear
    elements (``_driver.general_kernel``; more members after these are ignored).  Newmark's K_hat is
    (1/(beta h^2), gamma/(beta h), 1); the mass matrix is (1, 0, 0).
    """
    ms_dof, ms_coef, ms_val, ms_a0, le_dof, le_coef, le_k, le_c = linear[:8]
    for i in range(L.shape[0]):
        for d in range(p + 2):
            L[i, d] = 0.0
    for e in range(ms_val.size):
        _add_to_band(ms_dof, ms_coef, e, ms_val[e] * (cm + cc * ms_a0[e]), L)
    for e in range(le_k.size):
        _add_to_band(le_dof, le_coef, e, ck * le_k[e] + cc * le_c[e], L)


@njit(cache=True)
def linear_bands(linear, p, n):
    """K and C of a row of n DOFs and half bandwidth p for ``linear_forces``: (KC, sp_i, sp_d, sp_kc).

    linear: the masses and linear elements as ``assemble_band`` takes them.

    KC (2, w, n): the lower diagonals d < w of K and of C, each contiguous, KC[0, d, i] = K(i, i - d) for
    i >= d and zero for i < d (``assemble_band``'s entries); w - 1 is the last diagonal with more than
    n / 4 entries.  The entries on diagonals d >= w, few where a foundation numbered last couples its
    rows to every floor (an arrowhead, ``structure.band.profile_order``), are listed apart: row
    sp_i (m,), diagonal sp_d (m,), and sp_kc (2, m) their K and C.
    """
    L = np.empty((n, p + 2))
    KC = np.zeros((2, p + 1, n))
    for m in range(2):
        assemble_band(0.0, float(m), float(1 - m), linear, p, L)
        for i in range(n):
            for d in range(min(p, i) + 1):
                KC[m, d, i] = L[i, d]
    w = 1
    m_sp = 0
    for d in range(1, p + 1):
        nz = 0
        for i in range(d, n):
            nz += 1 if KC[0, d, i] != 0.0 or KC[1, d, i] != 0.0 else 0
        if 4 * nz > n:
            w = d + 1
    for d in range(w, p + 1):
        for i in range(d, n):
            m_sp += 1 if KC[0, d, i] != 0.0 or KC[1, d, i] != 0.0 else 0
    sp_i = np.empty(m_sp, np.int64)
    sp_d = np.empty(m_sp, np.int64)
    sp_kc = np.empty((2, m_sp))
    m_sp = 0
    for d in range(w, p + 1):
        for i in range(d, n):
            if KC[0, d, i] != 0.0 or KC[1, d, i] != 0.0:
                sp_i[m_sp], sp_d[m_sp] = i, d
                sp_kc[0, m_sp], sp_kc[1, m_sp] = KC[0, d, i], KC[1, d, i]
                m_sp += 1
    return np.ascontiguousarray(KC[:, :w]), sp_i, sp_d, sp_kc


@njit(cache=True)
def linear_forces(bands, u, v, f):
    """f = K u + C v [N], shape (n,), from ``linear_bands``: the linear elements' springs and dashpots and
    the mass-proportional damping (cheaper than a loop over the elements).

    The dense diagonals one by one: each sub-diagonal d adds its lower and its upper (mirror) products in
    two loops of unit stride on unsigned subscripts, which vectorise (a row-by-row loop scatters into
    f[i - d]); then the listed entries of the others, each with its mirror."""
    KC, sp_i, sp_d, sp_kc = bands
    n = np.uint64(f.size)
    w = np.uint64(KC.shape[1])
    for i in range(n):
        f[i] = KC[0, 0, i] * u[i] + KC[1, 0, i] * v[i]
    for d in range(np.uint64(1), w):
        for i in range(d, n):  # row i, column i - d
            f[i] += KC[0, d, i] * u[i - d] + KC[1, d, i] * v[i - d]
        for i in range(d, n):  # row i - d, column i: the mirror
            f[i - d] += KC[0, d, i] * u[i] + KC[1, d, i] * v[i]
    for e in range(sp_i.size):
        i = sp_i[e]
        j = i - sp_d[e]
        k, c = sp_kc[0, e], sp_kc[1, e]
        f[i] += k * u[j] + c * v[j]
        f[j] += k * u[i] + c * v[i]


@njit(cache=True)
def lumped_diagonal(ms_dof, ms_coef, ms_val, n):
    """M's diagonal [kg], shape (n,), when every mass element is lumped (one DOF, coefficient 1), so that M
    is diagonal; otherwise an empty array.  ``mass_times`` and ``kinetic_energy`` take it: a loop over
    the diagonal instead of one over the elements' slots."""
    md = np.zeros(n)
    for e in range(ms_val.size):
        used = 0
        for k in range(ms_dof.shape[1]):
            if ms_dof[e, k] >= 0:
                used += 1
                if used > 1 or ms_coef[e, k] != 1.0:
                    return np.zeros(0)
                md[ms_dof[e, k]] += ms_val[e]
    return md


@njit(cache=True)
def mass_times(ms_dof, ms_coef, ms_val, md, x, y):
    """y = M x, shape (n,); md: M's diagonal if M is diagonal, else empty (``lumped_diagonal``)."""
    if md.size:
        for i in range(y.size):
            y[i] = md[i] * x[i]
        return
    for i in range(y.size):
        y[i] = 0.0
    for e in range(ms_val.size):
        _scatter(ms_dof, ms_coef, e, ms_val[e] * _dot(ms_dof, ms_coef, e, x), y)


@njit(cache=True, inline="always")  # inlined: taken three times per step; as a call it cost the general driver 4-10 %
def kinetic_energy(ms_dof, ms_coef, ms_val, md, v):
    """v^T M v / 2 [J]; md: M's diagonal if M is diagonal, else empty (``lumped_diagonal``)."""
    s = 0.0
    if md.size:
        for i in range(v.size):
            s += 0.5 * md[i] * v[i] * v[i]
        return s
    for e in range(ms_val.size):
        w = _dot(ms_dof, ms_coef, e, v)
        s += 0.5 * ms_val[e] * w * w
    return s


@njit(cache=True, inline="always")  # inlined: taken at every output step (``kinetic_energy``)
def strain_energy(le_dof, le_coef, le_k, u):
    """u^T K u / 2 of the linear elements [J]."""
    s = 0.0
    for e in range(le_k.size):
        w = _dot(le_dof, le_coef, e, u)
        s += 0.5 * le_k[e] * w * w
    return s


# -- the two-node gap element of the fast driver (floor i against floor j) --------------------


@njit(cache=True, inline="always")
def _gap_kinematics(xi, dxi, xj, dxj, vi, dvi, vj, dvj, size, gu, gv):
    """Deformation of a gap element: penetration [m] and its rate [m/s], positive on approach.

    delta = (x_i + u_g,i) - (x_j + u_g,j) - size, rate = (v_i + v_g,i) - (v_j + v_g,j):
    x = xi + dxi, v = vi + dvi are the two floors' displacements and velocities
    relative to the ground under each (i the left floor, j the right one; a
    trial step passes its start and increment separately, summed here in one
    fixed order so that every caller gets the same rounding); gu = u_g,i - u_g,j
    and gv = v_g,i - v_g,j the differential ground motion (zero under one
    ground motion), so that the penetration is that of the absolute positions.
    """
    return xi + dxi - xj - dxj - size + gu, vi + dvi - vj - dvj + gv


@njit(cache=True, inline="always")
def _gap_deformation(u, v, i, j, size, gu, gv):
    """:func:`_gap_kinematics` of the gap between DOFs i and j for the state (u, v)."""
    return _gap_kinematics(u[i], 0.0, u[j], 0.0, v[i], 0.0, v[j], 0.0, size, gu, gv)


@njit(cache=True, inline="always")
def _gap_trial(u, Du, Vv, cc, i, j, size, gu, gv):
    """:func:`_gap_kinematics` at the end of a trial step: u + Du, velocity Vv + cc Du (Newmark's)."""
    return _gap_kinematics(u[i], Du[i], u[j], Du[j], Vv[i], cc * Du[i], Vv[j], cc * Du[j], size, gu, gv)


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
