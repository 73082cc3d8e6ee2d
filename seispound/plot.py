"""Figures of a study store (``seispound-study``) and of a single run (``seispound-result``).

Every figure is written twice, ``OUT.png`` (150 dpi) and ``OUT.svg``, atomically.
matplotlib is the optional extra ``plot`` (``pip install 'seispound[plot]'``); it,
numpy and xarray are imported inside the functions so that ``import seispound``
and the command line stay light.

Figures are built on a bare :class:`matplotlib.figure.Figure` with the Agg canvas,
never through :mod:`matplotlib.pyplot`: nothing is registered with pyplot, so no
figure stays open and no GUI backend is ever touched.

Functions that save (return the two paths written)
    :func:`study_amplification`, :func:`study_force`, :func:`run_histories`.
Functions that only build the Figure (for notebooks and tests)
    :func:`study_amplification_figure`, :func:`study_force_figure`,
    :func:`run_histories_figure`; write one with :func:`save_figure`.

Bad choices raise :class:`~seispound.errors.InputError` whose key is the name of
the matching command-line option (``--axis``, ``--by``, ``--over``, ``--sel``,
``--floors``, ``--kind``, ``--output``), so that the CLI message names what to fix.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from .errors import InputError

__all__ = [
    "study_amplification", "study_force", "run_histories", "run_spectra",
    "study_amplification_figure", "study_force_figure", "run_histories_figure", "spectra_figure",
    "save_figure", "add_plot_parser", "cmd_plot", "KINDS",
]

KINDS = ("amplification", "force", "histories", "spectrum")
DPI = 150
STUDY_FIGSIZE = (9.0, 5.0)    # inches: 1350 x 750 px at 150 dpi
RUN_FIGSIZE = (10.0, 9.0)     # inches: 1500 x 1350 px at 150 dpi (three panels)
STATUS_DONE = 1               # mirrors seispound.study.schema.STATUS_DONE (kept import-free)


# --------------------------------------------------------------------------- matplotlib

def _new_figure(figsize):
    """A bare Figure on the Agg canvas (no pyplot: no global state, no GUI)."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise InputError("matplotlib is needed: pip install 'seispound[plot]'", key="plot") from None
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize, dpi=DPI, layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def _out_paths(out) -> tuple[Path, Path]:
    """``OUT.png`` and ``OUT.svg`` from ``out`` given with or without one of those suffixes."""
    out = Path(out)
    if out.suffix.lower() in (".png", ".svg"):
        out = out.with_suffix("")
    if not out.name:
        raise InputError("output needs a file name", file=out, key="--output")
    from ._output import check_writable

    finals = out.with_name(out.name + ".png"), out.with_name(out.name + ".svg")
    for final in finals:  # a folder, a read-only or virtual file system: one line, before any work
        check_writable(final, key="--output")
    return finals


def save_figure(fig, out) -> tuple[Path, Path]:
    """Write ``fig`` as ``OUT.png`` (150 dpi) and ``OUT.svg``, atomically.

    Both files are first written under temporary names in the output folder and
    renamed only once both are complete, so a failure leaves no partial figure.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
    out : str or path-like
        Output name, with or without the suffix ``.png`` or ``.svg``.

    Returns
    -------
    (Path, Path)
        The PNG and SVG paths written.
    """
    from ._output import default_file_mode

    finals = _out_paths(out)
    temps = []
    try:
        for final in finals:
            fd, tmp = tempfile.mkstemp(prefix=f".{final.name}.", suffix=".tmp", dir=final.parent)
            os.close(fd)
            temps.append(tmp)
            fig.savefig(tmp, format=final.suffix[1:], dpi=DPI)
            os.chmod(tmp, default_file_mode())  # mkstemp's 0600 would ignore the umask
        for tmp, final in zip(temps, finals):
            os.replace(tmp, final)
    finally:
        for tmp in temps:
            if os.path.exists(tmp):
                os.unlink(tmp)
    return finals


def _close(fig):
    """Free the figure's artists (it was never registered with pyplot)."""
    fig.clear()


# --------------------------------------------------------------------------- labels

