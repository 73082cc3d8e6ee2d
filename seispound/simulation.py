"""Run a model: assemble, read the ground motion, integrate with and without pounding."""

from __future__ import annotations

import dataclasses
import functools
from pathlib import Path

import numpy as np
import xarray as xr

from .errors import InputError
from .integrate import integrate
from .structure import assemble

__all__ = ["simulate", "prepare_ground_motion"]


def prepare_ground_motion(model):
    """Ground acceleration on the analysis grid [m/s^2], shape (nsteps + 1,), and its provenance.

    Free vibration (no ``[ground_motion]``) gives zeros and provenance None.
    """
    an = model.analysis
    nsteps = an.nsteps
    spec = model.ground_motion
    if spec is None:
        return np.zeros(nsteps + 1), None
    try:
        st = spec.file.stat()
    except OSError:
        raise InputError("record file not found", file=spec.file, key="ground_motion.file") from None
    key = (str(spec.file), st.st_mtime_ns, st.st_size, spec.trace, spec.units, spec.calibration, spec.scale,
           spec.baseline, an.dt, nsteps)
    try:
        ag, prov = _read_prepared(*key)
    except _SettingError as err:
        raise InputError(f"{err.message} (record {err.record})", file=model.source,
                         key=f"{err.section}.{err.key}") from None
    return ag.copy(), dict(prov)


@functools.lru_cache(maxsize=32)
def _read_prepared(file, mtime_ns, size, trace, units, calibration, scale, baseline, dt, nsteps):
    """Read and prepare a record once per (file version, settings): studies rerun the same record."""
    from .motion import ground_acceleration, read_record

    path = Path(file)
    try:
        rec = read_record(path, trace=trace, units=units, calibration=calibration, scale=scale)
        if baseline is not None:
            rec = rec.baseline_corrected(order=baseline)
        ag = ground_acceleration(rec, dt, nsteps * dt)
    except InputError as err:
        if err.key in ("units", "trace", "calibration", "scale", "baseline", "dt"):
            # a setting of the model file that does not fit the record
            section = "analysis" if err.key == "dt" else "ground_motion"
            raise _SettingError(err.message, section, err.key, path.name) from None
        raise err.located(file=path) from None
    ag.setflags(write=False)
    return ag, dict(rec.provenance)


class _SettingError(Exception):
    """A model-file setting that does not fit the record (re-raised against the model file)."""

    def __init__(self, message, section, key, record):
        super().__init__(message)
        self.message, self.section, self.key, self.record = message, section, key, record


def simulate(model, *, twin: bool = True) -> xr.Dataset:
    """Simulate ``model`` and return its result Dataset (schema in :mod:`seispound.results.schema`).

    The no-pounding twin (all gaps disabled, same record and settings) runs
    automatically and gives the denominator of ``amplification``.

    Parameters
    ----------
    model : Model
    twin : bool
        Run the no-pounding twin (default True).  Without it the amplification is NaN.
    """
    from . import __version__
    from .results import build_dataset

    model.validate()
    system = assemble(model.buildings, model.gaps, model.contact)
    ag, prov = prepare_ground_motion(model)
    an = model.analysis
    raw = integrate(system, ag, an.dt, an.nsteps, an.newmark)
    if twin:
        raw0 = integrate(system.without_contact(), ag, an.dt, an.nsteps, an.newmark, store_history=False)
    else:
        raw0 = dataclasses.replace(raw, peak_displacement=np.full_like(raw.peak_displacement, np.nan))
    return build_dataset(model, system, raw, raw0, ag, prov, __version__)
