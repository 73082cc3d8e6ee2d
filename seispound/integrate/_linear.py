"""The linear part of the row: its K_hat = K + gamma/(beta h) C + 1/(beta h^2) M, factored and solved.

Masses are lumped, storeys are two-node springs (``el_i``, ``el_j``; -1 = the
ground) with a stiffness ``el_k`` and a stiffness-proportional dashpot
``el_a1 * el_k`` plus the mass-proportional ``dof_a0 * mass``.  Factor/solve
strategies: tridiagonal L D L^T (p = 1, shear buildings) or banded Cholesky
(p > 1), or for the general driver a profile (envelope) Cholesky, restricted
to a range of DOFs when only some buildings step; the
contact gaps enter as a low-rank border through Woodbury columns
K_hat^-1 b_g, or, for a one-off step size with several gaps closed, through
the semiseparable inverse of the tridiagonal K_hat (O(n + m^2)).
"""

from __future__ import annotations

import math

import numpy as np
from seispound._jit import njit

# _UNSIGNED: loops over a DOF range lo..hi-1 run on np.uint64 subscripts.  numba
# wraps negative subscripts around (x[-1] is the last entry), and it cannot drop
# that test for a loop that starts at a runtime lo, only for range(n): with
# signed subscripts the ranged loops ran 2.3x (tridiagonal solve) to 4.6x
# (elementwise, not vectorised) slower than over 0..n-1.  Mixing np.uint64
# and int64 in arithmetic gives float64 in numba, so index arithmetic stays
# in np.uint64 throughout (a float subscript fails to compile).


@njit(cache=True)
def _factor(h, beta, gamma, mass, dof_a0, el_i, el_j, el_k, el_a1, p, L):
    """Factor K_hat(h) of the whole row in place into L, shape (n, p + 2) (``_factor_range``)."""
    return _factor_range(h, (beta, gamma), (mass, dof_a0, el_i, el_j, el_k, el_a1), p, L, (0, mass.size, 0, el_i.size))


@njit(cache=True)
def _factor_range(h, nb, els, p, L, rows):
    """Factor K_hat(h) on DOFs lo..hi-1 in place into L; False if K_hat is not positive definite.

    [lo, hi) is a union of whole blocks (buildings) and elo..ehi-1 their
    elements; rows outside are left as they were.  A block's rows come out the
    same whichever other blocks are factored with it (no element couples them).

    Tridiagonal (p = 1, shear buildings): K_hat = L D L^T with L unit lower
    bidiagonal, stored as L[i, 0] = D_i, L[i, 1] = l_i = L(i, i - 1),
    L[i, 2] = 1 / D_i (no square root, and the recurrences of the factor and
    the solves carry one fused multiply-add per row instead of two operations).
    Otherwise banded Cholesky K_hat = L L^T: L[i, d] = L(i, i - d), d <= p, and
    L[i, p + 1] = 1 / L(i, i).  The stored reciprocals turn the solves'
    divisions into multiplications.  nb = (beta, gamma); els = (mass, dof_a0, el_i, el_j, el_k, el_a1);
    rows = (lo, hi, elo, ehi).
    """
    beta, gamma = nb
    mass, dof_a0, el_i, el_j, el_k, el_a1 = els
    lo, hi, elo, ehi = rows
    cm = 1.0 / (beta * h * h)
    cc = gamma / (beta * h)
    for i in range(np.uint64(lo), np.uint64(hi)):
        for d in range(p + 1):
            L[i, d] = 0.0
        L[i, 0] = mass[i] * (cm + cc * dof_a0[i])
    for e in range(elo, ehi):
        kk = el_k[e] * (1.0 + cc * el_a1[e])
        i = el_i[e]
        j = el_j[e]
        L[i, 0] += kk
        if j >= 0:
            L[j, 0] += kk
            if i > j:
                L[i, i - j] -= kk
            else:
                L[j, j - i] -= kk
    return _factor_band(L, p, lo, hi)