def _units_label(attrs) -> str:
    units = attrs.get("units")
    if units in (None, ""):
        return ""
    return " [-]" if units == "1" else f" [{units}]"


def _fmt(value) -> str:
    if isinstance(value, (float, int)) or hasattr(value, "dtype"):
        try:
            return f"{float(value):g}"
        except (TypeError, ValueError):
            pass
    return str(value)


def _members(ds, dim) -> list[str]:
    """The coordinates zipped along a study axis (``gap.1.size`` ...), empty for a plain axis."""
    if dim == "record":  # record_file is provenance, not a member
        return []
    return [c for c in ds.coords if c != dim and ds[c].dims == (dim,)]


def _value_labels(ds, dim) -> list[str]:
    """One short text per value of ``dim``: its value, or its zipped members' values."""
    import numpy as np

    members = _members(ds, dim)
    if dim in ds.coords and (ds[dim].dtype.kind in "OUS" or not np.array_equal(ds[dim].values,
                                                                              np.arange(ds.sizes[dim]))):
        members = []  # a zipped axis labelled by its first path's values (the law names ...)
    if members:
        units = {m: ds[m].attrs.get("units", "") for m in members}
        return [", ".join(f"{m}={_fmt(ds[m].values[i])}" + (f" {units[m]}" if units[m] not in ("", "1") else "")
                          for m in members)
                for i in range(ds.sizes[dim])]
    if dim in ds.coords:
        return [_fmt(v) for v in ds[dim].values]
    return [str(i) for i in range(ds.sizes[dim])]


def _dim_title(ds, dim) -> str:
    """``gap size [m]`` from a dimension's coordinate (long_name or name, and units)."""
    if dim in ds.coords:
        # the dimension's own name (a study axis's long_name is its dotted path: too technical)
        attrs = ds[dim].attrs
        return f"{dim.replace('_', ' ')}{_units_label(attrs)}"
    return dim.replace("_", " ")


# --------------------------------------------------------------------------- study stores

def _check_dim(name, dims, key, what):
    if name not in dims:
        raise InputError(f"unknown {what} {name!r}; choose from {', '.join(dims)}", key=key)


def _select(da, status, sel, reserved):
    """Apply ``sel`` ({dim: value}) to ``da`` and ``status``; values may be strings from the CLI."""
    import numpy as np

    picked = []
    for dim, value in (sel or {}).items():
        _check_dim(dim, list(da.dims), "--sel", "dimension")
        if dim in reserved:
            raise InputError(f"cannot select on {dim!r}: it is the {reserved[dim]} dimension", key="--sel")
        coord = da[dim].values if dim in da.coords else np.arange(da.sizes[dim])
        if np.issubdtype(coord.dtype, np.number):
            try:
                target = float(value)
            except (TypeError, ValueError):
                raise InputError(f"{dim}={value!r}: expected a number", key="--sel") from None
            hits = np.flatnonzero(np.isclose(coord.astype(float), target, rtol=1e-6, atol=0.0))
        else:
            hits = np.flatnonzero(coord.astype(str) == str(value))
        if hits.size == 0:
            raise InputError(f"{dim}={value}: no such value; {dim} has "
                             f"{', '.join(_fmt(v) for v in coord)}", key="--sel")
        da = da.isel({dim: hits[0]})
        if dim in status.dims:
            status = status.isel({dim: hits[0]})
        picked.append(f"{dim}={_fmt(coord[hits[0]])}")
    return da, status, picked


