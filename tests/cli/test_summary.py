"""The run summary: periods, the engineering peaks with and without pounding, and the findings."""

from __future__ import annotations

import json
import warnings

import numpy as np

import seispound as sp
from seispound.cli import summary
from tests._models import short_copy


def test_summary_prints_periods_peaks_and_findings(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = sp.simulate(sp.load_model(short_copy(tmp_path, 6.0)))
    ds.attrs["plausibility"] = json.dumps([{"code": "x", "message": "a hand-made finding", "key": "", "refuse": False}])
    text = summary(ds, "out.h5").splitlines()
    row = next(i for i, line in enumerate(text) if line.lstrip().startswith("B "))
    t = ds.period.sel(building="B").values[:3]
    assert text[row].split()[1:4] == [f"{t[0]:.3g},", f"{t[1]:.3g},", f"{t[2]:.3g}"]
    acc = ds.peak_acceleration.sel(building="B").values
    f = int(np.nanargmax(acc))
    cells = text[row].split("[g]")[1].split()
    assert cells[0] == f"{acc[f] / 9.80665:.3f}" and int(cells[3]) == f + 1
    without = float(ds.peak_acceleration_no_pounding.sel(building="B").values[f])
    assert cells[1] == f"{without / 9.80665:.3f}" and cells[2] == f"{acc[f] / without:.2f}"
    shear = text[row + 2]
    assert "storey shear [kN]" in shear
    s = ds.peak_storey_shear.sel(building="B").values
    assert shear.split("[kN]")[1].split()[0] == f"{np.nanmax(s) / 1e3:.0f}"
    assert text[-2] == "  warning: a hand-made finding" and text[-1] == "  written to out.h5"


def test_summary_never_prints_minus_zero_nor_a_ratio_of_near_zero_peaks(tmp_path):
    """A pendulum impact test: the struck slab does not move without the impact, so its "amplification" is
    a ratio of a peak to nothing; it is printed as '-', and no value reads -0.000."""
    from tests._models import REPO

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = sp.simulate(sp.load_model(REPO / "models" / "slab_pendulum.toml"))
    text = summary(ds)
    assert "-0.000" not in text and " -0 " not in text
    struck = text.splitlines()[next(i for i, ln in enumerate(text.splitlines()) if ln.lstrip().startswith("struck"))]
    assert struck.split("[g]")[1].split()[2] == "-"  # 4 g against 0: no ratio
    without = float(ds.peak_acceleration_no_pounding.sel(building="struck").max())
    assert without < 0.01 * float(ds.peak_acceleration.sel(building="struck").max())


def test_summary_gives_residual_drift_where_storeys_yield(tmp_path):
    from tests._models import REPO

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = sp.simulate(sp.load_model(REPO / "models" / "yielding_pair.toml"))
    lines = summary(ds).splitlines()
    rows = [ln for ln in lines if "residual drift [mm]" in ln]
    assert len(rows) == 2  # both buildings of the pair yield
    r = np.abs(ds.residual_drift.sel(building="A").values)
    assert float(rows[0].split("[mm]")[1].split()[0]) == round(float(np.nanmax(r)) * 1e3, 2)
    assert float(np.nanmax(r)) > 1e-3  # a permanent drift of millimetres, not vibration
    elastic = summary(sp.simulate(sp.load_model(short_copy(tmp_path, 2.0)), twin=False))
    assert "residual drift" not in elastic
