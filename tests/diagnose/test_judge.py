"""The acceptance rule of a round of hypotheses, on fits made up to sit either side of its thresholds.

A physics is accepted when its information criterion beats the model it was added to by
BIC_MARGIN and its NE by NE_GAIN, and only if it also beats by BIC_MARGIN the best fit of
wrong parameters beyond what recalibration spans (a soft first storey against a sway spring).
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import pytest

from seispound.diagnose.api import BIC_MARGIN, _base_specs, _judge, _partial, _reported, _Step

N = N_EFF = 1000


def _fit(ne):
    # one trial, one channel: the residual sum of squares is ne^2
    return SimpleNamespace(ne_mean_after=ne, ne_after={"t": {"c": ne}}, evaluations=1, parameters={})


def _bic(ne, p):
    return N_EFF * math.log(ne * ne / N) + p * math.log(N_EFF)


def _round(outcomes):
    ref = _Step(None, _fit(0.10), _bic(0.10, 4), 4)
    return _judge([(name, (_fit(ne), p, True)) for name, ne, p in outcomes], ref, N, N_EFF, lambda m: None,
                  offset=4)


def test_physics_that_beats_the_base_is_accepted_and_one_that_barely_moves_it_is_not():
    accepted, entries = _round([("soil-structure-interaction", 0.05, 2), ("inelastic-storey", 0.095, 2)])
    assert [st.name for st in accepted] == ["soil-structure-interaction"]
    assert entries["inelastic-storey"]["accepted"] is False  # 5 % better: under NE_GAIN


def test_wrong_parameters_that_fit_as_well_name_no_physics():
    # the stiffness distribution fits a little worse than the sway spring, within BIC_MARGIN: no physics
    ne_alt = 0.0502
    assert abs(_bic(ne_alt, 4 + 2) - _bic(0.05, 4 + 2)) < BIC_MARGIN
    accepted, entries = _round([("soil-structure-interaction", 0.05, 2), ("stiffness-distribution", ne_alt, 2)])
    assert [st.name for st in accepted] == ["stiffness-distribution"]
    assert entries["soil-structure-interaction"]["accepted"] is False
    assert "wrong parameters" in entries["soil-structure-interaction"]["beaten_by"]


def _fit2(a, b):
    # one trial, two channels: the BIC reads the sum of squares, the NE reported is their mean
    return SimpleNamespace(ne_mean_after=(a + b) / 2, ne_after={"t": {"c1": a, "c2": b}}, evaluations=1,
                           parameters={})


@pytest.mark.parametrize("soil, named", [((0.0958, 0.0958), False), ((0.0900, 0.0900), True)])
def test_physics_ahead_of_the_wrong_parameters_by_bic_is_named_only_if_not_behind_them_by_ne(soil, named):
    """BIC (the residual sum of squares) and the NE reported (the mean over channels) can rank two fits
    apart: development case 4105-007 named soil second at NE 0.0958, 10.8 BIC units ahead of wrong
    parameters that reached 0.0909."""
    ref = _Step(None, _fit2(0.20, 0.20), N_EFF * math.log(2 * 0.20 ** 2 / N) + 4 * math.log(N_EFF), 4)
    alt = _fit2(0.0018, 0.18)  # mean 0.0909, the error on one channel

    def rss(f):
        return sum(v * v for v in f.ne_after["t"].values())

    assert N_EFF * math.log(rss(alt) / rss(_fit2(*soil))) > BIC_MARGIN  # soil ahead by BIC either way
    accepted, entries = _judge([("soil-structure-interaction", (_fit2(*soil), 2, True)),
                                ("stiffness-distribution", (alt, 2, True))], ref, N, N_EFF, lambda m: None, offset=4)
    assert ("soil-structure-interaction" in [st.name for st in accepted]) is named
    if not named:
        assert "wrong parameters" in entries["soil-structure-interaction"]["beaten_by"]


def test_physics_that_beats_the_wrong_parameters_by_the_margin_is_named():
    accepted, _ = _round([("soil-structure-interaction", 0.03, 2), ("stiffness-distribution", 0.05, 2)])
    assert [st.name for st in accepted] == ["soil-structure-interaction", "stiffness-distribution"]


def test_recalibration_spans_a_mass_factor_per_building_when_buildings_can_pound():
    data = {"building": [{"name": "A", "floor_masses": [1e5, 1e5]}, {"name": "B", "floor_masses": 2e5}],
            "gap": [{"between": ["A", "B"], "size": 0.01}], "contact": {"stiffness": 1e9, "restitution": 0.6}}
    specs = _base_specs(data)
    assert "building.A.floor_masses=0.5:2.0" in specs and "building.B.floor_masses=100000.0:400000.0" in specs
    assert "contact.stiffness" in specs and "contact.restitution" in specs
    alone = _base_specs({"building": [{"name": "A", "floor_masses": [1e5]}]})
    assert not any("floor_masses" in s for s in alone)  # without pounding only k/m is seen


def test_every_finished_fit_task_is_reported_as_progress():
    from seispound.diagnose.api import CANDIDATES_ALL, _progress

    lines = []
    fit = _fit(0.0421)
    _progress(lines.append, "starts", ("soil-structure-interaction", 1), ({}, [], [{}, {}, {}, {}]), 0, 12)
    _progress(lines.append, "short", ("soil-structure-interaction", 1), (fit, []), 3, 12)
    _progress(lines.append, "polish", ("soil-structure-interaction", 1), fit, 12, 12)
    _progress(lines.append, "short", ("inelastic-storey", 0), "ValueError: bad", 4, 12)
    assert lines == ["  soil-structure-interaction, form 2 of 2: 4 starts chosen",
                     "  soil-structure-interaction, form 2 of 2: short fit NE 0.0421 (3 of 12 forms screened)",
                     "  soil-structure-interaction, form 2 of 2: polished with the base parameters, NE 0.0421",
                     f"  inelastic-storey, form 1 of {CANDIDATES_ALL['inelastic-storey'].variants}: cannot run "
                     "(ValueError: bad)"]


def _stubbed_fit_all(monkeypatch, results):
    """``_fit_all`` in this process (jobs 1) with each form's fit made up: results {(name, form): (ne, p)}."""
    from seispound.diagnose import api

    def starts(name, variant, data, alt, *common):
        if (name, variant) not in results:
            return "not in this test"  # a form that cannot run is left out
        ne, p = results[(name, variant)]
        return {}, [f"x.{name}.{variant}.{j}=1:2" for j in range(p)], [{"form": (name, variant)}], []

    def short(aug, specs, start, *common):
        fit = _fit(results[start["form"]][0])
        fit.model_text = fit.ne_mean_after
        return fit, specs, start

    monkeypatch.setattr(api, "_starts", starts)
    monkeypatch.setattr(api, "_short", short)
    monkeypatch.setattr(api, "_polish", lambda texts, *a: _fit(min(texts)))  # polishing moves nothing here
    names = sorted({n for n, _ in results})
    return dict(api._fit_all(names, {}, None, [], [], 400, 1, ne_base=0.0, n_eff=N_EFF))


