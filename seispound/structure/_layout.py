"""Degrees of freedom and elements of one building: lumped floors, with an optional flexible foundation.

A building contributes a contiguous block of DOFs.  Without a foundation:
floors 1..N (displacements relative to the ground), storey i a spring
between floors i - 1 and i (the ground for i = 1).  With one (``foundation``):
the block starts with the rocking theta [rad] and the sway u0 [m] of the
foundation, then the floors, whose displacements w_i are relative to the free
field; storey i deforms by w_i - w_(i-1) - (h_i - h_(i-1)) theta (w_0 = u0,
h_0 = 0), a three-DOF element (Wolf 1985, Dynamic Soil-Structure Interaction,
Sec. 2.2, in total coordinates so that the mass matrix stays diagonal); the
soil is a spring and a dashpot on u0 and on theta; the building's
mass-proportional Rayleigh damping acts on the floors' motion relative to the
foundation's rigid-body motion (a dashpot on w_i - u0 - h_i theta), so the
soil's damping is only the soil's.  A foundation on soil (``soil`` and ``footing``) adds a
third DOF after the sway, the rocking cone's internal rotation (kind CONE; Wolf 1994, Ch. 2,
``foundation.rocking_cone``): the rocking spring acts from theta to the ground and the rocking
dashpot from theta to that DOF, which carries the cone's inertia rho I0 z0 and nothing else.
It is neither a floor nor an output (the floors' sensors never read it).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

# what a DOF is
FLOOR, SWAY, ROCKING, NODE, ATTACHMENT, CONE = 0, 1, 2, 3, 4, 5
LEFT, RIGHT = 0, 1


@dataclass
class Layout:
    """What :func:`building_layout` adds to the row (lists, appended in DOF and element order)."""

    mass: list = field(default_factory=list)
    kind: list = field(default_factory=list)
    floor: list = field(default_factory=list)  # 1-based floor of a floor's DOF, 0 for the foundation's
    a0: list = field(default_factory=list)
    v0: list = field(default_factory=list)
    influence: list = field(default_factory=list)
    el: list = field(default_factory=list)  # (i, j, third, lever, k, a1, c, law, par row or None)
    face: dict = field(default_factory=dict)  # (floor, LEFT or RIGHT) -> DOF a gap acts on (floor 0: the base)
    sensor: dict = field(default_factory=dict)  # floor -> {dof: weight}: the floor's output point
    deformation: dict = field(default_factory=dict)  # floor -> {dof: weight}: the storey below's deformation
    foundation: tuple | None = None  # (rocking DOF, sway DOF)
    cone: int = -1  # the rocking cone's internal DOF (-1: none)
    nodes: dict = field(default_factory=dict)  # floor -> list of its rod nodes' DOFs
    storey_of: list = field(default_factory=list)  # per element: the floor whose storey spring it is (0: none)
    body_mass: dict = field(default_factory=dict)  # floor -> its whole mass with attachments [kg]


def building_layout(b, start: int, n_par: int, faces=(True, True)) -> Layout:
    """The DOFs (numbered from ``start``) and elements of building ``b``.

    ``faces``: whether the building has a neighbour on its left and on its right (where
    a rod floor's attachments go).
    """
    out = Layout()
    a0, a1 = b.rayleigh_coefficients()
    n = b.n_floors
    if b.storey_law is not None:
        codes, par = b.storey_law.kernel_rows(b.storey_stiffness, n_par)
    else:
        codes, par = np.zeros(n, np.int64), None
    f = b.foundation
    base, theta = -1, -1  # the DOF below the first storey (-1: the ground), the rocking DOF
    if f is not None:
        imp = f.impedances()
        theta, base = start, start + 1
        _dof(out, f.rocking_inertia(n), ROCKING, 0, 0.0, 0.0, 0.0)
        _dof(out, f.mass, SWAY, 0, 0.0, 0.0, 1.0)
        out.el.append((base, -1, -1, 0.0, imp["sway_stiffness"], 0.0, imp["sway_damping"], 0, None))
        if imp["rocking_cone_inertia"] > 0.0:  # Wolf's rotational cone: the dashpot acts through its own DOF
            out.cone = start + 2
            _dof(out, imp["rocking_cone_inertia"], CONE, 0, 0.0, 0.0, 0.0)
            out.el.append((theta, -1, -1, 0.0, imp["rocking_stiffness"], 0.0, 0.0, 0, None))
            out.el.append((out.cone, theta, -1, 0.0, 0.0, 0.0, imp["rocking_damping"], 0, None))
        else:  # springs and dashpots given: both to the ground
            out.el.append((theta, -1, -1, 0.0, imp["rocking_stiffness"], 0.0, imp["rocking_damping"], 0, None))
        out.foundation = (theta, base)
    out.face[(0, LEFT)] = out.face[(0, RIGHT)] = base
    rod = b.floor_model
    shares = [1.0] if rod is None else rod.node_shares().tolist()  # of the floor's mass
    spans = [1.0] if rod is None else rod.tributary_shares().tolist()  # of the storey below (by length)
    heights = [0.0] + b.floor_heights.tolist()
    masses, stiffness, velocity = b.floor_masses.tolist(), b.storey_stiffness.tolist(), b.initial_velocity.tolist()
    below_nodes = [base] * len(shares)
    for k in range(n):
        m = masses[k]
        dz = heights[k + 1] - heights[k]
        lever = -dz if f is not None else 0.0
        att = {side: None for side in (LEFT, RIGHT)}
        if rod is not None and rod.attachment is not None and faces[LEFT]:
            att[LEFT] = _attachment(out, start, rod.attachment, k + 1, velocity[k])
        nodes = []
        for p, (share, span) in enumerate(zip(shares, spans)):
            dof = start + len(out.mass)
            nodes.append(dof)
            _dof(out, m * share, FLOOR if rod is None else NODE, k + 1, 0.0 if f is not None else a0,
                 velocity[k], 1.0)
            law_par = None if par is None else _scaled(par[k], int(codes[k]), span)
            _pad_storeys(out)
            out.el.append((dof, below_nodes[p], theta, lever, stiffness[k] * span, a1, 0.0,
                           int(codes[k]), law_par))
            out.storey_of.append(k + 1)
            if f is not None and a0:  # mass-proportional damping on the motion relative to the foundation
                out.el.append((dof, base, theta, -heights[k + 1], 0.0, 0.0, a0 * m * share, 0, None))
        if rod is not None:
            ks = rod.segment_stiffness()
            cs = 2.0 * rod.axial_damping / rod.first_axial_omega(m) * ks
            for p in range(len(nodes) - 1):
                out.el.append((nodes[p + 1], nodes[p], -1, 0.0, ks, 0.0, cs, 0, None))
            for side, face_node in ((LEFT, nodes[0]), (RIGHT, nodes[-1])):
                if att[side] is None and side == RIGHT and rod.attachment is not None and faces[RIGHT]:
                    att[RIGHT] = _attachment(out, start, rod.attachment, k + 1, velocity[k])
                if att[side] is not None:
                    a = rod.attachment
                    out.el.append((att[side], face_node, -1, 0.0, a.joint_stiffness, 0.0, a.joint_damping, 0, None))
        out.face[(k + 1, LEFT)] = att[LEFT] if att[LEFT] is not None else nodes[0]
        out.face[(k + 1, RIGHT)] = att[RIGHT] if att[RIGHT] is not None else nodes[-1]
        out.nodes[k + 1] = nodes
        out.body_mass[k + 1] = m + sum(rod.attachment.mass for side in att if att[side] is not None)
        out.sensor[k + 1] = _sensor(rod, nodes, att)
        deformation = {}
        for p, span in enumerate(spans):  # the node springs' deformations weighted as their stiffness
            deformation[nodes[p]] = deformation.get(nodes[p], 0.0) + span
            if below_nodes[p] >= 0:
                deformation[below_nodes[p]] = deformation.get(below_nodes[p], 0.0) - span
        if f is not None:
            deformation[theta] = lever
        out.deformation[k + 1] = deformation
        below_nodes = nodes
    _pad_storeys(out)
    return out


def _pad_storeys(out):
    """storey_of for every element appended without one (foundation, dampers, rods, joints): 0."""
    out.storey_of += [0] * (len(out.el) - len(out.storey_of))


def _attachment(out, start, a, floor, v0):
    dof = start + len(out.mass)
    _dof(out, a.mass, ATTACHMENT, floor, 0.0, v0, 1.0)
    return dof


def _sensor(rod, nodes, att):
    if rod is None:
        return {nodes[0]: 1.0}
    if rod.sensor == "attachment":
        dof = att[RIGHT] if att[RIGHT] is not None else att[LEFT]
        return {dof: 1.0}
    return {nodes[p]: w for p, w in rod.sensor_weights().items()}


def _scaled(row, code, share):
    """A hysteretic storey law's parameters for a node carrying ``share`` of the floor: stiffness and yield
    force scale, the yield drift stays (so a rigid floor reproduces the lumped storey)."""
    from ..storey import codes as C

    row = np.array(row, float)
    if code == C.BILINEAR:
        row[[C.B_K, C.B_FY]] *= share
    elif code == C.PEAK_ORIENTED:
        row[[C.PO_K, C.PO_FY]] *= share
    elif code == C.BOUC_WEN:
        row[C.BW_K] *= share
    elif code == C.IWAN:
        row[C.IW_K] *= share
    elif code == C.FLAG:
        row[C.FL_K] *= share
    return row


def _dof(out, mass, kind, floor, a0, v0, influence):
    out.mass.append(float(mass))
    out.kind.append(kind)
    out.floor.append(floor)
    out.a0.append(a0)
    out.v0.append(v0)
    out.influence.append(influence)
