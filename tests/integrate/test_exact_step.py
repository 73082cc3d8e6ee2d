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
