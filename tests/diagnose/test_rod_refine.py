"""Rod floors refined for the recording's band: the segment rule, the refined table, the band and the polish's
keep-if-better step (``hypotheses/distributed_mass.py``, ``api._band_top``, ``api._refined``)."""

import copy
import math
import tomllib
from types import SimpleNamespace

import numpy as np
import pytest
from scipy.linalg import eigh

from seispound.diagnose import api
from seispound.diagnose.hypotheses import HYPOTHESES, REGISTRY, Context
from seispound.diagnose.hypotheses import distributed_mass as dm
from seispound.floor.rod import RodFloor
from tests._models import REPO


def _chain_frequencies(n, ea=1e10, length=20.0, mass=1e5):
    """Free-free axial frequencies [Hz] of a uniform lumped rod of n segments (half masses at the faces),
    assembled here from the segment stiffness EA n / L and the nodes' masses, not through RodFloor."""
    k = ea * n / length
    K = np.zeros((n + 1, n + 1))
    for s in range(n):
        K[s:s + 2, s:s + 2] += k * np.array([[1.0, -1.0], [-1.0, 1.0]])
    m = np.full(n + 1, mass / n)
    m[[0, -1]] *= 0.5
    return np.sqrt(np.maximum(eigh(K, np.diag(m), eigvals_only=True), 0.0))[1:] / (2.0 * math.pi)


def test_the_dispersion_formula_is_the_lumped_rods_eigenvalues():
    """Closed form (derived: omega_k = 2 (N c / L) sin(k pi / 2N)) against the eigenvalues of the assembled
    chain, for every mode of 4, 8 and 13 segments: round-off apart."""
    ea, length, mass = 1e10, 20.0, 1e5
    c_over_l = math.sqrt(ea * length / mass) / length
    for n in (4, 8, 13):
        f = _chain_frequencies(n, ea, length, mass)
        k = np.arange(1, n + 1)
        closed = 2.0 * n * c_over_l * np.sin(k * math.pi / (2 * n)) / (2.0 * math.pi)
        np.testing.assert_allclose(f, closed, rtol=1e-10)


@pytest.mark.parametrize("modes_in_band", [1.0, 1.5, 2.0, 2.7, 3.0])
def test_the_segments_chosen_hold_every_mode_in_the_band_within_the_stated_error(modes_in_band):
    """Every mode below the band's top within SEGMENT_ERROR of k times the rod's own first (the fit sets the
    first), from the assembled chain's eigenvalues; one segment fewer would not hold them (unless at the floor
    of SEGMENTS); beyond what MAX_SEGMENTS can hold, the cap."""
    ea, length, mass = 1e10, 20.0, 1e5
    f1 = math.sqrt(ea * length / mass) / length / 2.0  # the continuum's; the chain's own first is used below
    n = dm.segments_for(modes_in_band * f1, f1)
    k = np.arange(1, int(math.floor(modes_in_band + 1e-9)) + 1)

    def worst(segs):
        f = _chain_frequencies(segs, ea, length, mass)
        return float(np.max(1.0 - f[k - 1] / (k * f[0])))

    assert dm.SEGMENTS <= n <= dm.MAX_SEGMENTS
    if worst(n) <= dm.SEGMENT_ERROR:
        assert n == dm.SEGMENTS or worst(n - 1) > dm.SEGMENT_ERROR
    else:
        assert n == dm.MAX_SEGMENTS
    assert n == {1: 4, 2: 8, 3: 8}[int(k[-1])]  # 2 modes: cos(pi / 2N) >= 0.975 at N >= 7.01; 3 need 12


def _rod_table():
    base = tomllib.loads((REPO / "models" / "two_buildings.toml").read_text())
    aug, _, _ = HYPOTHESES["distributed-mass"].augment(base, 0)
    return aug


def _first_axial(table):
    out = []
    for b in table["building"]:
        rod = b["floor_model"]
        masses = b["floor_masses"] if isinstance(b["floor_masses"], list) else [b["floor_masses"]]
        f = RodFloor(**{k: rod[k] for k in ("segments", "length", "axial_stiffness", "centre_of_mass")})
        out.append(f.first_axial_omega(max(masses)) / (2.0 * math.pi))
    return min(out)


