"""Masses on several DOFs (coupled mass blocks) in the general driver.

A building on a flexible foundation is written twice: as the assembly writes it (floors relative to the
free field: diagonal mass, storeys on three DOFs), and by hand in coordinates relative to the foundation
(x_i, u0, theta: each floor a mass block on (x_i, u0, theta) with coefficients (1, 1, z_i), diagonal
storey springs).  Newmark-beta is invariant under a constant linear change of coordinates, so the two
runs must give the same floor motion w_i = x_i + u0 + z_i theta to round-off.
"""

import numpy as np

from seispound.foundation import Foundation
from seispound.integrate import integrate
from seispound.structure import Building, NoDamping, SystemArrays, assemble
from tests.verification._helpers import el_centro

M, K, H, N = 1e5, 1.2e8, 3.0, 3
M0, I0, KX, KT, CX, CT = 3e5, 8e6, 6e8, 3e10, 4e6, 1e8


def _relative_system() -> SystemArrays:
    """DOFs 0..N-1: x_i (relative to the foundation's rigid motion), N: u0, N+1: theta."""
    n = N + 2
    z = H * np.arange(1, N + 1)
    el_i = np.array(list(range(N)) + [N, N + 1])
    el_j = np.array([-1] + list(range(N - 1)) + [-1, -1])
    return SystemArrays(
        mass=np.array([0.0] * N + [M0, I0]), dof_building=np.zeros(n, np.int64),
        dof_floor=np.array(list(range(1, N + 1)) + [0, 0]), dof_motion=np.zeros(n, np.int64),
        dof_a0=np.zeros(n), el_i=el_i, el_j=el_j, el_k=np.array([K] * N + [KX, KT]), el_a1=np.zeros(N + 2),
        bandwidth=1, u0=np.zeros(n), v0=np.zeros(n), gap_i=np.zeros(0, np.int64), gap_j=np.zeros(0, np.int64),
        gap_size=np.zeros(0), gap_law=np.zeros(0, np.int64), gap_par=np.zeros((0, 44)), links=[],
        el_c=np.array([0.0] * N + [CX, CT]), dof_influence=np.array([0.0] * N + [1.0, 0.0]),
        mass_blocks=[((i, N, N + 1), (1.0, 1.0, z[i]), M) for i in range(N)])


def test_mass_blocks_reproduce_the_total_coordinate_building():
    dt, (ag, nsteps) = 0.005, el_centro(8.0, 0.005)
    f = Foundation(mass=M0, rotary_inertia=I0, sway_stiffness=KX, sway_damping=CX, rocking_stiffness=KT,
                   rocking_damping=CT)
    total = assemble([Building("A", [M] * N, [K] * N, [H] * N, NoDamping(), foundation=f)], [])
    rel = _relative_system()
    assert rel.needs_general_driver
    a = integrate(total, ag, dt, nsteps)
    b = integrate(rel, ag, dt, nsteps)
    z = H * np.arange(1, N + 1)
    w_rel = b.displacement[:, :N] + b.displacement[:, [N]] + b.displacement[:, [N + 1]] * z
    w_tot = a.displacement[:, 2:]  # total: theta, u0, then the floors
    err = float(np.abs(w_rel - w_tot).max() / np.abs(w_tot).max())
    err_found = float(np.abs(b.displacement[:, [N, N + 1]] - a.displacement[:, [1, 0]]).max()
                      / np.abs(a.displacement[:, [1, 0]]).max())
    e_a, e_b = a.energy[-1], b.energy[-1]
    print(f"MEASURED coupled mass blocks against the diagonal-mass formulation: floors {err:.1e}, foundation "
          f"{err_found:.1e}, input energy {e_b[0] / e_a[0] - 1:+.1e}")
    assert err <= 1e-10 and err_found <= 1e-10
    assert abs(e_b[0] / e_a[0] - 1) <= 1e-10
    M_rel = rel.matrices()[0]
    assert not np.allclose(M_rel, np.diag(np.diag(M_rel)))  # the mass matrix is coupled