@njit(cache=True, inline="always")
def _factor_band(L, p, lo, hi):
    """Factor in place the K_hat whose lower band L[i, d] = K_hat(i, i - d), d <= p, rows lo..hi-1 hold.

    The storage and the two factorisations of ``_factor_range`` (tridiagonal
    L D L^T for p = 1, banded Cholesky otherwise), which ``_solve_range``
    reads; False if K_hat is not positive definite.  Shared by every driver
    that assembles its own band (``_general.py``).
    """
    if p == 1:  # shear buildings: tridiagonal LDL^T, one straight-line recurrence
        one = np.uint64(1)  # unsigned subscripts (``_UNSIGNED``)
        ulo = np.uint64(lo)
        for j in range(ulo, np.uint64(hi)):
            s = L[j, 0]
            if j > ulo:
                c = L[j, one]  # K_hat(j, j - 1)
                lj = c * L[j - one, 2]
                L[j, one] = lj
                s -= lj * c
            if s <= 0.0:
                return False
            L[j, 0] = s
            L[j, 2] = 1.0 / s
        return True
    # in place: A is read from L's lower band before it is overwritten
    for j in range(lo, hi):
        s = L[j, 0]
        for k in range(max(lo, j - p), j):
            s -= L[j, j - k] * L[j, j - k]
        if s <= 0.0:
            return False
        L[j, 0] = math.sqrt(s)
        L[j, p + 1] = 1.0 / L[j, 0]
        for i in range(j + 1, min(hi, j + p + 1)):
            s = L[i, i - j]
            for k in range(max(lo, i - p), j):
                s -= L[i, i - k] * L[j, j - k]
            L[i, i - j] = s * L[j, p + 1]
    return True


@njit(cache=True, inline="always")
def _solve(L, p, b, x):
    """x = K_hat^-1 b with the banded Cholesky factor L (x may alias nothing)."""
    _solve_range(L, p, b, x, 0, b.size)


@njit(cache=True, inline="always")
def _solve_range(L, p, b, x, lo, hi):
    """x[lo:hi] = K_hat^-1 b on DOFs lo..hi-1, a union of whole uncoupled blocks (buildings).

    K_hat is block diagonal over the buildings, so with b zero outside
    [lo, hi) the solution is zero there too and only these rows take part.
    """
    if hi <= lo:
        return
    if p == 1:  # shear buildings: L D L^T, straight-line recurrences
        # unsigned subscripts (``_UNSIGNED``)
        one = np.uint64(1)
        ulo = np.uint64(lo)
        uhi = np.uint64(hi)
        x[ulo] = b[ulo]
        for i in range(ulo + one, uhi):
            x[i] = b[i] - L[i, one] * x[i - one]
        x[uhi - one] *= L[uhi - one, 2]
        top = uhi - np.uint64(2)
        for k in range(uhi - ulo - one):
            i = top - k
            x[i] = x[i] * L[i, 2] - L[i + one, one] * x[i + one]
        return
    for i in range(lo, hi):
        s = b[i]
        for k in range(max(lo, i - p), i):
            s -= L[i, i - k] * x[k]
        x[i] = s * L[i, p + 1]
    for i in range(hi - 1, lo - 1, -1):
        s = x[i]
        for k in range(i + 1, min(hi, i + p + 1)):
            s -= L[k, k - i] * x[k]
        x[i] = s * L[i, p + 1]


@njit(cache=True)
def _inverse_diagonals(L, p, sig, Sd):
    """Ratios and diagonal of K_hat^-1 from a tridiagonal (p = 1) or diagonal (p = 0) factor L.

    With K_hat = L D L^T, L unit lower bidiagonal (subdiagonal l_i), the
    inverse of a symmetric tridiagonal matrix is semiseparable (Meurant 1992,
    SIAM J. Matrix Anal. Appl. 13(3) 707-728, Sec. 2): for a <= b

        (K_hat^-1)_ab = Sd_b * prod_{k=a+1}^{b} sig_k,   sig_k = -l_k,
        Sd_b = (K_hat^-1)_bb = 1 / D_b + sig_(b+1)^2 Sd_(b+1),

    which follows from (L^-1)_ib = prod_{k=b+1}^{i} (-l_k) and
    K_hat^-1 = L^-T D^-1 L^-1.  Unlike
    the product form u_a v_b it neither overflows nor underflows: every factor
    is a ratio.  sig_k = 0 where no storey couples DOFs k - 1 and k (between
    buildings), so entries across buildings come out exactly zero.
    Shapes: L (n, p + 2); sig, Sd (n,) [sig: -, Sd: m/N].
    """
    _inverse_diagonals_range(L, p, sig, Sd, 0, L.shape[0])


