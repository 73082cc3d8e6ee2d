"""The concealed-effect benchmark (``benchmarks/diagnose``) on a small subset, as CI can afford it.

Cases come from the independent generator (solve_ivp, ``twin.py``), never from the package:
a control with only wrong parameters (a storey stiffness and a gap size off) and an effect
case, each a two-building row under 8 s of El Centro at 200 Hz with 1 % noise, diagnosed
exactly as a user would (``run.run_case``: model, recording and channel map from the folder).
The full benchmark, its confusion matrix and false-alarm rate are in docs/diagnose.md.
"""

import pytest

from benchmarks.diagnose.generate import write_case
from benchmarks.diagnose.run import run_case


@pytest.mark.parametrize("family", ["wrong-parameters", "spatially-varying-input", "inelastic-storey"])
def test_benchmark_case(tmp_path, family):
    key = write_case(tmp_path / "case", family, seed=7, duration=8.0, buildings=2)
    r = run_case(str(tmp_path / "case"))
    print(f"MEASURED benchmark subset {family}: named {r['named'] or 'nothing'}, NE {r['ne_before']:.4f} -> "
          f"{r['ne_after']:.4f} (effect NE {key['effect_ne']:.3f}, {key['impacts']} impacts) in {r['seconds']:.0f} s")
    assert (r["named"] or ["none"])[0] == key["label"]
    assert r["ne_after"] <= 0.5 * r["ne_before"]
    assert r["ne_after"] <= 0.03  # a few times the 1 % noise
    assert (tmp_path / "case" / "report.json").exists() and (tmp_path / "case" / "diagnosed.toml").exists()
