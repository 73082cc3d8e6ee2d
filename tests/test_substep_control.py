"""The study behind docs/performance.md's choice of a fixed substep count (``benchmarks.substep_control``).

Its march is checked against the LVe closed form (restitution exactly e for two free bodies, seed
Eqs. 1-3), then the documented comparison is rerun at 16 substeps per impact.  Both schedules are
second order, so a schedule's efficiency is its restitution error times its steps squared: the
fixed count's is the lower for every law (for NIVe by about a tenth, for the others by 1.7-2 times).
"""

import pytest

from benchmarks.substep_control import impact, run


def test_the_march_reaches_the_lve_closed_form():
    """LVe with tension: e = 0.65 exactly in the limit; 8192 substeps within 1e-6 of it, 16 within 0.5 %."""
    fine = impact("LVe", 8192, "uniform")
    assert fine["e"] == pytest.approx(0.65, rel=1e-6)
    assert impact("LVe", 16, "graded")["e"] == pytest.approx(0.65, rel=5e-3)


def test_fixed_count_beats_error_control_on_restitution():
    rows = {(r["law"], r["schedule"]): r for r in run(counts=(16,))}
    for law in ("LVe", "LHC", "NIVe", "Hd"):
        fixed, ctl = rows[law, "graded"], rows[law, "controlled"]
        print(f"MEASURED {law} at 16 substeps: restitution error fixed {fixed['e_err']:+.2e} in {fixed['steps']} "
              f"steps, controlled {ctl['e_err']:+.2e} in {ctl['steps']}")
        assert abs(fixed["e_err"]) < abs(ctl["e_err"])
        assert abs(fixed["e_err"]) * fixed["steps"] ** 2 < abs(ctl["e_err"]) * ctl["steps"] ** 2
