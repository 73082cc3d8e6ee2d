"""The 100 000-run study benchmark scaled down to 100 runs: a real kill -9 and resume, its report's fields.

``python -m benchmarks.study_scale --runs 100`` checks the contact substeps on a sample, runs the study
uninterrupted, then again killed (SIGKILL to the process group) at 40 % of the runs and resumed, and times
the queries (docs/studies.md, "A study of 100 000 runs"); about 15 s.  Its run against a cluster's address
is left out here: tests/study/test_study_dask.py runs one.
"""

import json
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def test_scaled_down_study_resumes_after_a_kill_to_the_uninterrupted_store(tmp_path):
    out = tmp_path / "scale.json"
    run = subprocess.run([sys.executable, "-m", "benchmarks.study_scale", "--runs", "100", "--repeat", "1",
                          "--cluster-workers", "0",  # the address of a cluster: test_study_dask.py
                          "--folder", str(tmp_path / "study"), "--json", str(out)],
                         cwd=REPO, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stdout + run.stderr
    r = json.loads(out.read_text())
    assert r["ok"] and r["runs"] == 100 and r["shape"] == [4, 5, 5, 1]
    assert r["run_dims"] == ["record", "law", "gap_size", "stiffness_A"] and r["contact_substeps"] == 32
    one = r["single_run"]
    assert one["run_s"] > 0 and one["run_default_tolerance_s"] > 0 and r["store_rewrite_s"] > 0
    assert one["substeps"] == {"32": one["runs_timed"]}  # as the model gives
    assert sum(one["substeps_default_tolerance"].values()) == one["runs_timed"]
    c = r["substeps_check"]
    assert c["runs"] == c["done"] == 4 * 5 * 2 * 1 * 4 and c["reference_substeps"] == 256
    assert sorted(c["errors"], key=int) == ["8", "16", "32"]
    assert all(0 <= e["median"] <= e["max"] < 0.05 for errs in c["errors"].values() for e in errs.values())
    u = r["uninterrupted"]
    assert u["rc"] == 0 and u["ran"] == 100 and u["wall_s"] > 0 and u["runs_per_s"] > 0
    assert u["maxrss_main_mb"] > 0 and u["maxrss_worker_mb"] > 0 and u["workers_cpu_s"] > 0
    assert u["store"]["done"] == 100 and u["store"]["failed"] == 0 and u["store"]["store_bytes"] > 0
    k = r["kill_and_resume"]
    assert k["killed"]["rc"] == -9 and k["killed"]["survivors"] == []
    assert 30 <= k["stored_at_kill"] < 100  # killed at about 40 (the journal's size)
    assert k["resumed"]["rc"] == 0 and k["resumed"]["ran"] == 100 - k["stored_at_kill"] and k["ran_twice"] == 0
    assert k["store"]["done"] == 100 and k["store"]["failed"] == 0 and not k["store"]["journal_left"]
    assert k["identical_to_uninterrupted"]
    assert r["cluster"] is None
    q = r["queries"]
    assert q["open_study_s"] > 0
    for name in ("overview", "max amplification per law and gap size", "safe gap per law and stiffness",
                 "one record's runs, as CSV"):
        assert q[name]["cli_s"] > 0 and q[name]["python_s"] > 0 and q[name]["command"].startswith("seispound query")
