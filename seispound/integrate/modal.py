"""Modal basis of the linear part of a row, for the kernel's free-flight blocks.

While every gap is open, the buildings are linear, uncoupled and (with Rayleigh
damping) classically damped.  The undamped modes Phi of each building
(Phi^T M Phi = I, Phi^T K Phi = diag(omega^2)) then also diagonalise C, and
Newmark-beta applied to M u'' + C u' + K u = -M iota a_g is, term for term,
Newmark-beta with the same beta, gamma and step applied to every modal equation

    q_j'' + c_j q_j' + omega_j^2 q_j = -Gamma_j a_g,    u = Phi q,

because the Newmark update is linear and its coefficients are the same scalars
for every coordinate (Bathe, Finite Element Procedures, 1996, Sec. 9.3.1-9.4.1:
direct integration of the coupled equations equals the integration of all mode
equations with the same operator and step; Chopra, Dynamics of Structures,
4th ed., 2012, Sec. 10.4-10.5, 11.4 and 13.1 for the decomposition, classical
damping and Gamma_j = phi_j^T M iota).  The kernel uses this to march many
steps at once without a single solve, and returns to the physical coordinates
for every step in which a gap is, or may become, closed.

A system qualifies only if each connected group of DOFs (a building) is a
contiguous block and Phi^T C Phi is diagonal to round-off; otherwise
:func:`modal_basis` returns None and the kernel steps physically throughout
(non-classical damping, future yielding storeys).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import eigh

__all__ = ["ModalBasis", "modal_basis", "dof_blocks"]

# Phi^T C Phi counts as diagonal when its off-diagonal terms are below this
# fraction of its largest diagonal term.
CLASSICAL_TOL = 1e-9

# Largest block (building) stepped in modal form.  Free flight costs about n_b
# multiply-adds per DOF and step (u = Phi q), a physical step a fixed ~30 flops
# per DOF: beyond ~64 storeys the physical step is the cheaper, and the cost of
# a run stays linear in the number of storeys.
MAX_MODAL_BLOCK = 64


@dataclass(frozen=True)
class ModalBasis:
    """Mass-normalised modes of each building, packed for the kernel.

    Attributes (n DOFs = n modes; block c spans DOFs ``start[c]:start[c+1]``)
    -------------------------------------------------------------------------
    start : (nc + 1,) int64
        First DOF of each block.
    phi_t : (n, n) float [1/sqrt(kg)]
        Phi^T, block diagonal: ``phi_t[j, i]`` is mode j at DOF i, so that the
        displacement rows of a block of steps are U = Q @ phi_t.
    phi_tm : (n, n) float [sqrt(kg)]
        Phi^T M, so that q = phi_tm @ u.
    blocks_t : (sum of n_b^2,) float [1/sqrt(kg)]
        Each block's Phi_c^T, row-major, one after the other (the kernel's
        per-block matrix products).
    block_offset : (nc + 1,) int64
        Where each block starts in ``blocks_t``.
    omega2 : (n,) float [1/s^2]
        Squared circular frequency of each mode.
    c : (n,) float [1/s]
        Modal damping coefficient 2 xi_j omega_j = phi_j^T C phi_j.
    """

    start: np.ndarray
    phi_t: np.ndarray
    phi_tm: np.ndarray
    blocks_t: np.ndarray
    block_offset: np.ndarray
    omega2: np.ndarray
    c: np.ndarray

    def participation(self, mass: np.ndarray, dof_motion: np.ndarray, n_motion: int) -> np.ndarray:
        """Gamma[r, j] = sum of Phi[i, j] m_i over the DOFs i driven by motion row r [sqrt(kg)].

        Shape (n_motion, n).  The modal load of mode j is -sum_r Gamma[r, j] a_g,r(t).
        """
        iota = np.zeros((mass.size, n_motion))
        iota[np.arange(mass.size), dof_motion] = 1.0
        return np.ascontiguousarray((self.phi_tm @ iota).T)


def dof_blocks(n: int, el_i: np.ndarray, el_j: np.ndarray) -> np.ndarray:
    """Starts of the contiguous DOF blocks that no element couples to each other, shape (nb + 1,).

    A block is the smallest contiguous range closed under the elements (a
    building, or several if a spring joins them); K and C are block diagonal.
    """
    # union of the index ranges [min(i, j), max(i, j)] of the coupling elements
    # (vectorised: integrate() calls this on every run, the twin's included)
    reach = np.arange(n)
    coupled = el_j >= 0
    i, j = el_i[coupled], el_j[coupled]
    np.maximum.at(reach, np.minimum(i, j), np.maximum(i, j))
    far = np.maximum.accumulate(reach)  # farthest DOF coupled to any DOF up to d
    ends = np.flatnonzero(far[:-1] == np.arange(n - 1))  # a block ends at d: nothing reaches past it
    return np.concatenate(([0], ends + 1, [n])).astype(np.int64)


def modal_basis(system) -> ModalBasis | None:
    """Mass-normalised modes of each building of ``system`` (SystemArrays), or None.

    None when some block's damping is not classical (Phi^T C Phi not diagonal),
    its stiffness is singular or it has more than ``MAX_MODAL_BLOCK`` DOFs; the
    kernel then steps physically throughout.
    """
    n = system.n_dof
    if n == 0:
        return None
    start = dof_blocks(n, system.el_i, system.el_j)
    if np.max(np.diff(start)) > MAX_MODAL_BLOCK:
        return None
    K = system.stiffness_matrix()
    C = system.damping_matrix()
    M = system.mass
    phi_t = np.zeros((n, n))
    phi_tm = np.zeros((n, n))
    omega2 = np.empty(n)
    cmod = np.empty(n)
    sizes = np.diff(start)
    block_offset = np.concatenate([[0], np.cumsum(sizes * sizes)]).astype(np.int64)
    blocks_t = np.empty(int(block_offset[-1]))
    for c in range(start.size - 1):
        o, e = int(start[c]), int(start[c + 1])
        if np.any(K[o:e, :o]) or np.any(K[o:e, e:]) or np.any(C[o:e, :o]) or np.any(C[o:e, e:]):
            return None  # coupled to another block: not block diagonal after all
        Kc, Cc, Mc = K[o:e, o:e], C[o:e, o:e], M[o:e]
        w2, phi = eigh(Kc, np.diag(Mc))
        if w2[0] <= 0.0:
            return None
        cq = phi.T @ Cc @ phi
        off = cq - np.diag(np.diag(cq))
        if np.max(np.abs(off), initial=0.0) > CLASSICAL_TOL * max(np.max(np.abs(np.diag(cq))), 1e-300):
            return None
        phi_t[o:e, o:e] = phi.T
        blocks_t[block_offset[c]:block_offset[c + 1]] = np.ascontiguousarray(phi.T).ravel()
        phi_tm[o:e, o:e] = phi.T * Mc[None, :]
        omega2[o:e] = w2
        cmod[o:e] = np.diag(cq)
    return ModalBasis(start=start, phi_t=phi_t, phi_tm=phi_tm, blocks_t=blocks_t, block_offset=block_offset,
                      omega2=omega2, c=cmod)
