"""The engineering peaks (floor acceleration, drift ratio, storey shear) against independent computations."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import seispound as sp
from seispound.simulation import prepare_ground_motion
from tests._models import short_copy


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("peaks")
    model = sp.load_model(short_copy(folder, 8.0))
    model.analysis.scheme = "newmark"  # compared with a dense Newmark below
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = sp.simulate(model)
    return model, ds


def _dense_newmark(b, ag, dt):
    """Average-acceleration Newmark on the dense M, C, K of one building (Chopra Table 5.4.2), written apart
    from the package's banded, modal kernel; returns relative u and absolute acceleration, (nt, n)."""
    M, K = b.mass_matrix(), b.stiffness_matrix()
    a0, a1 = b.rayleigh_coefficients()
    C = a0 * M + a1 * K
    n, nt = M.shape[0], ag.size
    u, v = np.zeros(n), np.zeros(n)
    r = np.ones(n)
    a = np.linalg.solve(M, -M @ r * ag[0] - C @ v - K @ u)
    khat = K + 2 / dt * C + 4 / dt ** 2 * M
    U, A = np.zeros((nt, n)), np.zeros((nt, n))
    A[0] = a + ag[0]
    for k in range(1, nt):
        p = -M @ r * ag[k] + M @ (4 / dt ** 2 * u + 4 / dt * v + a) + C @ (2 / dt * u + v)
        u1 = np.linalg.solve(khat, p)
        v1 = 2 / dt * (u1 - u) - v
        a = 4 / dt ** 2 * (u1 - u) - 4 / dt * v - a
        u, v = u1, v1
        U[k], A[k] = u, a + ag[k]
    return U, A


def test_no_pounding_peaks_equal_a_dense_newmark(run):
    model, ds = run
    ag, _ = prepare_ground_motion(model)
    dt = model.analysis.dt
    for b in model.buildings:
        U, A = _dense_newmark(b, ag, dt)
        n = b.n_floors
        sel = dict(building=b.name, floor=slice(1, n))
        np.testing.assert_allclose(ds.peak_acceleration_no_pounding.sel(**sel).values, np.abs(A).max(axis=0),
                                   rtol=1e-8)
        drift = np.diff(np.c_[np.zeros(U.shape[0]), U], axis=1)
        np.testing.assert_allclose(ds.peak_drift_ratio_no_pounding.sel(**sel).values,
                                   np.abs(drift).max(axis=0) / b.storey_heights, rtol=1e-8)
        np.testing.assert_allclose(ds.peak_storey_shear_no_pounding.sel(**sel).values,
                                   np.abs(drift * b.storey_stiffness).max(axis=0), rtol=1e-8)


def test_with_pounding_peaks_follow_from_the_histories(run):
    """Closed forms on the stored histories: shear = k x drift, drift ratio = drift / height."""
    model, ds = run
    for b in model.buildings:
        sel = dict(building=b.name, floor=slice(1, b.n_floors))
        drift = ds.drift.sel(**sel).values
        assert np.array_equal(ds.peak_acceleration.sel(**sel).values,
                              np.abs(ds.acceleration.sel(**sel).values).max(axis=0))
        np.testing.assert_allclose(ds.peak_drift_ratio.sel(**sel).values,
                                   np.abs(drift).max(axis=0) / b.storey_heights, rtol=1e-14)
        np.testing.assert_allclose(ds.peak_storey_shear.sel(**sel).values,
                                   np.abs(drift * b.storey_stiffness).max(axis=0), rtol=1e-14)
    for q in ("acceleration", "drift_ratio", "storey_shear"):
        np.testing.assert_allclose(ds[f"{q}_amplification"].values,
                                   ds[f"peak_{q}"].values / ds[f"peak_{q}_no_pounding"].values, rtol=1e-14)
    # pounding raises floor accelerations far more than displacements (short impact pulses)
    assert float(ds.acceleration_amplification.max()) > 2.0 * float(ds.amplification.max())


def test_periods_are_the_eigenvalues(run):
    model, ds = run
    for b in model.buildings:
        w2 = np.linalg.eigvals(np.linalg.solve(b.mass_matrix(), b.stiffness_matrix())).real
        np.testing.assert_allclose(ds.period.sel(building=b.name).values[:b.n_floors],
                                   np.sort(2 * np.pi / np.sqrt(w2))[::-1], rtol=1e-10)
        assert np.isnan(ds.period.sel(building=b.name).values[b.n_floors:]).all()
    assert ds.period.attrs["units"] == "s"


def test_without_twin_the_no_pounding_peaks_are_nan(tmp_path):
    model = sp.load_model(short_copy(tmp_path, 1.0))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = sp.simulate(model, twin=False)
    assert np.isnan(ds.peak_acceleration_no_pounding.values).all()
    assert np.isnan(ds.acceleration_amplification.values).all()
    assert np.isfinite(ds.peak_acceleration.sel(building="A", floor=slice(1, 4)).values).all()


@pytest.mark.parametrize("nt", [1, 63, 64, 65, 2001, 4096])
def test_folded_column_reduction_equals_numpy(nt):
    """The row-folded reduction behind the peaks gives numpy's values exactly, NaN included."""
    from seispound.results.peaks import _column_reduce, _peak_abs

    x = np.random.default_rng(nt).standard_normal((nt, 7))
    for uf in (np.maximum, np.minimum):
        np.testing.assert_array_equal(_column_reduce(uf, x), uf.reduce(x, axis=0))
    np.testing.assert_array_equal(_peak_abs(x), np.abs(x).max(axis=0))
    x[nt // 2, 3] = np.nan
    np.testing.assert_array_equal(_peak_abs(x), np.abs(x).max(axis=0))  # a NaN shows in its column only
    np.testing.assert_array_equal(_column_reduce(np.maximum, x[:, ::2]), x[:, ::2].max(axis=0))  # strided
