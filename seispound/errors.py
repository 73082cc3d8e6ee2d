"""Input errors that name the file and the key.

Every problem with user input (a model file, a record, a parameter) is raised as
:class:`InputError`; the CLI prints ``str(err)`` as one line and exits with code 2.
"""

from __future__ import annotations

__all__ = ["InputError"]


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