def test_wrong_parameters_keep_their_most_parsimonious_form_and_a_physics_its_closest(monkeypatch):
    from seispound.diagnose.hypotheses import ALTERNATIVES, HYPOTHESES

    physics = next(iter(HYPOTHESES))
    alt = next(iter(ALTERNATIVES))
    # every storey free fits 2 % closer than a soft first storey, with 18 parameters more: BIC worse by
    # 18 ln(1000) - 1000 ln(1.02^2) = 124.3 - 39.6; a physics's richer form fits 2 % closer with 2 more: kept
    out = _stubbed_fit_all(monkeypatch, {(alt, 0): (0.0102, 2), (alt, 2): (0.0100, 20),
                                         (physics, 0): (0.0102, 2), (physics, 1): (0.0100, 4)})
    assert out[alt][1] == 2 and out[alt][0].ne_mean_after == 0.0102
    assert out[physics][1] == 4 and out[physics][0].ne_mean_after == 0.0100
    # the same closer fit with few parameters more pays for them: BIC better by 39.6 - 2 ln(1000) = 25.8
    out = _stubbed_fit_all(monkeypatch, {(alt, 0): (0.0102, 2), (alt, 2): (0.0100, 4)})
    assert out[alt][1] == 4


@pytest.mark.parametrize("alt, expected", [({"gap.1.size": 0.02}, 60 * 21), (None, 400)],
                         ids=["first-round", "on-top-of-a-physics"])
