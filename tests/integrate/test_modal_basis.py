"""The modal basis behind the free-flight blocks (``seispound.integrate.modal``)."""

import dataclasses

import numpy as np
from scipy.linalg import eigh

from seispound.contact import make_law
from seispound.structure import Gap, assemble
from seispound.integrate.modal import modal_basis
from tests.verification._helpers import shear_building


def row():
    bs = [shear_building("A", 4, 0.5), shear_building("B", 7, 0.9, ratio=0.03, modes=(1, 3)),
          shear_building("C", 1, 0.3, mass=2e4, ratio=0.0)]
    return assemble(bs, [Gap(("A", "B"), 0.02), Gap(("B", "C"), 0.01)], make_law("Hd", stiffness=2.75e9, restitution=0.65))


def test_blocks_are_the_buildings_and_the_modes_are_mass_normalised():
    s = row()
    b = modal_basis(s)
    assert b is not None
    assert b.start.tolist() == [0, 4, 11, 12]
    K, C, M = s.stiffness_matrix(), s.damping_matrix(), np.diag(s.mass)
    phi = b.phi_t.T  # Phi, block diagonal
    assert np.allclose(phi.T @ M @ phi, np.eye(s.n_dof), atol=1e-12)
    assert np.allclose(phi.T @ K @ phi, np.diag(b.omega2), rtol=1e-10, atol=1e-10 * b.omega2.max())
    cq = phi.T @ C @ phi
    assert np.max(np.abs(cq - np.diag(np.diag(cq)))) <= 1e-9 * np.max(np.abs(cq))
    assert np.allclose(np.diag(cq), b.c, rtol=1e-10)
    assert np.allclose(b.phi_tm, phi.T @ M, rtol=0, atol=1e-15 * np.abs(b.phi_tm).max())
    # frequencies: the generalized eigenvalues of each building on its own
    w2 = np.sort(np.concatenate([eigh(K[o:e, o:e], M[o:e, o:e], eigvals_only=True)
                                 for o, e in ((0, 4), (4, 11), (11, 12))]))
    assert np.allclose(np.sort(b.omega2), w2, rtol=1e-12)
    # Rayleigh: 2 xi omega at the anchor modes equals 2 * ratio * omega
    wA = np.sqrt(b.omega2[:4])
    assert abs(b.c[0] / (2 * wA[0]) - 0.05) < 1e-9


def test_participation_adds_up_to_the_mass_of_each_motion():
    """Sum_j Gamma_rj^2 = iota_r^T M iota_r for mass-normalised modes (Chopra Eq. 13.2.13)."""
    s = row()
    b = modal_basis(s)
    motion = np.array([0] * 4 + [1] * 7 + [0])
    gam = b.participation(s.mass, motion, 2)
    assert gam.shape == (2, s.n_dof)
    assert np.isclose(np.sum(gam[0] ** 2), s.mass[motion == 0].sum(), rtol=1e-12)
    assert np.isclose(np.sum(gam[1] ** 2), s.mass[motion == 1].sum(), rtol=1e-12)
    assert np.all(gam[1, :4] == 0.0) and np.all(gam[0, 4:11] == 0.0)


def test_non_classical_damping_and_rigid_bodies_have_no_basis():
    s = row()
    a0 = s.dof_a0.copy()
    a0[5] *= 3.0  # one floor with its own mass-proportional damping: C no longer classical
    assert modal_basis(dataclasses.replace(s, dof_a0=a0)) is None
    k = s.el_k.copy()
    k[0] = 0.0  # building A loose from the ground: a rigid-body mode
    assert modal_basis(dataclasses.replace(s, el_k=k)) is None