@njit(cache=True)
def _inverse_diagonals_range(L, p, sig, Sd, lo, hi):
    """``_inverse_diagonals`` on DOFs lo..hi-1 only, a union of whole blocks (buildings)."""
    if p == 0:  # diagonal K_hat (single-storey buildings): L[i, 1] = 1 / L(i, i)
        for i in range(lo, hi):
            sig[i] = 0.0
            Sd[i] = L[i, 1] * L[i, 1]
        return
    sig[lo] = 0.0
    for i in range(lo + 1, hi):
        sig[i] = -L[i, 1]
    Sd[hi - 1] = L[hi - 1, 2]
    for i in range(hi - 2, lo - 1, -1):
        Sd[i] = L[i, 2] + sig[i + 1] * sig[i + 1] * Sd[i + 1]


# entries of K_hat^-1 below this fraction of the diagonal are set to zero
# (they underflow anyway, and subnormal products are slow)
INVERSE_FLOOR = 1e-200


@njit(cache=True)
def _compliance_tridiagonal(grp, gap_i, gap_j, inv, Gm, work):
    """Gm[lo:hi, lo:hi] = B^T K_hat^-1 B for the gaps act_list[lo:hi] in contact, from the semiseparable inverse.

    The 2m gap DOFs are sorted; the product of sig between each sorted pair of
    neighbours costs one pass over the floors they span, and every entry of
    K_hat^-1 among them follows as a running product: O(n + m^2) per call,
    independent of how many gaps are closed (columns K_hat^-1 b_g would cost
    O(n m)).  grp = (lo, hi, act_list); inv = (sig, Sd) from ``_inverse_diagonals``; with m = hi - lo,
    work = (dofs, order, pos, span) (>= 2m,) and Kd (>= 2m, >= 2m): scratch.
    """
    lo, hi, act_list = grp
    sig, Sd = inv
    dofs, order, pos, span, Kd = work
    m = hi - lo
    k = 2 * m
    for q in range(m):
        g = act_list[lo + q]
        dofs[2 * q] = gap_i[g]
        dofs[2 * q + 1] = gap_j[g]
    for s in range(k):  # insertion sort: k is small
        order[s] = s
    for s in range(1, k):
        o = order[s]
        x = dofs[o]
        t = s - 1
        while t >= 0 and dofs[order[t]] > x:
            order[t + 1] = order[t]
            t -= 1
        order[t + 1] = o
    for s in range(k):
        pos[order[s]] = s
    for s in range(k - 1):
        prod = 1.0
        for c in range(dofs[order[s]] + 1, dofs[order[s + 1]] + 1):
            prod *= sig[c]
            if abs(prod) < INVERSE_FLOOR:
                prod = 0.0
                break
        span[s] = prod
    for s in range(k):
        Kd[s, s] = Sd[dofs[order[s]]]
        prod = 1.0
        for t in range(s + 1, k):
            if prod != 0.0:
                prod *= span[t - 1]
                if abs(prod) < INVERSE_FLOOR:
                    prod = 0.0
            Kd[s, t] = Sd[dofs[order[t]]] * prod
            Kd[t, s] = Kd[s, t]
    for q in range(m):
        a = pos[2 * q]
        b = pos[2 * q + 1]
        for r in range(q, m):
            c = pos[2 * r]
            d = pos[2 * r + 1]
            Gm[lo + q, lo + r] = Kd[a, c] - Kd[a, d] - Kd[b, c] + Kd[b, d]
            Gm[lo + r, lo + q] = Gm[lo + q, lo + r]


@njit(cache=True)
def _woodbury_columns(L, p, W, rows, nr, lo, hi, gap_i, gap_j):
    """W[g, lo:hi] = K_hat^-1 b_g for the nr gaps g = rows[:nr], which all link the same blocks lo..hi-1.

    Solved together: in the tridiagonal sweeps the nr right-hand sides are
    independent recurrences, interleaved so that they overlap in the pipeline
    (a single sweep is latency bound).
    """
    for r in range(nr):
        g = rows[r]
        for i in range(np.uint64(lo), np.uint64(hi)):
            W[g, i] = 0.0
        W[g, gap_i[g]] = 1.0
        W[g, gap_j[g]] = -1.0
    if p != 1:
        for r in range(nr):
            _solve_range(L, p, W[rows[r]], W[rows[r]], lo, hi)  # in place: b[i] is read before x[i] is written
        return
    one = np.uint64(1)  # unsigned subscripts (``_UNSIGNED``)
    ulo = np.uint64(lo)
    uhi = np.uint64(hi)
    for i in range(ulo + one, uhi):  # L D L^T (``_factor``)
        l1 = L[i, one]
        for r in range(nr):
            g = rows[r]
            W[g, i] -= l1 * W[g, i - one]
    d = L[uhi - one, 2]
    for r in range(nr):
        W[rows[r], uhi - one] *= d
    top = uhi - np.uint64(2)
    for k in range(uhi - ulo - one):
        i = top - k
        l1 = L[i + one, one]
        d = L[i, 2]
        for r in range(nr):
            g = rows[r]
            W[g, i] = W[g, i] * d - l1 * W[g, i + one]


