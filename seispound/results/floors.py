"""The run as the results see it: one column per floor, whatever DOFs the row was integrated on.

A row of lumped, fixed-base buildings has one DOF per floor and passes through
unchanged.  A foundation adds DOFs that are not floors (sway, rocking; floor
displacements are then relative to the free field), and a rod floor has
several nodes and one sensor: ``SystemArrays.outputs`` says how each floor's
output point and its storey's deformation follow from the DOFs.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .. import _blas

__all__ = ["FloorSystem", "floor_view", "foundation_motion"]


@dataclass
class FloorSystem:
    """What the results need of a row, per floor output: building and floor of each, the gaps."""

    dof_building: np.ndarray
    dof_floor: np.ndarray
    links: list
    gap_size: np.ndarray

    @property
    def n_dof(self) -> int:
        return int(self.dof_building.size)


def floor_view(raw, system):
    """(raw, system) per floor: histories at each floor's sensor, drift as its storey's deformation.

    Peaks over every substep are kept where a floor's sensor is one DOF; elsewhere
    (a sensor between rod nodes) they are taken at the analysis instants.
    """
    out = system.outputs
    if out is None:
        return raw, system
    fsys = FloorSystem(out.building, out.floor, system.links, system.gap_size)
    if raw is None:
        return None, fsys
    S, D = out.sensor, out.deformation
    # one BLAS thread: on a busy machine (a study's workers on every core) the second one waits for a core,
    # and a study of a pair with soil took 1.6 times as long (docs/performance.md)
    with _blas.one_thread():
        if np.all(out.single >= 0):  # every sensor one DOF of weight 1 (lumped floors on a foundation): a selection
            u, vel, acc = (np.take(x, out.single, axis=1) for x in (raw.displacement, raw.velocity, raw.acceleration))
        else:
            u, vel, acc = raw.displacement @ S.T, raw.velocity @ S.T, raw.acceleration @ S.T
        drift = raw.displacement @ D.T
    peak = np.abs(u).max(axis=0) if u.shape[0] else np.zeros(S.shape[0])
    one = out.single >= 0
    peak[one] = raw.peak_displacement[out.single[one]]
    storey_force, storey_rows = raw.storey_force, np.zeros(0, np.int64)
    if raw.storey_force is not None and raw.storey_elements.size:  # a floor's storey: the sum of its springs
        rows = out.storey_output[raw.storey_elements]
        storey_rows = np.unique(rows)
        storey_force = np.zeros((raw.storey_force.shape[0], storey_rows.size))
        for q, r in enumerate(rows):
            storey_force[:, np.searchsorted(storey_rows, r)] += raw.storey_force[:, q]
    return replace(raw, displacement=u, velocity=vel, acceleration=acc,
                   peak_displacement=peak, drift=drift, storey_force=storey_force,
                   storey_dofs=storey_rows), fsys


def foundation_motion(raw, system, nb):
    """Sway [m] and rocking [rad] of each building's foundation, two (nt, nb) arrays (NaN: a fixed base)."""
    nt = raw.displacement.shape[0]
    sway, rock = np.full((nt, nb), np.nan), np.full((nt, nb), np.nan)
    if system.outputs is not None:
        for b, (theta, u0) in enumerate(system.outputs.foundation):
            if theta >= 0:
                rock[:, b] = raw.displacement[:, theta]
                sway[:, b] = raw.displacement[:, u0]
    return sway, rock
