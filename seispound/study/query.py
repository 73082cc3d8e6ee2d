"""Query a study store: pick a variable, select, reduce, filter, tabulate.

A study store (schema :mod:`seispound.study.schema`) is a labelled cube: every
variable has the *run dimensions* ``("record", *axes)`` first, then, for some,
``building``/``floor`` or ``gap``.  The functions here are small steps that
compose; the ``seispound query`` subcommand chains them in a fixed order::

    pick --var -> --sel -> mask by --status -> --reduce ... -> --where ... -> --smallest/--largest

Quick use::

    from seispound.study import query as q
    with q.open_study("study.h5") as ds:
        gap = q.smallest_passing(ds, "gap_size", 1.2)   # per law, metres
        print(q.to_table(gap))

Conventions
-----------
* Values of runs that are not done are NaN; every reduction skips NaN unless
  told otherwise (``skipna=False``).
* Quantiles are xarray's :meth:`xarray.DataArray.quantile` with its default
  method, numpy's ``"linear"`` interpolation (type 7 of Hyndman & Fan): for n
  sorted values ``x[0..n-1]`` the q-quantile is ``x[i] + (x[i+1] - x[i]) * f``
  with ``i + f = q * (n - 1)``.
* Coordinate values typed on the command line are matched exactly (strings) or
  within a relative tolerance of 1e-9 (floats); nothing is silently snapped to
  the nearest value.
* Every user-input problem raises :class:`~seispound.errors.InputError` whose
  key is the command-line option it came from (``--var``, ``--sel gap_size``).
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import math
import re
import sys
import warnings
from pathlib import Path

import numpy as np
import xarray as xr

from ..errors import InputError
from .schema import SCHEMA, SCHEMA_VERSION, STATUS_DONE, STATUS_FAILED, STATUS_PENDING

__all__ = [
    "open_study", "run_dims", "pick", "mask_status", "done", "worst", "reduce", "select", "where",
    "axis_limit", "fails_again", "smallest_passing", "overview", "to_table", "to_csv", "to_json",
    "add_query_parser", "cmd_query",
]

REL_TOL = 1e-9  # how close a typed float must be to a coordinate value (relative)
REDUCTIONS = ("max", "min", "mean", "median", "std", "count")
STATUS_CODES = {"done": STATUS_DONE, "failed": STATUS_FAILED, "pending": STATUS_PENDING}
WORST_DIMS = ("building", "floor", "gap")
DEFAULT_VAR = "max_amplification"


# --------------------------------------------------------------------- opening


def open_study(path) -> xr.Dataset:
    """Open a study store lazily (values are read when used).

    Parameters
    ----------
    path : str or path-like
        The study file (HDF5 / netCDF-4 written with h5netcdf).

    Returns
    -------
    xarray.Dataset
        The store as written; attributes are left as stored (JSON ones are
        strings).  Close it when done (``with open_study(p) as ds: ...``).

    Raises
    ------
    InputError
        The file is missing, is not HDF5, or is not a ``seispound-study``
        store (key ``schema``) of a version this code reads (key
        ``schema_version``).
    """
    import h5py  # only here: the signature check needs it, nothing else does

    path = Path(path)
    if not path.is_file():
        raise InputError("study file not found", file=path)
    if not h5py.is_hdf5(str(path)):
        raise InputError("not an HDF5 file, so not a study store", file=path)
    try:
        ds = xr.open_dataset(path, engine="h5netcdf")
    except Exception as err:  # HDF5 but not netCDF-4-like: report, no traceback
        raise InputError(f"cannot read as netCDF-4: {err}", file=path) from err
    schema = ds.attrs.get("schema")
    if schema != SCHEMA:
        ds.close()
        raise InputError(f"not a study store: schema is {schema!r}, expected {SCHEMA!r}", file=path, key="schema")
    version = ds.attrs.get("schema_version")
    try:
        too_new = int(version) > SCHEMA_VERSION
    except (TypeError, ValueError):
        too_new = True
    if too_new:
        ds.close()
        raise InputError(f"schema version {version!r} is not readable by this seispound "
                         f"(reads up to {SCHEMA_VERSION})", file=path, key="schema_version")
    return ds


def run_dims(ds: xr.Dataset) -> list[str]:
    """The run dimensions, ``["record", *axes]``, from ``ds.attrs["run_dims"]`` (JSON)."""
    try:
        dims = json.loads(ds.attrs["run_dims"])
    except KeyError:
        raise InputError("attribute missing", key="run_dims") from None
    except (TypeError, ValueError):
        raise InputError("attribute is not a JSON list", key="run_dims") from None
    return [str(d) for d in dims]


# ------------------------------------------------------------ picking, masking


def pick(ds: xr.Dataset, var: str) -> xr.DataArray:
    """``ds[var]``, or InputError (key ``--var``) listing the data variables."""
    if var not in ds.data_vars:
        raise InputError(f"no variable {var!r}; variables: {', '.join(ds.data_vars)}", key="--var")
    return ds[var]


def _status_codes(which: str) -> list[int] | None:
    """``"done"``, ``"failed,pending"``, ``"all"`` -> status codes (None for all)."""
    names = [w.strip() for w in str(which).split(",") if w.strip()]
    if "all" in names:
        return None
    bad = [n for n in names if n not in STATUS_CODES]
    if bad or not names:
        raise InputError(f"unknown status {which!r}; use done, failed, pending, all "
                         "or a comma list", key="--status")
    return [STATUS_CODES[n] for n in names]


def mask_status(da: xr.DataArray, status: xr.DataArray, which: str = "done") -> xr.DataArray:
    """Keep the values of runs whose status is in ``which``; NaN elsewhere.

    Parameters
    ----------
    da : xarray.DataArray
        Any variable of the store (run dims first, maybe trailing dims).
    status : xarray.DataArray
        ``ds.status`` (run dims), selected the same way as ``da``.
    which : str
        ``done``, ``failed``, ``pending``, a comma list of these, or ``all``.

    Returns
    -------
    xarray.DataArray
        Same dims and attrs; integer variables become float (NaN needs it),
        string ones object (NaN where masked).
    """
    codes = _status_codes(which)
    if codes is None:
        return da
    out = da.where(status.isin(codes))
    out.attrs = dict(da.attrs)
    return out


def done(ds: xr.Dataset, var: str) -> xr.DataArray:
    """``ds[var]`` where the run is done (status == 1), NaN elsewhere.

    Integer variables (``impact_count``, ``total_impacts``) come back as float
    so that not-done runs are NaN instead of their stored -1.
    """
    return mask_status(pick(ds, var), ds["status"], "done")


def worst(da: xr.DataArray) -> xr.DataArray:
    """Max over whichever of ``building``, ``floor``, ``gap`` ``da`` has (NaN skipped).

    Absent floors are NaN padding, so skipping NaN is what makes this the
    largest value over the real floors.  A DataArray with none of these dims is
    returned unchanged.
    """
    dims = [d for d in WORST_DIMS if d in da.dims]
    return _quiet(lambda: da.max(dim=dims, skipna=True, keep_attrs=True)) if dims else da


# ------------------------------------------------------------------- reducing


def _parse_how(how) -> str | float:
    """A reduction name, or a quantile as a fraction in [0, 1].

    ``qX``: X <= 1 is a fraction, 1 < X <= 100 a percentage (``q0.9`` = ``q90``).
    ``pX``: always a percentage, 0 <= X <= 100 (``p90`` = 0.9, ``p1`` = 0.01).
    A bare number is a fraction in [0, 1].
    """
    if isinstance(how, (int, float)) and not isinstance(how, bool):
        q, text = float(how), repr(how)
    else:
        text = str(how).strip().lower()
        if text in REDUCTIONS:
            return text
        m = re.fullmatch(r"([qp])([0-9]*\.?[0-9]+(?:e[+-]?[0-9]+)?)", text)
        if not m:
            raise InputError(f"unknown reduction {how!r}; use {', '.join(REDUCTIONS)}, "
                             "or a quantile q90 / q0.9 / p90", key="--reduce")
        q = float(m.group(2))
        q = q / 100 if m.group(1) == "p" or q > 1 else q
    if not 0.0 <= q <= 1.0:
        raise InputError(f"quantile {text} is out of range: fractions 0..1, percentages up to 100",
                         key="--reduce")
    return q


def _dims_of(da: xr.DataArray, dim, key: str) -> list[str]:
    """A dim name, comma list or sequence -> list, checked against ``da.dims``."""
    dims = [d.strip() for d in dim.split(",")] if isinstance(dim, str) else list(dim)
    missing = [d for d in dims if d not in da.dims]
    if missing or not dims:
        raise InputError(f"no dimension {', '.join(missing) or repr(dim)}; "
                         f"dimensions: {', '.join(map(str, da.dims)) or 'none'}", key=key)
    return dims


def _quiet(fn):
    """Run ``fn`` without numpy's all-NaN-slice warnings (those slices are NaN, as meant)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return fn()


