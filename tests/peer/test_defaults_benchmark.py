"""The defaults benchmark's quick mode (``python -m benchmarks.peer.defaults --quick``): its report's structure.

The pair under the first 4 s of El Centro, seispound at its defaults against OpenSeesPy (reference at
2.5e-4 s), one repeat; a few seconds once the kernels are compiled.  Timings are not asserted (the
machine is shared), only what the run reports and that the parts of the split add up.
"""

import json
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module", autouse=True)
def opensees():
    try:
        from benchmarks.peer.opensees import import_opensees

        return import_opensees()
    except (ImportError, RuntimeError) as exc:  # the peer extra is not installed here
        pytest.skip(f"openseespy unavailable ({exc}); install the 'peer' extra")


def test_quick_defaults_benchmark(tmp_path):
    out = tmp_path / "defaults.json"
    run = subprocess.run([sys.executable, "-m", "benchmarks.peer.defaults", "--quick", "--out", str(out)],
                         cwd=REPO, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    r = json.loads(out.read_text())
    assert r["quick"] and r["repeat"] == 1 and len(r["cases"]) == 1
    c = r["cases"][0]
    assert c["record_dt"] == 0.01 and c["reference_dt"] == r["opensees_steps"][-1] == 2.5e-4
    assert c["opensees"]["dt"] in r["opensees_steps"] and c["opensees_pick_in_issue_grid"]
    sp = c["seispound"]
    n = sp["contact_substeps"]
    assert n >= 4 and n & (n - 1) == 0 and sp["tolerance_runs"] >= 2 and sp["impacts"] > 0
    assert sp["within"] and abs(sp["error"]) <= 0.01 and 0 < sp["peak_error_estimate"] <= 0.01
    runs = c["split"]["runs"]
    assert len(runs) == sp["tolerance_runs"] and sum(x["final"] for x in runs) == 1
    assert next(x for x in runs if x["final"])["contact_substeps"] == n
    s = c["split"]
    assert s["python_s"] > 0 and s["kernel_final_s"] > 0 and s["kernel_check_s"] > 0
    assert abs(sum(s["parts_s"].values()) - s["python_s"]) <= 1e-9 + 1e-6 * s["python_s"]
    assert {"as is", "kernel of the final run only", "without the check's extra integrations",
            "without the Python around the kernels"} <= set(c["ratio"])
