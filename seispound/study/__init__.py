"""Parametric studies: many runs of one model over records and parameter axes, in one HDF5 store.

``load_study`` reads a study file (:mod:`.spec`), ``run_study`` runs it on dask
(:mod:`.execute`) into a resumable store (:mod:`.journal`, :mod:`.store`,
schema in :mod:`.schema`), and ``open_study`` opens the store for queries.
"""

from importlib import import_module

__all__ = ["load_study", "run_study", "open_study"]

# loaded on first use: the command line builds its parser from .query without dask, numba or xarray
_LAZY = {"load_study": ".spec", "run_study": ".execute", "open_study": ".query"}


def __getattr__(name):
    if name in _LAZY:
        value = getattr(import_module(_LAZY[name], __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'seispound.study' has no attribute {name!r}")
