"""Storey laws in the model: parsing, per-storey values, their kernel rows, and what a run stores."""

import numpy as np
import pytest

from seispound import simulate
from seispound.contact.codes import N_PAR
from seispound.model import load_model
from seispound.storey import StoreyLaw
from seispound.storey import codes as C
from tests._models import short_copy


def test_kernel_rows_per_storey_and_from_yield_force():
    law = StoreyLaw(kind="bilinear", yield_force=[2e5, 1e5], post_yield_ratio=[0.1, 0.0])
    law.validate(2)
    codes, par = law.kernel_rows([2e7, 1e7], N_PAR)
    assert list(codes) == [C.BILINEAR] * 2
    np.testing.assert_array_equal(par[:, C.B_K], [2e7, 1e7])
    np.testing.assert_array_equal(par[:, C.B_FY], [2e5, 1e5])
    np.testing.assert_array_equal(par[:, C.B_ALPHA], [0.1, 0.0])
    np.testing.assert_allclose(law.yield_drifts([2e7, 1e7]), [0.01, 0.01])
    bw = StoreyLaw(kind="bouc-wen", yield_drift=0.02, n=3, beta=0.6, gamma=0.4)
    bw.validate(1)
    codes, par = bw.kernel_rows([5e6], N_PAR)
    assert codes[0] == C.BOUC_WEN
    assert tuple(par[0, [C.BW_K, C.BW_DY, C.BW_N, C.BW_BETA, C.BW_GAMMA]]) == (5e6, 0.02, 3, 0.6, 0.4)


def test_elastic_kind_leaves_the_fast_driver(tmp_path):
    from seispound.structure import assemble

    model = load_model(short_copy(tmp_path, 1.0))
    model.buildings[0].storey_law = StoreyLaw(kind="elastic")
    model.buildings[0].validate()
    assert not assemble(model.buildings, model.gaps, model.contact).needs_general_driver


def test_yielding_model_runs_and_stores_what_yielding_adds(tmp_path):
    model = load_model(short_copy(tmp_path, 6.0, "yielding_pair.toml"))
    assert model.buildings[0].storey_law.kind == "bilinear"
    assert list(model.buildings[1].storey_law.yield_force) == [6e5, 6e5, 5e5, 4e5, 3e5]
    ds = simulate(model)
    assert ds.attrs["driver"] == "general" and ds.attrs["scheme"] == "exact"  # free flight between impacts
    e = ds.energy
    hyst = float(e.sel(energy_component="hysteretic")[-1])
    balance = e.sel(energy_component="input") - e.drop_sel(energy_component="input").sum("energy_component")
    print(f"MEASURED yielding pair, 6 s: hysteretic energy {hyst:.4g} J, balance "
          f"{float(abs(balance).max() / e.sel(energy_component='input').max()):.1e} of the input")
    assert hyst > 0.05 * float(e.sel(energy_component="input")[-1])
    assert float(abs(balance).max()) <= 1e-9 * float(e.sel(energy_component="input").max())
    np.testing.assert_array_equal(ds.residual_drift.values, ds.drift.isel(time=-1).values)
    # B's first storey (Bouc-Wen, fy = 6e5 N, alpha 0.05) never carries more than its bound
    f1 = ds.storey_force.sel(building="B", floor=1)
    dmax = float(abs(ds.drift.sel(building="B", floor=1)).max())
    bound = 0.05 * 8e7 * dmax + 0.95 * 6e5
    assert float(abs(f1).max()) <= bound * (1 + 1e-6)
    assert float(ds.peak_storey_shear.sel(building="B", floor=1)) == pytest.approx(float(abs(f1).max()))
    # A's bilinear storeys: |F| <= alpha k |d| + (1 - alpha) fy at every instant, reached while yielding
    d, f = ds.drift.sel(building="A"), ds.storey_force.sel(building="A")
    cap = 0.05 * 5e7 * abs(d) + 0.95 * 5e7 * 0.01
    assert float((abs(f) - cap).max()) <= 1e-6 * 5e5
    assert float((abs(f) - cap).max()) >= -1e-6 * 5e5


def test_elastic_storey_force_is_k_times_drift(tmp_path):
    ds = simulate(load_model(short_copy(tmp_path, 2.0)), twin=False)
    np.testing.assert_allclose(ds.storey_force.sel(building="A"), 1.3092e8 * ds.drift.sel(building="A"), rtol=1e-15)
    assert ds.attrs["driver"] == "fast"
