"""Normalised error NE, seed paper Eq. 10."""

import numpy as np
import pytest

from seispound.results import normalised_error


def test_ne_of_identical_histories_is_zero():
    f = np.sin(np.linspace(0, 3, 50))
    assert normalised_error(f, f) == 0.0


def test_ne_closed_forms():
    fr = np.array([3.0, 4.0])  # |F_r| = 5
    assert normalised_error(np.zeros(2), fr) == pytest.approx(1.0)  # a model that predicts nothing: 100 %
    assert normalised_error(2 * fr, fr) == pytest.approx(1.0)
    assert normalised_error(fr + np.array([0.3, -0.4]), fr) == pytest.approx(0.1)


def test_ne_of_a_scaled_and_shifted_pulse():
    # F_r = sin over a half period, F_m = 0.8 F_r: NE = 0.2 exactly
    t = np.linspace(0, np.pi, 1001)
    assert normalised_error(0.8 * np.sin(t), np.sin(t)) == pytest.approx(0.2, rel=1e-12)


def test_ne_rejects_mismatched_or_zero_records():
    with pytest.raises(ValueError):
        normalised_error(np.ones(3), np.ones(4))
    with pytest.raises(ValueError):
        normalised_error(np.ones(3), np.zeros(3))
