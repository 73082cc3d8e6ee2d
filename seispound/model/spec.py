"""The model: buildings, gaps, contact law, analysis settings and ground motion."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from ..errors import InputError
from .analysis import Analysis

__all__ = ["Analysis", "BuildingMotion", "GroundMotionSpec", "Model"]


@dataclass
class GroundMotionSpec:
    """Where the base motion comes from and how to read it.

    Parameters
    ----------
    file : path
        Record file (any format obspy reads, PEER .AT2 included).
    trace : int or str
        Trace index or id/channel/component to use.
    units : str
        "g", "m/s2", "cm/s2", "mm/s2", "counts" or "auto" (AT2 files state g).
    scale : float
        Factor applied to the record.
    calibration : float, optional
        m/s^2 per count when units = "counts".
    baseline : int or None
        Order of the least-squares polynomial removed (None: none; 0 mean; 1 linear).
    format : str, optional
        ObsPy format name ("MSEED", "SAC", "PEER_AT2", ...) instead of detection,
        or "text" for a one- or two-column text record.
    dt : float, optional
        Time step [s] of a one-column text record.
    """

    file: Path | None
    trace: object = 0
    units: str = "auto"
    scale: float = 1.0
    calibration: float | None = None
    baseline: int | None = None
    format: str | None = None
    dt: float | None = None
    samples: object = None  # in-memory samples (from_array / from_trace); file is then None
    source: str = ""
    apparent_velocity: float | None = None  # m/s: delay of each building = its position / this

    @classmethod
    def from_array(cls, acceleration, dt: float, *, units: str, scale: float = 1.0, baseline=None,
                   calibration=None, name: str = "numpy array") -> "GroundMotionSpec":
        """A ground motion from samples in memory.

        Parameters
        ----------
        acceleration : array_like, shape (npts,)
            Ground acceleration in ``units``, sample i at t = i dt.
        dt : float
            Time step [s].
        units : str
            "g", "m/s2", "cm/s2", "mm/s2" or "counts" (required: an array has no units).
        scale, baseline, calibration
            As for a record file.
        name : str
            What the samples are (stored in the provenance).
        """
        import numpy as np

        from ..motion.record import record_from_samples

        # validate now (one line naming the key), keep a read-only copy of the samples as given
        record_from_samples(acceleration, dt, units=units, calibration=calibration, scale=scale, source=name)
        data = np.array(acceleration, dtype=float)
        data.setflags(write=False)
        return cls(file=None, units=units, scale=float(scale), calibration=calibration, baseline=baseline,
                   format="memory", dt=float(dt), samples=data, source=name)

    @classmethod
    def from_trace(cls, trace, *, units: str, scale: float = 1.0, baseline=None,
                   calibration=None) -> "GroundMotionSpec":
        """A ground motion from an ``obspy.Trace`` (its data at ``trace.stats.delta``; units required)."""
        return cls.from_array(trace.data, trace.stats.delta, units=units, scale=scale, baseline=baseline,
                              calibration=calibration, name=f"obspy.Trace {trace.id}")


@dataclass
class BuildingMotion:
    """The ground motion under one building, when it differs from the row's (``[[building]] ground_motion``).

    Parameters
    ----------
    delay : float
        Arrival time after the row's record [s] (wave passage).  Negative: the
        wave reaches this building first; its motion at t is the record's at
        t + |delay|, the record's first |delay| s are cut (warned about when
        they hold more than 5 % of the peak) and it is zero after the record ends.
    lowpass : float, optional
        Cut-off [Hz] of a zero-phase Butterworth low-pass (loss of coherency).
    lowpass_order : int
        Poles of the filter, applied forward and backward (default 2).
    record : GroundMotionSpec, optional
        A record of the building's own instead of the row's (then delayed and
        low-passed as above, if asked).
    weight : float
        With ``record``: the building's motion is w a_own + (1 - w) a_row [-], the row's
        record plus w times the difference of its own from it, 0 <= w <= 2 (default 1:
        the own record alone).  ``diagnose`` fits w from 0, where the building is driven
        by the row's record, to drive it by the acceleration recorded at its base.

    See :mod:`seispound.motion.spatial`.
    """

    delay: float = 0.0
    lowpass: float | None = None
    lowpass_order: int = 2
    record: GroundMotionSpec | None = None
    weight: float = 1.0

    def validate(self, key: str) -> None:
        if not _finite(self.delay):
            raise InputError(f"must be a finite number of seconds, got {self.delay!r}", key=f"{key}.delay")
        if self.lowpass is not None and (not _finite(self.lowpass) or not self.lowpass > 0):
            raise InputError(f"must be a frequency > 0 in Hz, got {self.lowpass!r}", key=f"{key}.lowpass")
        order = self.lowpass_order
        if not isinstance(order, int) or isinstance(order, bool) or not 1 <= order <= 8:
            raise InputError(f"must be an integer 1..8, got {order!r}", key=f"{key}.lowpass_order")
        if self.record is not None and not isinstance(self.record, GroundMotionSpec):
            raise InputError("must be a GroundMotionSpec", key=f"{key}.file")
        if not _finite(self.weight) or not 0.0 <= self.weight <= 2.0:
            raise InputError(f"must be a share 0..2 of the building's own record, got {self.weight!r}",
                             key=f"{key}.weight")

    @property
    def is_identity(self) -> bool:
        """The row's record unchanged."""
        return self.record is None and not self.delay and self.lowpass is None