def test_the_alternatives_budget_is_uncapped_in_the_first_round_only(monkeypatch, alt, expected):
    # 20 parameters: 60 (p + 1) = 1260 simulations uncapped, against max_evaluations 400; a physics always capped
    from seispound.diagnose import api
    from seispound.diagnose.hypotheses import ALTERNATIVES, HYPOTHESES

    physics, alternative = next(iter(HYPOTHESES)), next(iter(ALTERNATIVES))
    budgets = {}

    def starts(name, variant, *a):
        if variant:
            return "one form each"
        return {}, [f"x.{name}.{j}=1:2" for j in range(20)], [{"form": name}], []

    def polish(texts, specs, both, base, chans, trial_list, budget, every_base=False, anchored=False, enough=None,
               refine=None, context=None):
        budgets[specs[0].split(".")[1]] = budget
        return _fit(0.01)

    def short(aug, specs, start, *common):
        fit = _fit(0.02)
        fit.model_text = ""
        return fit, specs, start

    monkeypatch.setattr(api, "_starts", starts)
    monkeypatch.setattr(api, "_short", short)
    monkeypatch.setattr(api, "_polish", polish)
    dict(api._fit_all([physics, alternative], {}, None, [], [], 400, 1, ne_base=1.0, alt=alt, n_eff=N_EFF))
    assert budgets == {physics: 400, alternative: expected}


def test_the_alternative_is_polished_jointly_from_each_set_of_base_values(monkeypatch):
    # own fits: nominal base values 0.05, recalibrated 0.04; joint fits from there: 0.011 and 0.030. A physics
    # goes on jointly from its better own fit only (0.030); the alternative from both (0.011)
    import dataclasses

    from seispound.calibrate import fit as fit_module
    from seispound.calibrate import observe
    from seispound.diagnose.api import _polish

    @dataclasses.dataclass
    class Param:
        path: str
        start: float = 1.0
        lo: float = 0.5
        hi: float = 2.0

    outcome = {("nominal", 1): 0.05, ("recal", 1): 0.04, ("nominal", 3): 0.011, ("recal", 3): 0.030}
    budgets = []

    def calibrate(obs, params, max_evaluations, **kw):
        budgets.append(max_evaluations)
        f = _fit(outcome[(obs.data["tag"], len(params))])
        f.model_text = f'tag = "{obs.data["tag"]}"'
        return f

    monkeypatch.setattr(fit_module, "calibrate_observer", calibrate)
    monkeypatch.setattr(fit_module, "parse_fit", lambda specs, data: [Param(s) for s in specs])
    monkeypatch.setattr(observe, "Observer", lambda data, *a: SimpleNamespace(data=data))
    texts, specs, both = ['tag = "nominal"', 'tag = "recal"'], ["own"], ["base1", "base2", "own"]
    assert _polish(texts, specs, both, None, [], [], 10_000).ne_mean_after == 0.030
    assert budgets == [120, 120, 240]  # 60 (p + 1) each stage
    assert _polish(texts, specs, both, None, [], [], 10_000, every_base=True).ne_mean_after == 0.011
    # the last text an anchored start's (a yielding form's start placed by the response): the joint stage
    # also runs from its own fit, though another own fit is better
    budgets.clear()
    assert _polish(texts, specs, both, None, [], [], 10_000, anchored=True).ne_mean_after == 0.030  # recal last
    assert _polish(texts[::-1], specs, both, None, [], [], 10_000, anchored=True).ne_mean_after == 0.011
    assert budgets == [120, 120, 240] + [120, 120, 240, 240]  # one joint stage where the anchor's own fit is best


