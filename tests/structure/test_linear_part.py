"""Seams of the linear part: dashpots that are not Rayleigh, and influence coefficients of the ground motion."""

import dataclasses
import math

import numpy as np
import pytest

from seispound.integrate import integrate
from seispound.structure import Building, NoDamping, assemble

M, K, ZETA, V0 = 1000.0, 4.0e5, 0.08, 0.3


def _sdof(**extra):
    s = assemble([Building("A", [M], [K], [3.0], NoDamping(), initial_velocity=V0)], [])
    return dataclasses.replace(s, **extra)


def _closed_form(t):
    """Damped free vibration from rest at u = 0 with velocity V0 (Chopra Eq. 2.2.4)."""
    w = math.sqrt(K / M)
    wd = w * math.sqrt(1 - ZETA**2)
    return V0 / wd * np.exp(-ZETA * w * t) * np.sin(wd * t)


@pytest.mark.parametrize("where", ["el_c", "dof_c"])
def test_a_dashpot_of_its_own_gives_the_damped_closed_form(where):
    c = 2 * ZETA * math.sqrt(K * M)
    s = _sdof(**{where: np.array([c])})
    assert s.damping_matrix()[0, 0] == pytest.approx(c, rel=1e-14)
    dt, n = 0.002, 1000
    t = np.arange(n + 1) * dt
    exact = integrate(s, np.zeros(n + 1), dt, n, scheme="exact").displacement[:, 0]
    newmark = integrate(s, np.zeros(20 * n + 1), 1e-4, 20 * n, scheme="newmark").displacement[::20, 0]
    ref = _closed_form(t)
    scale = np.abs(ref).max()
    print(f"MEASURED {where}: exact scheme {np.abs(exact - ref).max() / scale:.1e}, "
          f"Newmark dt = 1e-4 {np.abs(newmark - ref).max() / scale:.1e} of the peak")
    assert np.abs(exact - ref).max() <= 1e-10 * scale
    assert np.abs(newmark - ref).max() <= 1e-4 * scale


def test_an_element_dashpot_needs_a_spring():
    s = _sdof(el_c=np.array([10.0]), el_k=np.array([0.0]))
    with pytest.raises(ValueError, match="spring in parallel"):
        s.kernel_damping()


@pytest.mark.parametrize("scheme", ["exact", "newmark"])
def test_influence_coefficients_scale_the_ground_load(scheme):
    from tests.verification._helpers import el_centro, shear_building

    base = assemble([shear_building("A", 3, 0.3), shear_building("B", 2, 0.2)], [])
    ag, n = el_centro(4.0, 0.005)
    one = integrate(base, ag, 0.005, n, scheme=scheme)
    infl = np.array([0.5, 0.5, 0.5, 0.0, 0.0])  # A at half the motion, B a "rotation" the ground does not load
    half = integrate(dataclasses.replace(base, dof_influence=infl), ag, 0.005, n, scheme=scheme)
    np.testing.assert_allclose(half.displacement[:, :3], 0.5 * one.displacement[:, :3], rtol=1e-12,
                               atol=1e-12 * np.abs(one.displacement).max())
    assert np.all(half.displacement[:, 3:] == 0.0)
    # absolute acceleration: relative + influence x ground
    np.testing.assert_allclose(half.acceleration[:, :3], 0.5 * one.acceleration[:, :3], rtol=1e-10,
                               atol=1e-10 * np.abs(one.acceleration).max())
