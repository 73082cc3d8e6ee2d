"""Newmark-beta integration of a row of buildings with contact (numba kernels behind a validating front end).

The names below load :mod:`.newmark` (and numba) on first use, so that
:mod:`.settings` can be imported by the model reader without compiling or loading a kernel.
"""

from importlib import import_module

from .settings import Newmark

__all__ = ["Newmark", "RawResult", "integrate", "IntegrationError"]

_LAZY = {"RawResult", "integrate", "IntegrationError"}


def __getattr__(name):
    if name in _LAZY:
        value = getattr(import_module(".newmark", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
