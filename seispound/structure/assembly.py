"""Assembly of a row of buildings and its gaps into the flat arrays the kernel takes.

Degrees of freedom are numbered building by building, floors from the ground
up, so each building's stiffness is a contiguous tridiagonal block and the
linear operator is banded.  Every linear element is a two-node spring
(``el_i``, ``el_j``; ``el_j = -1`` means the ground).  Extra degrees of freedom (foundations,
rods) and storeys with history (yielding storeys) are elements of the same kind or, where they
couple more than two DOFs, coefficient-vector elements (``SystemArrays``, run on the
coefficient-vector linear part: ``integrate/_general.py``).
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
    el_law : (ne,) int, optional
        Storey law of each element: 0 linear (the spring el_k), else a
        hysteretic law code (``integrate._material``: BILINEAR, BOUC_WEN) with
        its parameters in ``el_par`` (ne, N_PAR); el_k is then the initial
        stiffness, from which the element's Rayleigh dashpot a1 k stays linear.
    el_third, el_lever : (ne,) int and float, optional
        A third DOF of an element and its coefficient: the deformation is
        u_i - u_j + lever u_third (a storey above a rocking foundation:
        lever = -(h_i - h_j), the third DOF the rotation); -1 / 0: none.
    mass_blocks : list of (dofs, coefs, mass), optional
        Masses acting on several DOFs (a rigid body seen from them): each adds
        mass b b^T to the mass matrix, b = coefs at dofs, beyond the lumped ``mass``.
    dof_kind : (n,) int, optional
        What each DOF is (``_layout``: FLOOR, SWAY, ROCKING, NODE, ATTACHMENT, CONE the rocking
        cone's internal DOF); None: every DOF a floor.
    outputs : FloorOutputs, optional
        How the floors' outputs follow from the DOFs when they are not the DOFs
        themselves (a foundation's DOFs, a rod floor's nodes); None: one DOF per floor.
    gap_dofs, gap_coefs : (ng, 4) int and float, optional
        Gaps whose sides are interpolated between two DOFs (a floor against a
        storey): penetration = sum coef u[dof] - size (+ ground terms); None:
        u_i - u_j - size for every gap.

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
    el_law: np.ndarray | None = None
    el_par: np.ndarray | None = None
    el_third: np.ndarray | None = None
    el_lever: np.ndarray | None = None
    mass_blocks: list | None = None
    gap_dofs: np.ndarray | None = None
    gap_coefs: np.ndarray | None = None
    dof_kind: np.ndarray | None = None
    outputs: FloorOutputs | None = None

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

    @property
    def needs_general_driver(self) -> bool:
        """True when the row has what only the general driver takes (``integrate._general``).

        Storeys with history, elements on a third DOF, masses on several DOFs,
        gaps with an interpolated side.
        """
        return bool((self.el_law is not None and np.any(self.el_law))
                    or (self.el_third is not None and np.any(self.el_third >= 0))
                    or self.mass_blocks or self.gap_dofs is not None)

    def matrices(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Dense M [kg], C [N s/m], K [N/m], shape (n, n), from every element (linear storeys at their
        initial stiffness), for eigenvalues and checks."""
        tab = self.element_tables()
        n = self.n_dof
        M, C, K = np.zeros((n, n)), np.zeros((n, n)), np.zeros((n, n))

        def add(A, dof, coef, c):
            b = np.zeros(n)
            used = dof >= 0
            b[dof[used]] = coef[used]
            A += c * np.outer(b, b)

        for e in range(tab["ms_val"].size):
            add(M, tab["ms_dof"][e], tab["ms_coef"][e], tab["ms_val"][e])
            add(C, tab["ms_dof"][e], tab["ms_coef"][e], tab["ms_a0"][e] * tab["ms_val"][e])
        for e in range(tab["le_k"].size):
            add(K, tab["le_dof"][e], tab["le_coef"][e], tab["le_k"][e])
            add(C, tab["le_dof"][e], tab["le_coef"][e], tab["le_c"][e])
        if self.el_law is not None:  # storeys with history at their initial stiffness
            for e in np.flatnonzero(self.el_law):
                third = -1 if self.el_third is None else self.el_third[e]
                dof = np.array([self.el_i[e], self.el_j[e], third])
                coef = np.array([1.0, -1.0, 0.0 if self.el_lever is None else self.el_lever[e]])
                add(K, dof, coef, self.el_k[e])
        return M, C, K

    def element_tables(self) -> dict:
        """The row as coefficient-vector elements (``integrate._elements``), as the general driver takes it.

        Returns a dict of arrays: masses ms_dof (nms, 3), ms_coef, ms_val [kg],
        ms_a0 [1/s]; linear elements le_dof (nle, 3), le_coef, le_k [N/m],
        le_c [N s/m] (springs of linear storeys with their Rayleigh and extra
        dashpots, the dashpots of hysteretic storeys, dashpots to the ground);
        elements with state ne_dof (nn, 4), ne_coef, ne_size [m], ne_code,
        ne_par, ne_gap (hysteretic storeys first, then the gaps, in order);
        p, the half bandwidth; dof_load (n,) [kg], M iota.
        """
        from .band import bandwidth

        n, ne = self.n_dof, self.el_i.size
        infl = np.ones(n) if self.dof_influence is None else np.asarray(self.dof_influence, float)
        ms = [((i, -1, -1), (1.0, 0.0, 0.0), self.mass[i], self.dof_a0[i]) for i in range(n)]
        for dofs, coefs, m in self.mass_blocks or []:
            d = list(dofs) + [-1] * (3 - len(dofs))
            c = list(coefs) + [0.0] * (3 - len(coefs))
            ms.append((tuple(d), tuple(c), float(m), 0.0))
        third = np.full(ne, -1) if self.el_third is None else np.asarray(self.el_third)
        lever = np.zeros(ne) if self.el_lever is None else np.asarray(self.el_lever, float)
        law = np.zeros(ne, np.int64) if self.el_law is None else np.asarray(self.el_law, np.int64)
        el_c = np.zeros(ne) if self.el_c is None else np.asarray(self.el_c, float)
        le, ne_rows = [], []
        for e in range(ne):
            dofs = (int(self.el_i[e]), int(self.el_j[e]), int(third[e]))
            coefs = (1.0, -1.0 if dofs[1] >= 0 else 0.0, float(lever[e]) if dofs[2] >= 0 else 0.0)
            c = self.el_a1[e] * self.el_k[e] + el_c[e]
            if law[e] == 0:
                le.append((dofs, coefs, self.el_k[e], c))
            else:
                if c:
                    le.append((dofs, coefs, 0.0, c))
                ne_rows.append((dofs + (-1,), coefs + (0.0,), 0.0, int(law[e]), self.el_par[e], False))
        if self.dof_c is not None:
            le += [((i, -1, -1), (1.0, 0.0, 0.0), 0.0, float(c)) for i, c in enumerate(self.dof_c) if c]
        for g in range(self.n_gap):
            if self.gap_dofs is None:
                dofs, coefs = (int(self.gap_i[g]), int(self.gap_j[g]), -1, -1), (1.0, -1.0, 0.0, 0.0)
            else:
                dofs, coefs = tuple(int(x) for x in self.gap_dofs[g]), tuple(float(x) for x in self.gap_coefs[g])
            ne_rows.append((dofs, coefs, float(self.gap_size[g]), int(self.gap_law[g]), self.gap_par[g], True))
        npar = self.gap_par.shape[1]

        out = dict(
            ms_dof=np.array([r[0] for r in ms], np.int64).reshape(-1, 3),
            ms_coef=np.array([r[1] for r in ms], float).reshape(-1, 3),
            ms_val=np.array([r[2] for r in ms], float), ms_a0=np.array([r[3] for r in ms], float),
            le_dof=np.array([r[0] for r in le], np.int64).reshape(-1, 3),
            le_coef=np.array([r[1] for r in le], float).reshape(-1, 3),
            le_k=np.array([r[2] for r in le], float), le_c=np.array([r[3] for r in le], float),
            ne_dof=np.array([r[0] for r in ne_rows], np.int64).reshape(-1, 4),
            ne_coef=np.array([r[1] for r in ne_rows], float).reshape(-1, 4),
            ne_size=np.array([r[2] for r in ne_rows], float), ne_code=np.array([r[3] for r in ne_rows], np.int64),
            ne_par=np.array([np.asarray(r[4], float) for r in ne_rows], float).reshape(-1, npar),
            ne_gap=np.array([r[5] for r in ne_rows], np.bool_),
        )
        out["p"] = bandwidth(n, out["ms_dof"], out["le_dof"])
        M_iota = np.zeros(n)
        for d, c, m, _ in ms:
            w = sum(ci * infl[di] for di, ci in zip(d, c) if di >= 0)
            for di, ci in zip(d, c):
                if di >= 0:
                    M_iota[di] += m * ci * w
        out["dof_load"] = M_iota
        out["dof_infl"] = infl
        return out

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


