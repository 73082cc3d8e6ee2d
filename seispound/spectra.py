"""Pseudo-acceleration response spectra of a record and of any floor's absolute acceleration.

PSA(T, xi) = omega^2 max_t |u(t)| of a linear oscillator of period T and damping
ratio xi under the base acceleration (Chopra, Dynamics of Structures, 4th ed.,
Sec. 6.6).  Computed with pyrotd (Kottke, https://github.com/arkottke/pyrotd,
PyPI ``pyrotd``), a maintained library used in strong-motion processing, rather
than a hand-written loop: it solves each oscillator in the frequency domain
(the exact steady-state transfer function on the zero-padded record), and
raises the sampling rate of the record in the frequency domain until every
oscillator frequency lies below 1/5 of the Nyquist frequency, so short periods
carry no time-stepping error.  The record is followed by zeros long enough for
the oscillators' free vibration to decay (4 time constants), so the periodic
extension of the FFT does not wrap it onto the start.  eqsig's Nigam-Jennings time stepping is the
other candidate; pyrotd was chosen for that short-period accuracy.

Default periods: 100 log-spaced values from 0.02 s to 5 s, the range of
design spectra (ASCE 7-22 Ch. 11; Eurocode 8, Sec. 3.2.2), which also spans the
fundamental periods of buildings that pound and the short periods of the
pulses impacts send up a floor.
"""

from __future__ import annotations

import math

import numpy as np

from .errors import InputError

__all__ = ["response_spectrum", "floor_spectrum", "default_periods"]

G = 9.80665


def default_periods() -> np.ndarray:
    """100 log-spaced periods from 0.02 to 5 s [s]."""
    return np.logspace(math.log10(0.02), math.log10(5.0), 100)


def _check(acc, dt, periods, damping, what):
    acc = np.asarray(acc, dtype=float)
    if acc.ndim != 1 or acc.size < 2:
        raise InputError(f"needs a 1-D series of at least 2 samples, got shape {acc.shape}", key=what)
    if not np.isfinite(acc).all():
        raise InputError("has non-finite samples", key=what)
    if not (isinstance(dt, (int, float)) and math.isfinite(dt) and dt > 0):
        raise InputError(f"must be a time step > 0 in s, got {dt!r}", key="dt")
    periods = default_periods() if periods is None else np.atleast_1d(np.asarray(periods, dtype=float))
    if periods.ndim != 1 or not (np.isfinite(periods).all() and (periods > 0).all()):
        raise InputError("must be finite periods > 0 in s", key="periods")
    if not (isinstance(damping, (int, float)) and 0.0 <= damping < 1.0):
        raise InputError(f"must be a damping ratio in [0, 1), got {damping!r}", key="damping")
    return acc, float(dt), periods, float(damping)


def response_spectrum(motion, dt=None, periods=None, damping: float = 0.05, *, name: str = "record"):
    """Pseudo-acceleration response spectrum of a base acceleration.

    Parameters
    ----------
    motion : seispound.motion.Record or array_like, shape (npts,)
        Acceleration [m/s^2] (a Record carries its own dt).
    dt : float, optional
        Time step [s] of an array.
    periods : array_like, shape (np,), optional
        Oscillator periods [s] (default :func:`default_periods`).
    damping : float
        Damping ratio of the oscillators (default 0.05).
    name : str
        What the motion is (stored in the attributes).

    Returns
    -------
    xarray.DataArray, dims ``period``, units m/s^2
        PSA; attrs: damping, method (library and version), source.
    """
    import pyrotd
    import xarray as xr

    if hasattr(motion, "acceleration") and hasattr(motion, "dt"):
        name = motion.provenance.get("file", name) if name == "record" else name
        motion, dt = motion.acceleration, motion.dt if dt is None else dt
    acc, dt, periods, damping = _check(motion, dt, periods, damping, "motion")
    # zeros after the record: the free vibration that follows it (where long-period peaks can fall)
    # must decay before the FFT's periodic extension wraps it onto the start (4 time constants)
    w_min = 2 * math.pi / periods.max()
    decay = 4.0 / (damping * w_min) if damping > 0 else math.inf
    pad = int(math.ceil(max(2.0 * periods.max(), min(decay, 20.0 * periods.max())) / dt))
    spec = pyrotd.calc_spec_accels(dt, np.r_[acc, np.zeros(pad)] / G, 1.0 / periods, osc_damping=damping)
    psa = np.asarray(spec.spec_accel, float) * G
    return xr.DataArray(psa, dims=("period",),
                        coords={"period": ("period", periods, {"units": "s", "long_name": "oscillator period"})},
                        name="psa",
                        attrs={"units": "m/s^2", "long_name": f"pseudo-spectral acceleration, {damping:.0%} damping",
                               "damping": damping, "method": f"pyrotd {pyrotd.__version__} (frequency domain)",
                               "source": str(name)})


def floor_spectrum(ds, building: str, floor: int, periods=None, damping: float = 0.05):
    """Floor response spectrum: the spectrum of a floor's absolute acceleration in a result Dataset.

    Parameters
    ----------
    ds : xarray.Dataset
        A result of :func:`seispound.simulate` (``acceleration`` is absolute).
    building : str
    floor : int
        1-based floor; 0 is the ground (the record on the analysis grid).
    periods, damping
        As in :func:`response_spectrum`.
    """
    if building not in ds.building.values:
        raise InputError(f"no building {building!r}; buildings: {', '.join(map(str, ds.building.values))}",
                         key="building")
    if floor == 0:
        acc, what = ds.ground_acceleration.values, "ground"
    else:
        if not isinstance(floor, (int, np.integer)) or floor not in ds.floor.values or \
                not np.isfinite(ds.acceleration.sel(building=building, floor=floor).values).all():
            raise InputError(f"building {building} has no floor {floor!r}", key="floor")
        acc, what = ds.acceleration.sel(building=building, floor=floor).values, f"{building} floor {floor}"
    dt = float(ds.attrs["dt"])
    da = response_spectrum(acc, dt, periods, damping, name=f"{ds.attrs.get('title', '')}: {what}")
    da.attrs.update(building=str(building), floor=int(floor))
    return da
