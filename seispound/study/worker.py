"""The tasks a study runs: the no-pounding twin of a group of runs, and a chunk of runs.

Plain functions of picklable arguments, so that any dask scheduler (or none)
can run them.  A task never raises for a bad run: the run comes back with
status failed and its one-line error, and the study goes on.
"""

from __future__ import annotations

import numpy as np

from .schema import STATUS_DONE, STATUS_FAILED

__all__ = ["twin_task", "chunk_task", "run_one"]


def _error_text(exc: BaseException) -> str:
    msg = " ".join(str(exc).split())
    return f"{type(exc).__name__}: {msg}" if msg else type(exc).__name__


def _layout(study):
    """DOF -> (building, floor) scatter indices of the study's structure (fixed across runs)."""
    floors = study.meta["floors"]
    b_of = np.repeat(np.arange(len(floors)), floors)
    f_of = np.concatenate([np.arange(n) for n in floors])
    return b_of, f_of, len(floors), max(floors)


_PARTS = {}  # (model file, its text) -> the Parts its runs share in this process (model/parts.py)


def _variant(study, index: int):
    """Run ``index``'s model, read reusing the buildings earlier runs in this process read unchanged."""
    from ..model.parts import REUSE, Parts

    if not REUSE:
        return study.model_for(index)
    key = (str(study.model_path), study.model_text)
    parts = _PARTS.get(key)
    if parts is None:
        _PARTS.clear()  # one study at a time in a worker
        parts = _PARTS[key] = Parts()
    return study.model_for(index, parts=parts)


def _per_floor(values, study):
    b_of, f_of, nb, nf = _layout(study)
    values = np.asarray(values, dtype=float)
    out = np.full(values.shape[:-1] + (nb, nf), np.nan)
    out[..., b_of, f_of] = values
    return out


def _storeys(model, system):
    from ..results.peaks import storey_arrays

    return storey_arrays(system, model.buildings)


def twin_task(study, index: int) -> dict:
    """The no-pounding twin of run ``index``'s group: its peaks per DOF (results/peaks.py), or its error."""
    from ..results.floors import floor_view
    from ..results.peaks import dof_peaks
    from ..simulation import run_inputs, run_row

    try:
        model = _variant(study, index)
        system, motions = run_inputs(model)
        raw = run_row(model, system.without_contact(), motions.rows)
        raw, floors = floor_view(raw, system)
        return {"peaks": dof_peaks(raw, *_storeys(model, floors)), "error": ""}
    except Exception as exc:  # a bad record fails every run of its group, not the study
        return {"peaks": None, "error": _error_text(exc)}


def run_one(study, index: int, twin: dict) -> dict:
    """Run ``index`` of the study: its summaries (and kept histories) as arrays, or its error."""
    from ..results.floors import floor_view
    from ..results.peaks import amplifications, dof_peaks, run_drift
    from ..simulation import run_inputs, run_row

    out = {"index": int(index), "status": STATUS_FAILED, "error": ""}
    if twin.get("error"):
        out["error"] = f"no-pounding twin failed: {twin['error']}"
        return out
    try:
        model = _variant(study, index)
        system, motions = run_inputs(model)
        raw = run_row(model, system, motions.rows)
    except Exception as exc:
        out["error"] = _error_text(exc)
        return out
    raw, floors = floor_view(raw, system)
    below, height, stiff = _storeys(model, floors)
    u = raw.displacement
    drift = run_drift(raw, below)
    peaks = dof_peaks(raw, below, height, stiff, drift)
    peaks0 = twin["peaks"]
    amps = amplifications(peaks, peaks0)
    ng = raw.force.shape[1]
    counts = np.bincount(raw.impacts["gap"], minlength=ng).astype(np.int64)
    amp_f = _per_floor(amps["displacement"], study)
    out.update(
        status=STATUS_DONE,
        amplification=amp_f,
        peak_displacement=_per_floor(peaks["displacement"], study),
        peak_displacement_no_pounding=_per_floor(peaks0["displacement"], study),
        peak_drift=_per_floor(peaks["drift"], study),
        peak_pounding_force=raw.peak_force.astype(float),
        impact_count=counts,
        max_amplification=_nanmax(amp_f),
        max_pounding_force=float(raw.peak_force.max(initial=0.0)),
        total_impacts=int(counts.sum()),
        contact_substeps=int(raw.stats["contact_substeps"]),
        contact_error_estimate=float(raw.stats["contact_error_estimate"]),
        peak_error_estimate=float(raw.stats["peak_error_estimate"]),
    )
    for name in ("acceleration", "drift_ratio", "storey_shear"):
        out[f"peak_{name}"] = _per_floor(peaks[name], study)
        out[f"peak_{name}_no_pounding"] = _per_floor(peaks0[name], study)
        out[f"{name}_amplification"] = _per_floor(amps[name], study)
        out[f"max_{name}_amplification"] = _nanmax(out[f"{name}_amplification"])
    out["max_peak_acceleration"] = float(peaks["acceleration"].max(initial=0.0))
    out["max_peak_drift_ratio"] = float(peaks["drift_ratio"].max(initial=0.0))
    if study.histories:
        k = slice(None, None, study.decimate)
        hist = {"displacement": u, "velocity": raw.velocity, "acceleration": raw.acceleration, "drift": drift}
        kept = {}
        for name in study.histories:
            if name == "pounding_force":
                kept[name] = np.ascontiguousarray(raw.force[k])
            else:
                kept[name] = _per_floor(hist[name][k], study)
        out["histories"] = kept
    return out


def _nanmax(values) -> float:
    return float(np.nanmax(values)) if np.isfinite(values).any() else float("nan")


def chunk_task(study, indices, twin: dict) -> list:
    """Run every index of a chunk that shares one twin; one result dict per run."""
    return [run_one(study, i, twin) for i in indices]