@dataclass
class FloorOutputs:
    """How the floors' output quantities follow from the DOFs when they are not the DOFs themselves.

    (A foundation adds DOFs that are not floors; a rod floor has several nodes and one sensor.)
    Attributes: building, floor (no,) of each output; sensor (no, n): the floor's output point
    (displacement, velocity, acceleration = sensor @ DOF values); deformation (no, n): the
    storey below's deformation (drift); single (no,): the DOF of a sensor that is one DOF with
    weight 1, else -1; foundation (nb, 2): the rocking and sway DOF of each building (-1: none);
    storey_output (ne,): the output whose storey each element is a spring of (-1: none); nodes:
    per output, the DOFs of its rod's nodes (left to right; empty for a lumped floor).
    """

    building: np.ndarray
    floor: np.ndarray
    sensor: np.ndarray
    deformation: np.ndarray
    single: np.ndarray
    foundation: np.ndarray
    storey_output: np.ndarray = None  # (ne,) the output whose storey an element is a spring of (-1: none)
    nodes: list = None  # per output: its rod nodes' DOFs (empty for a lumped floor)


def assemble(buildings, gaps, default_law=None, parts=None) -> SystemArrays:
    """Flatten ``buildings`` (left to right) and ``gaps`` into :class:`SystemArrays`.

    ``parts`` (:class:`seispound.model.parts.Parts`): the layouts of the buildings it keeps are
    kept there too (a variant of a model lays out only the buildings that changed).
    """
    from ._layout import LEFT, RIGHT, building_layout

    layouts, first = [], []
    n = 0
    for i, b in enumerate(buildings):
        first.append(n)
        faces = (i > 0, i < len(buildings) - 1)
        make = lambda: building_layout(b, n, S.N_PAR, faces)  # noqa: E731, B023 (called at once)
        lay = make() if parts is None else parts.layout(b, n, faces, make)  # (a building it does not keep: made)
        layouts.append(lay)
        n += len(lay.mass)
    cat = lambda name, dtype=float: np.asarray([x for lay in layouts for x in getattr(lay, name)], dtype)  # noqa
    mass = cat("mass")
    dof_b = np.concatenate([np.full(len(lay.mass), i, np.int64) for i, lay in enumerate(layouts)])
    els = [e for lay in layouts for e in lay.el]
    links: list[GapLink] = []
    for g_idx, gap in enumerate(gaps):
        links.extend(expand_gap(gap, g_idx, buildings, default_law))
    ng = len(links)
    # a gap acts on the left building's right face and the right building's left face
    gap_i = np.array([layouts[l.left].face[(l.left_floor, RIGHT)] for l in links], dtype=np.int64)
    gap_j = np.array([layouts[l.right].face[(l.right_floor, LEFT)] for l in links], dtype=np.int64)
    sides = [(_side(layouts[l.left], l.left_floor, RIGHT, l.left_weight, mass),
              _side(layouts[l.right], l.right_floor, LEFT, l.right_weight, mass)) for l in links]
    gap_par = np.zeros((ng, S.N_PAR))
    for g, l in enumerate(links):
        gap_par[g] = l.law.kernel_params(sides[g][0][2], sides[g][1][2])
    gap_dofs = gap_coefs = None
    if any(l.kind != "floor-to-floor" for l in links):  # some side is struck on a storey: interpolated
        gap_dofs = np.full((ng, 4), -1, np.int64)
        gap_coefs = np.zeros((ng, 4))
        for g, ((dl, cl, _), (dr, cr, _)) in enumerate(sides):
            gap_dofs[g] = dl + dr
            gap_coefs[g] = cl + [-c for c in cr]
    el_i = np.array([e[0] for e in els], np.int64)
    el_j = np.array([e[1] for e in els], np.int64)
    coupled = el_j >= 0
    bandwidth = int(np.max(np.abs(el_i[coupled] - el_j[coupled]))) if coupled.any() else 0
    el_law = np.array([e[7] for e in els], np.int64)
    el_third = np.array([e[2] for e in els], np.int64)
    el_c = np.array([e[6] for e in els], float)
    kind = cat("kind", np.int64)
    plain = not np.any(kind != 0)
    return SystemArrays(
        mass=mass,
        dof_building=dof_b,
        dof_floor=cat("floor", np.int64),
        dof_motion=np.zeros(n, np.int64),
        dof_a0=cat("a0"),
        el_i=el_i,
        el_j=el_j,
        el_k=np.array([e[4] for e in els], float),
        el_a1=np.array([e[5] for e in els], float),
        bandwidth=bandwidth,
        u0=np.zeros(n),
        v0=cat("v0"),
        gap_i=gap_i,
        gap_j=gap_j,
        gap_size=np.array([l.size for l in links], float),
        gap_law=np.array([l.law.code for l in links], dtype=np.int64),
        gap_par=gap_par,
        links=links,
        el_c=el_c if np.any(el_c) else None,
        gap_dofs=gap_dofs,
        gap_coefs=gap_coefs,
        dof_influence=None if plain else cat("influence"),
        el_law=el_law if np.any(el_law) else None,
        el_par=np.array([np.zeros(S.N_PAR) if e[8] is None else e[8] for e in els], float) if np.any(el_law)
        else None,
        el_third=el_third if np.any(el_third >= 0) else None,
        el_lever=np.array([e[3] for e in els], float) if np.any(el_third >= 0) else None,
        dof_kind=kind,
        outputs=None if plain else _floor_outputs(layouts, n, buildings),
    )