def _numeric(da: xr.DataArray, key: str) -> None:
    if da.dtype.kind not in "biuf":
        raise InputError(f"{da.name or 'the variable'} is not numeric (dtype {da.dtype})", key=key)


def reduce(da: xr.DataArray, dim, how, *, skipna: bool = True) -> xr.DataArray:
    """Reduce ``da`` over ``dim`` with a statistic.

    Parameters
    ----------
    da : xarray.DataArray
        Values (units in ``da.attrs["units"]``).
    dim : str or sequence of str
        Dimension(s) to reduce; a string may be a comma list
        (``"building,floor"``).
    how : str or float
        ``max``, ``min``, ``mean``, ``median``, ``std`` (population, ddof=0,
        as numpy), ``count`` (number of non-NaN values), or a quantile:
        ``q90`` / ``q0.9`` / ``p90`` / ``0.9``.  ``qX`` reads X <= 1 as a
        fraction and 1 < X <= 100 as a percentage; ``pX`` is always a
        percentage (``p1`` is the 1st percentile).  Quantiles use xarray's
        default method, numpy's ``"linear"`` interpolation.
    skipna : bool
        True: statistics over the non-NaN values (runs not done are NaN).
        False: NaN wherever any value reduced over is NaN.

    Returns
    -------
    xarray.DataArray
        ``da`` without ``dim``; same name and units (``count`` has units
        ``1``); no ``quantile`` coordinate.
    """
    dims = _dims_of(da, dim, "--reduce")
    how = _parse_how(how)
    if how != "count":
        _numeric(da, "--reduce")
    if how == "count":
        out = da.count(dim=dims)
        out.attrs = {**da.attrs, "units": "1"}
    elif isinstance(how, float):
        out = _quiet(lambda: da.quantile(how, dim=dims, skipna=skipna, keep_attrs=True))
        out = out.drop_vars("quantile")
    else:
        out = _quiet(lambda: getattr(da, how)(dim=dims, skipna=skipna, keep_attrs=True))
    out.name = da.name
    return out


