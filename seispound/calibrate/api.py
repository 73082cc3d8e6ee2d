"""The calibration entry point: model, recordings (or trials), channel map and fitted paths in; a result out."""

from __future__ import annotations

import os
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


def calibrate(model, recordings=None, *, channels, fit, trials=None, progress=True, max_evaluations=None,
              output=None):
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
    return calibrate_observer(observer, params, progress=progress, max_evaluations=max_evaluations,
                              write_base=write_base)
