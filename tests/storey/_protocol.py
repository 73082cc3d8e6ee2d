"""Shared by the storey-law tests: a drift history walked through the material protocol, and the history."""

import numpy as np

from seispound.integrate._material import N_STATE, material_commit, material_trial
from seispound.storey import codes as C


def growing_drift(t, dy):
    """(drift [m], its rate [m/s]) of a 1 Hz cycle growing to 4 dy over 3 s, then steady."""
    amp = 4 * dy * np.minimum(t / 3.0, 1.0)
    return amp * np.sin(2 * np.pi * t), 4 * dy / 3.0 * (t < 3.0) * np.sin(2 * np.pi * t) \
        + amp * 2 * np.pi * np.cos(2 * np.pi * t)


def walk(par, drift):
    """The force [N] of a Bouc-Wen storey (parameter table ``par``, one row) at each drift of ``drift``, each
    trial committed; and the committed state at the end."""
    committed, trial = np.zeros((1, N_STATE)), np.zeros((1, N_STATE))
    out = np.zeros(drift.size)
    for i, x in enumerate(drift):
        out[i] = material_trial(C.BOUC_WEN, par, committed, trial, 0, x, 0.0)[0]
        material_commit(committed, trial, 0)
    return out, committed