def test_finer_rods_follow_the_band_and_leave_a_fine_enough_rod_alone():
    table = _rod_table()
    f1 = _first_axial(table)
    assert dm._finer_rods(copy.deepcopy(table), None) is None
    assert dm._finer_rods(copy.deepcopy(table), Context()) is None
    assert dm._finer_rods(copy.deepcopy(table), Context(band_top_hz=1.6 * f1)) is None  # one mode: 4 suffice
    finer = dm._finer_rods(copy.deepcopy(table), Context(band_top_hz=2.2 * f1))  # two modes in the band
    assert finer is not None
    n = dm.segments_for(2.2 * f1, f1)
    assert n > dm.SEGMENTS
    assert {b["floor_model"]["segments"] for b in finer["building"]} == {n}
    for b, b0 in zip(finer["building"], table["building"]):  # EA, centre of mass, damping as fitted
        assert {k: v for k, v in b["floor_model"].items() if k != "segments"} == \
               {k: v for k, v in b0["floor_model"].items() if k != "segments"}
    assert dm._finer_rods(copy.deepcopy(finer), Context(band_top_hz=2.2 * f1)) is None  # refined once


def test_only_the_rod_form_refines():
    assert HYPOTHESES["distributed-mass"].refiner(0) is dm._finer_rods
    assert HYPOTHESES["distributed-mass"].refiner(1) is None
    for h in REGISTRY:
        assert len(h.refine) <= h.variants and all(r is None or callable(r) for r in h.refine)
        if h.name != "distributed-mass":
            assert all(h.refiner(k) is None for k in range(h.variants))


def test_the_band_top_reads_the_channels_that_hold_the_residual():
    mismatch = [{"band_hz": [0.0, 120.0], "residual_share": 0.6}, {"band_hz": [2.0, 290.0], "residual_share": 0.2},
                {"band_hz": [0.0, 480.0], "residual_share": 0.01}]  # a channel with 1 % of it does not count
    assert api._band_top(mismatch, 0.001) == 290.0
    assert api._band_top([{"band_hz": [0.0, 0.0], "residual_share": 1.0}], 0.005) == 100.0  # Nyquist


def test_the_polish_fits_each_screened_model_made_finer(monkeypatch):
    """``_polish`` fits each screened table made finer, then as screened (the finer first: where it explains the
    data, the coarse one is not needed), with the context, and goes on from the better."""
    import seispound.calibrate.fit as fit_mod

    fitted, seen = [], []

    def fake_fit(observer, params, **kw):
        fitted.append(copy.deepcopy(observer.model_data))
        dt = observer.model_data["analysis"]["dt"]
        return SimpleNamespace(ne_mean_after=0.02 if dt == 0.011 else 0.03, model_text=f'[analysis]\ndt = {dt}\n')

    def refine(table, context):
        seen.append(context)
        table["analysis"]["dt"] = 0.011
        return table

    monkeypatch.setattr(fit_mod, "calibrate_observer", fake_fit)
    ctx = Context(band_top_hz=100.0)
    texts = ['[analysis]\ndt = 0.01\n', '[analysis]\ndt = 0.012\n']
    out = api._polish(texts, ["analysis.dt=0.005:0.02"], ["analysis.dt=0.005:0.02"], REPO, [], [], 100,
                      refine=refine, context=ctx)
    assert out.ne_mean_after == 0.02 and out.model_text.endswith("0.011\n")  # the finer fitted better
    assert [t["analysis"]["dt"] for t in fitted] == [0.011, 0.01, 0.011, 0.012]
    assert len(seen) == 2 and all(c is ctx for c in seen)
    fitted.clear()
    out = api._polish(texts, ["analysis.dt=0.005:0.02"], ["analysis.dt=0.005:0.02"], REPO, [], [], 100,
                      enough=0.025, refine=refine, context=ctx)  # the finer explains the data: nothing more
    assert [t["analysis"]["dt"] for t in fitted] == [0.011]
    fitted.clear()
    api._polish(texts, ["analysis.dt=0.005:0.02"], ["analysis.dt=0.005:0.02"], REPO, [], [], 100,
                refine=lambda t, c: None, context=ctx)  # nothing to refine: the screened tables
    assert [t["analysis"]["dt"] for t in fitted] == [0.01, 0.012]