# ------------------------------------------------------------------ selecting


def _float_text(x: float) -> str:
    return f"{x:.12g}"


def _listing(values, limit: int = 20) -> str:
    """The values a coordinate has, for an error message (at most ``limit``)."""
    vals = [_float_text(v) if isinstance(v, float) else str(v) for v in np.asarray(values).tolist()]
    more = f", ... ({len(vals)} in all)" if len(vals) > limit else ""
    return ", ".join(vals[:limit]) + more


def _close(coord: np.ndarray, x: float) -> np.ndarray:
    """Which float coordinate values equal ``x`` within REL_TOL (relative)."""
    return np.abs(coord - x) <= REL_TOL * np.maximum(np.abs(coord), abs(x))


def _to_number(text: str, kind: str, key: str) -> float:
    try:
        x = float(text)
    except ValueError:
        raise InputError(f"{text!r} is not a number", key=key) from None
    if math.isnan(x):
        raise InputError("nan is not a coordinate value", key=key)
    if kind in "iu" and not (math.isfinite(x) and x == int(x)):
        raise InputError(f"{text!r} is not an integer", key=key)
    return x


def _positions(coord: xr.DataArray, value, key: str) -> tuple[np.ndarray, bool]:
    """Positions along ``coord``'s dim that ``value`` selects, and whether it is one scalar.

    ``value`` is a string as typed (``"Hd"``, ``"0.02"``, ``"0.01:0.03"``,
    ``"Hd,LVe"``), a number, or a sequence of those.
    """
    c = np.asarray(coord.values)
    if not isinstance(value, str) and np.ndim(value) > 0:
        parts, scalar = [str(v) for v in value], False
    elif not isinstance(value, str):
        parts, scalar = [repr(value) if isinstance(value, float) else str(value)], True
    elif c.dtype.kind in "USO" and value in c.astype(str):
        parts, scalar = [value], True  # a name that itself contains "," or ":"
    else:
        parts = [p.strip() for p in value.split(",")]
        scalar = len(parts) == 1 and ":" not in value
    keep = np.zeros(c.shape, bool)
    for part in parts:
        hit = _match(c, part, key)
        if not hit.any():
            raise InputError(f"no value {part!r}; values: {_listing(c)}", key=key)
        keep |= hit
    return np.flatnonzero(keep), scalar


