"""Plain-text accelerograms: one column (samples at a stated dt) or two (time, acceleration).

The form in which many engineers hold records (spreadsheets, old processing
software, design-code suites): numbers separated by whitespace, commas or
semicolons, lines starting with ``#`` ignored.  The units are never guessed:
the caller states them (``read_record(..., units=...)``).
"""

from __future__ import annotations

import math
import re

import numpy as np

from seispound.errors import InputError

__all__ = ["TEXT_FORMAT", "read_text_record"]

#: The format name of text records in ``read_record(format=...)`` and ``[ground_motion] format``.
TEXT_FORMAT = "text"
_SPLIT = re.compile(r"[\s,;]+")
# relative tolerance of a uniform time column (text files round the times)
_DT_RTOL = 1e-6


def read_text_record(path, dt=None) -> tuple[np.ndarray, float, int]:
    """Read a one- or two-column text record.

    Parameters
    ----------
    path : path-like
        The file (UTF-8 or ASCII).
    dt : float, optional
        Time step [s]; required for one column, checked against the time column for two.

    Returns
    -------
    (acceleration (npts,) in the file's units, dt [s], number of columns)

    Raises
    ------
    InputError
        ``line N`` for a non-numeric or short line, ``columns`` for more than two
        or a changing count, ``dt`` for a missing, non-positive or disagreeing step
        or a non-uniform time column (naming its first bad row).
    """
    rows, ncol = [], None
    with open(path, encoding="utf-8", errors="replace") as fh:
        for number, line in enumerate(fh, start=1):
            text = line.strip()
            if not text or text.startswith("#"):
                continue
            fields = [f for f in _SPLIT.split(text) if f]
            try:
                values = [float(f) for f in fields]
            except ValueError:
                raise InputError(f"not a number in {text[:60]!r}; a text record holds one column (acceleration) "
                                 "or two (time, acceleration), # for comments", file=path,
                                 key=f"line {number}") from None
            if ncol is None:
                ncol = len(values)
                if ncol not in (1, 2):
                    raise InputError(f"{ncol} columns; a text record holds one (acceleration) or two "
                                     "(time, acceleration)", file=path, key=f"line {number}")
            elif len(values) != ncol:
                raise InputError(f"{len(values)} values where the lines above have {ncol}", file=path,
                                 key=f"line {number}")
            rows.append(values)
    if len(rows) < 2:
        raise InputError("a text record needs at least 2 samples", file=path, key="data")
    table = np.asarray(rows)
    if ncol == 1:
        if dt is None:
            raise InputError("a one-column text record needs its time step: set [ground_motion] dt (s)",
                             file=path, key="dt")
        return table[:, 0], float(dt), 1
    t = table[:, 0]
    steps = np.diff(t)
    step = (t[-1] - t[0]) / (t.size - 1)
    if not step > 0:
        raise InputError("the time column must increase", file=path, key="dt")
    bad = np.flatnonzero(np.abs(steps - step) > _DT_RTOL * step + 1e-9)
    if bad.size:
        raise InputError(f"the time column is not uniform: row {bad[0] + 2} is at {t[bad[0] + 1]:g} s, "
                         f"expected {t[0] + (bad[0] + 1) * step:g} s", file=path, key="dt")
    if dt is not None and not math.isclose(dt, step, rel_tol=_DT_RTOL * 10):
        raise InputError(f"dt = {dt:g} s disagrees with the file's time column ({step:.10g} s)", file=path,
                         key="dt")
    return table[:, 1], float(step), 2
