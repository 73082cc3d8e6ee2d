"""The peak response quantities engineers report, with and without pounding: one code path.

``simulate`` (the result Dataset) and the study worker (the study store) both
call :func:`dof_peaks` on each run and :func:`amplifications` on a run and its
no-pounding twin, so the two can never disagree.

Quantities, per degree of freedom (a floor; the storey is the one below it):

``displacement`` [m]
    max |u| relative to the ground over every step taken (the kernel's own peak).
``acceleration`` [m/s^2]
    max |a| of the absolute floor acceleration at the analysis instants, as a
    recording sampled at 1/dt would give it: an impact spike shorter than dt is
    under-sampled (refine ``analysis.dt`` to resolve it).
``drift`` [m], ``drift_ratio`` [1]
    max |u_i - u_(i-1)| (the ground below floor 1) at the analysis instants, and
    the same divided by the storey height (storey drift and drift ratio as in
    ASCE 7-22 Sec. 12.8.6).
``storey_shear`` [N]
    max |k_i (u_i - u_(i-1))|, the force in the storey's spring: the elastic storey
    shear of a shear building (Chopra, Dynamics of Structures, 4th ed., Ch. 13:
    the storey shears of the equivalent static forces equal k times drift).  The stiffness-
    proportional dashpot force is left out, as design storey shears leave it out.
"""

from __future__ import annotations

import numpy as np

__all__ = ["PEAKS", "dof_peaks", "drift_history", "run_drift", "amplifications", "storey_arrays"]

#: (name, units, long name) of each peak quantity, per DOF.
PEAKS = [
    ("displacement", "m", "peak |displacement| relative to the ground"),
    ("acceleration", "m/s^2", "peak |absolute floor acceleration| at the analysis instants"),
    ("drift", "m", "peak |inter-storey drift| of the storey below the floor"),
    ("drift_ratio", "1", "peak |inter-storey drift| / storey height of the storey below the floor"),
    ("storey_shear", "N", "peak |storey shear| (storey spring force: k x drift, or a yielding storey's force) of the "
                          "storey below the floor"),
]


def storey_arrays(system, buildings) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per DOF: index of the DOF below (-1: the ground), storey height [m], storey stiffness [N/m]; (n,) each."""
    n = system.n_dof
    f0 = system.dof_floor - 1
    below = np.where(f0 > 0, np.arange(n) - 1, -1)
    height = np.array([buildings[b].storey_heights[f] for b, f in zip(system.dof_building, f0)], float)
    stiff = np.array([buildings[b].storey_stiffness[f] for b, f in zip(system.dof_building, f0)], float)
    return below, height, stiff


def drift_history(u, below) -> np.ndarray:
    """Inter-storey drift u_i - u_below(i) (the ground below a first floor) [m], shape of ``u`` (nt, n).

    DOFs are numbered floor after floor within a building, so the DOF below is the previous one.
    """
    drift = np.empty_like(u)
    drift[:, 0] = u[:, 0]
    np.subtract(u[:, 1:], u[:, :-1], out=drift[:, 1:])
    ground = below < 0
    drift[:, ground] = u[:, ground]
    return drift


def run_drift(raw, below) -> np.ndarray:
    """A run's storey deformations [m], (nt, n): the floor view's own (``raw.drift``, which knows a
    foundation's rocking) where it set them, else :func:`drift_history` of the displacements."""
    return raw.drift if raw.drift is not None else drift_history(raw.displacement, below)


FOLD = 64  # rows folded into one for a column reduction


def _column_reduce(ufunc, x) -> np.ndarray:
    """ufunc.reduce over the rows of x (nt, n), nt >= 1: the same values as ``ufunc.reduce(x, axis=0)``.

    A reduction over the rows of a narrow array runs one short vector operation per row (55 us
    for 2001 x 8); the rows are first folded FOLD at a time into rows FOLD times as long (9 us).
    """
    nt, n = x.shape
    k = nt // FOLD
    if k == 0 or not x.flags.c_contiguous:
        return ufunc.reduce(x, axis=0)
    out = ufunc.reduce(ufunc.reduce(x[:k * FOLD].reshape(k, FOLD * n), axis=0).reshape(FOLD, n), axis=0)
    return ufunc(out, ufunc.reduce(x[k * FOLD:], axis=0)) if nt > k * FOLD else out


def _peak_abs(x) -> np.ndarray:
    """max_t |x| per column, without an |x| temporary."""
    if x.shape[0] == 0:
        return np.zeros(x.shape[1])
    return np.maximum(_column_reduce(np.maximum, x), -_column_reduce(np.minimum, x))


def dof_peaks(raw, below, height, stiff, drift=None) -> dict:
    """Peak quantities of one run per DOF (module docstring), from its histories.

    Parameters
    ----------
    raw : RawResult
        With histories (``store_history=True``).
    below, height, stiff : ndarray, shape (n,)
        From :func:`storey_arrays`.
    drift : ndarray, shape (nt, n), optional
        :func:`run_drift` of the run, if the caller has it.

    Returns
    -------
    dict of name -> ndarray (n,)
    """
    if drift is None:
        drift = run_drift(raw, below)
    peak_drift = _peak_abs(drift)
    shear = peak_drift * stiff  # an elastic storey's k is constant in time: max |k d| = k max |d|
    if raw.storey_force is not None and raw.storey_dofs.size:  # yielding storeys: their own force
        shear[raw.storey_dofs] = _peak_abs(raw.storey_force)
    return {
        "displacement": np.asarray(raw.peak_displacement, float).copy(),
        "acceleration": _peak_abs(raw.acceleration),
        "drift": peak_drift,
        "drift_ratio": peak_drift / height,
        "storey_shear": shear,
        "residual_drift": drift[-1].copy() if drift.shape[0] else np.zeros(drift.shape[1]),
    }


def amplifications(peaks: dict, peaks_twin: dict | None) -> dict:
    """Each peak with pounding over the same without, per DOF (NaN where the twin's peak is 0 or absent)."""
    out = {}
    for name, _, _ in PEAKS:
        p = peaks[name]
        p0 = None if peaks_twin is None else peaks_twin[name]
        if p0 is None:
            out[name] = np.full_like(p, np.nan)
            continue
        with np.errstate(divide="ignore", invalid="ignore"):
            out[name] = np.where(p0 > 0, p / p0, np.nan)
    return out