def _side(layout, floor, face, weight, mass):
    """One side of a gap: two (dof, coefficient) slots and its apparent mass [kg].

    A floor: its face DOF (a rod's end node or its attachment), with the floor's whole mass
    (attachments included: the contact law's damping from e is a two-body law, so a rod
    floor and the lumped floor it refines get the same).  A storey: (1 - w) u_below + w u_floor;
    an impulse there moves the point by (1 - w)^2 / m_below + w^2 / m_floor per unit, so the
    apparent mass is the reciprocal (the ground below a first storey: infinite mass, no DOF;
    a foundation: its mass).
    """
    top = layout.face[(floor, face)]
    m_top = layout.body_mass[floor]
    if weight == 1.0:
        return [top, -1], [1.0, 0.0], m_top
    below = layout.face[(floor - 1, face)]
    m_below = layout.body_mass.get(floor - 1, mass[below] if below >= 0 else np.inf)
    flex = weight ** 2 / m_top + (1.0 - weight) ** 2 / m_below
    return [below, top], [1.0 - weight if below >= 0 else 0.0, weight], 1.0 / flex


def _floor_outputs(layouts, n, buildings) -> FloorOutputs:
    rows = [(i, fl, lay.sensor[fl], lay.deformation[fl]) for i, lay in enumerate(layouts) for fl in sorted(lay.sensor)]
    row_of = {(i, fl): r for r, (i, fl, _, _) in enumerate(rows)}
    storey_output = np.array([row_of[(i, fl)] if fl else -1 for i, lay in enumerate(layouts) for fl in lay.storey_of],
                             np.int64)
    nodes = [layouts[i].nodes[fl] if buildings[i].floor_model is not None else [] for i, fl, _, _ in rows]
    no = len(rows)
    sensor, deformation = np.zeros((no, n)), np.zeros((no, n))
    single = np.full(no, -1, np.int64)
    for r, (_, _, sen, dfm) in enumerate(rows):
        for d, w in sen.items():
            sensor[r, d] = w
        for d, w in dfm.items():
            deformation[r, d] = w
        if len(sen) == 1 and next(iter(sen.values())) == 1.0:
            single[r] = next(iter(sen))
    fnd = np.array([lay.foundation or (-1, -1) for lay in layouts], np.int64).reshape(-1, 2)
    return FloorOutputs(building=np.array([r[0] for r in rows], np.int64), floor=np.array([r[1] for r in rows], np.int64),
                        sensor=sensor, deformation=deformation, single=single, foundation=fnd,
                        storey_output=storey_output, nodes=nodes)
