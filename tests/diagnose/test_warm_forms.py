"""The second start of a yielding form polished from the leading form's values (``api._unreached_yield``).

Kind: a unit check of the rule on a stand-in fit (the storeys' reach given, not simulated): a building whose
fitted yield drift its storeys never reach starts the second time at its reach over the first ductility of
the yield anchors, within the parameter's bounds; a building that yields keeps its value; a fit without yield
drifts has no second start.
"""

from types import SimpleNamespace

import pytest

from seispound.diagnose import api


def _step(values):
    par = lambda v: dict(value=v, lo=0.0005, hi=5.0, stderr=1e-4, at_bound=False)  # noqa: E731
    params = {f"building.{b}.storey_law.yield_drift": par(v) for b, v in values.items()}
    params["building.*.storey_law.post_yield_ratio"] = par(0.08)
    return SimpleNamespace(fit=SimpleNamespace(parameters=params, model_text="[analysis]\ndt = 0.01\n"))


def test_an_unreached_yield_drift_starts_again_inside_the_reach(monkeypatch):
    import seispound.diagnose.quantities as quantities

    monkeypatch.setattr(quantities, "storey_reach", lambda data, base, chans, trials: {"A": 0.019, "B": 0.026,
                                                                                        "C": 0.0009})
    out = api._unreached_yield(_step({"A": 0.0118, "B": 2.0, "C": 3.0}), None, [], [])
    assert set(out) == {"building.B.storey_law.yield_drift", "building.C.storey_law.yield_drift"}
    assert out["building.B.storey_law.yield_drift"] == pytest.approx(0.026 / api.DUCTILITIES[0], rel=1e-15)
    assert out["building.C.storey_law.yield_drift"] == 0.0005  # (0.00045 is below the parameter's bound)
    assert api._unreached_yield(_step({"A": 0.0118}), None, [], []) == {}
    assert api._unreached_yield(SimpleNamespace(fit=SimpleNamespace(parameters={}, model_text="")), None, [], []) == {}
