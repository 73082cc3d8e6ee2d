"""The calibration entry point: model, recordings (or trials), channel map and fitted paths in; a result out."""

from __future__ import annotations

import os
import sys
from pathlib import Path

from ..errors import InputError
from .observe import Observer, Trial

__all__ = ["calibrate", "load_trials"]

_TRIAL_KEYS = {"recording", "model", "initial_velocity", "name"}


def load_trials(path, channels) -> list[Trial]:
    """``[[trial]] recording = "..." (or a list), model = "..." (optional), initial_velocity = { A = [...] }``.

    Paths are relative to the trials file; InputError names the file and ``trial.<i>.<key>``.
    """
    import tomllib

    from ..model.toml_loader import read_toml
    from .recording import read_recording

    path = Path(path)
    _, data = read_toml(path, "trials")
    tables = data.get("trial")
    if set(data) - {"trial"} or not isinstance(tables, list) or not tables:
        raise InputError("a trials file holds one or more [[trial]] tables", file=path, key="trial")
    out = []
    for i, t in enumerate(tables):
        key = f"trial.{i + 1}"
        if not isinstance(t, dict):
            raise InputError("must be a table", file=path, key=key)
        for k in t:
            if k not in _TRIAL_KEYS:
                raise InputError(f"unknown key; allowed: {', '.join(sorted(_TRIAL_KEYS))}", file=path, key=f"{key}.{k}")
        rec = t.get("recording")
        files = [rec] if isinstance(rec, str) else rec
        if not isinstance(files, list) or not files or not all(isinstance(f, str) for f in files):
            raise InputError("is required: a recording file or a list of them", file=path, key=f"{key}.recording")
        recording = read_recording([path.parent / f for f in files], channels)
        model_data, base = None, None
        if "model" in t:
            mpath = path.parent / t["model"]
            model_data, base = tomllib.loads(_read_text(mpath, path, f"{key}.model")), mpath.parent
        iv = t.get("initial_velocity")
        if iv is not None and not (isinstance(iv, dict) and all(isinstance(v, (int, float, list)) for v in iv.values())):
            raise InputError("must be a table { building = velocity or [one per floor] }", file=path,
                             key=f"{key}.initial_velocity")
        out.append(Trial(recording=recording, name=str(t.get("name", f"trial {i + 1}")), model_data=model_data,
                         base=base, initial_velocity=iv, source=path, key=key))
    return out


def _read_text(mpath, path, key):
    if not mpath.is_file():
        raise InputError(f"no such model file {mpath}", file=path, key=key)
    return mpath.read_text(encoding="utf-8")


def load_inputs(model, recordings, channels, trials):
    """(model, channels, trials): the model read and valid, its channel map, and the trials (one per
    recording set); what ``calibrate`` and ``diagnose`` both start from."""
    from ..model import load_model
    from .channels import load_channels
    from .recording import read_recording

    if isinstance(model, (str, os.PathLike)):
        model = load_model(model)
    if not model.text:
        raise InputError("the model must come from a model file (its text is what is fitted)", key="model")
    model.assembled()  # valid as given
    chans = load_channels(channels, model) if isinstance(channels, (str, os.PathLike)) else list(channels)
    if trials is not None:
        return model, chans, load_trials(trials, chans)
    if recordings is not None:
        return model, chans, [Trial(recording=read_recording(recordings, chans), name="recording")]
    raise InputError("give the recording files, or a trials file", key="recording")


STARTS = 16  # Sobol points across the bounds, each judged by one simulation, when the first fit ends far off
NEAR = 1.5  # ... far off: above this many times the NE the sensor noise leaves
NE_FLOOR = 1e-3  # the noise's NE taken no lower than this (noise-free synthetic recordings)


