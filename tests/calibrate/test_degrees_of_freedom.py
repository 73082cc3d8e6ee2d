"""The degrees of freedom of calibration's sandwich variance and its 68 % interval.

Kind: closed form.  A residual whose periodogram is flat (an impulse) and a Jacobian made of m
cosines on exact frequency bins, far enough apart that the working model's smoothing sees one at a
time: the variance is a sum of m equal bins of two degrees of freedom each, so Satterthwaite's nu is
exactly 2 m.  Student's t at two degrees of freedom has the closed-form quantile
t = c sqrt(2 / (1 - c^2)), c = 2 Phi(1) - 1.
"""

import math
from types import SimpleNamespace

import numpy as np
import pytest

from seispound.calibrate import fit as F


@pytest.mark.parametrize("m", [1, 3, 8])
def test_nu_is_two_per_bin_the_jacobian_lives_in(m):
    n = 1000
    t = np.arange(n)
    J = sum(np.cos(2 * np.pi * (40 * (j + 1)) * t / n) for j in range(m))[:, None]
    r = np.zeros(n)
    r[0] = 1e-3
    cov, _, _, bins = F._covariance(SimpleNamespace(fun=r, jac=J), [{"A": r}])
    res = F.CalibrationResult(parameters={"x": dict(value=1.0)}, correlation=np.eye(1), ne_before={}, ne_after={},
                              ne_mean_before=0.0, ne_mean_after=0.0, evaluations=0, seconds=0.0, model_text="",
                              n=n, n_eff=n, success=True, message="", dof_terms=(np.array([False]), bins))
    assert abs(res.dof([1.0]) - 2 * m) < 1e-5 * m


def test_half_width_is_students_t():
    c = 2 * F.Z68 - 1
    assert abs(F.interval68(1.0, 2.0) - c * math.sqrt(2 / (1 - c * c))) < 1e-9
    assert abs(F.interval68(0.5, 1e9) - 0.5) < 1e-6  # many degrees of freedom: +- one standard error
    assert F.interval68(0.5, math.inf) == 0.5
