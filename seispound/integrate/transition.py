"""State transition of a linear row over one analysis step, for the general driver's free flight.

While every gap is open and no element has state, a row on the general driver
(foundations, soil cones, coupled masses, floor-to-storey gaps) is linear:

    M u'' + C u' + K u = -L g(t),        x = [u; u'],   x' = A x + B g(t),

with A = [[0, I], [-M^-1 K, -M^-1 C]], B = [[0], [-M^-1 L]] and L (n, nm) the load
of each ground-motion row (M iota).  Its damping need not be classical (a
dashpot under a foundation, the soil cone's), so modes do not decouple it; but
its buildings do not touch, and over one analysis step with the ground
acceleration linear between samples each building's state maps linearly,

    x1 = Phi x0 + G0 g0 + G1 g1,   a1 = -M^-1 (K u1 + C v1 + L g1),

and the input energy of the step is a quadratic form in (x0, g0, g1):

    E_in,1 - E_in,0 = g^T Egx x0 + g^T Egg g,    g = [g0; g1].

Two schemes give these maps:

* ``exact``: the exact solution for the piecewise-linear ground acceleration.
  Phi and the G from one matrix exponential of the system augmented by the
  ground acceleration and its slope (Van Loan 1978, Sec. 1; Moler & Van Loan
  2003, method 19 for the exponential), and the input work
  -int g^T L^T u' dt over the step from the integrals int e^(F s) ds and
  int s e^(F s) ds, whose rows that meet the ground's load one exponential of
  F^T bordered by that load and an identity gives (Van Loan 1978, Thm. 1;
  ``_exact_maps``).
* ``newmark``: ``substeps`` Newmark-beta steps (Chopra, Dynamics of Structures,
  Table 5.7.2), each with the ground acceleration interpolated linearly
  within the analysis step, composed into one map; the input work is the
  physical path's trapezoidal sum, composed the same way.  The general
  driver's physical path takes exactly these steps, so the two agree to
  round-off: the off switch compares them.

Bilinear storeys (kinematic hardening) inside their elastic range are linear too:
F = k delta - (1 - alpha) k delta_p, the plastic deformation delta_p fixed while the
storey stays elastic (``_material.material_trial``).  Their stiffness k is in K
(``SystemArrays.matrices``: storeys at their initial stiffness) and
each storey's constant term is one more input, a load b_q c_q held over the step,
with its own columns Gc (and Egc in the input work); the driver screens each
storey's deformation against its elastic range as it screens the gaps.  A Bouc-Wen
storey's force is k delta - c with the offset c = (1 - alpha) k (delta - z), which
changes within the step: with ``quadratic`` the load is the quadratic through c at the
step's start, middle and end, two more columns per storey (Gq, Egq), and the driver
iterates the offsets (``_general_flight._hysteretic_flight``).

Either way the damping work of a step follows from the balance, input =
kinetic + linear strain + damping (nothing else acts in free flight): exact
for the exact scheme, and equal to the trapezoidal sums for average
acceleration (beta = 1/4, gamma = 1/2: the inertia's trapezoidal work is the
kinetic energy's change exactly).  Derived here; not read from a source.

The exact maps come from exponentials of the building's state matrix (and its
transpose, bordered: ``_exact_maps``) in which only decaying exponentials appear: a
soil cone's dashpot that damps a mode by e^-100 per step is as well conditioned as
an undamped mode.  Cost per analysis step: 6 n_b^2 multiply-adds per
building b (its displacements, velocities and accelerations from x0), against a
banded factor solve per Newmark substep on the physical path.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import expm

from .._blas import one_thread

__all__ = ["Transition", "transition", "blocks_of", "MAX_BLOCK_DOFS"]

# Largest building (DOFs) that takes free flight: the dense transition costs (2 n_b)^2 per
# step, a Newmark substep on the band about 30 n_b flops, so beyond ~100 DOFs the
# physical path is the cheaper.
MAX_BLOCK_DOFS = 96


@dataclass(frozen=True)
class Transition:
    """One analysis step of each building's linear part, packed for the kernel.

    Building c spans DOFs ``start[c]:start[c+1]`` (n_c DOFs, state 2 n_c = [u; v]).
    Its maps give the end-of-step displacements, velocities and relative accelerations
    [u1; v1; a1] (3 n_c rows) from x0 = [u0; v0] and the ground accelerations; they lie one
    after the other at ``off_x[c]`` (Phi, (3 n_c, 2 n_c), column-major), ``off_g[c]`` (G0, G1:
    (3 n_c, nm), column-major) and ``off_e[c]`` (Egx: (2 nm, 2 n_c), row-major).

    Attributes
    ----------
    start : (nc + 1,) int64
    off_x, off_g, off_e : (nc + 1,) int64
    phi : (sum 6 n_c^2,) float  [-, s, 1/s, 1/s^2]  [u1; v1; a1] = Phi x0 ...
    g0, g1 : (sum 3 n_c nm,) float  [s^2, s, -]  ... + G0 g0 + G1 g1 (g in m/s^2)
    egx : (sum 4 n_c nm,) float  [kg m/s, kg]  input work's bilinear part
    egg : (2 nm, 2 nm) float [kg s^2]  its part quadratic in the ground accelerations (all buildings)
    st_elem : (ns,) int64  the element (row of the element tables) of each bilinear storey, by building
    st_start : (nc + 1,) int64  building c's storeys are st_elem[st_start[c]:st_start[c+1]]
    gc : (sum 3 n_c ns_c,) float [m/N, m/(N s), m/(N s^2)]  per storey (rows) its column of the end
        state for a unit constant term c_q [N] (storey-major: one contiguous row per storey)
    egc : (sum 2 nm ns_c,) float [s]  per storey its input work per unit c_q and ground acceleration
    gq : (sum 6 n_c ns_c,) float  per storey two such columns, for its term's rise dm [N] to the step's middle
        and d1 [N] to its end (a quadratic in time, ``_exact_maps``); zeros unless ``quadratic``
    egq : (sum 4 nm ns_c,) float [s]  per storey the input work of dm and d1, as egc
    """

    start: np.ndarray
    off_x: np.ndarray
    off_g: np.ndarray
    off_e: np.ndarray
    phi: np.ndarray
    g0: np.ndarray
    g1: np.ndarray
    egx: np.ndarray
    egg: np.ndarray
    st_elem: np.ndarray
    st_start: np.ndarray
    gc: np.ndarray
    egc: np.ndarray
    gq: np.ndarray
    egq: np.ndarray


def components(tab: dict, n: int) -> np.ndarray:
    """The building of each DOF: a root DOF per connected component under the masses, the linear
    elements and the storeys with state (gaps link nothing), (n,) int64."""
    parent = np.arange(n)

    def find(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for dof in (tab["ms_dof"], tab["le_dof"], tab["ne_dof"][~tab["ne_gap"]]):
        for row in dof:
            used = [int(d) for d in row if d >= 0]
            for d in used[1:]:
                parent[find(d)] = find(used[0])
    return np.array([find(i) for i in range(n)], np.int64)


def blocks_of(tab: dict, n: int) -> np.ndarray | None:
    """First DOF of each building (:func:`components`), (nc + 1,) int64.

    None if a building is not a contiguous run of DOFs or holds more than MAX_BLOCK_DOFS.
    """
    root = components(tab, n)
    start = [0] + [i for i in range(1, n) if root[i] != root[i - 1]] + [n]
    seen = set()
    for a, b in zip(start[:-1], start[1:]):
        if root[a] in seen or b - a > MAX_BLOCK_DOFS:
            return None  # a building in two runs, or too large
        seen.add(root[a])
    return np.asarray(start, np.int64)


def transition(tab: dict, matrices: tuple, dof_motion: np.ndarray, nm: int, dt: float, scheme: str,
               beta: float = 0.25, gamma: float = 0.5, substeps: int = 1,
               quadratic: bool = False) -> Transition | None:
    """The per-building maps of one analysis step ``dt`` [s] (module docstring), or None where not valid.

    ``tab``: ``SystemArrays.element_tables()`` of a row whose elements with state are gaps and
    bilinear storeys (the caller checks); ``matrices``: its dense (M, C, K), storeys at their
    initial (elastic) stiffness (``SystemArrays.matrices``); ``dof_motion`` (n,) the motion row of
    each DOF;
    ``scheme`` "exact" or "newmark" (``beta``, ``gamma``, ``substeps`` Newmark steps per analysis
    step); ``quadratic``: the storeys' terms may vary quadratically within the step (``gq``, ``egq``;
    Bouc-Wen storeys, exact scheme).
    """
    n = matrices[0].shape[0]
    start = blocks_of(tab, n)
    if start is None:
        return None
    # one BLAS thread: these matrices are small, and a second thread that spins beside the driver (or
    # competes with other work on a busy machine) cost up to 100 times the computation (seispound/_blas.py)
    with one_thread():
        return _transition(tab, matrices, start, dof_motion, nm, dt, scheme, beta, gamma, substeps, quadratic)


def _transition(tab, matrices, start, dof_motion, nm, dt, scheme, beta, gamma, substeps, quadratic):
    M, C, K = (np.array(x, float) for x in matrices)
    n = M.shape[0]
    L = np.zeros((n, nm))
    L[np.arange(n), dof_motion] = tab["dof_load"]
    storeys = np.flatnonzero(~tab["ne_gap"])
    R = np.zeros((n, storeys.size))  # each storey's b_q: its constant term's load direction
    for j, q in enumerate(storeys):
        used = tab["ne_dof"][q] >= 0
        R[tab["ne_dof"][q][used], j] = tab["ne_coef"][q][used]
    phi, g0, g1, egx, gc, egc, gq, egq, st_elem, st_start = [], [], [], [], [], [], [], [], [], [0]
    egg = np.zeros((2 * nm, 2 * nm))
    for a, b in zip(start[:-1], start[1:]):
        s = slice(a, b)
        mine = np.flatnonzero(np.any(R[s] != 0.0, axis=0))
        Mb, Cb, Kb, Lb, Rb = M[s, s], C[s, s], K[s, s], L[s], R[s][:, mine]
        P, G0, G1, Gc, Gq, Egx, Egg, Egc, Egq = (_exact_maps if scheme == "exact" else _newmark_maps)(
            Mb, Cb, Kb, Lb, Rb, dt, beta, gamma, substeps, quadratic)
        if not all(np.all(np.isfinite(x)) for x in (P, G0, G1, Gc, Gq, Egx, Egg, Egc, Egq)):
            return None
        # the accelerations from equilibrium at the step's end: a1 = M^-1 (-[K C] x1 - L g1 + R c)
        KC = np.linalg.solve(Mb, np.hstack([Kb, Cb]))
        P, G0 = np.vstack([P, -KC @ P]), np.vstack([G0, -KC @ G0])
        G1 = np.vstack([G1, -KC @ G1 - np.linalg.solve(Mb, Lb)])
        Gc = np.vstack([Gc, -KC @ Gc + np.linalg.solve(Mb, Rb)])
        # the load at the step's end is R (c0 + d1): the d1 columns carry R too, the dm columns none
        Gq = np.vstack([Gq, -KC @ Gq + np.hstack([np.zeros_like(Rb), np.linalg.solve(Mb, Rb)])])
        ns = Rb.shape[1]  # per storey: its dm column then its d1 column (storey-major)
        Gq_t = np.stack([Gq[:, :ns].T, Gq[:, ns:].T], axis=1)  # (ns, 2, 3 nb)
        Egq_t = np.stack([Egq[:, :ns].T, Egq[:, ns:].T], axis=1)  # (ns, 2, 2 nm)
        # (the maps column-major: the kernel sums their columns, ``_general_flight._free_flight_trial``)
        for lst, x in zip((phi, g0, g1, egx, gc, egc, gq, egq), (P.T, G0.T, G1.T, Egx, Gc.T, Egc.T, Gq_t, Egq_t)):
            lst.append(np.ascontiguousarray(x).ravel())
        egg += Egg
        st_elem.extend(storeys[mine])
        st_start.append(len(st_elem))
    sizes = np.diff(start)

    def offsets(size):
        return np.concatenate([[0], np.cumsum(size)]).astype(np.int64)

    return Transition(start=start, off_x=offsets(6 * sizes * sizes), off_g=offsets(3 * sizes * nm),
                      off_e=offsets(4 * sizes * nm), phi=np.concatenate(phi), g0=np.concatenate(g0),
                      g1=np.concatenate(g1), egx=np.concatenate(egx), egg=egg,
                      st_elem=np.asarray(st_elem, np.int64), st_start=np.asarray(st_start, np.int64),
                      gc=np.concatenate(gc), egc=np.concatenate(egc), gq=np.concatenate(gq),
                      egq=np.concatenate(egq))


def _split(Q, nx, nm):
    """(Egx, Egg, Egc) of a quadratic form z^T Q z in z = [x (nx); g0 (nm); g1 (nm); c] whose only
    terms are g's with x, with g and with c (the input work: the ground's power)."""
    Qs = 0.5 * (Q + Q.T)
    g = slice(nx, nx + 2 * nm)
    return 2.0 * Qs[g, :nx], Qs[g, g], 2.0 * Qs[g, nx + 2 * nm:]


def _exact_maps(M, C, K, L, R, h, beta, gamma, substeps, quadratic=False):
    """Phi, G0, G1, Gc, Gq, Egx, Egg, Egc, Egq of the exact step.

    R (nb, ns): loads R c(s) on the building, c held constant over the step (bilinear storeys'
    constant terms), or with ``quadratic`` the quadratic through c0, c0 + dm and c0 + d1 at the
    step's start, middle and end (a Bouc-Wen storey's offset force, ``_general_flight._free_flight``):
    c(s) = c0 + (4 dm - d1) s / h + (2 d1 - 4 dm) s^2 / h^2.  Gc, Egc: the columns of c0; Gq
    (nx, 2 ns), Egq (2 nm, 2 ns): those of [dm; d1] (zeros without ``quadratic``).

    The state w = [x; g; g'; l; l'; l''/2] (the ground acceleration, its slope, and the load's
    value, slope and half curvature augmented) obeys w' = F w, so w(s) = e^(F s) w0 (Van Loan
    1978, Sec. 1).  The input work -int_0^h g(s)^T L^T v(s) ds has g(s) = g0 + s g' exactly, so
    it is bilinear in w0:

        W = w0^T [S_g^T (-L^T) S_v J0 + S_s^T (-L^T) S_v J1] w0,
        J0 = int_0^h e^(F s) ds,   J1 = int_0^h s e^(F s) ds,

    (S_g, S_s, S_v pick g, g', v out of w).  Only the nm rows (-L^T S_v) J0 and (-L^T S_v) J1 are
    needed, and one exponential of B = [[F^T, -S_v^T L, 0], [0, 0, I], [0, 0, 0]] gives them with
    e^(F h): its blocks (1, 2) and (1, 3) are J0^T (-S_v^T L) and (h J0 - J1)^T (-S_v^T L), since
    the (1, 3) block is int_0^h e^(F^T (h - s)) s ds times the border (Van Loan 1978, Thm. 1; the
    reduction to J0, J1 and the load's augmentation derived here).  Only decaying exponentials
    appear (F^T has F's eigenvalues and the augmented blocks' zeros), never e^(-F^T s): a mode
    damped by e^-100 per step is as well conditioned as an undamped one (soil cones' dashpots).
    """
    nb, nm = L.shape
    ns = R.shape[1]
    nl = 3 * ns if quadratic else ns
    nx = 2 * nb
    Minv = np.linalg.inv(M)
    # w = [x; g; g'; l (; l'; l''/2)]
    ig, islope, ic = nx, nx + nm, nx + 2 * nm
    nw = ic + nl
    F = np.zeros((nw, nw))
    F[:nb, nb:nx] = np.eye(nb)
    F[nb:nx, :nb] = -Minv @ K
    F[nb:nx, nb:nx] = -Minv @ C
    F[nb:nx, ig:islope] = -Minv @ L
    F[nb:nx, ic:ic + ns] = Minv @ R
    F[ig:islope, islope:ic] = np.eye(nm)
    if quadratic:  # l' = l', (l')' = 2 (l''/2)
        F[ic:ic + ns, ic + ns:ic + 2 * ns] = np.eye(ns)
        F[ic + ns:ic + 2 * ns, ic + 2 * ns:] = 2.0 * np.eye(ns)
    # the rows (-L^T S_v) J0 and (-L^T S_v) J1, transposed: blocks of the exponential of F^T bordered by
    # -S_v^T L and an identity (nw + 2 nm square: about the cost of e^(F h) alone)
    LSv = np.zeros((nm, nw))
    LSv[:, nb:nx] = -L.T
    B = np.zeros((nw + 2 * nm, nw + 2 * nm))
    B[:nw, :nw] = F.T
    B[:nw, nw:nw + nm] = LSv.T
    B[nw:nw + nm, nw + nm:] = np.eye(nm)
    E = expm(B * h)
    E22 = E[:nw, :nw].T  # e^(F h)
    A0 = E[:nw, nw:nw + nm].T  # (-L^T S_v) J0
    Qw = np.zeros((nw, nw))
    Qw[ig:islope] = A0
    Qw[islope:ic] = h * A0 - E[:nw, nw + nm:].T  # (-L^T S_v) J1 = h (...) J0 - (...) int e^(F (h - s)) s ds
    # w0 = T z, z = [x0; g0; g1; c0 (; dm; d1)]: the slope is (g1 - g0) / h, the load's terms as above
    T = np.eye(nw)
    T[islope:ic, ig:islope] = -np.eye(nm) / h
    T[islope:ic, islope:ic] = np.eye(nm) / h
    if quadratic:
        dm, d1 = slice(ic + ns, ic + 2 * ns), slice(ic + 2 * ns, nw)
        T[dm, dm], T[dm, d1] = 4.0 * np.eye(ns) / h, -np.eye(ns) / h
        T[d1, dm], T[d1, d1] = -4.0 * np.eye(ns) / h**2, 2.0 * np.eye(ns) / h**2
    X = E22[:nx] @ T
    egx, egg, egl = _split(T.T @ Qw @ T, nx, nm)
    Gq = X[:, ic + ns:] if quadratic else np.zeros((nx, 2 * ns))
    Egq = egl[:, ns:] if quadratic else np.zeros((2 * nm, 2 * ns))
    return X[:, :nx], X[:, ig:islope], X[:, islope:ic], X[:, ic:ic + ns], Gq, egx, egg, egl[:, :ns], Egq


def _newmark_maps(M, C, K, L, R, h_dt, beta, gamma, substeps, quadratic=False):
    """Phi, G0, G1, Gc, Gq, Egx, Egg, Egc, Egq of ``substeps`` Newmark steps (the general driver's
    ``_predictor``).  Gq and Egq are zeros: the Newmark scheme's free flight holds the constant terms
    only (a Bouc-Wen row takes its physical path there, so that the off switch compares to round-off)."""
    nb, nm = L.shape
    ns = R.shape[1]
    nx = 2 * nb
    nz = nx + 2 * nm + ns
    h = h_dt / substeps
    Minv = np.linalg.inv(M)
    Khat_inv = np.linalg.inv(K + gamma / (beta * h) * C + M / (beta * h * h))
    # every quantity as a linear map of z = [u0; v0; g0; g1; c]
    U = np.zeros((nb, nz))
    V = np.zeros((nb, nz))
    U[:, :nb] = np.eye(nb)
    V[:, nb:nx] = np.eye(nb)
    Rc = np.zeros((nb, nz))
    Rc[:, nx + 2 * nm:] = R

    def ground(j):  # the ground accelerations at substep j, interpolated within the analysis step
        G = np.zeros((nm, nz))
        G[:, nx:nx + nm] = (1.0 - j / substeps) * np.eye(nm)
        G[:, nx + nm:nx + 2 * nm] = (j / substeps) * np.eye(nm)
        return G

    Q = np.zeros((nz, nz))
    for j in range(substeps):
        Gj, Gj1 = ground(j), ground(j + 1)
        A = Minv @ (-L @ Gj + Rc - K @ U - C @ V)  # equilibrium at the substep's start
        Vv = (1.0 - gamma / beta) * V + (1.0 - 0.5 * gamma / beta) * h * A
        Av = -V / (beta * h) - (0.5 / beta - 1.0) * A
        Du = Khat_inv @ (-L @ Gj1 + Rc - M @ Av - C @ Vv - K @ U)
        Q += -0.5 * (Gj + Gj1).T @ L.T @ Du  # the trapezoidal input work
        U = U + Du
        V = Vv + gamma / (beta * h) * Du
    X = np.vstack([U, V])
    egx, egg, egc = _split(Q, nx, nm)
    return (X[:, :nx], X[:, nx:nx + nm], X[:, nx + nm:nx + 2 * nm], X[:, nx + 2 * nm:], np.zeros((nx, 2 * ns)),
            egx, egg, egc, np.zeros((2 * nm, 2 * ns)))
