"""The rocking signature (``seispound/diagnose/signature.py``): the first-order foundation shift against exact
eigenvalues, and the band-limited stiffness change against synthetic records whose modal shift is known."""

import math

import numpy as np
import pytest
from scipy.linalg import eigh
from scipy.signal import lsim

from seispound.diagnose.signature import (
    Z_ROCKING,
    band_factors,
    foundation_shift,
    rocking_score,
    shear_modes,
)


def _flexible_base_omega2(m, k, h, kx, kt):
    """Exact omega^2 (lowest N) of a shear building on sway and rocking springs with a massless foundation.

    Floor displacements w_i relative to the free field, storey deformation w_i - w_(i-1) - h_i theta
    (w_0 = u0); the foundation's sway u0 and rocking theta carry no mass and are condensed out.
    """
    n = len(m)
    K = np.zeros((n + 2, n + 2))
    for s in range(n):
        b = np.zeros(n + 2)
        b[s] = 1.0
        b[s - 1 if s > 0 else n] -= 1.0
        b[n + 1] = -h[s]
        K += k[s] * np.outer(b, b)
    K[n, n] += kx
    K[n + 1, n + 1] += kt
    Kc = K[:n, :n] - K[:n, n:] @ np.linalg.solve(K[n:, n:], K[n:, :n])
    return eigh(Kc, np.diag(m), eigvals_only=True)


def test_one_storey_is_the_closed_form():
    # one storey on sway and rocking springs: 1 / w~^2 = 1 / w^2 + m / Kx + m h^2 / Kt (Veletsos & Meek 1974)
    m, k, h, kx, kt = 2.0e5, 3.0e8, 4.0, 5.0e9, 2.0e11
    d = foundation_shift([m], [k], [h], kx, kt)[0]
    w2 = k / m
    assert d == pytest.approx(w2 * (m / kx + m * h * h / kt), rel=1e-12)
    exact = 1.0 / (1.0 / w2 + m / kx + m * h * h / kt)
    assert _flexible_base_omega2([m], [k], [h], kx, kt)[0] == pytest.approx(exact, rel=1e-6)
    assert exact / w2 == pytest.approx(1.0 / (1.0 + d), rel=1e-12)


@pytest.mark.parametrize("kt_over_kx", [60.0, 1e6])
def test_first_order_shift_matches_exact_eigenvalues(kt_over_kx):
    # 8 storeys, 3 m, masses 1e5 kg, stiffness tapering 1.6e8 -> 1e8 N/m; springs stiff enough for d ~ 0.5-1 %
    m = np.full(8, 1.0e5)
    k = np.linspace(1.6e8, 1.0e8, 8)
    h = np.full(8, 3.0)
    kx = 2.0e10
    d = foundation_shift(m, k, h, kx, kt_over_kx * kx)
    w2 = shear_modes(m, k)[0] ** 2
    exact = 1.0 - _flexible_base_omega2(m, k, h, kx, kt_over_kx * kx) / w2
    assert 1e-3 < d[0] < 0.03
    np.testing.assert_allclose(d[:3], exact[:3], rtol=0.015)  # the error is second order in d (0.9 % at d = 0.9 %)


def test_rocking_lowers_the_first_mode_far_more_than_the_second():
    # the physics the signature rests on: sway alone shifts the modes alike (nearly), rocking the first far more
    m = np.full(8, 1.0e5)
    k = np.linspace(1.6e8, 1.0e8, 8)
    h = np.full(8, 3.0)
    sway = foundation_shift(m, k, h, 2.0e10, 1e30)
    rock = foundation_shift(m, k, h, 1e30, 1.2e12)
    assert 0.5 < sway[1] / sway[0] < 2.0
    assert rock[1] / rock[0] < 0.1


def _two_modes(f1, f2, c1, c2, t, ag):
    """Acceleration-like response: two modal oscillators (5 % damping) driven by ag, omega_j^2 scaled by c_j."""
    y = np.zeros_like(t)
    for f, c, g in ((f1, c1, 1.0), (f2, c2, 0.4)):
        w = 2 * math.pi * f * math.sqrt(c)
        sys_ = ([[0.0, 1.0], [-w * w, -2 * 0.05 * w]], [[0.0], [-g]], [[-w * w, -2 * 0.05 * w]], [[0.0]])
        y += lsim(sys_, ag, t)[1]
    return y


@pytest.mark.parametrize(("c1", "c2", "rocking"), [(1.0 - 0.004, 1.0, True), (1.0 - 0.004, 1.0 - 0.004, False),
                                                   (1.0, 1.0, False)])
def test_band_factors_find_the_modal_shift(c1, c2, rocking):
    dt, f1, f2 = 0.005, 1.5, 4.2
    t = np.arange(4001) * dt
    ag = np.random.default_rng(3).standard_normal(t.size)
    rec = _two_modes(f1, f2, c1, c2, t, ag)
    rec = rec + 0.01 * np.sqrt(np.mean(rec ** 2)) * np.random.default_rng(4).standard_normal(t.size)
    sim = _two_modes(f1, f2, 1.0, 1.0, t, ag)
    step = 0.003
    sens = (_two_modes(f1, f2, 1 + step, 1 + step, t, ag) - _two_modes(f1, f2, 1 - step, 1 - step, t, ag)) / (2 * step)
    fac = band_factors({"x": rec - sim}, {"x": sens}, dt, [(0.85 * f1, 1.15 * f1), (0.85 * f2, 1.15 * f2)])
    (d1, s1), (d2, s2) = fac
    assert d1 == pytest.approx(c1 - 1.0, abs=max(3 * s1, 3e-4))
    assert d2 == pytest.approx(c2 - 1.0, abs=max(3 * s2, 3e-4))
    z = rocking_score(fac)
    assert (z > Z_ROCKING) == rocking
    if rocking:
        assert z > 5.0  # a 0.4 % first-mode shift on 20 s of 1 % noise is plain to see
