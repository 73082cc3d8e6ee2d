"""Build a result Dataset without xarray's merge: the variables are already consistent.

``xr.Dataset(data_vars, coords, attrs)`` checks, aligns and merges its inputs and makes a
pandas index for every dimension coordinate: 3-4 ms for a run's ~55 variables, more than the
integration of a 20 s record on a pair of low-rise buildings.  A result's variables come from
one run, on dimensions that agree by construction, so :func:`dataset` makes each variable and
index once and hands them to ``Dataset._construct_direct`` (xarray's own constructor for
already-valid parts, which its operations use internally).  The indexes of the coordinates
that do not change between runs of a model (building, floor, gap, ...) are kept.

``FAST`` switches the path off: the public constructor then builds the same Dataset, which
``tests/results/test_construct.py`` checks with ``xarray.testing.assert_identical``.
"""

from __future__ import annotations

import functools

import numpy as np
import pandas as pd
import xarray as xr
from xarray.indexes import PandasIndex

__all__ = ["dataset", "variable", "FAST"]

FAST = hasattr(xr.Dataset, "_construct_direct")


def dataset(data_vars: dict, coords: dict, attrs: dict, *, fast: bool | None = None) -> xr.Dataset:
    """A Dataset from ``data_vars`` {name: Variable} and ``coords`` {name: (dims, values, attrs)}.

    Parameters
    ----------
    data_vars : dict of str to xarray.Variable
    coords : dict of str to tuple
        (dims, values, attrs); a coordinate named as its only dimension gets a pandas index.
    attrs : dict
    fast : bool, optional
        Build without merging (default ``FAST``); False: ``xr.Dataset(data_vars, coords, attrs)``.
    """
    if not (FAST if fast is None else fast):
        return xr.Dataset(data_vars, {k: (d, v, a) for k, (d, v, a) in coords.items()}, attrs)
    variables, indexes = {}, {}
    for name, (dims, values, vattrs) in coords.items():
        dims = (dims,) if isinstance(dims, str) else tuple(dims)
        if dims == (name,):
            index = _index(name, np.asarray(values))
            indexes[name] = index
            variables.update(index.create_variables({name: variable(dims, values, vattrs)}))
        else:
            variables[name] = variable(dims, values, vattrs)
    variables.update(data_vars)
    sizes: dict = {}
    for name, var in variables.items():
        for d, n in zip(var.dims, var.shape):
            if sizes.setdefault(d, n) != n:
                raise ValueError(f"dimension {d!r} of {name!r} has size {n}, others {sizes[d]}")
    return xr.Dataset._construct_direct(variables, set(coords), sizes, dict(attrs), indexes)


def variable(dims, data, attrs) -> xr.Variable:
    """``xr.Variable(dims, data, attrs)``; for a numeric NumPy array, or an object array of names, on the fast
    path without the conversions of ``as_compatible_data`` (which leave such an array as it is)."""
    if FAST and isinstance(data, np.ndarray) and (data.dtype.kind in "biuf" or (
            data.dtype == object and data.ndim == 1 and all(type(x) is str for x in data))):
        return xr.Variable(dims, data, attrs, fastpath=True)
    return xr.Variable(dims, data, attrs)


def _index(name, values):
    """The pandas index of a dimension coordinate, kept for values seen before (up to 4096 of them)."""
    if values.dtype == object:  # names
        return _index_of(name, "O", (), tuple(values.tolist()))
    if values.size <= 4096:
        return _index_of(name, values.dtype.str, values.shape, values.tobytes())
    return PandasIndex(pd.Index(values), name)


@functools.lru_cache(maxsize=256)
def _index_of(name, dtype, shape, data):
    values = np.array(data, dtype=object) if dtype == "O" else np.frombuffer(data, dtype).reshape(shape)
    return PandasIndex(pd.Index(values), name)
