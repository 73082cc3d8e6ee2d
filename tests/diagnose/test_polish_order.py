"""Which polishes a diagnosis still needs once a physics explains the data (``diagnose.polish_order``).

Regression guards of the rule's logic, on made-up short fits and polishes: the forms of one hypothesis are
polished in the order of their short fits and a form ranked behind one that explains the data is not needed;
a form whose short fit is over WITHIN times the best waits for the forms within WITHIN and is not needed when
one of those physics explains the data; the outcome does not depend on which polish finished first; and
``_fit_all`` with the rule leaves the polishes out, where without it every one runs.
"""

from __future__ import annotations

import os

import pytest

from seispound.diagnose import api
from seispound.diagnose.hypotheses import ALTERNATIVES, HYPOTHESES
from seispound.diagnose.polish_order import PolishOrder

AT = 0.015  # NE at which a polish explains the data (EXPLAINED 1.5 x a noise NE of 0.01)
P, Q = sorted(HYPOTHESES)[:2]
ALT = next(iter(ALTERNATIVES))


def _order(screen, at=AT):
    return PolishOrder(screen, api.WITHIN, at, ALTERNATIVES)


def _start(order, *forms):
    """Request the forms, then start what ``next`` gives: (started, dropped) in order."""
    for f in forms:
        order.request(f)
    started, dropped = [], []
    while True:
        form, gone = order.next()
        dropped += gone
        if form is None:
            return started, dropped
        started.append(form)


def test_without_a_noise_estimate_every_polish_starts_and_is_needed():
    screen = {(P, 0): 0.4, (P, 1): 0.43, (Q, 0): 0.9}
    order = _order(screen, at=None)
    assert _start(order, *screen) == ([(P, 0), (P, 1), (Q, 0)], [])
    for f in screen:
        order.done(f, 0.01)
    assert all(order.needed(f) for f in screen)


@pytest.mark.parametrize("first_ne, needed", [(0.012, False), (0.02, True)], ids=["explains", "does-not"])
def test_a_sibling_waits_for_the_better_ranked_form_and_is_left_out_when_it_explains(first_ne, needed):
    screen = {(P, 0): 0.40, (P, 2): 0.43}
    order = _order(screen)
    assert _start(order, (P, 2), (P, 0)) == ([(P, 0)], [])  # (P, 2) waits: (P, 0) ranks ahead of it
    order.done((P, 0), first_ne)
    assert _start(order) == (([], [(P, 2)]) if not needed else ([(P, 2)], []))
    assert order.needed((P, 2)) is needed


def test_a_far_form_waits_for_the_screen_and_is_left_out_when_a_near_physics_explains():
    screen = {(P, 0): 0.40}
    order = _order(screen)
    assert _start(order, (P, 0)) == ([(P, 0)], [])
    screen[(Q, 0)] = 0.63  # over 1.5 x 0.40: polished only because it beat the recalibrated base
    assert order.far((Q, 0)) and _start(order, (Q, 0)) == ([], [])
    order.screened = True
    assert _start(order) == ([], [])  # (P, 0) is still being polished
    order.done((P, 0), 0.011)
    assert _start(order) == ([], [(Q, 0)])
    assert order.needed((Q, 0)) is False and order.needed((P, 0)) is True


def test_an_alternative_that_fits_to_the_noise_does_not_stop_the_search():
    screen = {(ALT, 0): 0.40, (ALT, 1): 0.41, (P, 0): 0.62}
    order = _order(screen)
    assert _start(order, (ALT, 0), (ALT, 1), (P, 0)) == ([(ALT, 0), (ALT, 1)], [])  # no sibling rule among them
    order.screened = True
    order.done((ALT, 0), 0.011)
    order.done((ALT, 1), 0.012)
    assert _start(order) == ([(P, 0)], [])  # the physics is still polished: wrong parameters do not explain


def test_the_outcome_does_not_depend_on_which_polish_finished_first():
    # (P, 1)'s short fit came in first and its polish ran; (P, 0)'s ranked ahead of it and explains
    screen = {(P, 1): 0.50}
    order = _order(screen)
    assert _start(order, (P, 1)) == ([(P, 1)], [])
    screen[(P, 0)] = 0.40
    assert _start(order, (P, 0)) == ([(P, 0)], [])
    order.done((P, 1), 0.010)
    order.done((P, 0), 0.012)
    order.screened = True
    assert order.needed((P, 1)) is False  # the same as if (P, 1) had waited for (P, 0)


