"""Input errors that name the file and the key.

Every problem with user input (a model file, a record, a parameter) is raised as
:class:`InputError`; the CLI prints ``str(err)`` as one line and exits with code 2.
"""

from __future__ import annotations

__all__ = ["InputError", "number_array"]


class InputError(ValueError):
    """Bad user input, reported as ``FILE: KEY: MESSAGE`` on one line.

    Parameters
    ----------
    message : str
        What is wrong and, where useful, what was expected.
    file : str or path-like, optional
        The file the input came from (model file, record file).
    key : str, optional
        The dotted key inside that file (``building.A.floor_masses``, ``NPTS``).
    """

    def __init__(self, message: str, *, file=None, key: str | None = None):
        self.message = " ".join(str(message).split())  # always one line
        self.file = None if file is None else str(file)
        self.key = key
        super().__init__(str(self))

    def __str__(self) -> str:
        parts = [p for p in (self.file, self.key) if p]
        return ": ".join(parts + [self.message])

    def located(self, *, file=None, key: str | None = None) -> "InputError":
        """Return a copy with a file/key filled in where still missing."""
        return InputError(self.message, file=self.file or file, key=self.key or key)


def number_array(value, key: str, *, file=None):
    """``value`` as a 1-D float array, accepting only numbers or lists of numbers.

    Strings and booleans are refused even where numpy would convert them
    (``np.asarray("1e5", float)`` is 1e5): a quoted number in a model file or
    a string set from Python is a mistake reported at its own key, on both paths.

    Parameters
    ----------
    value : number or sequence of numbers
    key : str
        The dotted key, for the error.

    Returns
    -------
    numpy.ndarray, shape (n,), float64

    Raises
    ------
    InputError
        Naming ``key`` and what was found.
    """
    import numbers

    import numpy as np

    items = value.tolist() if isinstance(value, np.ndarray) else value
    seq = items if isinstance(items, (list, tuple)) else [items]
    for pos, x in enumerate(seq):
        if isinstance(x, bool) or not isinstance(x, numbers.Real):
            what = f"a string ({x!r})" if isinstance(x, str) else repr(x)
            where = "" if seq is not items else f"entry {pos + 1} is "
            raise InputError(f"must be a number or a list of numbers; {where}{what}", file=file, key=key)
    return np.atleast_1d(np.asarray(seq, dtype=float)).reshape(-1)


def finite_number(value, key: str, *, positive: bool = False, nonnegative: bool = False, file=None) -> float:
    """``value`` as a float if it is a finite number (not a bool), > 0 or >= 0 if asked; else InputError at ``key``."""
    import math

    if not (isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)):
        raise InputError(f"must be a finite number, got {value!r}", file=file, key=key)
    if positive and value <= 0:
        raise InputError(f"must be > 0, got {value:g}", file=file, key=key)
    if nonnegative and value < 0:
        raise InputError(f"must be >= 0, got {value:g}", file=file, key=key)
    return float(value)
