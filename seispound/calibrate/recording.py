"""Recordings: the mapped traces of one or more files, on one time grid, in SI units."""

from __future__ import annotations

import os
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError

__all__ = ["Recording", "read_recording"]


@dataclass
class Recording:
    """The mapped channels of one test or event.

    Attributes
    ----------
    dt : float
        Sampling interval [s] (every mapped trace shares it).
    data : dict
        trace id -> samples (npts,), SI units (the channel map's units converted).
    sources : list of str
        The files read.
    files : dict
        trace id -> the file it was read from.
    """

    dt: float
    data: dict
    sources: list
    files: dict = field(default_factory=dict)

    @property
    def npts(self) -> int:
        return int(next(iter(self.data.values())).size)

    @property
    def time(self) -> np.ndarray:
        """Sample times [s] from the first sample."""
        return np.arange(self.npts) * self.dt


def read_recording(paths, channels) -> Recording:
    """Read the traces ``channels`` map from the files ``paths`` (anything obspy reads).

    One line naming the file and the trace id for a missing file or trace, a trace
    mapped twice across files, non-finite samples, or traces that differ in sampling
    interval, start time or length.
    """
    import obspy

    if isinstance(paths, (str, os.PathLike)):
        paths = [paths]
    traces, where = {}, {}
    for p in paths:
        f = os.fspath(p)
        if not os.path.isfile(f):
            raise InputError("no such file", file=f, key="file")
        try:
            stream = obspy.read(f)
        except Exception as exc:  # obspy raises many types for unreadable files
            raise InputError(f"obspy cannot read it ({type(exc).__name__}: {exc})", file=f, key="format") from None
        for tr in stream:
            if tr.id in traces:
                raise InputError(f"trace {tr.id} is also in {where[tr.id]}", file=f, key=tr.id)
            traces[tr.id], where[tr.id] = tr, f
    data, ref = {}, None
    for ch in channels:
        tr = traces.get(ch.id)
        if tr is None:
            raise InputError(f"no trace {ch.id} (the traces are {', '.join(sorted(traces)) or 'none'})",
                             file=", ".join(os.fspath(p) for p in paths), key=ch.id)
        x = np.asarray(tr.data, float) * ch.factor
        if not np.all(np.isfinite(x)):
            bad = int(np.flatnonzero(~np.isfinite(x))[0])
            raise InputError(f"sample {bad} is not finite", file=where[ch.id], key=ch.id)
        st = tr.stats
        if ref is None:
            ref = (st.delta, st.starttime, st.npts, ch.id)
        elif abs(st.delta - ref[0]) > 1e-9 * ref[0] or abs(st.starttime - ref[1]) > 0.5 * ref[0] \
                or st.npts != ref[2]:
            raise InputError(f"sampled differently from {ref[3]}: dt {st.delta:g} s, start {st.starttime}, "
                             f"{st.npts} samples against {ref[0]:g} s, {ref[1]}, {ref[2]}", file=where[ch.id],
                             key=ch.id)
        data[ch.id] = x
    if ref[2] < 2:
        raise InputError("fewer than 2 samples", file=where[ref[3]], key=ref[3])
    return Recording(dt=float(ref[0]), data=data, sources=[os.fspath(p) for p in paths],
                     files={cid: os.path.abspath(where[cid]) for cid in data})