@pytest.mark.parametrize("criterion, ahead", [({(P, 0): 879.7, (P, 2): 911.8}, (P, 0)),
                                               ({(P, 0): 911.8, (P, 2): 879.7}, (P, 2)), (None, (P, 2))],
                         ids=["fewer-parameters-ahead", "criterion-agrees-with-ne", "by-ne"])
def test_siblings_rank_by_their_short_fits_information_criterion(criterion, ahead):
    """Given each short fit's information criterion, a hypothesis's forms are ordered by it for the sibling rule:
    the degrading form's short fit 0.08 % closer than the Bouc-Wen form's but 32 higher in BIC (the speed
    case's numbers, its 5 more parameters at n_eff about 600) waits for the Bouc-Wen form and is left out when
    that explains the data; without a criterion the closer short fit ranks ahead, as before."""
    screen = {(P, 0): 0.39574, (P, 2): 0.39543}
    order = PolishOrder(screen, api.WITHIN, AT, ALTERNATIVES, criterion)
    behind = (P, 2) if ahead == (P, 0) else (P, 0)
    assert _start(order, (P, 2), (P, 0)) == ([ahead], [])
    order.done(ahead, 0.0113)
    assert _start(order) == ([], [behind])
    assert order.needed(behind) is False


def _fit(ne):
    from types import SimpleNamespace

    return SimpleNamespace(ne_mean_after=ne, parameters={}, evaluations=1, n=1000, residual_ss=ne * ne,
                           ne_after={"XX.A.01.HNX": {"acceleration": ne}})


SHORTS = {(P, 0): 0.40, (P, 1): 0.45}  # each form's short fit (a test may replace it); module level: picklable


def _stub_starts(name, variant, *a):
    if (name, variant) not in SHORTS:
        return "not in this test"  # a form that cannot run is left out
    return {}, [f"x.{name}.{variant}=1:2"], [{"form": (name, variant)}], []


def _stub_short(aug, specs, start, *common):
    fit = _fit(SHORTS[start["form"]])
    fit.model_text = repr(start["form"])
    return fit, specs, start


@pytest.mark.parametrize("explained", [None, AT], ids=["every-polish", "explained"])
def test_fit_all_leaves_out_the_polishes_the_data_no_longer_need(monkeypatch, explained):
    # P's first form explains the data when polished; P's second form and Q (far) would polish closer still
    shorts = {(P, 0): 0.40, (P, 1): 0.45, (Q, 0): 0.63}
    polished = {(P, 0): 0.012, (P, 1): 0.011, (Q, 0): 0.0105}
    calls = []

    def polish(texts, specs, both, base, chans, trial_list, budget, every_base=False, anchored=False,
               enough=None, refine=None, context=None):
        form = eval(texts[0])  # noqa: S307 (the test's own repr)
        calls.append(form)
        return _fit(polished[form])

    monkeypatch.setattr(api, "_starts", _stub_starts)
    monkeypatch.setattr(api, "_short", _stub_short)
    monkeypatch.setattr(api, "_polish", polish)
    monkeypatch.setitem(globals(), "SHORTS", shorts)
    monkeypatch.setattr(api, "_rss", lambda fit: 1000 * fit.ne_mean_after ** 2)
    out = dict(api._fit_all([P, Q], {}, None, [], [], 400, 1, ne_base=0.64, n_eff=1000, explained=explained))
    if explained is None:
        assert sorted(calls) == sorted(shorts)
        assert out[P][0].ne_mean_after == 0.011 and out[Q][0].ne_mean_after == 0.0105
    else:
        # the serial path takes the slowest hypothesis first (COST_ORDER): Q's polish ran before P's short fits
        # were in, and is not used; (P, 1) waited for (P, 0) and was left out
        assert (P, 0) in calls and (P, 1) not in calls
        assert out[P][0].ne_mean_after == 0.012 and out[P][2] is True
        assert out[Q][0].ne_mean_after == 0.63 and out[Q][2] == api.NOT_NEEDED  # its short fit stands


