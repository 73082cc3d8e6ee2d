"""Ground-motion records: reading, unit conversion and preparation for analysis.

A :class:`Record` holds one component of ground acceleration in SI units
(m/s²) on a uniform time grid, plus a provenance dictionary that states where
the samples came from and every processing step applied since.  Records are
read with :func:`read_record`, which goes through plain :func:`obspy.read`, so
every waveform format ObsPy reads works, and PEER ``.AT2`` files work through
the :mod:`seispound.motion.at2` plugin.

Standard gravity, used to convert records in g, is the conventional value
g_n = 9.80665 m/s² adopted by the 3rd General Conference on Weights and
Measures (CGPM, 1901; BIPM SI Brochure, 9th ed., 2019).
"""

from __future__ import annotations

import copy
import glob
import hashlib
import math
import numbers
import os
from dataclasses import dataclass, field
from fractions import Fraction

import numpy as np
import obspy
import scipy.signal

from seispound.errors import InputError

__all__ = ["G_STANDARD", "Record", "read_record", "ground_acceleration", "on_analysis_grid",
           "record_from_samples", "UNIT_FACTORS"]

from seispound.motion.units import G_STANDARD, UNIT_FACTORS, _canonical_units

# Largest denominator accepted when expressing a coarsening ratio as up/down
# for polyphase resampling; larger ones mean an unusual analysis step.
_MAX_RATIO_DENOMINATOR = 1000
# Anti-alias FIR for coarsening: Kaiser window (beta 8.6, about -87 dB
# stopband) with 2 * 40 * max(up, down) + 1 taps.
_KAISER_BETA = 8.6
_HALF_TAPS_PER_PHASE = 40
# Relative tolerance for "same time step" and for grid-length rounding.
_RTOL = 1e-9


def _fmt(x: float) -> str:
    return f"{x:.10g}"


