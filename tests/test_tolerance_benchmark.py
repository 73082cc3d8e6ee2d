"""The tolerance benchmark's quick mode: its report's structure, and each quick case within its tolerance.

``python -m benchmarks.tolerance --quick`` runs two short strong-pounding pairs (Hd, LVe) at 0.1 %, 1 % and
5 % against a 1024-substep reference (docs/tolerance.md); a few seconds once the kernels are compiled.
"""

import json
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
TOLERANCES = [0.001, 0.01, 0.05]
ERRORS = ("force_largest", "force_gaps", "acceleration", "displacement")


def test_quick_tolerance_benchmark_meets_each_tolerance(tmp_path):
    out = tmp_path / "tolerance.json"
    run = subprocess.run([sys.executable, "-m", "benchmarks.tolerance", "--quick", "--json", str(out)],
                         cwd=REPO, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    r = json.loads(out.read_text())
    assert r["quick"] and r["tolerances"] == TOLERANCES and r["reference_substeps"] == 1024
    assert [c["case"] for c in r["cases"]] == ["quick pair 3+5 Hd", "quick pair 3+5 LVe"]
    for c in r["cases"]:
        ref = c["reference"]
        assert ref["driver"] == "fast" and ref["dt"] == ref["model_dt"] == 0.005 and ref["impacts"] > 10
        assert ref["gaps_hit"] == ref["n_gap"] == 3
        assert ref["converged"] and ref["worst_check"] <= 1e-4  # 512, 2048 substeps and dt / 4 agree
        runs = c["runs"]
        assert [x["tolerance"] for x in runs] == TOLERANCES
        substeps = [x["substeps"] for x in runs]
        assert substeps == sorted(substeps, reverse=True) and substeps[0] > substeps[-1]  # fewer as it loosens
        for x in runs:
            tol = x["tolerance"]
            assert x["substeps_from"] == "tolerance" and x["attr_tolerance"] == tol
            assert x["substeps"] >= 4 and x["substeps"] & (x["substeps"] - 1) == 0  # a power of two
            assert 0 < x["estimate"] <= 0.5 * tol  # what the rule promises of its estimate
            assert 0 < x["peak_estimate"] <= tol and x["runs"] >= 2  # and of the run's own check
            assert x["worst"] == max(x[k] for k in ERRORS)
            assert x["worst"] <= tol and x["within"], (c["case"], tol, {k: x[k] for k in ERRORS})
            assert x["seconds"] > 0 and x["steps"] >= 1200  # 6 s at 5 ms
        assert runs[1]["cost_ratio"] == 1.0 and runs[1]["steps_ratio"] == 1.0
        # more substeps, more steps (5 % may refine to 1 %'s: a check that cannot coarsen refines)
        assert runs[0]["steps"] > runs[1]["steps"] >= runs[2]["steps"]
