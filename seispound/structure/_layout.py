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
soil's damping is only the soil's.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

# what a DOF is
FLOOR, SWAY, ROCKING = 0, 1, 2


@dataclass
class Layout:
    """What :func:`building_layout` adds to the row (lists, appended in DOF and element order)."""

    mass: list = field(default_factory=list)
    kind: list = field(default_factory=list)
    floor: list = field(default_factory=list)  # 1-based floor of a FLOOR DOF, 0 otherwise
    a0: list = field(default_factory=list)
    v0: list = field(default_factory=list)
    influence: list = field(default_factory=list)
    el: list = field(default_factory=list)  # (i, j, third, lever, k, a1, c, law, par row or None)
    face: dict = field(default_factory=dict)  # floor -> DOF a gap acts on
    sensor: dict = field(default_factory=dict)  # floor -> {dof: weight}: the floor's output point
    deformation: dict = field(default_factory=dict)  # floor -> {dof: weight}: the storey below's deformation
    foundation: tuple | None = None  # (rocking DOF, sway DOF)


def building_layout(b, start: int, n_par: int) -> Layout:
    """The DOFs (numbered from ``start``) and elements of building ``b``."""
    out = Layout()
    a0, a1 = b.rayleigh_coefficients()
    n = b.n_floors
    if b.storey_law is not None:
        codes, par = b.storey_law.kernel_rows(b.storey_stiffness, n_par)
    else:
        codes, par = np.zeros(n, np.int64), None
    f = b.foundation
    base = -1  # the DOF below the first storey (-1: the ground)
    theta = -1
    if f is not None:
        imp = f.impedances()
        theta, base = start, start + 1
        _dof(out, f.rocking_inertia(n), ROCKING, 0, 0.0, 0.0, 0.0)
        _dof(out, f.mass, SWAY, 0, 0.0, 0.0, 1.0)
        out.el.append((base, -1, -1, 0.0, imp["sway_stiffness"], 0.0, imp["sway_damping"], 0, None))
        out.el.append((theta, -1, -1, 0.0, imp["rocking_stiffness"], 0.0, imp["rocking_damping"], 0, None))
        out.foundation = (theta, base)
    first = start + len(out.mass)
    heights = np.concatenate([[0.0], b.floor_heights])
    for k in range(n):
        dof = first + k
        _dof(out, b.floor_masses[k], FLOOR, k + 1, 0.0 if f is not None else a0, b.initial_velocity[k], 1.0)
        below = dof - 1 if k > 0 else base
        lever = -(heights[k + 1] - heights[k]) if f is not None else 0.0
        out.el.append((dof, below, theta, lever, b.storey_stiffness[k], a1, 0.0, int(codes[k]),
                       None if par is None else par[k]))
        out.face[k + 1] = dof
        out.sensor[k + 1] = {dof: 1.0}
        deformation = {dof: 1.0}
        if below >= 0:
            deformation[below] = -1.0
        if f is not None:
            deformation[theta] = lever
            if a0:  # mass-proportional damping on the motion relative to the foundation
                out.el.append((dof, base, theta, -heights[k + 1], 0.0, 0.0, a0 * b.floor_masses[k], 0, None))
        out.deformation[k + 1] = deformation
    return out


def _dof(out, mass, kind, floor, a0, v0, influence):
    out.mass.append(float(mass))
    out.kind.append(kind)
    out.floor.append(floor)
    out.a0.append(a0)
    out.v0.append(v0)
    out.influence.append(influence)