def _study_cube(ds, var, axis, by, over, sel):
    """The values to plot as an array (by, axis, over), runs not done set to NaN.

    Returns the array (a leading axis of length 1 when ``by`` is None) and the
    notes for the title: selections, max reductions, runs left out.
    """
    import numpy as np

    if "status" not in ds:
        raise InputError("not a study store: no 'status' variable", key="schema")
    if var not in ds:
        raise InputError(f"no variable {var!r} in the study store", key="var")
    run_dims = list(ds["status"].dims)
    _check_dim(axis, run_dims, "--axis", "study axis")
    _check_dim(over, run_dims, "--over", "run dimension")
    if by is not None:
        _check_dim(by, run_dims, "--by", "run dimension")
    roles = {axis: "--axis", over: "--over"}
    if over == axis:
        raise InputError(f"--over {over!r} is also the --axis", key="--over")
    if by is not None:
        if by in roles:
            raise InputError(f"--by {by!r} is also the {roles[by]}", key="--by")
        roles[by] = "--by"

    status = ds["status"]
    da = ds[var].where(status == STATUS_DONE)  # failed and pending runs are left out
    da, status, notes = _select(da, status, sel, roles)
    extra = [d for d in da.dims if d not in roles]
    if extra:
        da = da.max(extra, skipna=True)
        notes.append(f"max over {', '.join(extra)}")
    n_runs, n_done = int(status.size), int((status == STATUS_DONE).sum())
    if n_done == 0:
        raise InputError("no finished run (status 1) in the selection", key="--sel")
    if n_done < n_runs:
        notes.append(f"{n_runs - n_done} of {n_runs} runs not done, left out")
    order = ([by] if by is not None else []) + [axis, over]
    values = np.asarray(da.transpose(*order).values, dtype=float)
    if by is None:
        values = values[np.newaxis]
    return values, notes


def _spread(values):
    """Median, min and max over the last axis, ignoring NaN (left out runs)."""
    import warnings

    import numpy as np

    with warnings.catch_warnings():  # an axis value with no finished run gives NaN, on purpose
        warnings.simplefilter("ignore", RuntimeWarning)
        return (np.nanmedian(values, axis=-1), np.nanmin(values, axis=-1), np.nanmax(values, axis=-1))


def _study_figure(ds, var, axis, by, over, sel, *, scale, ylabel, what, reference=None):
    import numpy as np
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    values, notes = _study_cube(ds, var, axis, by, over, sel)
    values = values / scale
    median, low, high = _spread(values)

    numeric_axis = (axis in ds.coords and not _members(ds, axis)
                    and np.issubdtype(ds[axis].dtype, np.number))
    x = ds[axis].values.astype(float) if numeric_axis else np.arange(ds.sizes[axis], dtype=float)
    order = np.argsort(x, kind="stable")  # axis values come in study-file order: draw left to right
    x, values, median, low, high = x[order], values[:, order], median[:, order], low[:, order], high[:, order]
    by_labels = _value_labels(ds, by) if by is not None else [what]
    over_labels = _value_labels(ds, over)

    fig = _new_figure(STUDY_FIGSIZE)
    ax = fig.add_subplot()
    colors = [f"C{i % 10}" for i in range(len(by_labels))]
    for i, (label, color) in enumerate(zip(by_labels, colors)):
        ax.fill_between(x, low[i], high[i], color=color, alpha=0.18, linewidth=0, label="_band")
        for j, rec in enumerate(over_labels):  # each record, faint, to show what the band hides
            ax.plot(x, values[i, :, j], color=color, alpha=0.45, linewidth=0.7, marker=".",
                    markersize=3, label=f"_{over}={rec}")
        ax.plot(x, median[i], color=color, linewidth=2.2, marker="o", markersize=5, label=label)
    if reference is not None:
        ax.axhline(reference, color="0.2", linestyle="--", linewidth=1.0, label="_reference")
    if not numeric_axis:
        ax.set_xticks(x, [t.replace(", ", "\n") for t in _value_labels(ds, axis)])

    ax.set_xlabel(_dim_title(ds, axis))
    ax.set_ylabel(ylabel)
    ax.grid(True, alpha=0.3)
    n_over = values.shape[-1]
    handles = [Line2D([], [], color=c, linewidth=2.2, marker="o", markersize=5, label=lab)
               for lab, c in zip(by_labels, colors)]
    handles += [Line2D([], [], color="0.4", linewidth=2.2, marker="o", markersize=5,
                       label=f"median over {over} ({n_over})"),
                Patch(color="0.4", alpha=0.25, linewidth=0, label=f"min to max over {over}"),
                Line2D([], [], color="0.4", alpha=0.6, linewidth=0.7, marker=".", markersize=3,
                       label=f"each {over}")]
    if reference is not None:
        handles.append(Line2D([], [], color="0.2", linestyle="--", linewidth=1.0,
                              label=f"{reference:g}: no amplification"))
    ax.legend(handles=handles, title=by.replace("_", " ") if by else None, loc="upper left",
              bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, fontsize="small", title_fontsize="small")
    fig.suptitle(ds.attrs.get("title") or "seispound study", fontsize="medium")
    ax.set_title(f"{what}: median over {over}, band min to max over {over}"
                 + (f"\n{'; '.join(notes)}" if notes else ""), fontsize="small")
    return fig