@dataclass(frozen=True, eq=False)
class Record:
    """One component of ground acceleration on a uniform time grid.

    Instances are immutable: every processing method returns a new Record and
    appends a sentence describing the step to ``provenance["processing"]``.

    Parameters
    ----------
    acceleration : numpy.ndarray, shape (npts,)
        Ground acceleration in m/s², float64; sample ``i`` is at ``t = i * dt``.
        Stored as a read-only copy.
    dt : float
        Time step in s, > 0.
    provenance : dict
        Where the record came from.  :func:`read_record` fills ``file``,
        ``sha256``, ``format``, ``station``, ``component``, ``event``, ``npts``
        and ``dt_original`` (of the file, s), ``units`` (of the file),
        ``calibration``, ``scale`` (total factor applied by the user),
        ``trace`` (ObsPy trace id) and ``processing`` (list of str).

    Raises
    ------
    InputError
        If the acceleration is not a finite 1-D array of at least 2 samples or
        dt is not positive and finite.
    """

    acceleration: np.ndarray
    dt: float
    provenance: dict = field(default_factory=dict)

    def __post_init__(self):
        file = self.provenance.get("file")
        acc = np.array(self.acceleration, dtype=np.float64)  # own copy
        if acc.ndim != 1 or acc.size < 2:
            raise InputError(
                f"a record needs a 1-D series of at least 2 samples, got shape {acc.shape}",
                file=file, key="data")
        bad = np.flatnonzero(~np.isfinite(acc))
        if bad.size:
            raise InputError(
                f"sample {bad[0]} is {float(acc[bad[0]])}; all samples must be finite",
                file=file, key="data")
        dt = _positive_finite(self.dt, "dt", file)
        acc.setflags(write=False)
        prov = copy.deepcopy(dict(self.provenance))
        prov.setdefault("processing", [])
        object.__setattr__(self, "acceleration", acc)
        object.__setattr__(self, "dt", dt)
        object.__setattr__(self, "provenance", prov)

    # ------------------------------------------------------------ properties
    @property
    def npts(self) -> int:
        """Number of samples."""
        return int(self.acceleration.size)

    @property
    def time(self) -> np.ndarray:
        """Sample times ``i * dt`` in s, shape (npts,)."""
        return np.arange(self.npts) * self.dt

    @property
    def duration(self) -> float:
        """Time of the last sample, ``(npts - 1) * dt``, in s."""
        return (self.npts - 1) * self.dt

    @property
    def pga(self) -> float:
        """Peak ground acceleration ``max |a|`` in m/s²."""
        return float(np.max(np.abs(self.acceleration)))

    # ------------------------------------------------------------ processing
    def _derived(self, acceleration, dt, step: str, **updates) -> "Record":
        prov = copy.deepcopy(self.provenance)
        prov.update(updates)
        prov["processing"] = list(prov.get("processing", [])) + [step]
        return Record(acceleration, dt, prov)

    def resampled(self, dt: float) -> "Record":
        """Return the record on a new time step *dt* (s).

        * Finer step (``dt < self.dt``, e.g. an analysis step that divides the
          record step): linear interpolation onto ``t = 0, dt, ...`` up to the
          last record sample.  Linear variation of the excitation between
          samples is also what the Newmark-beta step assumes, so this adds no
          content the integrator would not assume anyway.
        * Coarser step: polyphase resampling with
          :func:`scipy.signal.resample_poly` by ``up/down = self.dt/dt``
          (a rational with denominator <= 1000).  The anti-alias low-pass is
          a linear-phase FIR (:func:`scipy.signal.firwin`, Kaiser window
          beta = 8.6, ``80 * max(up, down) + 1`` taps) with cutoff at the new
          Nyquist frequency ``1/(2 dt)``, applied centred, i.e. with zero phase
          shift; content below about 0.8 of the new Nyquist frequency passes
          with relative error ~1e-5.  The samples within about
          ``40 * dt`` of either end feel the implicit zero padding.  The
          output is cut to the record's duration.
        * Same step (to 1e-9 relative): the record itself is returned.

        Parameters
        ----------
        dt : float
            New time step in s, > 0.

        Returns
        -------
        Record
            New record; ``provenance["processing"]`` gains one entry.

        Raises
        ------
        InputError
            Key ``dt`` if dt is not positive and finite, or if a coarser dt is
            not a rational multiple (denominator <= 1000) of the record step.
        """
        file = self.provenance.get("file")
        dt = _positive_finite(dt, "dt", file)
        if math.isclose(dt, self.dt, rel_tol=_RTOL):
            return self
        n_new = int(math.floor(self.duration / dt * (1 + _RTOL))) + 1
        if dt < self.dt:
            t_new = np.arange(n_new) * dt
            acc = np.interp(t_new, self.time, self.acceleration)
            step = (f"resampled from dt={_fmt(self.dt)} s to dt={_fmt(dt)} s by linear "
                    "interpolation (upsampling)")
            return self._derived(acc, dt, step)

        ratio = Fraction(self.dt / dt).limit_denominator(_MAX_RATIO_DENOMINATOR)
        up, down = ratio.numerator, ratio.denominator
        if not math.isclose(self.dt * down / up, dt, rel_tol=_RTOL):
            raise InputError(
                f"cannot resample from dt={_fmt(self.dt)} s to dt={_fmt(dt)} s: the "
                f"ratio is not a fraction with denominator <= {_MAX_RATIO_DENOMINATOR}; "
                "choose an analysis step that is a simple multiple or fraction of the "
                "record step", file=file, key="dt")
        # scipy's default filter (Kaiser beta=5, 20 taps per phase) leaves
        # ~4e-4 passband error; a longer, beta=8.6 design keeps it near 1e-5.
        rate = max(up, down)
        taps = scipy.signal.firwin(2 * _HALF_TAPS_PER_PHASE * rate + 1, 1.0 / rate,
                                   window=("kaiser", _KAISER_BETA))
        acc = scipy.signal.resample_poly(self.acceleration, up, down, window=taps)[:n_new]
        step = (f"decimated (resampled to a coarser step) from dt={_fmt(self.dt)} s to dt={_fmt(dt)} s by "
                f"scipy.signal.resample_poly(up={up}, down={down}) with a zero-phase "
                f"{taps.size}-tap Kaiser (beta={_KAISER_BETA}) FIR anti-alias low-pass "
                f"at {_fmt(0.5 / dt)} Hz: content up to {_fmt(0.4 / dt)} Hz is kept")
        return self._derived(acc, dt, step)

    def baseline_corrected(self, order: int = 1) -> "Record":
        """Return the record minus its least-squares polynomial in time.

        ``order=0`` removes the mean, ``1`` a linear trend, ``2``/``3`` a
        quadratic/cubic one.  This is the classical polynomial baseline
        correction of strong-motion processing (e.g. Boore & Bommer, 2005,
        Soil Dyn. Earthq. Eng. 25, 93-115).  PEER NGA-West2 ``.AT2`` records
        are already filtered and baseline-corrected by PEER (Ancheta et al.,
        2014, Earthq. Spectra 30(3)), so for them this changes little; it
        matters for raw or uncorrected (Volume 1, counts) records.

        Parameters
        ----------
        order : int, default 1
            Polynomial order, 0 to 3.

        Returns
        -------
        Record

        Raises
        ------
        InputError
            Key ``order`` if order is not an integer 0-3.
        """
        if isinstance(order, bool) or not isinstance(order, numbers.Integral) \
                or not 0 <= order <= 3:
            raise InputError(f"baseline order must be an integer 0 to 3, got {order!r}",
                             file=self.provenance.get("file"), key="order")
        # Time mapped to [-1, 1] keeps the Vandermonde matrix well conditioned.
        x = np.linspace(-1.0, 1.0, self.npts)
        vander = np.vander(x, int(order) + 1)
        coef, *_ = np.linalg.lstsq(vander, self.acceleration, rcond=None)
        acc = self.acceleration - vander @ coef
        name = {0: "mean", 1: "linear trend", 2: "quadratic trend", 3: "cubic trend"}[order]
        return self._derived(acc, self.dt,
                             f"baseline corrected: least-squares polynomial of order "
                             f"{order} ({name}) removed")

    def truncated(self, duration: float) -> "Record":
        """Return the record cut to samples with ``t <= duration``.

        Parameters
        ----------
        duration : float
            Last time to keep, s, >= dt.  A duration at or beyond the record's
            end returns the record unchanged.

        Returns
        -------
        Record
        """
        file = self.provenance.get("file")
        duration = _positive_finite(duration, "duration", file)
        n = int(math.floor(duration / self.dt * (1 + _RTOL))) + 1
        if n >= self.npts:
            return self
        if n < 2:
            raise InputError(f"duration {_fmt(duration)} s keeps fewer than 2 samples "
                             f"at dt={_fmt(self.dt)} s", file=file, key="duration")
        return self._derived(self.acceleration[:n], self.dt,
                             f"truncated to {_fmt((n - 1) * self.dt)} s ({n} samples)")

    def padded(self, duration: float) -> "Record":
        """Return the record zero-padded so that it lasts at least *duration*.

        Parameters
        ----------
        duration : float
            Minimum duration (time of the last sample), s, > 0.  A record
            already that long is returned unchanged.

        Returns
        -------
        Record
            ``npts = ceil(duration / dt) + 1`` samples if padding was needed.
        """
        file = self.provenance.get("file")
        duration = _positive_finite(duration, "duration", file)
        n = int(math.ceil(duration / self.dt * (1 - _RTOL))) + 1
        if n <= self.npts:
            return self
        acc = np.concatenate([self.acceleration, np.zeros(n - self.npts)])
        return self._derived(acc, self.dt,
                             f"zero-padded from {_fmt(self.duration)} s to "
                             f"{_fmt((n - 1) * self.dt)} s ({n} samples)")

    def scaled(self, factor: float) -> "Record":
        """Return the record multiplied by *factor* (finite, > 0).

        ``provenance["scale"]`` becomes the total factor applied since reading.
        """
        file = self.provenance.get("file")
        factor = _positive_finite(factor, "scale", file)
        total = self.provenance.get("scale", 1.0) * factor
        return self._derived(self.acceleration * factor, self.dt,
                             f"scaled by {_fmt(factor)}", scale=total)


