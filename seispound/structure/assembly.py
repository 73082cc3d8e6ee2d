"""Assembly of a row of buildings and its gaps into the flat arrays the kernel takes.

Degrees of freedom are numbered building by building, floors from the ground
up, so each building's stiffness is a contiguous tridiagonal block and the
linear operator is banded.  Every linear element is a two-node spring
(``el_i``, ``el_j``; ``el_j = -1`` means the ground), which leaves room for
extra degrees of freedom (foundations, rods) and, later, per-element history
state (yielding storeys) without changing the kernel's interface.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..contact import codes as S
from .gap import GapLink, expand_gap

__all__ = ["SystemArrays", "assemble"]


@dataclass
class SystemArrays:
    """Flat arrays describing the whole row (shapes: n DOFs, ne elements, ng gaps).

    Attributes
    ----------
    mass : (n,) float, [kg]
    dof_building, dof_floor : (n,) int
        Building index and 1-based floor number of each DOF.
    dof_motion : (n,) int
        Which base-motion row drives each DOF (all 0 for one ground motion).
    dof_a0 : (n,) float, [1/s]
        Mass-proportional Rayleigh coefficient of the DOF's building.
    el_i, el_j : (ne,) int
        Element end DOFs (el_j = -1: ground).
    el_k : (ne,) float, [N/m]
    el_a1 : (ne,) float, [s]
        Stiffness-proportional Rayleigh coefficient of the element's building.
    bandwidth : int
        Half bandwidth of the linear operator.
    u0, v0 : (n,) float
        Initial displacement [m] and velocity [m/s] relative to the ground.
    gap_i, gap_j : (ng,) int
        Left and right DOF of each gap element; penetration = u_i - u_j - size.
    gap_size : (ng,) float, [m]
    gap_law : (ng,) int
        Law code (``contact.codes``).
    gap_par : (ng, N_PAR) float
        Law parameters (columns ``P_*``).
    links : list of GapLink
    el_c : (ne,) float [N s/m], optional
        A dashpot of each element in parallel with its spring, beyond the
        Rayleigh term el_a1 el_k (an axial rod damper, a foundation dashpot).
    dof_c : (n,) float [N s/m], optional
        A dashpot from each DOF to its ground, beyond the Rayleigh term dof_a0 mass.
    dof_influence : (n,) float, optional
        Influence coefficient of each DOF on its ground-motion row: the effective
        load is -mass x influence x a_g (1 for a translation along the motion,
        0 for a rotation); default 1.

    The kernel takes every dashpot as a0 m per DOF and a1 k per element; the
    extra dashpots join them there (``kernel_arrays``).
    """

    mass: np.ndarray
    dof_building: np.ndarray
    dof_floor: np.ndarray
    dof_motion: np.ndarray
    dof_a0: np.ndarray
    el_i: np.ndarray
    el_j: np.ndarray
    el_k: np.ndarray
    el_a1: np.ndarray
    bandwidth: int
    u0: np.ndarray
    v0: np.ndarray
    gap_i: np.ndarray
    gap_j: np.ndarray
    gap_size: np.ndarray
    gap_law: np.ndarray
    gap_par: np.ndarray
    links: list
    el_c: np.ndarray | None = None
    dof_c: np.ndarray | None = None
    dof_influence: np.ndarray | None = None

    @property
    def n_dof(self) -> int:
        return int(self.mass.size)

    @property
    def n_gap(self) -> int:
        return int(self.gap_size.size)

    def without_contact(self) -> "SystemArrays":
        """The same row with every gap disabled (the no-pounding twin)."""
        from dataclasses import replace

        return replace(self, gap_law=np.zeros_like(self.gap_law))

    def stiffness_matrix(self) -> np.ndarray:
        """Dense stiffness matrix [N/m], shape (n, n) (for checks and small problems)."""
        return self._springs(np.zeros((self.n_dof, self.n_dof)), self.el_k)

    def damping_matrix(self) -> np.ndarray:
        """Dense damping matrix [N s/m], shape (n, n): Rayleigh plus any extra dashpots."""
        a0, a1 = self.kernel_damping()
        return self._springs(np.diag(a0 * self.mass), a1 * self.el_k)

    def kernel_damping(self) -> tuple[np.ndarray, np.ndarray]:
        """(dof_a0, el_a1) with the extra dashpots folded in: a0 + c/m per DOF, a1 + c/k per element.

        An element dashpot needs a spring in parallel (k > 0), a DOF dashpot acts
        to the DOF's ground; with no extra dashpots the Rayleigh arrays themselves.
        """
        a0, a1 = self.dof_a0, self.el_a1
        if self.dof_c is not None and np.any(self.dof_c):
            a0 = a0 + np.asarray(self.dof_c, float) / self.mass
        if self.el_c is not None and np.any(self.el_c):
            c = np.asarray(self.el_c, float)
            if np.any((c != 0.0) & (self.el_k <= 0.0)):
                raise ValueError("an element dashpot needs a spring in parallel (el_k > 0)")
            a1 = a1 + np.divide(c, self.el_k, out=np.zeros_like(c), where=c != 0.0)
        return a0, a1

    def kernel_arrays(self) -> "SystemArrays":
        """This row as the kernel takes it: extra dashpots folded into dof_a0 and el_a1 (same object if none)."""
        if (self.el_c is None or not np.any(self.el_c)) and (self.dof_c is None or not np.any(self.dof_c)):
            return self
        from dataclasses import replace

        a0, a1 = self.kernel_damping()
        return replace(self, dof_a0=a0, el_a1=a1, el_c=None, dof_c=None)

    def motion_rows(self, ag: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Ground-motion rows (m, nt) and each DOF's row, with the influence coefficients applied.

        A DOF of influence c on motion r reads the row c a_g,r (added once per
        distinct pair (r, c)); with every influence 1, ``ag`` and ``dof_motion``
        themselves.  Rotations (c = 0) read a row of zeros: no inertial load,
        and their absolute acceleration is their relative one.
        """
        infl = self.dof_influence
        if infl is None or np.all(np.asarray(infl) == 1.0):
            return ag, self.dof_motion
        rows = [ag[r] for r in range(ag.shape[0])]
        pair_row = {}
        dof_motion = self.dof_motion.copy()
        for i, (r, c) in enumerate(zip(self.dof_motion, np.asarray(infl, float))):
            if c == 1.0:
                continue
            key = (int(r), float(c))
            if key not in pair_row:
                pair_row[key] = len(rows)
                rows.append(c * ag[r])
            dof_motion[i] = pair_row[key]
        return np.vstack(rows), dof_motion

    def _springs(self, A: np.ndarray, values) -> np.ndarray:
        """Add the two-node elements with coefficients ``values`` into the dense matrix A."""
        for i, j, c in zip(self.el_i, self.el_j, values):
            A[i, i] += c
            if j >= 0:
                A[j, j] += c
                A[i, j] -= c
                A[j, i] -= c
        return A