def study_amplification_figure(ds, axis, by=None, over="record", var="max_amplification", sel=None):
    """Build (not save) the amplification figure; see :func:`study_amplification`.

    Returns
    -------
    matplotlib.figure.Figure
        One Axes; each median line carries the ``by`` value as its label, each
        single-run line the label ``"_<over>=<value>"``.
    """
    units = _units_label(ds[var].attrs) if var in ds else ""
    long = var.replace("_", " ")
    return _study_figure(ds, var, axis, by, over, sel, scale=1.0, ylabel=f"{long}{units or ' [-]'}",
                         what=long, reference=1.0)


def study_amplification(ds, axis, by=None, over="record", var="max_amplification", *, sel=None, out):
    """Displacement amplification against a study axis, written as PNG and SVG.

    One thick line per value of ``by`` is the median over ``over`` (the records);
    the shaded band spans min to max over ``over`` and thin faint lines show each
    record. A dashed line at 1 marks "no amplification". Only runs with
    ``status == 1`` (done) count. Run dimensions other than ``axis``, ``by``,
    ``over`` and those fixed by ``sel`` are reduced with max, which the figure
    title states.

    Parameters
    ----------
    ds : xarray.Dataset
        A study store (schema ``seispound-study``).
    axis : str
        The run dimension on the x axis (label and units from its coordinate's
        ``long_name``/``units`` attributes, e.g. "gap size [m]").
    by : str, optional
        Run dimension giving one line per value (e.g. the contact law axis).
    over : str, default "record"
        Run dimension the median and the band are taken over.
    var : str, default "max_amplification"
        Variable to plot [-]; one with more dimensions (``amplification``:
        building, floor) is reduced with max unless ``sel`` fixes them.
    sel : dict, optional
        ``{dim: value}`` fixing other dimensions first; values may be strings
        (numbers match to a relative 1e-6).
    out : str or path-like
        Output name, with or without suffix; ``OUT.png`` and ``OUT.svg`` are written.

    Returns
    -------
    (Path, Path)
        The PNG and SVG written.

    Raises
    ------
    InputError
        Unknown or conflicting dimensions (key ``--axis``, ``--by``, ``--over``,
        ``--sel``), no finished run, missing matplotlib (key ``plot``).
    """
    paths = _out_paths(out)  # fail on a bad output before the work
    fig = study_amplification_figure(ds, axis, by=by, over=over, var=var, sel=sel)
    try:
        return save_figure(fig, paths[0])
    finally:
        _close(fig)


def _force_unit(ds, var):
    """kN, or MN when the largest force reaches 1000 kN: (scale from N, unit)."""
    import numpy as np

    if var not in ds or ds[var].attrs.get("units", "N") != "N":
        return 1.0, ds[var].attrs.get("units", "N") if var in ds else "N"
    done = ds[var].where(ds["status"] == STATUS_DONE) if "status" in ds else ds[var]
    peak = float(np.nanmax(np.abs(done.values), initial=0.0))
    return (1e6, "MN") if peak >= 1e6 else (1e3, "kN")


def study_force_figure(ds, axis, by=None, over="record", var="max_pounding_force", sel=None):
    """Build (not save) the pounding force figure; see :func:`study_force`."""
    scale, unit = _force_unit(ds, var)
    long = "peak pounding force" if var == "max_pounding_force" else var.replace("_", " ")
    return _study_figure(ds, var, axis, by, over, sel, scale=scale, ylabel=f"{long} [{unit}]", what=long)