def calibrate(model, recordings=None, *, channels, fit, trials=None, progress=True, max_evaluations=None,
              output=None, starts=STARTS):
    """Fit ``fit`` (``PATH[=lo:hi]`` strings) so that ``model`` reproduces the recordings.

    Parameters
    ----------
    model : Model or path
        The model (read from a file: its text is what the calibrated model is written from).
    recordings : path or list of paths, optional
        One test's recording files (obspy formats); or give ``trials``.
    channels : path or list of Channel
        The channel map (``channels.py``).
    fit : list of str
        Dotted paths, each optionally ``=lo:hi`` (defaults: ``fit.default_bounds``).
    trials : path, optional
        A trials file (tests that differ in initial conditions or model).
    progress : bool
        Report each simulation on stderr.
    max_evaluations : int, optional
        Cap on simulations (scipy's ``max_nfev``).
    output : path, optional
        Where the calibrated model will be written: its relative record paths are rebased there.
    starts : int
        Global starts (default 16; 0: the nominal point only).  When the fit from the model's own
        values ends above NEAR (1.5) times the NE the sensor noise leaves, ``starts`` points of a
        scrambled Sobol sequence (fixed seed) across the parameters' (log-)bounds are each judged
        by one simulation, a second fit runs from the best, and the better fit is kept: a
        pounding misfit has local minima (a stiffness factor of 1.38 and a gap three times too
        large where the truth is 0.82 and 0.65).  The same scan as ``diagnose``'s recalibration.

    Returns
    -------
    CalibrationResult
    """
    import tomllib

    from .fit import calibrate_observer, parse_fit

    model, chans, trial_list = load_inputs(model, recordings, channels, trials)
    data = tomllib.loads(model.text)
    base = Path(model.source).parent if model.source else Path(".")
    params = parse_fit(list(fit), data)
    observer = Observer(data, base, chans, trial_list)
    write_base = None if output is None else os.path.dirname(os.path.abspath(output))
    best = calibrate_observer(observer, params, progress=progress, max_evaluations=max_evaluations,
                              write_base=write_base)
    noise = max(best.noise_ne, NE_FLOOR)
    if starts < 1 or not best.ne_mean_after > NEAR * noise:
        return best
    start = _best_start(observer, params, data, starts)
    if start is None:
        return best
    if progress:
        print(f"  NE {best.ne_mean_after:.4f} is {best.ne_mean_after / noise:.1f} times the noise's: "
              f"fitted again from the best of {starts} points across the bounds", file=sys.stderr)
    from dataclasses import replace

    again = calibrate_observer(observer, [replace(p, start=start[p.path]) for p in params], progress=progress,
                               max_evaluations=max_evaluations, write_base=write_base)
    out = again if again.ne_mean_after < best.ne_mean_after else best
    out.starts = 2
    return out


def _best_start(observer, params, data, n):
    """{path: start} at the best of ``n`` scrambled Sobol points across the (log-)bounds, each judged by one
    simulation (sum of NE^2 over channels and trials), or None if none runs.  A key is scanned as one value
    across the buildings (every building's storey-stiffness factor alike), so that a few points cover the
    scan's few dimensions; the fit then sets the buildings apart."""
    import math

    from scipy.stats import qmc

    from ..model.paths import get_value
    from .fit import normalised_errors

    recs = [{c.id: t.recording.data[c.id] for c in observer.channels} for t in observer.trials]
    groups = {}  # a key of every building scanned as one value: the scan's dimension is the number of keys
    for p in params:
        parts = p.path.split(".")
        groups.setdefault(".".join(["building", "*"] + parts[2:]) if parts[0] == "building" else p.path, []).append(p)
    best = None
    for u in qmc.Sobol(len(groups), scramble=True, seed=2026).random(n):
        x = {p.path: (p.lo * (p.hi / p.lo) ** ui if p.log else p.lo + ui * (p.hi - p.lo))
             for members, ui in zip(groups.values(), u) for p in members}
        over = [(p.path, p.value_at(get_value(data, p.path), x[p.path])) for p in params]
        try:
            sims = observer.simulate(over)
        except Exception:  # noqa: BLE001 (a point where the model cannot run is no start)
            continue
        rss = sum(v * v for s, r in zip(sims, recs) for v in normalised_errors(s, r).values())
        if math.isfinite(rss) and (best is None or rss < best[0]):
            best = (rss, x)
    return None if best is None else best[1]