# ---------------------------------------------------------------------- helpers
def _positive_finite(value, key: str, file) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{key} must be a number, got {value!r}", file=file, key=key) from None
    if isinstance(value, bool) or not (math.isfinite(x) and x > 0.0):
        raise InputError(f"{key} must be positive and finite, got {value!r}", file=file, key=key)
    return x


def _conversion(units, calibration, scale) -> tuple[float, list]:
    """The factor to m/s^2 and the provenance sentences of the unit conversion and the scaling."""
    factor = calibration if units == "counts" else UNIT_FACTORS[units]
    steps = [f"converted from {units} to m/s2 (x {_fmt(factor)})"]
    if scale != 1.0:
        steps.append(f"scaled by {_fmt(scale)}")
    return factor, steps


def _trace_label(tr) -> str:
    peer = tr.stats.get("peer_at2")
    comp = f" (component {peer.component!r})" if peer and peer.component else ""
    return f"{tr.id!r}{comp}"


def _select_trace(stream, trace, file):
    available = ", ".join(f"{i}: {_trace_label(tr)}" for i, tr in enumerate(stream))
    if isinstance(trace, numbers.Integral) and not isinstance(trace, bool):
        if 0 <= trace < len(stream):
            return stream[int(trace)]
        raise InputError(f"trace index {trace} out of range; available: {available}",
                         file=file, key="trace")
    if not isinstance(trace, str):
        raise InputError(f"trace must be an index or a name, got {trace!r}; "
                         f"available: {available}", file=file, key="trace")
    want = trace.strip().upper()

    def keys(tr):
        peer = tr.stats.get("peer_at2")
        # Most specific first: full id, channel, PEER component, 1-letter component.
        return (tr.id, tr.stats.channel, peer.component if peer else None,
                tr.stats.component)

    for level in range(4):
        hits = [tr for tr in stream
                if keys(tr)[level] is not None and keys(tr)[level].strip().upper() == want]
        if len(hits) == 1:
            return hits[0]
        if len(hits) > 1:
            raise InputError(f"trace {trace!r} matches {len(hits)} traces; use the full "
                             f"id or an index; available: {available}",
                             file=file, key="trace")
    raise InputError(f"no trace {trace!r}; available: {available}", file=file, key="trace")


