"""A hysteretic storey's state along a free-flight step's cubic path (``_material.bilinear_path``,
``bouc_wen_path``) against the law stepped through the material protocol at 20 000 points of the same path.

The reference knows nothing of turning points: it moves the law from sample to sample (``material_trial``
from the committed state, then commit), which is exact for the bilinear law between samples where the
path is monotonic, and leaves an error of the order of the path's curvature times the sample spacing
squared where it turns.  A regression guard of the paths' splitting, and a check of the bilinear path's
return map, not a verification of the laws (``tests/verification/test_yielding_storeys.py`` does that).
"""

import numpy as np
import pytest

from seispound.integrate._material import (N_STATE, ST_DELTA, ST_PLASTIC, ST_Q, ST_Z, bilinear_path, bouc_wen_advance,
                                           bouc_wen_path, material_commit, material_trial)
from seispound.storey import StoreyLaw

K, DY, ALPHA = 2.0e7, 0.01, 0.05  # N/m, m, -


def _rows(kind):
    law = StoreyLaw(kind=kind, yield_drift=DY, post_yield_ratio=ALPHA, n=2.0 if kind == "bouc-wen" else None)
    code, par = law.kernel_rows([K], 44)
    return int(code[0]), par[:1].copy()


def _sampled(kind, state, d0, ca, cb, cc, n=20000):
    """z [m] at tau = 0.5 and 1 and the largest |z| reached, the law stepped along the path's samples."""
    code, par = _rows(kind)
    committed, trial = state.copy(), state.copy()
    zs = {}
    tau = np.linspace(0.0, 1.0, n + 1)
    path = d0 + tau * (ca + tau * (cb + tau * cc))
    for i in range(1, n + 1):
        material_trial(code, par, committed, trial, 0, path[i], 0.0)
        material_commit(committed, trial, 0)
        if i in (n // 2, n):
            zs[i] = committed[0, ST_Q] / K if kind == "bilinear" else committed[0, ST_Z]
    return zs[n // 2], zs[n]


# (d0, ca, cb, cc) [m]: monotonic; one turning point, the smaller root of delta' outside (0, 1); one, the larger
# outside; two inside
PATHS = {"monotonic": (0.0, 0.004, 0.001, -0.0005),
         "turn-larger-root": (0.0, 0.006, -0.001, -0.004),  # delta' = 0.006 - 0.002 t - 0.012 t^2: t = 0.625
         "turn-smaller-root": (0.0, -0.006, 0.001, 0.004),
         "two-turns": (0.0, 0.003, -0.012, 0.008)}


def _state(kind, z0, d0):
    s = np.zeros((1, N_STATE))
    if kind == "bilinear":
        s[0, ST_Q], s[0, ST_PLASTIC] = K * z0, d0 - z0
    else:
        s[0, ST_Z], s[0, ST_DELTA] = z0, d0
    return s


@pytest.mark.parametrize("name", list(PATHS))
@pytest.mark.parametrize("z0", [0.0, 0.6 * DY, DY, -DY])
def test_bilinear_path_equals_the_law_stepped_along_it(name, z0):
    d0, ca, cb, cc = PATHS[name]
    code, par = _rows("bilinear")
    zm, z1, pm, p1, onset = bilinear_path(par, 0, z0, d0, ca, cb, cc)
    ref_m, ref_1 = _sampled("bilinear", _state("bilinear", z0, d0), d0, ca, cb, cc)
    print(f"MEASURED {name} z0={z0}: |zm - ref| {abs(zm - ref_m):.1e}, |z1 - ref| {abs(z1 - ref_1):.1e} m")
    assert abs(zm - ref_m) <= 1e-11 and abs(z1 - ref_1) <= 1e-11  # measured <= 2.5e-12 (sampling at the turns)
    assert abs(z1) <= DY * (1 + 1e-12)
    assert p1 == (0.0 if abs(z1) >= DY and (ca + 2 * cb + 3 * cc) * z1 > 0 else 1.0)


def test_bilinear_path_says_when_it_yields_from_inside():
    code, par = _rows("bilinear")
    assert bilinear_path(par, 0, 0.0, 0.0, 0.02, 0.0, 0.0)[4]  # 0 -> 2 dy: a kink in c(t)
    assert not bilinear_path(par, 0, DY, 0.0, 0.02, 0.0, 0.0)[4]  # on the surface, loading on
    assert not bilinear_path(par, 0, 0.0, 0.0, 0.005, 0.0, 0.0)[4]  # within the elastic range
    assert bilinear_path(par, 0, DY, 0.0, -0.025, 0.0, 0.0)[4]  # unloads through to -dy


@pytest.mark.parametrize("name", list(PATHS))
def test_bouc_wen_path_equals_the_law_stepped_along_it(name):
    """The paths at a quarter of the size above (spans of about 0.1 dy, a 5 ms step's); the larger root alone
    inside (0, 1) was once taken for a monotonic step, z advanced over the net span in one piece: 4.0e-3 dy
    off at the step's end here, 2000 times the error of the path cut at its turning point."""
    d0, ca, cb, cc = (0.25 * c for c in PATHS[name])
    code, par = _rows("bouc-wen")
    z0 = 0.3 * DY
    zm, z1, _, _, _ = bouc_wen_path(par, 0, z0, 0.0, d0, ca, cb, cc)
    ref_m, ref_1 = _sampled("bouc-wen", _state("bouc-wen", z0, d0), d0, ca, cb, cc)
    one_piece = bouc_wen_advance(par, 0, z0, 0.0, ca + cb + cc)[0]
    print(f"MEASURED {name}: |zm - ref| {abs(zm - ref_m) / DY:.1e} dy, |z1 - ref| {abs(z1 - ref_1) / DY:.1e} dy; "
          f"as one piece {abs(one_piece - ref_1) / DY:.1e} dy")
    assert abs(zm - ref_m) <= LIMIT_M[name] * DY and abs(z1 - ref_1) <= LIMIT_1[name] * DY
    if name != "monotonic":  # the test sees the error of a path taken as monotonic
        assert abs(one_piece - ref_1) >= 20 * LIMIT_1[name] * DY


# limits on |zm - ref|, |z1 - ref| [dy], about 3 times the measured (the law's sub-increments of 0.02 dy against the
# samples' finer ones): monotonic 3.4e-6, 3.5e-6; turn-larger-root 2.0e-6, 2.0e-6 (as one piece: 4.0e-3 at the
# end); turn-smaller-root 1.3e-15, 1.3e-6 (2.3e-3); two-turns 1.5e-8, 3.2e-8 (8.6e-4)
LIMIT_M = {"monotonic": 1e-5, "turn-larger-root": 6e-6, "turn-smaller-root": 1e-6, "two-turns": 5e-8}
LIMIT_1 = {"monotonic": 1e-5, "turn-larger-root": 6e-6, "turn-smaller-root": 4e-6, "two-turns": 1e-7}


@pytest.mark.parametrize("n", [1.37, 2.7, 8.0, 60.5])
def test_power_carried_by_its_series_equals_the_power(n):
    """``_bouc_wen_power_near`` (|z/dy|^n carried from a nearby z0's by the binomial series) against the power in
    extended precision (numpy's longdouble), the start xn0 given to double precision: closed form.  The
    series is as close as a double can be: worst 6.9e-16, 6.3e-16, 6.3e-16 and 6.9e-16 of it at n = 1.37, 2.7, 8
    and 60.5 (``_bouc_wen_power``'s exp((n - 1) ln x): 4.8e-16 to 9.0e-15 at n up to 8); the limit 1.5e-15."""
    from seispound.integrate._material import BW_SERIES_REACH, _bouc_wen_power_near

    rng = np.random.default_rng(7)
    worst = 0.0
    for _ in range(20000):
        z0 = rng.uniform(-1.5, 1.5) * DY
        r = rng.choice([1e-12, 1e-8, 1e-5, min(1e-3, BW_SERIES_REACH / n), min(BW_SERIES_REACH, 2 * BW_SERIES_REACH / n)]) * rng.uniform(-1, 1)
        z = z0 * (1.0 + r)
        x0, x = np.longdouble(abs(z0)) / np.longdouble(DY), np.longdouble(abs(z)) / np.longdouble(DY)
        xn, dxn = _bouc_wen_power_near(z, DY, n, z0, float(x0 ** np.longdouble(n)))
        exact = x ** np.longdouble(n)
        dexact = np.longdouble(n) * exact / np.longdouble(z)
        worst = max(worst, float(abs(xn - exact) / exact), float(abs(dxn - dexact) / abs(dexact)))
    print(f"MEASURED n={n}: series against the power, worst {worst:.1e} of it")
    assert worst <= 1.5e-15


def test_gaussian_carried_by_its_series_equals_the_exponential():
    """``_gauss_near`` (the pinching function's exp(-(z/w)^2) carried from a nearby z0's by the exponential
    series) against the exponential in extended precision, the start given to double precision: closed form.
    Measured at most 6.4e-16 of it; the limit 1.5e-15."""
    from seispound.integrate._material import BW_SERIES_REACH, _gauss_near

    rng = np.random.default_rng(11)
    width, worst = 0.3 * DY, 0.0
    for _ in range(20000):
        z0 = rng.uniform(-1.5, 1.5) * DY
        a = rng.choice([1e-12, 1e-8, 1e-5, 1e-3, BW_SERIES_REACH]) * rng.uniform(-1.0, 1.0)
        z = np.sign(z0) * np.sqrt(max(z0 * z0 + a * width * width, 0.0))
        w = np.longdouble(width)
        e0 = float(np.exp(-(np.longdouble(z0) / w) ** 2))
        if e0 == 0.0:
            continue
        exact = np.exp(-(np.longdouble(z) / w) ** 2)
        worst = max(worst, float(abs(_gauss_near(z, width, z0, e0) - exact) / exact))
    print(f"MEASURED the Gaussian's series against the exponential, worst {worst:.1e} of it")
    assert worst <= 1.5e-15


# at n = 2.7 (a fit's exponent: the power carried by its series along the path), limits on |zm - ref|, |z1 - ref|
# [dy] about 3 times the measured: monotonic 2.7e-6, 5.6e-6; turn-larger-root 2.8e-6, 2.8e-6; turn-smaller-root
# 1.3e-15, 1.4e-6; two-turns 2.0e-8, 3.9e-8 (the law's sub-increments against the samples', as at n = 2)
LIMITS_N27 = {"monotonic": (8e-6, 1.7e-5), "turn-larger-root": (8.4e-6, 8.4e-6),
              "turn-smaller-root": (4e-15, 4.2e-6), "two-turns": (6e-8, 1.2e-7)}


@pytest.mark.parametrize("name", list(PATHS))
def test_bouc_wen_path_at_a_non_integer_exponent_equals_the_law_stepped_along_it(name):
    d0, ca, cb, cc = (0.25 * c for c in PATHS[name])
    law = StoreyLaw(kind="bouc-wen", yield_drift=DY, post_yield_ratio=ALPHA, n=2.7)
    code, par = law.kernel_rows([K], 44)
    code, par = int(code[0]), par[:1].copy()
    z0 = 0.3 * DY
    zm, z1, _, _, _ = bouc_wen_path(par, 0, z0, 0.0, d0, ca, cb, cc)
    committed = _state("bouc-wen", z0, d0)
    trial = committed.copy()
    tau = np.linspace(0.0, 1.0, 20001)
    path = d0 + tau * (ca + tau * (cb + tau * cc))
    ref = {}
    for i in range(1, tau.size):
        material_trial(code, par, committed, trial, 0, path[i], 0.0)
        material_commit(committed, trial, 0)
        ref[i] = committed[0, ST_Z]
    err_m, err_1 = abs(zm - ref[10000]) / DY, abs(z1 - ref[20000]) / DY
    print(f"MEASURED {name}, n = 2.7: |zm - ref| {err_m:.1e} dy, |z1 - ref| {err_1:.1e} dy")
    assert err_m <= LIMITS_N27[name][0] and err_1 <= LIMITS_N27[name][1]
