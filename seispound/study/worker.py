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


def _per_floor(values, study):
    b_of, f_of, nb, nf = _layout(study)
    values = np.asarray(values, dtype=float)
    out = np.full(values.shape[:-1] + (nb, nf), np.nan)
    out[..., b_of, f_of] = values
    return out


def twin_task(study, index: int) -> dict:
    """Peak |displacement| per DOF without pounding for the twin group of run ``index`` [m], or its error."""
    from ..integrate import integrate
    from ..simulation import prepare_ground_motion
    from ..structure import assemble

    try:
        model = study.model_for(index)
        system = assemble(model.buildings, model.gaps, model.contact)
        ag, _ = prepare_ground_motion(model)
        an = model.analysis
        raw = integrate(system.without_contact(), ag, an.dt, an.nsteps, an.newmark, store_history=False)
        return {"peak": raw.peak_displacement.copy(), "error": ""}
    except Exception as exc:  # a bad record fails every run of its group, not the study
        return {"peak": None, "error": _error_text(exc)}


def run_one(study, index: int, twin: dict) -> dict:
    """Run ``index`` of the study: its summaries (and kept histories) as arrays, or its error."""
    from ..integrate import integrate
    from ..simulation import prepare_ground_motion
    from ..structure import assemble

    out = {"index": int(index), "status": STATUS_FAILED, "error": ""}
    if twin.get("error"):
        out["error"] = f"no-pounding twin failed: {twin['error']}"
        return out
    try:
        model = study.model_for(index)
        system = assemble(model.buildings, model.gaps, model.contact)
        ag, _ = prepare_ground_motion(model)
        an = model.analysis
        raw = integrate(system, ag, an.dt, an.nsteps, an.newmark)
    except Exception as exc:
        out["error"] = _error_text(exc)
        return out
    u = raw.displacement
    floors = np.concatenate([np.arange(n) for n in study.meta["floors"]])
    drift = u.copy()
    lower = np.flatnonzero(floors > 0)
    drift[:, lower] -= u[:, lower - 1]
    peak = raw.peak_displacement
    peak0 = twin["peak"]
    with np.errstate(divide="ignore", invalid="ignore"):
        amp = np.where(peak0 > 0, peak / peak0, np.nan)
    ng = raw.force.shape[1]
    counts = np.bincount(raw.impacts["gap"], minlength=ng).astype(np.int64)
    amp_f = _per_floor(amp, study)
    out.update(
        status=STATUS_DONE,
        amplification=amp_f,
        peak_displacement=_per_floor(peak, study),
        peak_displacement_no_pounding=_per_floor(peak0, study),
        peak_drift=_per_floor(np.max(np.abs(drift), axis=0, initial=0.0), study),
        peak_pounding_force=raw.peak_force.astype(float),
        impact_count=counts,
        max_amplification=float(np.nanmax(amp_f)) if np.isfinite(amp_f).any() else float("nan"),
        max_pounding_force=float(raw.peak_force.max(initial=0.0)),
        total_impacts=int(counts.sum()),
    )
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


def chunk_task(study, indices, twin: dict) -> list:
    """Run every index of a chunk that shares one twin; one result dict per run."""
    return [run_one(study, i, twin) for i in indices]