def study_force(ds, axis, by=None, over="record", var="max_pounding_force", *, sel=None, out):
    """Peak pounding force against a study axis, written as PNG and SVG.

    Same layout and parameters as :func:`study_amplification`, without the line
    at 1. ``max_pounding_force`` [N] (the largest over the gap elements) is shown
    in kN, or in MN when it reaches 1000 kN; the unit is in the y label.

    Returns
    -------
    (Path, Path)
        The PNG and SVG written.
    """
    paths = _out_paths(out)
    fig = study_force_figure(ds, axis, by=by, over=over, var=var, sel=sel)
    try:
        return save_figure(fig, paths[0])
    finally:
        _close(fig)


# --------------------------------------------------------------------------- single runs

def _parse_floor(item):
    """("A", 4) from ("A", 4) or the CLI text "A:4"."""
    if isinstance(item, str):
        name, sep, floor = item.rpartition(":")
        if not sep or not name:
            raise InputError(f"{item!r}: expected BUILDING:FLOOR, e.g. A:4", key="--floors")
        item = (name, floor)
    try:
        name, floor = item
        return str(name), int(floor)
    except (TypeError, ValueError):
        raise InputError(f"{item!r}: expected (building, floor) with an integer floor", key="--floors") from None


def _check_floors(ds, floors):
    import numpy as np

    names = [str(b) for b in ds.building.values]
    checked = []
    for item in floors:
        name, floor = _parse_floor(item)
        if name not in names:
            raise InputError(f"unknown building {name!r}; buildings: {', '.join(names)}", key="--floors")
        heights = ds.floor_height.values[names.index(name)]
        n = int(np.count_nonzero(~np.isnan(heights)))
        if not 1 <= floor <= n:
            raise InputError(f"building {name} has floors 1 to {n}, not {floor}", key="--floors")
        if (name, floor) not in checked:
            checked.append((name, floor))
    if not checked:
        raise InputError("no floor chosen", key="--floors")
    return checked


def default_floors(ds) -> list[tuple[str, int]]:
    """Floors shown when none are chosen: both sides of the gap element with the most impacts.

    Ties go to the higher gap element (usually the top of the lower building).
    Without gap elements: the top floor of every building.
    """
    import numpy as np

    if ds.sizes.get("gap", 0):
        counts = ds.impact_count.values
        g = len(counts) - 1 - int(np.argmax(counts[::-1]))
        return [(str(ds.gap_left.values[g]), int(ds.gap_left_floor.values[g])),
                (str(ds.gap_right.values[g]), int(ds.gap_right_floor.values[g]))]
    tops = (~np.isnan(ds.floor_height.values)).sum(axis=1)
    return [(str(b), int(n)) for b, n in zip(ds.building.values, tops)]


def _gaps_at(ds, floors):
    """Gap elements with one side at one of ``floors``, in gap order."""
    chosen = set(floors)
    return [g for g in range(ds.sizes.get("gap", 0))
            if (str(ds.gap_left.values[g]), int(ds.gap_left_floor.values[g])) in chosen
            or (str(ds.gap_right.values[g]), int(ds.gap_right_floor.values[g])) in chosen]


#: Runs shorter than this [s] (impact tests) get their time axis in ms.
MS_BELOW = 1.0


