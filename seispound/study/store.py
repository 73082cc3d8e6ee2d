"""Write the study store (schema in :mod:`seispound.study.schema`) from run results.

The store is rebuilt whole from the journal's results into a temporary file
next to it, then moved into place with ``os.replace``: a reader (or a kill)
never sees a half-written store.  Summaries are gathered in memory (a few
numbers per run); histories are streamed run by run into chunked, compressed
variables, so memory does not grow with the number of runs.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import xarray as xr

from .schema import (HISTORY_VARIABLES, SCHEMA, SCHEMA_VERSION, STATUS_DONE, STATUS_FAILED, STATUS_PENDING,
                     SUMMARY_VARIABLES)

__all__ = ["write_store", "axis_units"]

# units of the model keys a study commonly varies (a factor is always dimensionless)
_UNITS = {"size": "m", "restitution": "1", "scale": "1", "dt": "s", "duration": "s", "ratio": "1",
          "floor_masses": "kg", "storey_stiffness": "N/m", "storey_heights": "m", "initial_velocity": "m/s",
          "law": "", "beta": "1", "gamma": "1"}


def axis_units(path: str, factor: bool) -> str:
    """Units of an axis coordinate: "1" for factors, else those of the model key (stiffness: law-dependent)."""
    if factor:
        return "1"
    key = path.rsplit(".", 1)[-1]
    if key == "stiffness":
        return "N/m^n (law-dependent)"
    return _UNITS.get(key, "")


def _tmp_name(out: Path) -> Path:
    return out.parent / f".{out.name}.tmp-{os.getpid()}"


def write_store(study, results, out) -> dict:
    """Write the store of ``study`` to ``out`` from ``results()``, an iterable factory of run result dicts.

    ``results`` is called once for the summaries and once more for the
    histories (if any are kept), so that histories stream from disk.
    Returns counts {"done", "failed", "pending"}.
    """
    out = Path(out)
    shape, dims = study.shape, study.run_dims
    meta = study.meta
    nb, nf, ng = len(meta["buildings"]), max(meta["floors"]), len(meta["links"])
    trailing = {"building": nb, "floor": nf, "gap": ng}
    status = np.full(shape, STATUS_PENDING, np.int8)
    error = np.full(shape, "", dtype=object)
    data = {}
    for name, tdims, _, _, dtype in SUMMARY_VARIABLES:
        full = shape + tuple(trailing[d] for d in tdims)
        data[name] = np.full(full, -1, np.int64) if dtype == "i8" else np.full(full, np.nan)
    for r in results():
        pos = study.run_position(r["index"])
        status[pos] = r["status"]
        error[pos] = r["error"]
        if r["status"] == STATUS_DONE:
            for name, *_ in SUMMARY_VARIABLES:
                data[name][pos] = r[name]

    ds = xr.Dataset(coords=_coords(study))
    ds["status"] = xr.Variable(dims, status, attrs={
        "long_name": "run status", "flag_values": np.array([STATUS_PENDING, STATUS_FAILED, STATUS_DONE], np.int8),
        "flag_meanings": "pending failed done"})
    ds["error"] = xr.Variable(dims, error, attrs={"long_name": "error of a failed run"})
    for name, tdims, units, long_name, _ in SUMMARY_VARIABLES:
        ds[name] = xr.Variable(dims + tdims, data[name], attrs={"units": units, "long_name": long_name})
    counts = {"done": int((status == STATUS_DONE).sum()), "failed": int((status == STATUS_FAILED).sum()),
              "pending": int((status == STATUS_PENDING).sum())}
    ds.attrs.update(_attributes(study, counts))

    tmp = _tmp_name(out)
    try:
        ds.to_netcdf(tmp, engine="h5netcdf")
        if study.histories:
            _write_histories(study, results, tmp, shape, dims, trailing)
        os.replace(tmp, out)
    finally:
        tmp.unlink(missing_ok=True)
    return counts


def _coords(study) -> dict:
    meta = study.meta
    names = meta["buildings"]
    coords = {
        "record": ("record", np.array([r.name for r in study.records], dtype=object),
                   {"long_name": "ground-motion record"}),
        "record_file": ("record", np.array([str(r.file) for r in study.records], dtype=object)),
    }
    for ax in study.axes:
        if ax.zipped:
            c = ax.coordinate()
            m0 = ax.members[0]
            labelled = c.dtype == object or not np.array_equal(c, np.arange(ax.size))
            coords[ax.name] = (ax.name, c, {"units": axis_units(m0.path, m0.factor), "long_name": m0.path}
                               if labelled else {"long_name": "entry of the zipped axis " + ax.name})
            for m in ax.members[1 if labelled else 0:]:
                coords[m.path] = (ax.name, _member_coord(m), {"units": axis_units(m.path, m.factor),
                                                            "long_name": ("factor on " if m.factor else "") + m.path})
        else:
            m = ax.members[0]
            coords[ax.name] = (ax.name, ax.coordinate(), {"units": axis_units(m.path, m.factor),
                                                          "long_name": ("factor on " if m.factor else "") + m.path})
    links = meta["links"]
    coords.update(
        building=("building", np.array(names, dtype=object), {"long_name": "building, left to right"}),
        floor=("floor", np.arange(1, max(meta["floors"]) + 1), {"long_name": "floor number (1 = first above ground)"}),
        gap=("gap", np.arange(len(links)), {"long_name": "gap element"}),
        gap_left=("gap", np.array([names[l[0]] for l in links], dtype=object), {"long_name": "left building"}),
        gap_right=("gap", np.array([names[l[1]] for l in links], dtype=object), {"long_name": "right building"}),
        gap_left_floor=("gap", np.array([l[2] for l in links], np.int64), {"units": "1"}),
        gap_right_floor=("gap", np.array([l[3] for l in links], np.int64), {"units": "1"}),
        gap_height=("gap", np.array(meta["gap_height"], float), {"units": "m"}),
    )
    return coords


def _member_coord(m) -> np.ndarray:
    vals = m.values
    if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in vals):
        return np.asarray(vals, dtype=float)
    return np.array([json.dumps(v) if isinstance(v, list) else str(v) for v in vals], dtype=object)


def _attributes(study, counts) -> dict:
    from .. import __version__

    return dict(
        schema=SCHEMA, schema_version=SCHEMA_VERSION, title=study.title, seispound_version=__version__,
        study_file=str(study.path), study_text=study.text, model_file=str(study.model_path),
        model_text=study.model_text,
        records=json.dumps([{"name": r.name, "file": str(r.file), "sha256": r.sha256,
                             "provenance": _provenance(study, k)} for k, r in enumerate(study.records)]),
        axes=json.dumps([a.describe() for a in study.axes]), run_dims=json.dumps(list(study.run_dims)),
        study_hash=study.hash(), runs_total=study.n_runs, runs_done=counts["done"],
        runs_failed=counts["failed"],
    )


def prefetch(study) -> None:
    """Load what :func:`write_store` needs (netCDF writer, record provenance) ahead of time."""
    import h5netcdf  # noqa: F401
    import xarray.backends.h5netcdf_  # noqa: F401  (the engine's module: most of the import time)

    for k in range(len(study.records)):
        _provenance(study, k)


def _provenance(study, k: int) -> dict:
    """What the reader says of record k (station, component, units, processing ...), or its error."""
    from ..simulation import prepare_ground_motion

    try:  # the first run of the record: prepared records are cached, so this reads each file once
        _, prov = prepare_ground_motion(study.model_for(k * (study.n_runs // len(study.records))))
        return prov or {}
    except Exception as exc:  # a record that cannot be read: its runs are failed already
        return {"error": " ".join(str(exc).split())}


def _write_histories(study, results, path, shape, dims, trailing) -> None:
    import h5netcdf

    an = study.model_for(0).analysis
    t = np.arange(0, an.nsteps + 1, study.decimate) * an.dt
    trailing = dict(trailing, time=t.size)
    with h5netcdf.File(path, "a") as f:
        f.dimensions["time"] = t.size
        tv = f.create_variable("time", ("time",), "f8")
        tv[:] = t
        tv.attrs["units"] = "s"
        tv.attrs["long_name"] = "time (every %d analysis instants)" % study.decimate
        var = {}
        for name in study.histories:
            tdims, units, long_name = HISTORY_VARIABLES[name]
            chunk = (1,) * len(shape) + tuple(trailing[d] for d in tdims)  # one run per chunk
            v = f.create_variable(name, dims + tdims, "f8", chunks=chunk, compression="gzip",
                                  compression_opts=4, shuffle=True, fillvalue=np.nan)
            v.attrs["units"] = units
            v.attrs["long_name"] = long_name
            var[name] = v
        for r in results():
            if r["status"] != STATUS_DONE:
                continue
            pos = study.run_position(r["index"])
            for name, arr in r["histories"].items():
                var[name][pos] = arr
