"""The exact modal step: scipy's matrix exponential, Chopra's closed form, and a free and a forced oscillator."""

import math

import numpy as np
import pytest
from scipy.linalg import expm

from seispound.integrate._exact import exact_coefficients


def _ours(w, zeta, h):
    out = np.empty((8, 1))
    exact_coefficients(np.array([w * w]), np.array([2 * zeta * w]), h, out)
    return out[:, 0]


@pytest.mark.parametrize("w, zeta, h", [(2 * math.pi, 0.05, 0.005), (300.0, 0.05, 0.005), (3000.0, 1.7, 0.005),
                                        (1.0, 0.02, 1e-7), (60.0, 0.0, 0.01)])
def test_against_scipy_expm(w, zeta, h):
    M = np.array([[0, 1, 0, 0], [-w * w, -2 * zeta * w, 1, 0], [0, 0, 0, 1], [0, 0, 0, 0.0]]) * h
    E = expm(M)
    ref = [E[0, 0], E[0, 1], E[1, 0], E[1, 1], E[0, 2] - E[0, 3] / h, E[1, 2] - E[1, 3] / h, E[0, 3] / h,
           E[1, 3] / h]
    np.testing.assert_allclose(_ours(w, zeta, h), ref, rtol=1e-11, atol=1e-14 * max(1.0, abs(E).max()))


@pytest.mark.parametrize("w", [0.5, 6.0, 60.0, 600.0])
@pytest.mark.parametrize("zeta", [0.0, 0.05, 1.5])
@pytest.mark.parametrize("h", [1e-7, 1e-5, 1e-4, 1e-3])
def test_short_steps_against_scipy_expm(w, zeta, h):
    """The parts of a step located around events: w h << 1, where the series stops after fewer terms."""
    test_against_scipy_expm(w, zeta, h)


def test_against_chopra_table_5_2_1():
    """Chopra, Dynamics of Structures, Table 5.2.1 (m = 1, k = w^2, zeta < 1)."""
    w, z, h = 2 * math.pi / 0.3, 0.05, 0.01
    wd = w * math.sqrt(1 - z * z)
    ex = math.exp(-z * w * h)
    s, c = math.sin(wd * h), math.cos(wd * h)
    r = z / math.sqrt(1 - z * z)
    k = w * w
    A = ex * (r * s + c)
    B = ex * s / wd
    C = (2 * z / (w * h) + ex * (((1 - 2 * z * z) / (wd * h) - r) * s - (1 + 2 * z / (w * h)) * c)) / k
    D = (1 - 2 * z / (w * h) + ex * ((2 * z * z - 1) / (wd * h) * s + 2 * z / (w * h) * c)) / k
    Ap = -ex * w / math.sqrt(1 - z * z) * s
    Bp = ex * (c - r * s)
    Cp = (-1 / h + ex * ((w / math.sqrt(1 - z * z) + z / (h * math.sqrt(1 - z * z))) * s + c / h)) / k
    Dp = (1 - ex * (r * s + c)) / (k * h)
    np.testing.assert_allclose(_ours(w, z, h), [A, B, Ap, Bp, C, Cp, D, Dp], rtol=1e-10)


def _scipy(w, zeta, h):
    M = np.array([[0, 1, 0, 0], [-w * w, -2 * zeta * w, 1, 0], [0, 0, 0, 1], [0, 0, 0, 0.0]]) * h
    E = expm(M)
    return np.array([E[0, 0], E[0, 1], E[1, 0], E[1, 1], E[0, 2] - E[0, 3] / h, E[1, 2] - E[1, 3] / h,
                     E[0, 3] / h, E[1, 3] / h])


@pytest.mark.parametrize("wh", [0.0, 1e-6, 1e-3, 0.03, 0.1, 0.2])
@pytest.mark.parametrize("zeta", [0.0, 0.05, 0.5])
@pytest.mark.parametrize("h", [1e-6, 1e-3, 0.02])
def test_two_scalar_series_against_scipy_expm(wh, zeta, h):
    """The short-step series (Cayley-Hamilton, two scalars) gives each of the eight coefficients to
    round-off: relative 1e-13 of the entry, against scipy's Pade exponential of the 4 x 4 matrix."""
    from seispound.integrate._exact import _series

    w = wh / h
    out = np.empty((8, 1))
    _series(w * w, 2 * zeta * w, h, out, 0)
    ref = _scipy(w, zeta, h) if w > 0 else np.array([1, h, 0, 1, h * h / 3, h / 2, h * h / 6, h / 2])
    np.testing.assert_allclose(out[:, 0], ref, rtol=1e-13, atol=1e-300)


@pytest.mark.parametrize("w, c, h", [(2.0, 300.0, 5e-4), (1e-3, 40.0, 4e-3)])
def test_two_scalar_series_overdamped(w, c, h):
    """Over-damped modes (c h up to 0.2) take the series too, to round-off."""
    from seispound.integrate._exact import _series

    out = np.empty((8, 1))
    _series(w * w, c, h, out, 0)
    np.testing.assert_allclose(out[:, 0], _scipy(w, c / (2 * w), h), rtol=1e-13, atol=1e-300)


@pytest.mark.parametrize("wh", [1e-6, 1e-3, 0.1, 2.0])
@pytest.mark.parametrize("zeta", [0.05, 1.5])
def test_four_by_four_exponential_against_scipy_expm(wh, zeta):
    """The general path (the 4 x 4 exponential, which over-damped modes with long steps take), also on
    the short steps the series now serves, where its Taylor series stops early."""
    from seispound.integrate._exact import _exponential

    h = 1e-3
    w = wh / h
    out = np.empty((8, 1))
    _exponential(w * w, 2 * zeta * w, h, out, 0)
    np.testing.assert_allclose(out[:, 0], _scipy(w, zeta, h), rtol=1e-11, atol=1e-14 * max(1.0, w * w * h))