def run_histories_figure(ds, floors=None):
    """Build (not save) the history figure of one run; see :func:`run_histories`.

    Returns
    -------
    matplotlib.figure.Figure
        Three Axes: displacement; relative displacement of each gap element's two floors
        (u_left - u_right) against its at-rest size, so the closing gap shows; pounding force.
        Displacement lines are labelled ``"A floor 4"``, relative displacement lines
        ``"u_A4 - u_B4 (gap 3)"`` with the gap size as a dashed line ``"_size gap 3"``,
        force lines ``"gap 3: A 4 | B 4"``, and the impact markers of gap g ``"_impacts gap g"``.
        Runs shorter than ``MS_BELOW`` (impact tests) use ms on the time axis.
    """
    import numpy as np
    from matplotlib.lines import Line2D

    if ds.attrs.get("schema", "seispound-result") != "seispound-result":
        raise InputError("histories need a single-run result (schema seispound-result)", key="--kind")
    floors = _check_floors(ds, default_floors(ds) if floors is None else floors)
    gaps = _gaps_at(ds, floors)
    t = ds.time.values
    ms = t[-1] < MS_BELOW
    scale_t, t_unit = (1e3, "ms") if ms else (1.0, "s")
    t = t * scale_t

    fig = _new_figure(RUN_FIGSIZE)
    ax_u, ax_d, ax_f = fig.subplots(3, 1, sharex=True)
    for i, (name, floor) in enumerate(floors):
        u = ds.displacement.sel(building=name, floor=floor).values * 100.0  # m -> cm
        ax_u.plot(t, u, color=f"C{i % 10}", linewidth=0.9, label=f"{name} floor {floor}")
    ax_u.axhline(0.0, color="0.5", linewidth=0.6)
    ax_u.set_ylabel("displacement [cm]")
    ax_u.legend(loc="upper right", fontsize="small", ncols=min(len(floors), 4))

    onsets, peaks, gap_of = (ds[v].values for v in ("impact_onset", "impact_peak_force", "impact_gap"))
    for k, g in enumerate(gaps):
        color = f"C{(len(floors) + k) % 10}"
        left, right = str(ds.gap_left.values[g]), str(ds.gap_right.values[g])
        fl, fr = int(ds.gap_left_floor.values[g]), int(ds.gap_right_floor.values[g])
        rel = (ds.displacement.sel(building=left, floor=fl).values
               - ds.displacement.sel(building=right, floor=fr).values) * 100.0
        ax_d.plot(t, rel, color=color, linewidth=0.9, label=f"u_{left}{fl} - u_{right}{fr} (gap {g})")
        ax_d.axhline(float(ds.gap_size.values[g]) * 100.0, color=color, linestyle="--", linewidth=0.8,
                     label=f"_size gap {g}")
        ax_f.plot(t, ds.pounding_force.isel(gap=g).values / 1e3, color=color, linewidth=0.9,
                  label=f"gap {g}: {left} {fl} | {right} {fr}")
        hit = gap_of == g
        # peak over every substep, at the onset: the sampled history can miss the true peak
        ax_f.plot(onsets[hit] * scale_t, peaks[hit] / 1e3, linestyle="none", marker="v", markersize=5,
                  markerfacecolor="none", markeredgecolor=color, markeredgewidth=0.9,
                  label=f"_impacts gap {g}")
    ax_d.set_ylabel("u_left - u_right [cm]")
    ax_f.set_ylabel("pounding force [kN]")
    ax_f.set_xlabel(f"time [{t_unit}]")
    if gaps:
        handles, _ = ax_d.get_legend_handles_labels()
        handles.append(Line2D([], [], color="0.3", linestyle="--", linewidth=0.8,
                              label="gap size: contact above the dashed line"))
        ax_d.legend(handles=handles, loc="upper right", fontsize="small")
        handles, _ = ax_f.get_legend_handles_labels()
        n_imp = int(np.isin(gap_of, gaps).sum())
        first = ", ".join(f"{x:.1f}" for x in np.sort(onsets[np.isin(gap_of, gaps)])[:4] * 1e3) if ms else ""
        handles.append(Line2D([], [], linestyle="none", marker="v", markersize=5, markerfacecolor="none",
                              markeredgecolor="0.3",
                              label=f"impact: at onset time, its peak force ({n_imp}"
                                    + (f"; onsets {first} ms" if first else "") + ")"))
        ax_f.legend(handles=handles, loc="upper right", fontsize="small")
    else:
        for ax in (ax_d, ax_f):
            ax.text(0.5, 0.5, "no gap element at these floors", transform=ax.transAxes,
                    ha="center", va="center", color="0.4")
    for ax in (ax_u, ax_d, ax_f):
        ax.grid(True, alpha=0.3)
    ax_f.set_xlim(t[0], t[-1])
    law = ds.attrs.get("contact_law", "").strip("[]").replace(chr(34), "")
    where = ", ".join(f"{b} floor {f}" for b, f in floors)
    fig.suptitle(f"{ds.attrs.get('title') or 'seispound run'}\nHistories of {where}"
                 + (f"; contact law {law}" if law else ""), fontsize="medium")
    return fig