# A located step's one-off factor takes the semiseparable shortcut when at
# least this many gaps are closed; with fewer, m Woodbury columns cost less.
SEMISEPARABLE_GAPS = 3


@njit(cache=True)
def _subtract_contact(L, p, m, act_list, gap_i, gap_j, gap_lo, gap_hi, Fm, xs, Du):
    """Du -= K_hat^-1 B F: the contact forces' share of the step, one solve.

    The right-hand side is nonzero at the 2m gap DOFs only, so the solve runs
    on the blocks the closed gaps link (``_solve_range``).  xs (n,) scratch.
    """
    lo = L.shape[0]
    hi = 0
    nonzero = False
    for q in range(m):
        g = act_list[q]
        lo = min(lo, gap_lo[g])
        hi = max(hi, gap_hi[g])
        nonzero = nonzero or Fm[q] != 0.0
    if not nonzero:
        return
    for i in range(np.uint64(lo), np.uint64(hi)):
        xs[i] = 0.0
    for q in range(m):
        g = act_list[q]
        xs[gap_i[g]] += Fm[q]
        xs[gap_j[g]] -= Fm[q]
    _solve_range(L, p, xs, xs, lo, hi)  # in place: b[i] is read before x[i] is written
    for i in range(np.uint64(lo), np.uint64(hi)):
        Du[i] -= xs[i]


@njit(cache=True)
def _dense_solve(m, A, b):
    """Solve the small m x m system A y = b in place (partial pivoting); b becomes y.

    One and two unknowns (most Newton iterations: one or two floors in
    contact) are solved in closed form.
    """
    if m == 1:
        b[0] /= A[0, 0]
        return
    if m == 2:
        det = A[0, 0] * A[1, 1] - A[0, 1] * A[1, 0]
        if abs(det) > 1e-12 * (abs(A[0, 0] * A[1, 1]) + abs(A[0, 1] * A[1, 0])):
            y0 = (b[0] * A[1, 1] - A[0, 1] * b[1]) / det
            b[1] = (A[0, 0] * b[1] - A[1, 0] * b[0]) / det
            b[0] = y0
            return
    for c in range(m):
        piv = c
        for r in range(c + 1, m):
            if abs(A[r, c]) > abs(A[piv, c]):
                piv = r
        if piv != c:
            for k in range(m):
                tmp = A[c, k]
                A[c, k] = A[piv, k]
                A[piv, k] = tmp
            tmp = b[c]
            b[c] = b[piv]
            b[piv] = tmp
        for r in range(c + 1, m):
            f = A[r, c] / A[c, c]
            for k in range(c, m):
                A[r, k] -= f * A[c, k]
            b[r] -= f * b[c]
    for c in range(m - 1, -1, -1):
        s = b[c]
        for k in range(c + 1, m):
            s -= A[c, k] * b[k]
        b[c] = s / A[c, c]


@njit(cache=True)
def _internal(mass, dof_a0, el_i, el_j, el_k, el_a1, u, v, fs, fd):
    """Storey-spring forces fs = K u [N] and Rayleigh damping forces fd = C v [N]."""
    _internal_range((mass, dof_a0, el_i, el_j, el_k, el_a1), u, v, fs, fd, (0, mass.size, 0, el_i.size))