def _match(c: np.ndarray, part: str, key: str) -> np.ndarray:
    """Boolean mask of ``c`` matching one typed value or inclusive range ``a:b``."""
    if c.dtype.kind in "USO":
        if ":" in part and part not in c.astype(str):
            raise InputError(f"range {part!r} needs a numeric coordinate; values: {_listing(c)}", key=key)
        return c.astype(str) == part
    if c.dtype.kind not in "iuf":
        raise InputError(f"cannot select on a coordinate of dtype {c.dtype}", key=key)
    cf = c.astype(float)
    if ":" in part:
        lo_text, _, hi_text = part.partition(":")
        lo = _to_number(lo_text, "f", key) if lo_text.strip() else -np.inf
        hi = _to_number(hi_text, "f", key) if hi_text.strip() else np.inf
        # inclusive ends, with the same tolerance as a single value
        return ((cf >= lo) | _close(cf, lo)) & ((cf <= hi) | _close(cf, hi))
    x = _to_number(part, c.dtype.kind, key)
    return cf == x if c.dtype.kind in "iu" else _close(cf, x)


def select(obj, sel: dict):
    """Select by coordinate values typed as text (``--sel DIM=VALUE``).

    Parameters
    ----------
    obj : xarray.DataArray or xarray.Dataset
    sel : dict
        ``{name: value}``.  ``name`` is a dimension (``law``, ``gap_size``,
        ``building``) or a 1-D coordinate along one (``record_file``,
        ``gap.1.size`` of a zipped axis).  ``value``:

        * ``"Hd"``: one value, the dimension is dropped (as ``.sel``);
        * ``"Hd,LVe"``: several values, the dimension is kept;
        * ``"0.01:0.03"``: inclusive range on a numeric coordinate (either
          end may be empty), the dimension is kept;
        * a number or a list also works from Python.

        Strings match exactly, integers exactly, floats within 1e-9
        relative; nothing is snapped to the nearest value.

    Returns
    -------
    Same type as ``obj``, indexed by position (lazy arrays stay lazy).

    Raises
    ------
    InputError
        Key ``--sel NAME``: unknown name (lists the dimensions) or value
        (lists the values), malformed number or range.
    """
    for name, value in sel.items():
        key = f"--sel {name}"
        if name in obj.dims and name not in obj.coords:
            coord = xr.DataArray(np.arange(obj.sizes[name]), dims=name)  # bare dim: positions
        elif name in obj.coords and obj.coords[name].ndim == 1:
            coord = obj.coords[name]
        else:
            raise InputError(f"no dimension {name!r}; dimensions: {', '.join(map(str, obj.dims))}", key=key)
        pos, scalar = _positions(coord, value, key)
        dim = coord.dims[0]
        obj = obj.isel({dim: int(pos[0]) if scalar and len(pos) == 1 else pos})
    return obj


# ------------------------------------------------------------------ filtering

_COND = re.compile(r"\s*(<=|>=|==|!=|=|<|>)\s*([-+]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][-+]?[0-9]+)?|[-+]?inf)\s*")


def where(da: xr.DataArray, condition: str) -> xr.DataArray:
    """Keep the values satisfying ``condition``, NaN elsewhere.

    Parameters
    ----------
    da : xarray.DataArray
        Numeric values.
    condition : str
        An operator and a number: ``"<1.2"``, ``">= 5e5"``, ``"==0"``,
        ``"!=0"``.  ``==`` / ``!=`` compare within 1e-9 relative (like
        ``select``), so ``==0.3`` finds 0.1 + 0.2.  NaN never satisfies.

    Returns
    -------
    xarray.DataArray
        Same dims, name and attrs; float.
    """
    m = _COND.fullmatch(str(condition))
    if not m:
        raise InputError(f"cannot read condition {condition!r}; write an operator (< <= > >= == !=) "
                         "and a number, like '<1.2' or '>= 5e5'", key="--where")
    _numeric(da, "--where")
    op, x = m.group(1), float(m.group(2))
    v = da.astype(float)
    with np.errstate(invalid="ignore"):  # inf - inf is NaN: not equal, as wanted
        same = np.abs(v - x) <= REL_TOL * np.maximum(np.abs(v), abs(x))
    keep = {"<": v < x, "<=": v <= x, ">": v > x, ">=": v >= x,
            "==": same, "=": same, "!=": ~same}[op]
    out = v.where(keep)
    out.attrs = dict(da.attrs)
    out.name = da.name
    return out


# ---------------------------------------------------- smallest value that passes