def test_an_idle_worker_takes_a_waiting_form_and_the_search_stops_waiting_once_it_is_not_needed():
    screen = {(P, 0): 0.40, (P, 1): 0.45, (Q, 0): 0.63}
    order = _order(screen)
    order.screened = True
    assert _start(order, (P, 0), (P, 1), (Q, 0)) == ([(P, 0)], [])
    assert order.speculate() == (P, 1)  # ranked behind (P, 0), but a worker would idle
    assert not order.settled([(P, 0), (P, 1)])
    order.done((P, 0), 0.012)  # explains: (P, 1), still running, and (Q, 0), waiting, are not needed
    assert _start(order) == ([], [(Q, 0)])
    assert order.settled([(P, 1)])
    assert order.needed((P, 1)) is False


def test_a_speculative_polish_is_used_where_the_form_ranked_ahead_does_not_explain():
    screen = {(P, 0): 0.40, (P, 1): 0.45}
    order = _order(screen)
    order.screened = True
    assert _start(order, (P, 0), (P, 1)) == ([(P, 0)], []) and order.speculate() == (P, 1)
    order.done((P, 0), 0.2)
    order.done((P, 1), 0.1)
    assert order.needed((P, 1)) is True and order.settled([])


def test_the_best_short_fit_so_far_is_polished_early_only_when_clearly_better_than_the_base():
    """``early``: the best short fit so far, below the recalibrated base's NE over WITHIN (0.64 / 1.5 = 0.427
    here), starts before the short fits still queued; one that is not the best so far, or not clearly better,
    waits for ``next`` as before."""
    clearly = 0.64 / api.WITHIN
    screen = {(P, 0): 0.40, (Q, 0): 0.30}
    order = _order(screen)
    order.request((P, 0))
    assert order.early(clearly) is None  # (Q, 0), not yet requested, has the better short fit
    order.request((Q, 0))
    assert order.early(clearly) == (Q, 0) and (Q, 0) in order.running and (Q, 0) not in order.waiting
    screen = {(P, 0): 0.50}
    order = _order(screen)
    order.request((P, 0))
    assert order.early(clearly) is None  # better than the base (0.64), not clearly: waits for the screen
    screen = {(P, 0): 0.40, (P, 1): 0.38}
    order = _order(screen)
    order.request((P, 0))
    assert order.early(clearly) is None  # its sibling (P, 1) has the better short fit


MARK = "SEISPOUND_TEST_POLISH_STARTED"  # environment variable: the file the unneeded polish touches when it starts




def _pool_polish(texts, specs, both, base, chans, trial_list, budget, every_base=False, anchored=False,
                 enough=None, refine=None, context=None):
    import time

    form = eval(texts[0])  # noqa: S307 (the test's own repr)
    if form == (P, 1):
        open(os.environ[MARK], "w").close()
        time.sleep(60)  # a long polish that the data will not need
    time.sleep(1.0)  # (P, 0): long enough for the idle worker to take (P, 1)
    return _fit(0.012 if form == (P, 0) else 0.011)


def test_a_search_in_worker_processes_does_not_wait_for_a_polish_it_does_not_need(monkeypatch, tmp_path):
    import time

    monkeypatch.setattr(api, "_starts", _stub_starts)
    monkeypatch.setattr(api, "_short", _stub_short)
    monkeypatch.setattr(api, "_polish", _pool_polish)
    monkeypatch.setattr(api, "CANDIDATES_ALL", {P: type("H", (), {"variants": 2, "screened": (0, 1), "refiner": lambda self, k: None})()})
    monkeypatch.setenv(MARK, str(tmp_path / "started"))  # reaches the workers however they are started
    t0 = time.perf_counter()
    out = dict(api._fit_all([P], {}, None, [], [], 400, 2, ne_base=0.64, n_eff=1000, explained=AT))
    took = time.perf_counter() - t0
    print(f"MEASURED the search took {took:.2f} s beside a 60 s polish it did not need")
    assert (tmp_path / "started").exists()  # the idle worker did take the polish that was then not needed
    assert took < 3.0  # measured 1.04 s: (P, 0)'s polish, against the 60 s it would wait
    assert out[P][0].ne_mean_after == 0.012 and out[P][2] is True  # (P, 0)'s polish, not (P, 1)'s