@njit(cache=True, inline="always")
def _internal_range(els, u, v, fs, fd, rows):
    """fs = K u and fd = C v on DOFs lo..hi-1 (whole blocks), whose elements are elo..ehi-1.

    els = (mass, dof_a0, el_i, el_j, el_k, el_a1); rows = (lo, hi, elo, ehi)."""
    mass, dof_a0, el_i, el_j, el_k, el_a1 = els
    lo, hi, elo, ehi = rows
    # unsigned subscripts (``_UNSIGNED``); el_j < 0 is the ground
    for i in range(np.uint64(lo), np.uint64(hi)):
        fs[i] = 0.0
        fd[i] = dof_a0[i] * mass[i] * v[i]
    for e in range(np.uint64(elo), np.uint64(ehi)):
        i = np.uint64(el_i[e])
        jj = el_j[e]
        du = u[i]
        dv = v[i]
        if jj >= 0:
            j = np.uint64(jj)
            du -= u[j]
            dv -= v[j]
        f = el_k[e] * du
        c = el_a1[e] * el_k[e] * dv
        fs[i] += f
        fd[i] += c
        if jj >= 0:
            j = np.uint64(jj)
            fs[j] -= f
            fd[j] -= c


@njit(cache=True)
def _strain_energy(el_i, el_j, el_k, u):
    """Strain energy 0.5 u^T K u of the storey springs [J], element by element."""
    es = 0.0
    for e in range(el_i.size):
        du = u[el_i[e]]
        if el_j[e] >= 0:
            du -= u[el_j[e]]
        es += 0.5 * el_k[e] * du * du
    return es


# -- profile (envelope) storage: the general driver's A, M and banded tangent -----------------
# Row i of a profile matrix holds its entries from column first[i] to i in the band storage
# L[i, i - j] (j >= first[i] >= i - p); outside that envelope the entries are zero and stay zero
# through the factorisation (George & Liu 1981, Computer Solution of Large Sparse Positive Definite
# Systems, Sec. 4.2: fill is confined to the envelope).  A building on a foundation couples every
# floor to its sway and rocking DOFs; numbered last (``structure.band.profile_order``), they make
# an arrowhead whose envelope is the tridiagonal plus two full rows, where the band is full.


@njit(cache=True, inline="always")
def _factor_profile(L, p, first, lo, hi):
    """Factor in place, rows lo..hi-1, the matrix whose lower envelope L[i, i - j], first[i] <= j <= i,
    holds (``_factor_band``'s storage: the inverse diagonal in column p + 1, or 2 for p = 1).

    Row-oriented (skyline) Cholesky (Bathe 1996, Finite Element Procedures, Sec. 8.2.3, in its
    L L^T form): L[i, j] = (A[i, j] - sum_k L[i, k] L[j, k]) / L[j, j] over k from max(first[i],
    first[j]) to j - 1.  The envelope is taken within the band, first[i] >= i - p, so that one
    envelope (of the union of the matrices) serves factors of different half bandwidths p; with
    first[i] <= i - p it is the banded Cholesky in another order; p = 1 takes the tridiagonal
    L D L^T of ``_factor_band``.  False if not positive definite.
    """
    if p == 1:
        return _factor_band(L, p, lo, hi)
    for i in range(lo, hi):
        fi = max(lo, first[i], i - p)  # (an envelope wider than this band is clipped to it)
        for j in range(fi, i):
            s = L[i, i - j]
            for k in range(max(fi, first[j]), j):  # (fi > j - p)
                s -= L[i, i - k] * L[j, j - k]
            L[i, i - j] = s * L[j, p + 1]
        s = L[i, 0]
        for k in range(fi, i):
            s -= L[i, i - k] * L[i, i - k]
        if s <= 0.0:
            return False
        L[i, 0] = math.sqrt(s)
        L[i, p + 1] = 1.0 / L[i, 0]
    return True


@njit(cache=True, inline="always")
def _solve_profile(L, p, first, b, x, lo, hi):
    """x[lo:hi] = A^-1 b on DOFs lo..hi-1 (whole buildings) with the factor of ``_factor_profile``.

    Forward by rows, backward by columns of L (each row of L^T's transpose at once), so that both
    sweeps touch only the envelope; x may alias b.
    """
    if hi <= lo:
        return
    if p == 1:
        _solve_range(L, p, b, x, lo, hi)
        return
    for i in range(lo, hi):
        s = b[i]
        for k in range(max(lo, first[i], i - p), i):
            s -= L[i, i - k] * x[k]
        x[i] = s * L[i, p + 1]
    for i in range(hi - 1, lo - 1, -1):
        xi = x[i] * L[i, p + 1]
        x[i] = xi
        for k in range(max(lo, first[i], i - p), i):
            x[k] -= L[i, i - k] * xi
