"""The first physics fitted on before a second is sought (``diagnose.api._continued``).

A second form polished on top of a first physics whose polish stopped early gains by finishing the
first's fit; the second round is judged against the first fitted on.  Regression guard on a fit stopped
after one Gauss-Newton iteration: fitted on, it reaches the noise (a closed form: the data were made by
the model with the true values and 1 % noise, so the noise's NE is what a converged fit leaves)."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import pytest

from seispound.calibrate.channels import Channel
from seispound.calibrate.fit import calibrate_observer, parse_fit
from seispound.calibrate.observe import Observer
from seispound.diagnose import api
from tests._models import made_recording

REPO = Path(__file__).resolve().parents[2]
MODELS = REPO / "models"
FACTORS = {"A": 1.06, "B": 0.95}  # the true storey stiffness over the model's


def _truth(data):
    k = {b["name"]: float(b["storey_stiffness"]) for b in data["building"]}
    true = {f"building.{b}.storey_stiffness": f * k[b] for b, f in FACTORS.items()}
    return true, [f"building.{b}.storey_stiffness={0.5 * k[b]!r}:{2.0 * k[b]!r}" for b in FACTORS]


def _case():
    data = tomllib.loads((MODELS / "two_buildings.toml").read_text())
    data["analysis"]["duration"] = 4.0
    chans = [Channel(f"XX.{b}.{f:02d}.HNX", "acceleration", b, f) for b in ("A", "B") for f in (1, 3)]
    true, specs = _truth(data)
    return data, chans, made_recording(data, MODELS, chans, true, seed=5), true, specs


def _step(fit, n_eff, p, prev=None):
    return api._Step("stiffness-distribution" if prev else None, fit,
                     n_eff * math.log(api._rss(fit) / fit.n) + p * math.log(n_eff), p, 0.0, prev, 0.7)


def test_a_fit_stopped_early_is_fitted_on_and_a_converged_one_is_kept():
    data, chans, trials, true, specs = _case()
    obs = Observer(data, MODELS, chans, trials)
    params = parse_fit(specs, data)
    start = calibrate_observer(obs, params, progress=False, max_evaluations=1, tolerance=api.TOLERANCE,
                               step_fraction=api.STEP)
    early = calibrate_observer(obs, params, progress=False, max_evaluations=2 * (len(params) + 1),
                               tolerance=api.TOLERANCE, step_fraction=api.STEP)
    ref = _step(start, early.n_eff, 0)
    first = _step(early, early.n_eff, 2, ref)
    said = []
    on = api._continued(first, MODELS, chans, trials, 400, early.n, early.n_eff, said.append)
    print(f"MEASURED NE as given {start.ne_mean_after:.4f}, stopped early {early.ne_mean_after:.4f}, "
          f"fitted on {on.fit.ne_mean_after:.4f} ({on.fit.evaluations} evaluations), parameters off by "
          f"{[on.fit.parameters[p]['value'] / v - 1 for p, v in true.items()]}")
    assert early.ne_mean_after > 0.02  # the early stop leaves the fit well above the 1 % noise
    assert on.fit.ne_mean_after < 0.012 and on.bic < first.bic - 10.0
    assert (on.name, on.p, on.prev, on.probability) == (first.name, first.p, first.prev, first.probability)
    assert on.gain == pytest.approx(1.0 - on.fit.ne_mean_after / start.ne_mean_after)
    for path, value in true.items():
        assert on.fit.parameters[path]["value"] == pytest.approx(value, rel=1e-4)  # measured 1e-5
    again = api._continued(on, MODELS, chans, trials, 400, early.n, early.n_eff, said.append)
    assert again.fit.ne_mean_after <= on.fit.ne_mean_after * (1 + 1e-9)
    assert "fitted on" in said[0]
