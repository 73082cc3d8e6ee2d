"""A calibration that ends far above the sensor noise says that its values are the model's closest, not
measurements; one near the noise does not.  Regression guard of the summary's words."""

from __future__ import annotations

import numpy as np

from seispound.calibrate.fit import FAR, CalibrationResult


def _result(ne_after, noise):
    par = dict(value=1.0, start=1.0, stderr=0.01, half68=0.01, lo=0.1, hi=10.0, at_bound=False, identified=True)
    return CalibrationResult(parameters={"building.A.storey_stiffness": par}, correlation=np.eye(1), ne_before={},
                             ne_after={}, ne_mean_before=0.5, ne_mean_after=ne_after, evaluations=10, seconds=1.0,
                             model_text="", n=1000, n_eff=100.0, success=True, message="", noise_ne=noise)


def test_far_above_the_noise_the_summary_says_the_intervals_assume_the_form():
    far = _result(FAR * 0.01 * 1.5, 0.01).summary()
    assert "4.5 times above what the sensor noise leaves" in far
    assert "their intervals hold for a model of the right form only" in far
    near = _result(FAR * 0.01 * 0.9, 0.01).summary()
    assert "times above what the sensor noise leaves" not in near and "right form only" not in near
