"""Comparison metrics between simulated and recorded signals."""

from __future__ import annotations

import numpy as np

__all__ = ["normalised_error"]


def normalised_error(simulated, recorded) -> float:
    """Normalised error NE of a simulated against a recorded history (seed paper, Eq. 10).

    NE = sqrt(sum (F_m - F_r)^2) / sqrt(sum F_r^2), over the n samples of the same
    time grid, F_m the model's and F_r the recorded value.

    Parameters
    ----------
    simulated, recorded : array_like, shape (n,)
        The two histories on the same time grid (any consistent units).

    Returns
    -------
    float
        NE as a fraction (0.5612 = 56.12 %).
    """
    fm = np.asarray(simulated, dtype=float)
    fr = np.asarray(recorded, dtype=float)
    if fm.shape != fr.shape or fm.ndim != 1:
        raise ValueError(f"histories must be 1-D and of equal length, got {fm.shape} and {fr.shape}")
    den = np.sqrt(np.sum(fr * fr))
    if den == 0.0:
        raise ValueError("the recorded history is identically zero")
    return float(np.sqrt(np.sum((fm - fr) ** 2)) / den)
