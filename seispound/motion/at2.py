"""PEER NGA ``.AT2`` accelerogram reader, registered as an ObsPy waveform plugin.

The PEER Ground Motion Database distributes processed records as plain-text
files with four header lines followed by the samples (PEER, *NGA-West2
Database*, PEER Report 2013/03, and the record files' own headers)::

    PEER NGA STRONG MOTION DATABASE RECORD
    Imperial Valley-02, 5/19/1940, El Centro Array #9, 180
    ACCELERATION TIME SERIES IN UNITS OF G
    NPTS=   5372, DT=   .0100 SEC,
       .9984852E-03   .9991426E-03   .9997266E-03   .1000268E-02 ...

Older (pre-West2) NGA files carry the same information in a different layout::

    PEER NGA STRONG MOTION DATABASE RECORD
    KOBE 01/16/95 2046, NISHI-AKASHI, 090 (CUE)
    ACCELERATION TIME HISTORY IN UNITS OF G
    4096    0.0100    NPTS, DT

Both layouts are read.  Velocity (``.VT2``) and displacement (``.DT2``) files
share the layout but are rejected: this package needs ground acceleration.

The module follows ObsPy's plugin conventions (compare ``obspy.io.sac.core``):
:func:`is_at2` is the ``isFormat`` probe and never raises, :func:`read_at2` is
the ``readFormat`` function returning a :class:`obspy.Stream`.  Once seispound
is installed, ``obspy.read("record.AT2")`` dispatches here through the
``obspy.plugin.waveform`` entry point declared in ``pyproject.toml``.
"""

from __future__ import annotations

import math
import os
import re

import numpy as np
from obspy import Stream, Trace
from obspy.core.util import AttribDict

from seispound.errors import InputError

__all__ = ["is_at2", "read_at2", "parse_at2_header"]

# The probe only looks at the start of a file; four header lines fit easily.
_PROBE_BYTES = 4096

_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eEdD][-+]?\d+)?"
# NGA-West2: "NPTS=   5372, DT=   .0100 SEC," (sometimes followed by filter notes).
_NPTS_WEST2 = re.compile(r"\bNPTS\s*=\s*(\d+)", re.IGNORECASE)
_DT_WEST2 = re.compile(r"\bDT\s*=\s*(" + _NUMBER + ")", re.IGNORECASE)
# Old NGA: "4096    0.0100    NPTS, DT".
_OLD_STYLE = re.compile(
    r"^\s*(\d+)\s*,?\s+(" + _NUMBER + r")\s*,?\s+NPTS\s*,?\s*DT\b", re.IGNORECASE
)
_DATE = re.compile(r"\b\d{1,2}/\d{1,2}/\d{2,4}\b")
# Fortran E-format columns (5E15.7) can run together when a negative value
# fills its field (``.1E-03-.2E-03``).  Only exponent-carrying numbers whose
# successors start with a sign are split, so "1.0.0" is still rejected.
_MANTISSA_EXP = r"(?:\d+\.?\d*|\.\d+)[eEdD][-+]?\d+"
_RUN_TOGETHER = re.compile(r"[-+]?" + _MANTISSA_EXP + r"(?:[-+]" + _MANTISSA_EXP + ")+")
_ONE_NUMBER = re.compile(r"[-+]?" + _MANTISSA_EXP)


# --------------------------------------------------------------------------- probe
def is_at2(filename) -> bool:
    """Return True if *filename* looks like a PEER NGA ``.AT2``-style file.

    The check reads at most the first 4 KiB: line 1 must mention ``PEER`` and
    line 4 must give NPTS and DT in either header layout.  Velocity and
    displacement files of the same family are accepted here so that
    :func:`read_at2` can reject them with a clear message about their units.

    Parameters
    ----------
    filename : str, bytes, os.PathLike or file-like
        Path, or an open binary/text file object.  The position of a file
        object is restored before returning.

    Returns
    -------
    bool
        Never raises; any problem (missing file, binary content, ...) gives
        False.
    """
    try:
        head = _read_head(filename, _PROBE_BYTES)
        if "\x00" in head:  # binary file
            return False
        lines = head.splitlines()
        if len(lines) < 4 or "PEER" not in lines[0].upper():
            return False
        _parse_npts_dt(lines[3])
        return True
    except Exception:  # the probe must never raise (ObsPy plugin contract)
        return False