def _sha256(path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


# ---------------------------------------------------------------------- reading
def read_record(path, *, trace=0, units="auto", calibration=None, scale=1.0,
                format=None, dt=None) -> Record:
    """Read one ground-acceleration component from a waveform file.

    Parameters
    ----------
    path : str or os.PathLike
        The file.  Read with ``obspy.read(path, format=format)``, so any
        ObsPy waveform format works; PEER ``.AT2`` through seispound's plugin.
    trace : int or str, default 0
        Index into the stream, or a name matched (case-insensitively) against,
        in order, the trace id (``"IU.ANMO.00.HNE"``), the channel
        (``"HNE"``), the PEER component (``"180"``) and ObsPy's one-letter
        component (``"E"``).
    units : str, default "auto"
        Units of the samples: ``"g"``; ``"m/s2"`` (also ``"m/s^2"``,
        ``"m/s**2"``, ``"mps2"``); ``"cm/s2"`` (also ``"gal"``,
        ``"cm/s^2"``); ``"mm/s2"``; ``"counts"`` (needs *calibration*).
        ``"auto"`` means g for PEER ``.AT2`` files (their header states it)
        and is an error for every other format, whose units must be stated.
    calibration : float, optional
        m/s² per count, > 0; required with ``units="counts"`` and not allowed
        otherwise.  ObsPy's ``stats.calib`` is not used: files rarely carry a
        trustworthy value.
    scale : float, default 1.0
        Factor applied after unit conversion (finite, > 0), e.g. to scale a
        record to a target intensity.
    format : str, optional
        ObsPy format name (``"MSEED"``, ``"SAC"``, ``"PEER_AT2"``, ...) if
        auto-detection should be bypassed, or ``"text"`` for a one- or
        two-column text record (:mod:`seispound.motion.text`; units required).
    dt : float, optional
        Time step [s] of a one-column text record (checked against the time
        column of a two-column one); not used by other formats.

    Returns
    -------
    Record
        Acceleration in m/s², shape (npts,), at the file's time step.

    Raises
    ------
    InputError
        ``file``: missing or unreadable file; ``format``: ObsPy cannot read
        it; ``trace``: no such trace; ``units``/``calibration``/``scale``: bad
        or missing values; ``data``: non-finite samples or fewer than 2; plus
        the AT2 reader's own errors (``NPTS``, ``DT``, ``units``, ``data``).
    """
    if isinstance(path, obspy.Trace):
        return record_from_samples(path.data, path.stats.delta, units=units, calibration=calibration,
                                   scale=scale, source=f"obspy.Trace {path.id}")
    if not isinstance(path, (str, os.PathLike)):
        raise InputError(f"path must be a file name or an obspy.Trace, got {path!r}", key="file")
    file = os.fspath(path)
    if not os.path.isfile(file):
        raise InputError("no such file" if not os.path.exists(file) else "not a regular file",
                         file=file, key="file")
    units = _canonical_units(units, file)
    scale = _positive_finite(scale, "scale", file)
    if units == "counts":
        if calibration is None:
            raise InputError("units='counts' needs calibration (m/s2 per count)",
                             file=file, key="calibration")
        calibration = _positive_finite(calibration, "calibration", file)
    elif calibration is not None:
        raise InputError(f"calibration applies only to units='counts', not {units!r}",
                         file=file, key="calibration")

    if format is not None and str(format).lower() == "text":
        return _read_text(file, trace, units, calibration, scale, dt)
    if dt is not None:
        raise InputError("dt is stated only for text records (format = \"text\"); other formats carry their "
                         "own time step", file=file, key="dt")
    try:
        sha = _sha256(file)
        # obspy.read expands glob patterns; escape them so "[1].AT2" is one file.
        stream = obspy.read(glob.escape(file), format=format)
    except InputError as err:
        raise err.located(file=file) from None
    except OSError as err:
        raise InputError(f"cannot read file: {err.strerror or err}",
                         file=file, key="file") from None
    except Exception as err:  # any reader failure becomes one line, no traceback
        detail = " ".join(str(err).split()) or type(err).__name__
        hint = "" if format else ('; if it is a waveform file, name its format ([ground_motion] format = "MSEED", '
                                  '"SAC", ...; "text" for a one- or two-column text record)')
        raise InputError(f"ObsPy cannot read this file ({type(err).__name__}: {detail})"
                         f"{hint}", file=file, key="format") from None
    if len(stream) == 0:
        raise InputError("the file holds no traces", file=file, key="trace")

    tr = _select_trace(stream, trace, file)
    fmt = str(tr.stats.get("_format", format or ""))
    peer = tr.stats.get("peer_at2")
    if units == "auto":
        if peer is None:
            raise InputError(
                f"the units of a {fmt or 'non-AT2'} record are not known; state them with "
                "units='g', 'm/s2', 'cm/s2', 'mm/s2' or 'counts' (with calibration)",
                file=file, key="units")
        units = peer.units
    elif peer is not None and units != peer.units:
        raise InputError(f"the AT2 header states units of {peer.units}, not {units}",
                         file=file, key="units")

    data = tr.data
    if np.ma.isMaskedArray(data) and np.ma.count_masked(data):
        raise InputError(f"trace {tr.id} has gaps (masked samples)", file=file, key="data")
    data = np.asarray(data, dtype=np.float64)
    bad = np.flatnonzero(~np.isfinite(data))
    if bad.size:
        raise InputError(f"sample {bad[0]} is {float(data[bad[0]])}; all samples must be finite",
                         file=file, key="data")
    dt = _positive_finite(tr.stats.delta, "delta", file)

    factor, converted = _conversion(units, calibration, scale)
    steps = [f"read trace {tr.id} from {os.path.basename(file)} ({fmt}) with "
             f"{data.size} samples at dt={_fmt(dt)} s", *converted]
    provenance = {
        "file": file,
        "sha256": sha,
        "format": fmt,
        "station": peer.station_name if peer else tr.stats.station,
        "component": peer.component if peer else tr.stats.channel,
        "event": peer.event if peer else "",
        "date": peer.date if peer else "",
        "npts": int(data.size),
        "dt_original": dt,
        "units": units,
        "calibration": calibration,
        "scale": scale,
        "trace": tr.id,
        "processing": steps,
    }
    return Record(data * (factor * scale), dt, provenance)


#: Share of the new Nyquist frequency below which the decimation filter passes content
#: with relative error ~1e-5 (the Kaiser FIR of :meth:`Record.resampled`).
PASSBAND_SHARE = 0.8


def record_from_samples(samples, dt, *, units, calibration=None, scale=1.0, source="numpy array") -> Record:
    """A Record from samples in memory (a numpy array or an obspy.Trace's data) at step ``dt``.

    Parameters
    ----------
    samples : array_like, shape (npts,)
        Ground acceleration in ``units``; finite, at least 2 samples.
    dt : float
        Time step [s], > 0.
    units : str
        "g", "m/s2", "cm/s2", "mm/s2" or "counts" (with ``calibration``); required:
        samples carry no units of their own.
    calibration, scale : float, optional
        As in :func:`read_record`.
    source : str
        What the samples are, for the provenance.

    Returns
    -------
    Record
        Provenance: ``source``, the sha256 of the float64 samples' bytes, every step.
    """
    key = source
    units = _canonical_units(units, key)
    if units == "auto":
        raise InputError("samples in memory carry no units: state units = 'g', 'm/s2', 'cm/s2', 'mm/s2' or "
                         "'counts'", file=key, key="units")
    if np.ma.isMaskedArray(samples) and np.ma.count_masked(samples):
        raise InputError("the samples have gaps (masked values)", file=key, key="data")
    data = np.asarray(samples, dtype=np.float64)
    if data.ndim != 1:
        raise InputError(f"samples must be a 1-D array, got shape {data.shape}", file=key, key="data")
    dt = _positive_finite(dt, "dt", key)
    scale = _positive_finite(scale, "scale", key)
    if units == "counts":
        if calibration is None:
            raise InputError("units='counts' needs calibration (m/s2 per count)", file=key, key="calibration")
        calibration = _positive_finite(calibration, "calibration", key)
    factor, converted = _conversion(units, calibration, scale)
    steps = [f"taken from {source} with {data.size} samples at dt={_fmt(dt)} s", *converted]
    provenance = {"file": source, "sha256": hashlib.sha256(np.ascontiguousarray(data).tobytes()).hexdigest(),
                  "format": "memory", "station": "", "component": "", "event": "", "date": "",
                  "npts": int(data.size), "dt_original": dt, "units": units, "calibration": calibration,
                  "scale": scale, "trace": source, "processing": steps}
    return Record(data * (factor * scale), dt, provenance)


def _read_text(file, trace, units, calibration, scale, dt) -> Record:
    """A text record (:func:`seispound.motion.text.read_text_record`) as a Record with provenance."""
    from seispound.motion.text import read_text_record

    if units == "auto":
        raise InputError("the units of a text record are not known; state them with units = 'g', 'm/s2', "
                         "'cm/s2', 'mm/s2' or 'counts' (with calibration)", file=file, key="units")
    if trace not in (0, None):
        raise InputError(f"a text record holds one trace; got trace = {trace!r}", file=file, key="trace")
    if dt is not None:
        dt = _positive_finite(dt, "dt", file)
    data, step, ncol = read_text_record(file, dt)
    factor, converted = _conversion(units, calibration, scale)
    steps = [f"read {data.size} samples from {os.path.basename(file)} (text, {ncol} column"
             f"{'s: time, acceleration' if ncol == 2 else ', dt stated'}) at dt={_fmt(step)} s", *converted]
    provenance = {"file": file, "sha256": _sha256(file), "format": "text", "station": "", "component": "",
                  "event": "", "date": "", "npts": int(data.size), "dt_original": step, "units": units,
                  "calibration": calibration, "scale": scale, "trace": os.path.basename(file),
                  "processing": steps}
    return Record(data * (factor * scale), step, provenance)


def on_analysis_grid(record: Record, dt: float, duration: float) -> Record:
    """The record on the analysis grid ``t = 0, dt, ..., duration``, every step in its provenance.

    Resampled with :meth:`Record.resampled` if its step differs (linear
    interpolation when refining, anti-aliased decimation when coarsening),
    then cut (:meth:`Record.truncated`) or zero-padded (:meth:`Record.padded`)
    to the grid.  Each step appends its sentence to ``provenance["processing"]``,
    and the provenance gains the facts the plausibility guards read:

    ``pga`` [m/s^2] and ``dt_record`` [s], ``record_duration`` [s] of the record
    as given (read, converted, scaled, baseline-corrected); ``decimated`` (bool);
    ``highest_resolved_frequency`` [Hz] (the decimation filter's passband edge,
    ``PASSBAND_SHARE`` of the new Nyquist frequency, else the record's Nyquist
    frequency); ``zero_padded_from`` [s] (the record's end, if the grid goes
    beyond it, else None); ``truncated_to`` [s] (the grid's end, if the record
    goes beyond it, else None).

    Parameters
    ----------
    record : Record
    dt : float
        Analysis step [s], > 0.
    duration : float
        Analysis duration [s], >= 0.

    Returns
    -------
    Record
        ``round(duration / dt) + 1`` samples at ``dt``.
    """
    file = record.provenance.get("file")
    dt = _positive_finite(dt, "dt", file)
    try:
        duration = float(duration)
    except (TypeError, ValueError):
        duration = math.nan
    if not (math.isfinite(duration) and duration >= 0.0):
        raise InputError(f"duration must be finite and >= 0, got {duration!r}", file=file, key="duration")
    n = int(round(duration / dt)) + 1
    end = (n - 1) * dt
    decimated = dt > record.dt * (1 + _RTOL)
    facts = {
        "pga": record.pga, "dt_record": record.dt, "record_duration": record.duration, "decimated": decimated,
        "highest_resolved_frequency": (PASSBAND_SHARE * 0.5 / dt) if decimated else 0.5 / record.dt,
        "zero_padded_from": record.duration if end > record.duration * (1 + _RTOL) + 1e-12 else None,
        "truncated_to": end if end < record.duration * (1 - _RTOL) else None,
    }
    rec = record.resampled(dt)
    if n > 1:
        rec = rec.truncated(end).padded(end)
    acc = rec.acceleration
    if acc.size != n:  # rounding of the grid's last sample: keep exactly n, say so if it pads
        acc = np.concatenate([acc[:n], np.zeros(max(0, n - acc.size))])
        rec = Record(acc, dt, rec.provenance) if n >= 2 else rec
    prov = dict(rec.provenance)
    prov.update(facts)
    return Record(rec.acceleration, dt, prov)


def ground_acceleration(record: Record, dt: float, duration: float) -> np.ndarray:
    """Ground acceleration on the analysis grid ``t = 0, dt, ..., duration`` [m/s^2].

    The samples of :func:`on_analysis_grid` (which also returns the provenance
    of every step); a new, writable array of shape ``(round(duration / dt) + 1,)``.
    """
    return np.array(on_analysis_grid(record, dt, duration).acceleration)