def axis_limit(ok: xr.DataArray, axis: str, *, largest: bool = False, monotone: bool = True) -> xr.DataArray:
    """The smallest (or largest) value of coordinate ``axis`` at which ``ok`` is true.

    Parameters
    ----------
    ok : xarray.DataArray of bool
        The condition, with ``axis``'s dimension among its dims.
    axis : str
        A numeric coordinate: a dimension coordinate (``gap_size``) or a 1-D
        coordinate along one (``gap.1.size`` of a zipped axis).  Values are
        compared by coordinate value, never by position, so an axis written
        in any order works.
    largest : bool
        False: the smallest passing value; True: the largest.
    monotone : bool
        True (default): the smallest value from which ``ok`` holds at *every*
        larger value studied too (what an engineer means by "a safe gap": a
        larger gap can fail again); with ``largest``, the largest value below
        which every smaller value passes.  False: the first value where ``ok``
        holds, whatever happens beyond it (:func:`fails_again` says where).

    Returns
    -------
    xarray.DataArray
        Float, over the remaining dims; NaN where no value qualifies.  Named
        ``smallest_<axis>`` / ``largest_<axis>``, units of the coordinate.
    """
    if axis not in ok.coords or ok.coords[axis].ndim != 1:
        raise InputError(f"no coordinate {axis!r} to search along; dimensions: "
                         f"{', '.join(map(str, ok.dims))}", key="--largest" if largest else "--smallest")
    coord = ok.coords[axis]
    dim = coord.dims[0]
    if coord.dtype.kind not in "iuf":
        raise InputError(f"{axis} has no order (values: {_listing(coord.values)})",
                         key="--largest" if largest else "--smallest")
    ok = ok.fillna(False).astype(bool)
    if monotone:
        # sort by value; a run of passing values from the far end is what counts
        order = np.argsort(coord.values.astype(float), kind="stable")
        if not largest:
            order = order[::-1]  # walk from the largest value down
        walked = ok.isel({dim: order}).astype(int).cumprod(dim).astype(bool)
        ok = walked.isel({dim: np.argsort(order, kind="stable")})
    values = xr.where(ok, coord.astype(float), np.nan)
    out = _quiet(lambda: values.max(dim) if largest else values.min(dim))
    out.name = f"{'largest' if largest else 'smallest'}_{axis}"
    out.attrs = {k: v for k, v in coord.attrs.items() if k in ("units", "long_name")}
    return out


def fails_again(ok: xr.DataArray, axis: str, *, largest: bool = False) -> list[str]:
    """Where the first passing value of ``axis`` and the safe one differ: the condition holds at the first and
    fails again beyond it.  One line per combination of the remaining dims, as ``law=Hd: ...``."""
    first = axis_limit(ok, axis, largest=largest, monotone=False)
    safe = axis_limit(ok, axis, largest=largest, monotone=True)
    units = first.attrs.get("units", "")
    lines = []
    for idx in np.ndindex(first.shape):
        a, b = float(first.values[idx]), float(safe.values[idx])
        if np.isnan(a) or a == b:
            continue
        where = ", ".join(f"{d}={first.coords[d].values[i]}" for d, i in zip(first.dims, idx)) or axis
        then = f"the safe answer is {b:g} {units}".rstrip() if not np.isnan(b) else "no value is safe"
        lines.append(f"{where}: the condition holds at {axis} = {a:g} {units} but fails again "
                     f"{'below' if largest else 'above'} it; {then}".replace("  ", " "))
    return lines


