"""Response spectra (seispound.spectra, pyrotd) against a closed form and an independent solve_ivp oscillator."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import seispound as sp
from seispound import InputError
from seispound.motion import read_record
from seispound.spectra import floor_spectrum, response_spectrum
from tests._models import REPO, short_copy

RECORD = REPO / "ground_motions" / "RSN6_IMPVALL.I_I-ELC180-hor1.AT2"


def _oscillator_psa(t, a, period, xi=0.05):
    """omega^2 max|u| of u'' + 2 xi w u' + w^2 u = -a(t), a piecewise linear then zero (DOP853, rtol 1e-8)."""
    w = 2 * math.pi / period

    def rhs(tt, y):
        ag = np.interp(tt, t, a) if tt <= t[-1] else 0.0
        return [y[1], -ag - 2 * xi * w * y[1] - w * w * y[0]]

    sol = solve_ivp(rhs, (0.0, t[-1] + 6 * period), [0.0, 0.0], method="DOP853", rtol=1e-8, atol=1e-11,
                    max_step=min(t[1] - t[0], period / 10))
    return w * w * np.abs(sol.y[0]).max()


def test_record_spectrum_against_an_independent_oscillator():
    """El Centro 180: worst measured difference 0.62 % (T = 0.2 s); the two read the record differently between
    samples (band-limited in pyrotd's frequency-domain method, piecewise linear in the reference)."""
    rec = read_record(RECORD)
    periods = np.array([0.1, 0.2, 1.0, 5.0])
    psa = response_spectrum(rec, periods=periods)
    ref = np.array([_oscillator_psa(rec.time, rec.acceleration, T) for T in periods])
    np.testing.assert_allclose(psa.values, ref, rtol=0.01)
    assert psa.attrs["units"] == "m/s^2" and psa.attrs["damping"] == 0.05 and "pyrotd" in psa.attrs["method"]
    # a very stiff oscillator moves with the ground: PSA(0.02 s) -> PGA (0.2808 g in the PEER header)
    assert response_spectrum(rec, periods=[0.02]).item() == pytest.approx(0.2808 * 9.80665, rel=0.02)


def test_harmonic_resonance_closed_form():
    """A sine of amplitude A at the oscillator's own frequency, 60 cycles: steady state u0 = A / (2 xi w^2),
    so PSA -> A / (2 xi) (Chopra, Dynamics of Structures, Sec. 3.2: R_d = 1 / (2 xi) at resonance), reached to exp(-xi w t)."""
    T, xi, amp = 0.5, 0.05, 1.0
    dt = T / 200
    t = np.arange(0, 60 * T, dt)
    psa = response_spectrum(amp * np.sin(2 * math.pi * t / T), dt, periods=[T], damping=xi)
    transient = math.exp(-xi * 2 * math.pi * 60)  # 6.5e-9
    assert float(psa.values[0]) == pytest.approx(amp / (2 * xi), rel=2e-3 + transient)


def test_floor_spectrum_of_a_result(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = sp.simulate(sp.load_model(short_copy(tmp_path, 6.0)))
    periods = np.array([0.1, 0.5, 1.0])
    roof = floor_spectrum(ds, "A", 4, periods)
    ref = response_spectrum(ds.acceleration.sel(building="A", floor=4).values, float(ds.attrs["dt"]), periods)
    np.testing.assert_array_equal(roof.values, ref.values)
    ground = floor_spectrum(ds, "A", 0, periods)
    np.testing.assert_array_equal(ground.values,
                                  response_spectrum(ds.ground_acceleration.values, 0.005, periods).values)
    assert roof.attrs["building"] == "A" and roof.attrs["floor"] == 4
    # the roof of a building with T1 = 0.5 s amplifies the ground near 0.5 s
    assert roof.sel(period=0.5).item() > 2 * ground.sel(period=0.5).item()
    with pytest.raises(InputError, match="building A has no floor 5"):
        floor_spectrum(ds, "A", 5, periods)
    with pytest.raises(InputError, match="no building 'Q'"):
        floor_spectrum(ds, "Q", 1, periods)


@pytest.mark.parametrize("kwargs, key", [
    (dict(motion=np.zeros(5), dt=0.0), "dt"),
    (dict(motion=np.zeros(5), dt=0.01, periods=[0.1, -1.0]), "periods"),
    (dict(motion=np.zeros(5), dt=0.01, damping=1.0), "damping"),
    (dict(motion=np.array([0.0, np.nan, 1.0]), dt=0.01), "motion"),
])
def test_bad_arguments(kwargs, key):
    with pytest.raises(InputError) as info:
        response_spectrum(**kwargs)
    assert info.value.key == key


def test_spectrum_figure_from_the_command_line(tmp_path):
    from seispound import cli
    from seispound.plot import spectra_figure

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = sp.simulate(sp.load_model(short_copy(tmp_path, 4.0)))
    sp.write_result(ds, tmp_path / "r.h5")
    assert cli.main(["plot", str(tmp_path / "r.h5"), "--kind", "spectrum", "--floors", "A:4", "-o",
                     str(tmp_path / "spec")]) == 0
    assert (tmp_path / "spec.png").stat().st_size > 10_000 and (tmp_path / "spec.svg").exists()
    roof = floor_spectrum(ds, "A", 4)
    fig = spectra_figure([("A floor 4", roof)])
    (line,) = fig.axes[0].get_lines()
    np.testing.assert_array_equal(line.get_ydata(), roof.values / 9.80665)
    assert fig.axes[0].get_title() == "Pseudo-acceleration response spectra, 5% damping"