def assemble(buildings, gaps, default_law=None) -> SystemArrays:
    """Flatten ``buildings`` (left to right) and ``gaps`` into :class:`SystemArrays`."""
    mass, dof_b, dof_f, a0s, v0 = [], [], [], [], []
    el_i, el_j, el_k, el_a1 = [], [], [], []
    first = []
    for b_idx, b in enumerate(buildings):
        a0, a1 = b.rayleigh_coefficients()
        start = len(mass)
        first.append(start)
        for f in range(b.n_floors):
            mass.append(b.floor_masses[f])
            dof_b.append(b_idx)
            dof_f.append(f + 1)
            a0s.append(a0)
            v0.append(b.initial_velocity[f])
            el_i.append(start + f)
            el_j.append(start + f - 1 if f > 0 else -1)
            el_k.append(b.storey_stiffness[f])
            el_a1.append(a1)
    links: list[GapLink] = []
    for g_idx, gap in enumerate(gaps):
        links.extend(expand_gap(gap, g_idx, buildings, default_law))
    mass = np.asarray(mass, float)
    ng = len(links)
    gap_i = np.array([first[l.left] + l.left_floor - 1 for l in links], dtype=np.int64)
    gap_j = np.array([first[l.right] + l.right_floor - 1 for l in links], dtype=np.int64)
    gap_par = np.zeros((ng, S.N_PAR))
    for g, l in enumerate(links):
        gap_par[g] = l.law.kernel_params(mass[gap_i[g]], mass[gap_j[g]])
    el_i = np.asarray(el_i, np.int64)
    el_j = np.asarray(el_j, np.int64)
    coupled = el_j >= 0
    bandwidth = int(np.max(np.abs(el_i[coupled] - el_j[coupled]))) if coupled.any() else 0
    n = mass.size
    return SystemArrays(
        mass=mass,
        dof_building=np.asarray(dof_b, np.int64),
        dof_floor=np.asarray(dof_f, np.int64),
        dof_motion=np.zeros(n, np.int64),
        dof_a0=np.asarray(a0s, float),
        el_i=el_i,
        el_j=el_j,
        el_k=np.asarray(el_k, float),
        el_a1=np.asarray(el_a1, float),
        bandwidth=bandwidth,
        u0=np.zeros(n),
        v0=np.asarray(v0, float),
        gap_i=gap_i,
        gap_j=gap_j,
        gap_size=np.array([l.size for l in links], float),
        gap_law=np.array([l.law.code for l in links], dtype=np.int64),
        gap_par=gap_par,
        links=links,
    )