@pytest.mark.parametrize("anchor_ne, on_recalibrated, polished_from", [
    (0.40, False, ["nominal", "recalibrated", "anchor"]),
    (0.46, False, ["nominal", "recalibrated", "anchor"]),  # beats its own base's 0.47, not the other's 0.45
    (0.50, False, ["nominal", "recalibrated"]),
    (0.46, True, ["nominal", "recalibrated"])])  # its own base's scan reached 0.45
def test_an_anchored_start_is_polished_beside_the_scans_best_not_in_place_of_them(monkeypatch, anchor_ne,
                                                                                    on_recalibrated, polished_from):
    """The best short fit from each set of base values is polished; the anchored start's (a yielding form's
    start placed by the response) too where it fits better than the scan's best on its own base values, never
    in their place (on the speed case's Bouc-Wen storeys the anchor's short fit was the best, 0.40 against
    0.45, and its polish ended in another basin than the scan point's, which reaches the noise; on development
    case 4104-006 it beat its own base's scan but not the other base's, and only its polish ends low)."""
    from seispound.diagnose import api

    physics = "inelastic-storey"
    fits = {"nominal": 0.47, "recalibrated": 0.45, "anchor": anchor_ne}
    anchor = {"building.A.storey_law.yield_drift": 0.01} | ({"k": 1.0} if on_recalibrated else {})

    def starts(name, variant, data, alt, *common):
        if variant:
            return "one form"
        return {}, ["x=1:2"], [{"at": "nominal"}, {"at": "recalibrated", "k": 1.0}, anchor], [anchor]

    def short(aug, specs, start, *common):
        fit = _fit(fits["anchor" if start == anchor else start["at"]])
        fit.model_text = "anchor" if start == anchor else start["at"]
        return fit, specs, start

    seen = []

    def polish(texts, *a, **k):
        seen.extend(texts)
        return _fit(0.01)

    monkeypatch.setattr(api, "_starts", starts)
    monkeypatch.setattr(api, "_short", short)
    monkeypatch.setattr(api, "_polish", polish)
    dict(api._fit_all([physics], {}, None, [], [], 400, 1, ne_base=1.0, alt={"k": 1.0}, n_eff=N_EFF))
    assert sorted(seen) == sorted(polished_from)


def test_a_physics_under_the_ne_gain_is_taken_on_trial_only_ahead_of_the_wrong_parameters():
    """Two effects, each part of the misfit: no physics alone lowers the NE by NE_GAIN, and the one with the
    strongest evidence is taken on trial (named only if a second physics on top of it is accepted)."""
    accepted, entries = _round([("distributed-mass", 0.092, 2), ("velocity-dependent-restitution", 0.091, 2)])
    assert accepted == []  # 8 % and 9 % better: each under NE_GAIN
    assert _partial(entries).name == "velocity-dependent-restitution"  # the better BIC
    # wrong parameters beyond the recalibration that fit as well (or better by the NE): nothing on trial
    _, entries = _round([("distributed-mass", 0.092, 2), ("stiffness-distribution", 0.0921, 2)])
    assert _partial(entries) is None
    # a physics that does not beat the base by BIC_MARGIN, or does not lower the NE, is not taken on trial
    _, entries = _round([("distributed-mass", 0.0995, 2)])
    assert entries["distributed-mass"]["delta_bic"] > -BIC_MARGIN and _partial(entries) is None
    # the report's entries carry no fitted step
    assert all("step" not in e for e in _reported(entries).values())