def run_histories(ds_run, floors=None, *, out):
    """Displacement and pounding force histories of one run, written as PNG and SVG.

    Top panel: displacement relative to the ground [cm] of each chosen floor.
    Bottom panel: pounding force [kN] (compression positive) of every gap element
    with a side at one of those floors, and each of its impacts as a marker at
    (onset time, peak force of that impact). Shared time axis [s].

    Parameters
    ----------
    ds_run : xarray.Dataset
        A single-run result (schema ``seispound-result``).
    floors : list of (str, int) or "BUILDING:FLOOR" strings, optional
        (building name, floor number from 1). Default :func:`default_floors`:
        both sides of the gap element with the most impacts.
    out : str or path-like
        Output name, with or without suffix; ``OUT.png`` and ``OUT.svg`` are written.

    Returns
    -------
    (Path, Path)
        The PNG and SVG written.

    Raises
    ------
    InputError
        Unknown building or floor (key ``--floors``), not a single-run result
        (key ``--kind``), missing matplotlib (key ``plot``).
    """
    paths = _out_paths(out)
    fig = run_histories_figure(ds_run, floors)
    try:
        return save_figure(fig, paths[0])
    finally:
        _close(fig)


# --------------------------------------------------------------------------- command line

def add_plot_parser(subparsers):
    """Add the ``plot`` subcommand to an ``argparse`` subparsers object; returns its parser."""
    p = subparsers.add_parser(
        "plot", help="figures (PNG and SVG) of a study store or a single-run result",
        description="Write OUT.png and OUT.svg. A study store gives --kind amplification (default) or "
                    "force; a single-run result gives --kind histories (default).")
    p.add_argument("file", help="study store or result file (.h5)")
    p.add_argument("-o", "--output", required=True, metavar="OUT",
                   help="output name; OUT.png and OUT.svg are written (a .png/.svg suffix is dropped)")
    p.add_argument("--kind", help=f"one of {', '.join(KINDS)}; default from the file")
    p.add_argument("--axis", metavar="NAME",
                   help="study axis on the x axis; default: the axis whose name contains 'gap', else the last")
    p.add_argument("--by", metavar="NAME", help="run dimension giving one line per value (e.g. a law axis)")
    p.add_argument("--over", metavar="NAME", default="record",
                   help="run dimension for the median and min-max band (default: record)")
    p.add_argument("--sel", metavar="DIM=VALUE", nargs="+", action="extend", default=[],
                   help="fix a dimension at one value; other run dimensions are reduced with max")
    p.add_argument("--var", metavar="NAME",
                   help="study variable to plot (default: max_amplification for --kind amplification, "
                        "max_pounding_force for force), e.g. max_acceleration_amplification, "
                        "max_drift_ratio_amplification, max_storey_shear_amplification")
    p.add_argument("--floors", metavar="B:F", nargs="+", action="extend", default=[],
                   help="floors for histories, e.g. A:4 B:4; default: both sides of the gap "
                        "element with the most impacts")
    return p


def _parse_sel(items) -> dict:
    sel = {}
    for item in items:
        dim, sep, value = item.partition("=")
        if not sep or not dim or not value:
            raise InputError(f"{item!r}: expected DIM=VALUE", key="--sel")
        sel[dim] = value
    return sel


def default_axis(ds) -> str:
    """The study axis whose name contains "gap", else the last axis."""
    axes = [d for d in ds["status"].dims if d != "record"]
    if not axes:
        raise InputError("the study has no axis besides record", key="--axis")
    return next((a for a in axes if "gap" in a), axes[-1])


def _open(path: Path):
    import xarray as xr

    if not path.is_file():
        raise InputError("file not found", file=path)
    try:
        return xr.open_dataset(path, engine="h5netcdf")
    except (OSError, ValueError) as err:
        raise InputError(f"cannot read as HDF5/netCDF-4: {err}", file=path) from None