def smallest_passing(ds: xr.Dataset, axis: str, threshold: float, var: str = DEFAULT_VAR,
                     over="record", q: float = 0.9, below: bool = True, *,
                     monotone: bool = True, skipna: bool = False) -> xr.DataArray:
    """The smallest value of study axis ``axis`` for which a quantile passes a threshold.

    "The smallest gap per law for which the 90th percentile over records of
    the largest amplification is below 1.2" is
    ``smallest_passing(ds, "gap_size", 1.2)``.

    Steps: ``var`` of the done runs; its worst value over building/floor/gap
    (if it has them); the ``q``-quantile over ``over`` (linear interpolation,
    numpy's ``"linear"``); pass where it is strictly below ``threshold``
    (strictly above with ``below=False``); the smallest passing coordinate
    value of ``axis`` (:func:`axis_limit`).

    Parameters
    ----------
    ds : xarray.Dataset
        The study store.
    axis : str
        A numeric study axis (dimension coordinate), or a numeric member
        coordinate of a zipped axis (``gap.1.size``).
    threshold : float
        In the units of ``var``.
    var : str
        A variable of the store (default ``max_amplification``, units 1).
    over : str, sequence of str or None
        Dimension(s) the quantile is taken over (default ``record``); None:
        no quantile, each run must pass on its own.
    q : float
        Quantile as a fraction in [0, 1] (0.9 = 90th percentile).
    below : bool
        True: pass where the quantile < threshold; False: where > threshold.
    monotone : bool
        True (default): the smallest value from which every larger value
        studied passes as well (a safe gap).  False: the first passing value.
    skipna : bool
        False (default): an axis value where any run along ``over`` is not
        done (failed or pending) gives a NaN quantile, which does not pass:
        a missing record cannot make a gap look safe.  True: the quantile
        over the done runs only.

    Returns
    -------
    xarray.DataArray
        ``smallest_<axis>`` over the remaining run dims (e.g. ``law``), in the
        units of the axis; NaN where no value passes.
    """
    da = worst(done(ds, var))
    if over:
        da = reduce(da, over, q, skipna=skipna)
    _numeric(da, "--var")
    ok = (da < threshold) if below else (da > threshold)
    return axis_limit(ok, axis, monotone=monotone)


# ------------------------------------------------------------------ tabulating


def _header(name, attrs) -> str:
    units = attrs.get("units")
    return f"{name} [{units}]" if units not in (None, "") else str(name)


def _is_missing(v) -> bool:
    return v is None or (isinstance(v, float) and math.isnan(v))


def _columns(da: xr.DataArray, dropna: bool):
    """Headers and rows (python scalars): one row per element, C order."""
    name = da.name if da.name is not None else "value"
    heads = [_header(d, da.coords[d].attrs if d in da.coords else {}) for d in da.dims]
    heads.append(_header(name, da.attrs))
    axes = [np.asarray(da.coords[d].values if d in da.coords else np.arange(da.sizes[d])).tolist()
            for d in da.dims]
    values = np.asarray(da.values)
    rows = []
    for idx in np.ndindex(values.shape):
        v = values[idx].item() if hasattr(values[idx], "item") else values[idx]
        if dropna and _is_missing(v):
            continue
        rows.append([axes[k][i] for k, i in enumerate(idx)] + [v])
    return heads, rows


def _cell(v, missing: str) -> str:
    if _is_missing(v):
        return missing
    if isinstance(v, float):
        return str(int(v)) if v.is_integer() and abs(v) < 1e15 else f"{v:.6g}"
    return str(v)


def to_table(da: xr.DataArray, *, dropna: bool = False, missing: str = "nan") -> str:
    """An aligned text table: one row per element of ``da``.

    Columns: one per dimension (its coordinate values, units in brackets when
    the coordinate has them), then the values, headed ``NAME [UNITS]``.
    Floats are shown with 6 significant digits; use :func:`to_csv` for full
    precision.  ``dropna`` leaves out rows whose value is missing;
    ``missing`` is what a missing value prints as.
    """
    heads, rows = _columns(da, dropna)
    cells = [[_cell(v, missing) for v in row] for row in rows]
    numeric = [all(isinstance(row[k], (int, float)) for row in rows) for k in range(len(heads))]
    widths = [max([len(h)] + [len(r[k]) for r in cells]) for k, h in enumerate(heads)]

    def line(items):
        return "  ".join(s.rjust(w) if num else s.ljust(w)
                         for s, w, num in zip(items, widths, numeric)).rstrip()

    return "\n".join([line(heads)] + [line(r) for r in cells]) + "\n"


def to_csv(da: xr.DataArray, *, dropna: bool = False) -> str:
    """CSV (comma separated, one header line), same columns as :func:`to_table`.

    Floats are written with full precision (shortest round-trip repr);
    missing values are empty cells.
    """
    heads, rows = _columns(da, dropna)
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(heads)
    writer.writerows([[_csv_cell(v) for v in row] for row in rows])
    return buf.getvalue()


def _csv_cell(v):
    if _is_missing(v):
        return ""
    if isinstance(v, float):
        return _cell(v, "") if v.is_integer() and abs(v) < 1e15 else repr(v)
    return v