def _read_head(filename, nbytes: int) -> str:
    """Return the first *nbytes* of a path or file object as text."""
    if hasattr(filename, "read"):
        pos = filename.tell() if hasattr(filename, "tell") else None
        try:
            chunk = filename.read(nbytes)
        finally:
            if pos is not None:
                filename.seek(pos, 0)
    else:
        with open(os.fspath(filename), "rb") as fh:
            chunk = fh.read(nbytes)
    return _decode(chunk)


def _decode(chunk) -> str:
    if isinstance(chunk, str):
        return chunk
    try:
        return chunk.decode("utf-8")
    except UnicodeDecodeError:
        # The files are ASCII in practice; latin-1 never fails, so a stray
        # accented character in a station name cannot stop the read.
        return chunk.decode("latin-1")


# -------------------------------------------------------------------------- header
def _parse_npts_dt(line: str) -> tuple[int, float, str]:
    """Parse header line 4; return ``(npts, dt, style)``.

    Raises
    ------
    ValueError
        If neither layout matches.
    """
    old = _OLD_STYLE.match(line)
    if old:
        return int(old.group(1)), _to_float(old.group(2)), "old"
    npts = _NPTS_WEST2.search(line)
    dt = _DT_WEST2.search(line)
    if npts and dt:
        return int(npts.group(1)), _to_float(dt.group(1)), "west2"
    raise ValueError(f"cannot find NPTS and DT in header line 4: {line.strip()!r}")


def _to_float(token: str) -> float:
    # Fortran double-precision exponents ("1.0D-03") appear in some hand-made files.
    return float(token.replace("D", "E").replace("d", "e"))


def _parse_line2(line: str) -> dict:
    """Split header line 2 into event, date, station and component.

    NGA-West2 writes ``event, M/D/YYYY, station, component``; the event or
    station may itself contain commas (``Chi-Chi, Taiwan``), so the date field
    anchors the split.  Old files write ``EVENT MM/DD/YY HHMM, STATION, COMP``.
    """
    fields = [f.strip() for f in line.split(",")]
    fields = [f for f in fields if f] or [""]
    date_at = next((i for i, f in enumerate(fields) if _DATE.search(f)), None)
    component = fields[-1] if len(fields) >= 2 else ""
    if date_at is None:
        event, date = fields[0], ""
        station = ", ".join(fields[1:-1]) if len(fields) >= 3 else ""
    else:
        m = _DATE.search(fields[date_at])
        before = ", ".join(fields[:date_at] + [fields[date_at][: m.start()].strip()])
        event = before.strip(" ,")
        date = fields[date_at][m.start():].strip()
        if date_at == len(fields) - 1:  # nothing after the date
            component, station = "", ""
        else:
            station = ", ".join(fields[date_at + 1: -1])
    return {"event": event, "date": date, "station_name": station,
            "component": component}


def parse_at2_header(lines, *, file=None) -> dict:
    """Parse and validate the four header lines of a PEER ``.AT2`` file.

    Parameters
    ----------
    lines : sequence of str
        At least the first four lines of the file.
    file : str, optional
        File name used in error messages.

    Returns
    -------
    dict
        ``npts`` (int), ``dt`` (float, s), ``style`` (``"west2"`` or
        ``"old"``), ``event``, ``date``, ``station_name``, ``component``,
        ``units`` (always ``"g"``) and ``header`` (the four lines, right-stripped).

    Raises
    ------
    InputError
        Fewer than four lines (key ``header``), line 4 unreadable (key
        ``NPTS``), DT not positive and finite (key ``DT``), or units other than
        acceleration in g (key ``units``).
    """
    if len(lines) < 4:
        raise InputError(
            f"a PEER AT2 file has 4 header lines, found only {len(lines)}",
            file=file, key="header")
    header = [ln.rstrip() for ln in lines[:4]]
    try:
        npts, dt, style = _parse_npts_dt(header[3])
    except ValueError:
        raise InputError(
            "header line 4 must give NPTS and DT, as 'NPTS=   5372, DT=   .0100 SEC,'"
            f" or '4096    0.0100    NPTS, DT'; found {header[3].strip()!r}",
            file=file, key="NPTS") from None
    if not (math.isfinite(dt) and dt > 0.0):
        raise InputError(f"DT must be a positive time step in s, got {dt!r}",
                         file=file, key="DT")
    units_line = " ".join(header[2].upper().split())
    if "ACCELERATION" not in units_line or not re.search(r"\bUNITS OF G\b", units_line):
        raise InputError(
            f"header line 3 says {header[2].strip()!r}; only acceleration time "
            "series in units of g (.AT2) are supported, not velocity (.VT2) or "
            "displacement (.DT2)", file=file, key="units")
    info = _parse_line2(header[1])
    info.update(npts=npts, dt=dt, style=style, units="g", header=header)
    return info


