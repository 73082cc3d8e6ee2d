"""The benchmark module runs and reports consistent figures (a smoke test, not a timing test)."""

import json
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def test_bench_reports_every_figure_and_consistent_ratios():
    out = subprocess.run([sys.executable, "-m", "benchmarks.canonical", "--repeat", "1", "--json"],
                         cwd=REPO, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    r = json.loads(out.stdout)
    assert r["n_dof"] == 8 + 12 + 6 and r["n_gap"] == 8 + 6 and r["nsteps"] == 8000
    assert r["impacts"] > 0 and r["steps_taken"] > r["nsteps"]  # contact substeps were taken
    for key in ("run_s", "pounding_kernel_s", "twin_kernel_s", "simulate_s", "bare_loop_s"):
        assert r[key] > 0
    assert abs(r["run_over_bare"] - r["run_s"] / r["bare_loop_s"]) < 1e-12
    assert abs(r["ns_per_dof_step_bare"] - r["bare_loop_s"] / (8000 * 26) * 1e9) < 1e-9
    assert 0 < r["free_flight_steps"] < r["steps_taken"] and r["rejected_steps"] >= 0
    assert abs(r["ns_per_dof_step_taken_pounding"] - r["pounding_kernel_s"] / (r["steps_taken"] * 26) * 1e9) < 1e-9
