"""The held-out runner's ``--collect``: a case whose diagnosis finished in a run that stopped is scored from
its report, and a report older than the set's key (left from another set) is not.  Regression guard."""

from __future__ import annotations

import json
import os

from benchmarks.diagnose.run import collected


def _report(ne_after):
    return {"left_out": [{"physics": "inelastic-storey", "probability": 0.9, "quantities": []}],
            "fit": {"before": 0.5, "after": ne_after}, "noise_ne": 0.01, "hypotheses": {"inelastic-storey": {"ne": 0.02}},
            "instrument_fault": None, "kept_as_given": False, "numerics": {}, "seconds": 12.5}


def test_a_report_written_after_the_key_is_collected_and_an_older_one_is_not(tmp_path):
    for case, ne in (("case-001", 0.02), ("case-002", 0.03)):
        (tmp_path / case).mkdir()
        (tmp_path / case / "report.json").write_text(json.dumps(_report(ne)))
    key_time = os.stat(tmp_path / "case-002" / "report.json").st_mtime
    os.utime(tmp_path / "case-001" / "report.json", (key_time + 10, key_time + 10))
    os.utime(tmp_path / "case-002" / "report.json", (key_time - 10, key_time - 10))
    out = collected(tmp_path, ["case-001", "case-002", "case-003"], key_time)
    assert list(out) == ["case-001"]
    r = out["case-001"]
    assert r["named"] == ["inelastic-storey"] and r["ne_after"] == 0.02 and r["seconds"] == 12.5
    assert r["probability"] == {"inelastic-storey": 0.9} and r["hypotheses"] == {"inelastic-storey": 0.02}
