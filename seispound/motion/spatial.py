"""A ground motion per building: the row's record delayed (wave passage) and low-passed (loss of coherency).

Buildings of a row stand metres to tens of metres apart; a seismic wave
crossing them with apparent velocity V reaches each at its own time
(delay = position / V), and the motions lose coherency with distance, first at
high frequencies.  Here a building's motion is the row's record shifted by its
delay and, optionally, low-passed with a zero-phase Butterworth filter
(forward and backward, ``scipy.signal.sosfiltfilt``: no phase shift, so the
delay stays exactly the stated one; the amplitude response is the square of
the filter's, -6 dB at the cut-off).  Kinematic soil-structure interaction is
not modelled.  This is the simplest model of spatial variation (Der Kiureghian
1996, EESD 25:1219-1231, for the coherency it stands in for: wave passage
exactly, incoherence only as a loss of high frequencies).
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError

__all__ = ["delayed", "ground_motion_integrals", "lowpassed", "variant"]


LOST_SHARE = 0.05  # an advanced record whose cut start reaches this share of its peak is warned about


def delayed(ag, dt: float, delay: float, rise: float = 0.0) -> np.ndarray:
    """The motion ``ag`` (nt,) [m/s^2], sampled at k dt, as it arrives ``delay`` [s] later (earlier if < 0).

    ag_b(t) = ag(t - delay), linear between samples (the kernel's own
    interpolation of a record); zero before the record starts and after it ends.
    A record whose first sample is not zero (a triggered recording) is read as
    rising linearly from zero over ``rise`` [s] before it (the record's own step):
    without it the arrival would ramp over one *analysis* step, so that the
    input, and a pounding sequence that is sensitive to it, changed with dt
    (El Centro's first sample, 0.015 m/s^2, delayed 0.05 s: floor accelerations
    4.1 % apart at 5 ms and 0.5 ms; 0.13 % with the same input; derived here, not
    read).  ``rise`` = 0 keeps the ramp of one analysis step.
    """
    ag = np.asarray(ag, dtype=float)
    t = np.arange(ag.size) * dt
    if delay > 0.0 and rise > 0.0:
        return np.interp(t - delay, np.concatenate(([-rise], t)), np.concatenate(([0.0], ag)), left=0.0, right=0.0)
    return np.interp(t - delay, t, ag, left=0.0, right=0.0)


def lowpassed(ag, dt: float, cutoff: float, order: int = 2, key: str = "ground_motion.lowpass") -> np.ndarray:
    """Zero-phase Butterworth low-pass of ``ag`` (nt,): ``order`` poles at ``cutoff`` [Hz], forward and backward.

    scipy.signal.butter (second-order sections) and sosfiltfilt with its
    default odd-extension padding.  The cut-off must lie below the Nyquist
    frequency 1 / (2 dt) of the analysis grid.
    """
    from scipy.signal import butter, sosfiltfilt

    nyquist = 0.5 / dt
    if not 0.0 < cutoff < nyquist:
        raise InputError(f"must lie between 0 and the Nyquist frequency {nyquist:g} Hz of analysis.dt = {dt:g} s, "
                         f"got {cutoff!r}", key=key)
    sos = butter(order, cutoff, btype="low", fs=1.0 / dt, output="sos")
    return sosfiltfilt(sos, np.asarray(ag, dtype=float))


def variant(ag, dt: float, delay: float = 0.0, lowpass: float | None = None, order: int = 2,
            key: str = "ground_motion", rise: float = 0.0) -> tuple[np.ndarray, list[str]]:
    """``ag`` delayed and low-passed; returns the samples and the provenance steps (empty for neither).

    ``rise`` [s]: the record's own step, over which a delayed record rises from zero (:func:`delayed`).
    """
    out = np.asarray(ag, dtype=float)
    steps = []
    if delay > 0:
        out = delayed(out, dt, delay, rise)
        steps.append(f"delayed by {delay:g} s (wave passage; zero before the record arrives)")
    elif delay < 0:
        # a negative delay is allowed: the wave reaches this building first, so its motion at time t is the
        # record's at t + |delay|; the record's first |delay| s fall before the analysis starts and are lost
        lost = out[: int(round(-delay / dt))]
        if lost.size and np.max(np.abs(lost)) > LOST_SHARE * np.max(np.abs(out)):
            import warnings

            from ..plausibility import PlausibilityWarning

            warnings.warn(f"{key}.delay: {delay:g} s advances the record, and its first {-delay:g} s, which reach "
                          f"{np.max(np.abs(lost)) / np.max(np.abs(out)):.0%} of its peak, are cut for this building",
                          PlausibilityWarning, stacklevel=2)
        out = delayed(out, dt, delay)
        steps.append(f"advanced by {-delay:g} s (the wave reaches this building first; the record's first "
                     f"{-delay:g} s are cut, zero after it ends)")
    if lowpass is not None:
        out = lowpassed(out, dt, lowpass, order, key=f"{key}.lowpass")
        steps.append(f"low-passed: zero-phase Butterworth, order {order} forward and backward, {lowpass:g} Hz "
                     "(loss of coherency)")
    return out, steps


def ground_motion_integrals(ag, dt):
    """Ground velocity [m/s] and displacement [m] of each motion row at the samples, shapes (nm, nt).

    Exact integrals, from rest at t = 0, of the acceleration as the kernel sees
    it, linear between samples: v_k+1 = v_k + dt (a_k + a_k+1) / 2,
    u_k+1 = u_k + dt v_k + dt^2 (a_k / 3 + a_k+1 / 6).
    """
    ag = np.atleast_2d(ag)
    vg = np.zeros_like(ag)
    ug = np.zeros_like(ag)
    vg[:, 1:] = np.cumsum(0.5 * dt * (ag[:, :-1] + ag[:, 1:]), axis=1)
    ug[:, 1:] = np.cumsum(dt * vg[:, :-1] + dt * dt * (ag[:, :-1] / 3.0 + ag[:, 1:] / 6.0), axis=1)
    return vg, ug
