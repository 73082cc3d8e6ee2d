"""The yielding forms' scan points anchored on the response (``diagnose.api._yield_anchors``).

Regression guard: the anchors against the peak storey deformation of the same model read from a user's
``simulate`` Dataset (another read-out path of the same integrator, so not a verification)."""

from __future__ import annotations

import tomllib
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from seispound import load_model, simulate
from seispound.calibrate.observe import Trial
from seispound.diagnose import api
from seispound.diagnose.hypotheses import HYPOTHESES

REPO = Path(__file__).resolve().parents[2]


def test_yield_drifts_start_at_the_elastic_peak_over_the_ductilities():
    path = REPO / "models" / "two_buildings.toml"
    data = tomllib.loads(path.read_text())
    data["analysis"]["duration"] = 6.0
    model = load_model(path)
    dt = model.analysis.dt
    rec = SimpleNamespace(npts=int(round(6.0 / dt)) + 1, dt=dt)
    aug, specs, null = HYPOTHESES["inelastic-storey"].augment(data, 1)  # bilinear
    anchors = api._yield_anchors(data, specs, [null], path.parent, [Trial(recording=rec)])
    assert [k for k, _ in anchors] == [0] * len(api.DUCTILITIES)

    from dataclasses import replace
    res = simulate(replace(model, analysis=replace(model.analysis, duration=6.0)), twin=False)
    assert res["drift"].attrs.get("units") == "m"
    for mu, (_, point) in zip(api.DUCTILITIES, anchors):
        for b in ("A", "B"):
            peak = float(np.abs(res["drift"].sel(building=b)).max())
            # measured 0.17 % apart: a fit's run keeps the model's contact substeps and no contact-step limit
            assert point[f"building.{b}.storey_law.yield_drift"] == pytest.approx(peak / mu, rel=5e-3)
        assert point["building.*.storey_law.post_yield_ratio"] == null["building.*.storey_law.post_yield_ratio"]


def test_a_form_without_a_yield_drift_has_no_anchors():
    data = tomllib.loads((REPO / "models" / "two_buildings.toml").read_text())
    aug, specs, null = HYPOTHESES["soil-structure-interaction"].augment(data, 0)
    assert api._yield_anchors(data, specs, [null], REPO / "models", []) == []