def to_json(da: xr.DataArray, *, dropna: bool = False) -> str:
    """JSON: ``{"variable", "long_name", "units", "dims", "records": [...]}``.

    ``units`` maps each column that has units (the variable, coordinates) to
    them; ``records`` holds one object per element, keyed by dimension names
    and the variable name; missing values are ``null``.
    """
    name = str(da.name if da.name is not None else "value")
    heads, rows = _columns(da, dropna)
    keys = [str(d) for d in da.dims] + [name]
    units = {str(d): da.coords[d].attrs["units"] for d in da.dims
             if d in da.coords and da.coords[d].attrs.get("units")}
    if da.attrs.get("units") not in (None, ""):
        units[name] = da.attrs["units"]
    records = [{k: (None if _is_missing(v) else v) for k, v in zip(keys, row)} for row in rows]
    meta = {"variable": name, "long_name": da.attrs.get("long_name", ""), "units": units, "dims": keys[:-1]}
    # one record per line: readable, and still greppable for a large table
    head = "".join(f" {json.dumps(k)}: {json.dumps(v)},\n" for k, v in meta.items())
    body = ",\n".join("  " + json.dumps(r, allow_nan=False) for r in records)
    return "{\n" + head + ' "records": [\n' + body + ("\n" if body else "") + " ]\n}\n"


def overview(ds: xr.Dataset) -> str:
    """A text overview: title, run dims with sizes and values, run counts, variables."""
    dims = run_dims(ds)
    status = np.asarray(ds["status"].values)
    n = {k: int((status == c).sum()) for k, c in STATUS_CODES.items()}
    lines = [str(ds.attrs.get("title", "")) or "(untitled study)",
             f"  runs: {status.size} = {n['done']} done, {n['failed']} failed, {n['pending']} pending",
             "  run dimensions:"]
    for d in dims:
        lines.append(f"    {_header(d, ds[d].attrs):<20} {ds.sizes[d]:>4}: {_listing(ds[d].values, 8)}")
    lines.append("  variables:")
    for name, v in ds.data_vars.items():
        trailing = [d for d in v.dims if d not in dims]
        shape = f"(runs{''.join(', ' + d for d in trailing)})"
        lines.append(f"    {_header(name, v.attrs):<40} {shape:<28} {v.attrs.get('long_name', '')}".rstrip())
    return "\n".join(lines) + "\n"


# ------------------------------------------------------------------ command line

USAGE_EPILOG = """\
steps, in this order: --var, --sel, --status, --reduce (in the order given),
--where (all must hold), --smallest/--largest.
examples:
  seispound query study.h5
  seispound query study.h5 --sel law=Hd --reduce record=max
  seispound query study.h5 --reduce record=q90 --where '<1.2' --smallest gap_size --strict
"""