def _plot_file(ds, args):
    schema = ds.attrs.get("schema")
    if schema not in ("seispound-study", "seispound-result"):
        raise InputError(f"not a seispound study store or result (schema {schema!r})", key="schema")
    study = schema == "seispound-study"
    kind = args.kind or ("amplification" if study else "histories")
    if kind not in KINDS:
        raise InputError(f"unknown kind {kind!r}; choose from {', '.join(KINDS)}", key="--kind")
    if study != (kind not in ("histories", "spectrum")):
        wanted = "amplification or force" if study else "histories or spectrum"
        raise InputError(f"a {schema} file gives --kind {wanted}, not {kind}", key="--kind")
    if study:
        if args.floors:
            raise InputError("--floors is for single-run results", key="--floors")
        axis = args.axis or default_axis(ds)
        plot = study_amplification if kind == "amplification" else study_force
        extra = {}
        if getattr(args, "var", None):
            if args.var not in ds.data_vars or set(ds[args.var].dims) - set(ds.status.dims):
                runs = [v for v in ds.data_vars if set(ds[v].dims) == set(ds.status.dims)
                        and v not in ("status", "error")]
                raise InputError(f"{args.var!r} is not a run variable of the store; choose from "
                                 f"{', '.join(runs)}", key="--var")
            extra["var"] = args.var
        return plot(ds, axis, by=args.by, over=args.over, sel=_parse_sel(args.sel), out=args.output, **extra)
    for option in ("axis", "by", "sel", "var"):
        if getattr(args, option, None):
            raise InputError(f"--{option} is for study stores", key=f"--{option}")
    if args.over != "record":
        raise InputError("--over is for study stores", key="--over")
    if kind == "spectrum":
        return run_spectra(ds.load(), args.floors or None, out=args.output)
    return run_histories(ds.load(), args.floors or None, out=args.output)


def cmd_plot(args) -> int:
    """Run ``seispound plot``: print the two files written; raise InputError on bad input."""
    path = Path(args.file)
    _out_paths(args.output)  # a bad output folder is reported before reading anything
    with _open(path) as ds:
        try:
            png, svg = _plot_file(ds, args)
        except InputError as err:
            raise err.located(file=path) from None
    print(f"written {png} and {svg}")
    return 0


# --------------------------------------------------------------------------- response spectra

def spectra_figure(spectra, title=None):
    """PSA [g] against period [s] (log x) of several spectra (``seispound.spectra``), one line each.

    Parameters
    ----------
    spectra : sequence of (label, xarray.DataArray)
        Pseudo-spectral accelerations [m/s^2] on dimension ``period``.
    title : str, optional
        Default: "Pseudo-acceleration response spectra, <damping> damping".
    """
    fig = _new_figure(STUDY_FIGSIZE)
    ax = fig.add_subplot()
    damping = None
    for label, da in spectra:
        ax.plot(da.period.values, da.values / 9.80665, label=label)
        damping = da.attrs.get("damping", damping)
    ax.set_xscale("log")
    ax.set_xlabel("period [s]")
    ax.set_ylabel("pseudo-spectral acceleration [g]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize="small")
    what = f", {damping:.0%} damping" if damping is not None else ""
    ax.set_title(title or f"Pseudo-acceleration response spectra{what}", fontsize="medium")
    return fig


def run_spectra(ds, floors=None, *, out, periods=None, damping=0.05):
    """Floor response spectra of a single run (with pounding): the ground and each chosen floor.

    ``floors``: (building, floor) pairs or "B:F" texts (default: both sides of the busiest gap element).
    Returns the PNG and SVG paths.
    """
    from .spectra import floor_spectrum

    _out_paths(out)  # an unwritable output costs no work
    chosen = _check_floors(ds, floors) if floors else default_floors(ds)
    curves = [("ground", floor_spectrum(ds, chosen[0][0], 0, periods, damping))]
    curves += [(f"{b} floor {f}", floor_spectrum(ds, b, f, periods, damping)) for b, f in chosen]
    where = ", ".join(f"{b} floor {f}" for b, f in chosen)
    fig = spectra_figure(curves, title=f"{ds.attrs.get('title', '')}\nFloor response spectra ({damping:.0%} "
                                      f"damping): ground, {where}")
    try:
        return save_figure(fig, out)
    finally:
        _close(fig)
