"""A named physics whose own fit stays well above the noise: its quantities are its form's, and the report says so.

The quantities' intervals hold for a model of the right form (the residual is noise about it); a fit left at
several times the noise carries a misfit of form that biases its parameters beyond those intervals
(``api._mark_form_limited``).  Unit checks of the marking, on stub fits whose misfit is set by hand.
"""

from __future__ import annotations

from types import SimpleNamespace

import pytest

from seispound.diagnose import api
from seispound.diagnose.api import FORM_LIMITED, _interval, _mark_form_limited

NOISE = 0.01


def _trials():
    return [SimpleNamespace(name="T1"), SimpleNamespace(name="T2")]


def _chans(*ids):
    return [SimpleNamespace(id=c) for c in ids]


def _item():
    return {"physics": "inelastic-storey", "quantities": [
        {"name": "A: yield drift", "value": 0.012, "units": "m", "stderr": 0.0004, "half68": 0.0004, "dof": 40.0},
        {"name": "A: post-yield stiffness ratio", "value": 0.1, "units": "", "stderr": None,
         "reason": "the data do not constrain it"}]}


def _step(ne):
    """A named physics's step whose fit leaves NE ``ne[channel]`` on every trial."""
    return SimpleNamespace(fit=SimpleNamespace(ne_after={t.name: dict(ne) for t in _trials()}))


@pytest.mark.parametrize("ratio, marked", [(1.8, False), (FORM_LIMITED * 0.99, False), (FORM_LIMITED * 1.01, True),
                                           (6.0, True)])
def test_a_physics_is_marked_only_above_the_factor(ratio, marked):
    item = _item()
    _mark_form_limited([item], [_step({"a": ratio * NOISE, "b": ratio * NOISE})], _trials(), _chans("a", "b"), None, NOISE)
    assert ("form_limited" in item) is marked
    assert ("form_limited" in item["quantities"][0]) is marked
    if marked:
        assert item["form_limited"] == pytest.approx(ratio, abs=0.01)
    # a quantity the data do not determine says so already; it is not marked again
    assert "form_limited" not in item["quantities"][1]


def test_a_suspected_faulty_channel_is_left_out_of_the_ratio():
    """The others at 1.2 times the noise, the faulty one at 40: marked at (1.2 + 1.2 + 40) / 3 = 14.1 without the
    fault found, not marked with it."""
    ne = {"a": 1.2 * NOISE, "b": 1.2 * NOISE, "bad": 40 * NOISE}
    item = _item()
    _mark_form_limited([item], [_step(ne)], _trials(), _chans("a", "b", "bad"), None, NOISE)
    assert item["form_limited"] == pytest.approx((1.2 + 1.2 + 40) / 3, abs=0.01)
    item = _item()
    _mark_form_limited([item], [_step(ne)], _trials(), _chans("a", "b", "bad"), {"channel": "bad"}, NOISE)
    assert "form_limited" not in item


def test_each_physics_is_judged_by_its_own_fit():
    """Two named physics: the first's fit (before the second was added) at 5 times the noise, the second's at 1.1."""
    first, second = _item(), _item()
    _mark_form_limited([first, second], [_step({"a": 5 * NOISE}), _step({"a": 1.1 * NOISE})], _trials(),
                       _chans("a"), None, NOISE)
    assert first["form_limited"] == pytest.approx(5.0) and "form_limited" not in second


def test_the_report_says_a_marked_value_is_the_forms():
    q = dict(_item()["quantities"][0])
    assert "its form's value" not in _interval(q)
    q["form_limited"] = 6.0
    text = _interval(q)
    assert "its form's value: the fit leaves 6.0 times the noise" in text
    assert text.startswith("0.012 +- 0.0004 m (68 % interval")
    summary = api.Diagnosis.summary(SimpleNamespace(
        seconds=1.0, ne_before=0.5, ne_after=0.06, numerics={"ne": 0.001, "sufficient": True}, wrong_parameters=[],
        left_out=[{"physics": "inelastic-storey", "share": 1.0, "probability": 1.0, "evidence": "e",
                   "form_limited": 6.0, "quantities": [q]}],
        instrument_fault=None, verdict="v", recalibrated={}, recalibrated_factors=[], held={}, mismatch=[]))
    assert "its fit leaves 6.0 times the noise: the quantities below are the closest its form comes" in summary