def add_query_parser(subparsers) -> argparse.ArgumentParser:
    """Add the ``query`` subcommand to ``subparsers`` (from ``add_subparsers``)."""
    p = subparsers.add_parser(
        "query", help="tabulate, reduce and filter a study store",
        description="Query a study store. With only the file: an overview.",
        epilog=USAGE_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("study", metavar="STUDY", help="study store (.h5)")
    p.add_argument("--var", help=f"variable to show (default {DEFAULT_VAR})")
    p.add_argument("--sel", action="append", default=[], metavar="DIM=VALUE",
                   help="keep these coordinate values: VALUE, V1,V2 or an inclusive range A:B (repeatable)")
    p.add_argument("--status", help="runs kept: done, failed, pending, a comma list or all "
                                    "(default: done; all for the status and error variables)")
    p.add_argument("--reduce", action="append", default=[], metavar="DIM=HOW",
                   help="reduce DIM (or DIM1,DIM2) with max, min, mean, median, std, count, "
                        "or a quantile q90 / q0.9 / p90 (repeatable, applied in order)")
    p.add_argument("--strict", action="store_true",
                   help="a reduction is NaN where any run it covers is not done "
                        "(default: over the done runs only)")
    p.add_argument("--where", action="append", default=[], metavar="COND",
                   help="keep values meeting COND, like '<1.2' or '>=5e5' (repeatable: all must hold)")
    lim = p.add_mutually_exclusive_group()
    lim.add_argument("--smallest", metavar="AXIS",
                     help="per remaining combination, the smallest AXIS value meeting --where")
    lim.add_argument("--largest", metavar="AXIS",
                     help="per remaining combination, the largest AXIS value meeting --where")
    reading = p.add_mutually_exclusive_group()
    reading.add_argument("--monotone", action="store_true",
                         help="with --smallest: the smallest value from which every larger one passes too "
                              "(with --largest: every smaller one); the default")
    reading.add_argument("--first-passing", action="store_true",
                         help="with --smallest/--largest: the first value that passes, even if a larger "
                              "(smaller) one fails again")
    p.add_argument("--dropna", action="store_true", help="leave out rows whose value is missing")
    p.add_argument("--format", choices=("table", "csv", "json"),
                   help="output format (default: from the -o suffix .csv/.json, else table)")
    p.add_argument("-o", "--output", metavar="FILE", help="write to FILE (atomically) instead of stdout")
    return p


def _pairs(items, key: str, form: str) -> list[tuple[str, str]]:
    """``["a=b", ...]`` -> ``[("a", "b"), ...]``; InputError naming ``form`` if malformed."""
    out = []
    for item in items:
        name, eq, value = item.partition("=")
        if not eq or not name.strip() or not value.strip():
            raise InputError(f"write {form}, got {item!r}", key=key)
        out.append((name.strip(), value.strip()))
    return out


def _write_atomic(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` via a temporary file and ``os.replace``: never half-written."""
    from .._output import atomic_output, check_writable

    check_writable(path, key="-o")
    with atomic_output(path, key="-o") as tmp:
        with open(tmp, "w", encoding="utf-8", newline="") as fh:
            fh.write(text)


def _is_overview(args) -> bool:
    return not (args.var or args.sel or args.status or args.reduce or args.where or args.smallest
                or args.largest or args.format or args.strict or args.monotone or args.dropna
                or args.first_passing)


def _query(ds: xr.Dataset, args):
    """Run the query steps on an open store.

    Returns the result, the text for a missing value, and a note for stderr
    (or "") when reductions silently skipped runs that are not done.
    """
    var = args.var or DEFAULT_VAR
    pick(ds, var)
    sel = {}
    for name, value in _pairs(args.sel, "--sel", "DIM=VALUE"):
        if name in sel:
            raise InputError("given twice; list values as V1,V2 instead", key=f"--sel {name}")
        sel[name] = value
    # select first (cheap, lazy), then mask: both act elementwise, so the order is immaterial
    sub = select(ds[list(dict.fromkeys([var, "status"]))], sel)
    which = args.status or ("all" if var in ("status", "error") else "done")
    da = mask_status(sub[var], sub["status"], which)
    note = ""
    not_done = int((sub["status"] != STATUS_DONE).sum())
    if args.reduce and not args.strict and not_done:
        # a statistic over fewer records than asked for deserves a word
        note = (f"note: {not_done} of {sub['status'].size} selected runs are not done (NaN values); "
                "reductions skip NaN (--strict: NaN instead)")
    for dims, how in _pairs(args.reduce, "--reduce", "DIM=HOW"):
        da = reduce(da, dims, how, skipna=not args.strict)
    for cond in args.where:
        da = where(da, cond)
    axis = args.smallest or args.largest
    for flag, given in (("--monotone", args.monotone), ("--first-passing", args.first_passing)):
        if given and not axis:
            raise InputError("needs --smallest AXIS or --largest AXIS", key=flag)
    if axis:
        key = "--smallest" if args.smallest else "--largest"
        if not args.where:
            raise InputError("needs --where COND: the condition the value must meet", key=key)
        ok = da.notnull()
        da = axis_limit(ok, axis, largest=bool(args.largest), monotone=not args.first_passing)
        again = fails_again(ok, axis, largest=bool(args.largest)) if axis in ok.coords else []
        if again:  # the two readings differ: say so, whichever was asked
            note = "\n".join(([note] if note else []) + [f"note: {line}" for line in again])
        return da, "none", note
    return da, "nan", note


def cmd_query(args) -> int:
    """The ``seispound query`` subcommand; returns the exit code (0).

    Raises
    ------
    InputError
        Any bad input, located at the study file (or the output file).
    """
    if args.output:  # an output that cannot be written: one line, before reading the store
        from .._output import check_writable

        check_writable(Path(args.output), key="-o")
    fmt = args.format or {".csv": "csv", ".json": "json"}.get(Path(args.output or "").suffix.lower(), "table")
    try:
        with open_study(args.study) as ds:
            if _is_overview(args):
                text = overview(ds)
            else:
                da, missing, note = _query(ds, args)
                if note:
                    print(note, file=sys.stderr)
                if fmt == "csv":
                    text = to_csv(da, dropna=args.dropna)
                elif fmt == "json":
                    text = to_json(da, dropna=args.dropna)
                else:
                    text = to_table(da, dropna=args.dropna, missing=missing)
    except InputError as err:
        raise err.located(file=args.study) from None
    if args.output:
        _write_atomic(Path(args.output), text)
    else:
        print(text, end="")
    return 0
