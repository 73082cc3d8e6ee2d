"""Parametric studies: many runs of one model over records and parameter axes, in one HDF5 store.

``load_study`` reads a study file (:mod:`.spec`), ``run_study`` runs it on dask
(:mod:`.execute`) into a resumable store (:mod:`.journal`, :mod:`.store`,
schema in :mod:`.schema`), and ``open_study`` opens the store for queries.
"""

from .execute import run_study
from .spec import load_study

__all__ = ["load_study", "run_study", "open_study"]


def __getattr__(name):
    if name == "open_study":
        from .query import open_study

        return open_study
    raise AttributeError(name)
