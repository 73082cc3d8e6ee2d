"""The held-out scorer counts quantities within 15 % over all identified ones and, apart, over those the report
reads as measurements (not marked ``form_limited``).  Regression guard of the benchmark's arithmetic."""

from __future__ import annotations

from benchmarks.diagnose.score_suite import markdown, score


def _q(name, value, form_limited=None, stderr=0.001):
    q = {"name": name, "value": value, "stderr": stderr}
    if form_limited:
        q["form_limited"] = form_limited
    return q


def test_marked_quantities_are_counted_apart():
    truth = {"buildings": {"A": {"yield_drift": 0.010}, "B": {"yield_drift": 0.020}, "C": {"yield_drift": 0.030}}}
    key = {"case-001": {"labels": ["inelastic-storey"], "family": "inelastic-storey", "form": "takeda",
                        "quantities": truth}}
    results = {"case-001": {"named": ["inelastic-storey"], "ne_before": 1.0, "ne_after": 0.1, "noise_ne": 0.01,
                            "seconds": 1.0, "probability": {"inelastic-storey": 1.0}, "quantities": {
                                "inelastic-storey": [_q("A: yield drift", 0.0105),  # +5 %, a measurement
                                                     _q("B: yield drift", 0.026, 12.0),  # +30 %, marked
                                                     _q("C: yield drift", 0.031, 12.0),  # +3 %, marked
                                                     _q("A: post-yield stiffness ratio", 0.1),  # no counterpart
                                                     _q("C: yield drift", 0.5, stderr=None)]}}}  # not identified
    s = score(key, results)
    assert (s["quantities_within_15"], s["quantities_compared"]) == (2, 3)
    assert (s["measured_within_15"], s["measured_compared"]) == (1, 1)
    text = markdown(key, results)
    assert "of them read as measurements (not marked form-limited): 1 of 1 (100 %) within 15 %" in text
    assert "| case-001 | B: yield drift | 0.026 | 0.02 | +30.0 % | 12.0 |" in text
    assert "| case-001 | A: yield drift | 0.0105 | 0.01 | +5.0 % | - |" in text
