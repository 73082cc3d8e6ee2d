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
