"""The integrator's outputs on several rows and laws equal those pinned in tests/data/kernel_reference.npz.

The file was written by ``python -m tests.integrate.kernel_reference`` (the energy array without its
hysteretic column, zero on these rows); a refactoring must reproduce it to 1e-12 relative to each
array's largest entry.  It was rewritten, by an unchanged integrator, when numpy 2.4 / scipy 1.17 /
numba 0.68 moved its outputs by up to 3e-9 on the row of three under NIVe (pounding amplifies
round-off differences of 1e-16: this is a regression guard of one environment, not verification),
and again, by an unchanged integrator (the session's first commit fails the old file the same way), when a fresh
install of numpy 2.4.6 / scipy 1.17.1 / numba 0.68.1 moved them by up to 2.8e-9 on that row (7.6e-11 in its
displacements); the rewritten file pins the kernel's peak forces as they are now.
Peak forces (per gap and per impact) are the one deliberate change since: the pinned ones are
the largest force sample, the kernel's now the vertex of the parabola through the samples around
it (``_contact._peak_through``), never below the largest sample (at most 2 % above it here, on a
grazing impact whose largest sample missed 26 % of the converged peak; closer to the converged
peaks: tests/verification/test_convergence.py).
"""

import numpy as np
import pytest

from tests.integrate.kernel_reference import FILE, cases, run

CASES = cases()
REFERENCE = np.load(FILE)
PEAKS = ("peak_force", "impacts.fmax")


@pytest.mark.parametrize("name", sorted(CASES))
def test_outputs_equal_the_pinned_reference(name):
    got = run(CASES[name])
    for key, value in got.items():
        ref = REFERENCE[f"{name}/{key}"]
        if key == "energy":  # the hysteretic column came later: zero on rows without history
            assert value.shape[1] == ref.shape[1] + 1 and not np.any(value[:, -1]), key
            value = value[:, :-1]
        assert value.shape == ref.shape, (key, value.shape, ref.shape)
        if key in PEAKS:  # the largest sample then, the interpolated peak now: never below it
            ok = ~np.isnan(ref)
            assert np.all(value[ok] >= ref[ok]), key
            assert np.all(value[ok] <= ref[ok] * 1.05 + 1e-9 * np.max(ref[ok], initial=0.0)), key
            continue
        if key == "impacts.gap":
            np.testing.assert_array_equal(value, ref)
            continue
        # an impact still in progress at the end has NaN exit velocity and duration
        np.testing.assert_array_equal(np.isnan(value), np.isnan(ref), err_msg=f"{name} {key}: NaN entries")
        value, ref = value[~np.isnan(ref)], ref[~np.isnan(ref)]
        scale = max(float(np.max(np.abs(ref), initial=0.0)), 1e-300)
        err = float(np.max(np.abs(value - ref), initial=0.0)) / scale
        assert err <= 1e-12, f"{name} {key}: relative difference {err:.3g}"
