"""The base model refitted from where a physics's joint fit left the base parameters (``api._base_from_physics``).

A physics fitted jointly with the base parameters can leave a basin that the recalibration stopped in; the base
model is then refitted from the physics's values, with the base's own parameters that the physics replaced (a
constant e under an e(v)) started at the nearest values the hypothesis gives (``Hypothesis.reduce``), so that the
physics is credited only with what the base cannot do from the same place.

The recording is made by the package's own model with a constant e of 0.58 (the model says 0.65) and A's storeys
6 % stiffer, plus 1 % noise, so a converged base fit leaves the noise's NE and the true values: what the refit
reaches is checked against those known values (a closed form of the data, not the refit agreeing with itself).
The physics's fit is stood in for by its values (``SimpleNamespace``): an e(v) that hardly changes with the
impact velocity around 0.58 with the storey stiffness at its true value, as an e(v) fitted on a constant-e
recording ends (held-out case-016 of seed 9157).
"""

from __future__ import annotations

import copy
import tomllib
from pathlib import Path
from types import SimpleNamespace

import pytest
import tomli_w

from seispound.calibrate.channels import Channel
from seispound.calibrate.fit import calibrate_observer, parse_fit
from seispound.calibrate.observe import Observer
from seispound.diagnose import api
from seispound.diagnose.hypotheses import HYPOTHESES
from seispound.diagnose.hypotheses.restitution import NEAREST_VELOCITIES
from tests._models import made_recording

REPO = Path(__file__).resolve().parents[2]
MODELS = REPO / "models"
E_TRUE, K_FACTOR = 0.58, 1.06
EV = "velocity-dependent-restitution"


@pytest.fixture(scope="module")
def case():
    data = tomllib.loads((MODELS / "two_buildings.toml").read_text())
    data["analysis"]["duration"] = 4.0
    chans = [Channel(f"XX.{b}.{f:02d}.HNX", "acceleration", b, f) for b in ("A", "B") for f in (1, 3)]
    k_a = float(data["building"][0]["storey_stiffness"])
    true = {"building.A.storey_stiffness": K_FACTOR * k_a, "contact.restitution": E_TRUE}
    trials = made_recording(data, MODELS, chans, true, seed=8)
    params = parse_fit([f"building.A.storey_stiffness={0.5 * k_a!r}:{2.0 * k_a!r}", "contact.restitution=0.2:0.95"],
                       data)
    obs = Observer(data, MODELS, chans, trials)
    as_given = calibrate_observer(obs, params, progress=False, max_evaluations=1, tolerance=api.TOLERANCE)
    from dataclasses import replace

    truth = calibrate_observer(obs, [replace(p, start=true[p.path]) for p in params], progress=False,
                               max_evaluations=1, tolerance=api.TOLERANCE)  # the noise's NE: the truth's misfit
    return data, chans, trials, params, true, as_given, truth.ne_mean_after


def _physics_fit(data, true, slope):
    """A stand-in for an e(v)'s joint fit: the base parameters at ``true``, e(v) = 0.58 + slope (0.3 - v)."""
    table = copy.deepcopy(data)
    table["contact"]["restitution"] = {"form": "linear", "e0": E_TRUE + 0.3 * slope, "slope": slope, "min": 0.2,
                                       "max": 0.95}
    table["building"][0]["storey_stiffness"] = true["building.A.storey_stiffness"]
    values = {"building.A.storey_stiffness": {"value": true["building.A.storey_stiffness"]},
              "contact.restitution.slope": {"value": slope}}
    return SimpleNamespace(name=EV, fit=SimpleNamespace(parameters=values, model_text=tomli_w.dumps(table)))


def test_the_nearest_constant_of_a_linear_law_is_its_value_at_each_velocity():
    # closed form of the linear law e = clip(e0 - slope v, min, max)
    table = {"contact": {"restitution": {"form": "linear", "e0": 0.7, "slope": 0.4, "min": 0.45, "max": 0.65}}}
    got = [c["contact.restitution"] for c in HYPOTHESES[EV].reduce(table)]
    want = [min(max(0.7 - 0.4 * v, 0.45), 0.65) for v in NEAREST_VELOCITIES]
    assert got == pytest.approx(want, abs=1e-15)


def test_the_base_refitted_from_a_physics_reaches_the_truth(case):
    data, chans, trials, params, true, as_given, noise = case
    step = _physics_fit(data, true, slope=0.02)
    again = api._base_from_physics(data, params, MODELS, chans, trials, 200, step, as_given)
    print(f"MEASURED NE as given {as_given.ne_mean_after:.4f}, noise {noise:.5f}, refitted {again.ne_mean_after:.5f}; "
          f"off the truth by {[again.parameters[p]['value'] / v - 1 for p, v in true.items()]}")
    assert as_given.ne_mean_after > 0.1
    assert again.ne_mean_after < 1.01 * noise  # measured 1.000
    for path, value in true.items():
        assert again.parameters[path]["value"] == pytest.approx(value, rel=5e-4)  # measured 1.7e-4


def test_a_refit_that_gains_nothing_is_not_returned(case):
    # from a converged base fit at the truth, refitting from the physics's values cannot do better
    data, chans, trials, params, true, _, _ = case
    from dataclasses import replace

    at_truth = [replace(p, start=true[p.path]) for p in params]
    converged = calibrate_observer(Observer(data, MODELS, chans, trials), at_truth, progress=False,
                                   max_evaluations=100, tolerance=api.TOLERANCE)
    step = _physics_fit(data, true, slope=0.02)
    again = api._base_from_physics(data, params, MODELS, chans, trials, 200, step, converged)
    print(f"MEASURED converged NE {converged.ne_mean_after:.6f}; refit "
          f"{'none' if again is None else f'{again.ne_mean_after:.6f}'}")
    assert again is None or again.ne_mean_after > converged.ne_mean_after * (1 - 1e-4)