def _freeze(system) -> None:
    """Make the arrays of an assembled system read-only: it is shared by every run of its model."""
    import dataclasses

    import numpy as np

    for f in dataclasses.fields(system):
        value = getattr(system, f.name)
        if isinstance(value, np.ndarray):
            value.setflags(write=False)


def _finite(x) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


@dataclass
class Model:
    """A row of buildings, the gaps between them, a contact law and the loading.

    ``buildings`` are ordered left to right.  ``ground_motion = None`` is a
    free-vibration or impact test driven by initial velocities.
    """

    title: str
    buildings: list
    gaps: list
    contact: object
    analysis: Analysis
    ground_motion: GroundMotionSpec | None = None
    source: str | None = None  # path of the model file
    text: str | None = None  # its text, stored in the results

    def gap(self, a: str, b: str):
        """The :class:`~seispound.structure.Gap` between buildings ``a`` and ``b`` (either order).

        ``model.gap("A", "B").size = 0.05`` widens that gap; InputError (key ``gap``)
        listing the gaps there are if none joins the two.
        """
        for g in self.gaps:
            if isinstance(g.between, (list, tuple)) and sorted(g.between) == sorted((a, b)):
                return g
        have = ", ".join("|".join(g.between) for g in self.gaps) or "none"
        raise InputError(f"no gap between {a} and {b}; gaps: {have}", file=self.source, key="gap")

    def validate(self) -> None:
        """Check every part of the model as the file reader does; InputError naming the file and key."""
        self.assembled()

    def assembled(self):
        """Validate the model and return its assembled arrays (``structure.SystemArrays``), in one pass.

        Kept for the model's current content, as ``Building.modes`` is: a study, a fit or a
        script reruns one model, and validation and assembly cost as much as integrating a
        20 s record on a low-rise pair.  The content is what pickling the parts gives, so any
        change made from Python (a field set, a building replaced) assembles afresh.  The
        kept arrays are read-only.
        """
        return self.kept()["system"]

    def kept(self) -> dict:
        """What is kept for the model's current content: ``{"system": assembled arrays}``, and what the
        callers add that depends on the content alone (``simulate`` adds the result's
        ``results.schema.Layout`` and the model-only plausibility findings).  Validates and assembles afresh when the content has changed; a dict that is not
        kept (a part that cannot be pickled) otherwise."""
        memo = self.__dict__.get("_assembled")
        variant = self.__dict__.get("_parts") is not None  # read as a variant: never changed after (parts.py)
        if memo is not None and (variant or memo[0] == self._content()):
            return memo[1]
        system = self._assemble()
        key = b"variant" if variant else self._content()  # after validation, which may normalise fields
        kept = {"system": system}
        if key is not None:
            _freeze(system)
            self.__dict__["_assembled"] = (key, kept)
        return kept

    def _content(self):
        """The bytes of everything assembly and validation read, or None if a part cannot be pickled."""
        import pickle

        try:
            return pickle.dumps((self.buildings, self.gaps, self.contact, self.analysis, self.ground_motion),
                                protocol=pickle.HIGHEST_PROTOCOL)
        except Exception:  # noqa: BLE001 (a callable set from Python: no memo, assembled every time)
            return None

    def _assemble(self):
        names = [b.name for b in self.buildings]
        if not names:
            raise InputError("a model needs at least one [[building]]", file=self.source, key="building")
        dup = {n for n in names if names.count(n) > 1}
        if dup:
            raise InputError(f"building names must be unique; repeated: {', '.join(sorted(dup))}",
                             file=self.source, key="building.name")
        try:
            self.analysis.validate()
            parts = self.__dict__.get("_parts")
            for b in self.buildings:  # fields may have been set from Python since the model was read
                if parts is None or not parts.owns(b):  # (a variant's kept buildings: validated when read)
                    b.validate()
            if self.contact is not None:
                self.contact.validate(key="contact")
            from ..structure import assemble

            system = assemble(self.buildings, self.gaps, self.contact, parts)  # gap neighbours, levels, sizes, laws
            self._check_stability()
            self._check_motions()
        except InputError as err:
            raise err.located(file=self.source) from None
        return system

    def building_motions(self) -> list:
        """The ground motion under each building, left to right: a :class:`BuildingMotion` (delay from the
        position when ``[ground_motion] apparent_velocity`` is set), or None for the row's record unchanged."""
        gm = self.ground_motion
        out = []
        for b in self.buildings:
            m = b.ground_motion
            if gm is not None and gm.apparent_velocity is not None:
                from dataclasses import replace

                delay = float(b.position) / float(gm.apparent_velocity)
                m = BuildingMotion(delay=delay) if m is None else replace(m, delay=delay)
            out.append(None if m is None or m.is_identity else m)
        return out

    def _check_motions(self) -> None:
        """A delayed or filtered building needs a record to delay; apparent_velocity needs every position."""
        gm = self.ground_motion
        v = None if gm is None else gm.apparent_velocity
        if v is not None and not (_finite(v) and v > 0):
            raise InputError(f"must be a velocity > 0 in m/s, got {v!r}", key="ground_motion.apparent_velocity")
        for b in self.buildings:
            key = f"building.{b.name}"
            m = b.ground_motion
            if v is not None:
                if b.position is None:
                    raise InputError("is required when ground_motion.apparent_velocity is set (metres along the "
                                     "row)", key=f"{key}.position")
                if m is not None and m.delay:
                    raise InputError("state either this delay or a position with ground_motion.apparent_velocity, "
                                     "not both", key=f"{key}.ground_motion.delay")
            nyquist = 0.5 / self.analysis.dt
            if m is not None and m.lowpass is not None and not m.lowpass < nyquist:
                raise InputError(f"must lie below the Nyquist frequency {nyquist:g} Hz of analysis.dt = "
                                 f"{self.analysis.dt:g} s, got {m.lowpass:g}", key=f"{key}.ground_motion.lowpass")
            if m is not None and m.record is None and gm is None and not m.is_identity:
                raise InputError("delays or filters the row's record, but the model has no [ground_motion]; give "
                                 "the building a file of its own", key=f"{key}.ground_motion")

    def _check_stability(self) -> None:
        """Refuse a Newmark step beyond its stability limit for the stiffest mode of the row.

        For gamma >= 1/2 and 2 beta < gamma the Newmark method is stable for
        dt / T_n <= 1 / (pi sqrt(2) sqrt(gamma - 2 beta)) (Chopra, Dynamics of
        Structures, Eq. 5.5.1 and its generalisation; Hughes 1987, Sec. 9.1).
        The contact substeps, an impact duration split ``contact_substeps``
        times (half a contact period for a linear law), must satisfy it too
        for the contact stiffness.
        """
        nm = self.analysis.newmark
        limit = nm.stability_limit()
        if math.isinf(limit):
            return
        t_min, where = math.inf, ""
        for b in self.buildings:
            periods = b.periods
            if periods[-1] < t_min:
                t_min, where = float(periods[-1]), f"building {b.name}, mode {periods.size}"
        dt = self.analysis.dt
        if dt > limit * t_min:
            raise InputError(
                f"Newmark beta = {nm.beta:g}, gamma = {nm.gamma:g} is stable only for dt <= {limit:.3g} T_min = "
                f"{limit * t_min:.3g} s (T_min = {t_min:.3g} s, {where}); dt = {dt:g} s would diverge: "
                "use a smaller dt or beta = 0.25 (average acceleration, unconditionally stable)",
                key="analysis.dt")
        if nm.contact_substeps is not None and 1.0 / (2.0 * nm.contact_substeps) > limit:
            need = math.ceil(1.0 / (2.0 * limit) + 1e-12)
            raise InputError(
                f"with Newmark beta = {nm.beta:g}, gamma = {nm.gamma:g} the contact substeps are stable only "
                f"for contact_substeps >= {need} (half a contact period split into substeps of at most "
                f"{limit:.3g} contact periods), got {nm.contact_substeps}", key="analysis.contact_substeps")