# ---------------------------------------------------------------------------- data
def _parse_values(text_lines, first_line_no: int, *, file=None) -> np.ndarray:
    """Parse the data block into float64; report the first unreadable token."""
    values = []
    for offset, line in enumerate(text_lines):
        for token in line.split():
            try:
                values.append(_to_float(token))
            except ValueError:
                # Fixed-width E15.7 columns can run together without a blank
                # when a value fills its field; split those, reject anything else.
                if not _RUN_TOGETHER.fullmatch(token):
                    raise InputError(
                        f"line {first_line_no + offset}: cannot read {token!r} as a "
                        f"number (sample {len(values)})", file=file, key="data") from None
                values.extend(_to_float(t) for t in _ONE_NUMBER.findall(token))
    return np.asarray(values, dtype=np.float64)


def _sanitise_station(name: str) -> str:
    # SEED (and hence MiniSEED output) allows at most 5 upper-case
    # alphanumerics for a station code; the full name stays in peer_at2.
    return re.sub(r"[^A-Z0-9]", "", name.upper())[:5]


def _sanitise_channel(component: str) -> str:
    # A dot would break Trace.id ("NET.STA.LOC.CHA"); whitespace is dropped too.
    return re.sub(r"[\s.]+", "", component)


def _display_name(filename) -> str:
    if hasattr(filename, "read"):
        return str(getattr(filename, "name", "<file object>"))
    return os.fsdecode(os.fspath(filename))


def read_at2(filename, headonly: bool = False, **kwargs) -> Stream:
    """Read a PEER NGA ``.AT2`` acceleration file into an ObsPy Stream.

    Normally called through ``obspy.read(filename)`` (format ``"PEER_AT2"``),
    not directly.

    Parameters
    ----------
    filename : str, os.PathLike or file-like
        The ``.AT2`` file.
    headonly : bool, default False
        Read and validate only the header; the trace then has empty data but
        ``stats.npts`` set from the header (ObsPy convention).
    **kwargs
        Ignored; accepted for ObsPy's plugin interface.

    Returns
    -------
    obspy.Stream
        One :class:`obspy.Trace` with ``data`` as float64 acceleration in g,
        shape ``(npts,)``; ``stats.delta`` = DT (s); ``stats.station`` = station
        name reduced to at most 5 upper-case alphanumerics (SEED limit);
        ``stats.channel`` = component without whitespace or dots (may be
        ``""``); network and location empty; ``stats.starttime`` left at the
        ObsPy default because AT2 files carry no absolute start time (the
        event date is kept).  ``stats.peer_at2`` is an AttribDict with
        ``event``, ``date``, ``station_name``, ``component``, ``units``
        (``"g"``), ``header`` (the four header lines) and ``header_style``
        (``"west2"`` or ``"old"``).

    Raises
    ------
    InputError
        Bad header (see :func:`parse_at2_header`); a value that is not a
        number or not finite (key ``data``, naming the sample index); value
        count different from NPTS (key ``NPTS``).
    """
    name = _display_name(filename)
    try:
        if hasattr(filename, "read"):
            raw = filename.read()
        else:
            with open(os.fspath(filename), "rb") as fh:
                raw = fh.read()
    except OSError as err:
        raise InputError(f"cannot read file: {err.strerror or err}",
                         file=name, key="file") from None
    lines = _decode(raw).splitlines()
    info = parse_at2_header(lines, file=name)

    stats = {
        "delta": info["dt"],
        "station": _sanitise_station(info["station_name"]),
        "channel": _sanitise_channel(info["component"]),
        "calib": 1.0,
        "peer_at2": AttribDict({
            "event": info["event"],
            "date": info["date"],
            "station_name": info["station_name"],
            "component": info["component"],
            "units": info["units"],
            "header": info["header"],
            "header_style": info["style"],
        }),
    }
    if headonly:
        stats["npts"] = info["npts"]
        return Stream([Trace(header=stats)])

    data = _parse_values(lines[4:], 5, file=name)
    if data.size != info["npts"]:
        raise InputError(
            f"header says NPTS={info['npts']} but the file holds {data.size} values",
            file=name, key="NPTS")
    bad = np.flatnonzero(~np.isfinite(data))
    if bad.size:
        raise InputError(
            f"sample {bad[0]} is {float(data[bad[0]])} ({bad.size} non-finite value(s) "
            "in total)", file=name, key="data")
    return Stream([Trace(data=data, header=stats)])
