"""Run a model: assemble, read the ground motion, integrate with and without pounding."""

from __future__ import annotations

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
    from .motion import ground_acceleration, read_record

    an = model.analysis
    nsteps = an.nsteps
    spec = model.ground_motion
    if spec is None:
        return np.zeros(nsteps + 1), None
    try:
        rec = read_record(spec.file, trace=spec.trace, units=spec.units, calibration=spec.calibration,
                          scale=spec.scale)
        if spec.baseline is not None:
            rec = rec.baseline_corrected(order=spec.baseline)
        ag = ground_acceleration(rec, an.dt, nsteps * an.dt)
    except InputError as err:
        if err.key in ("units", "trace", "calibration", "scale", "baseline", "dt"):
            # a setting of the model file that does not fit the record
            section = "analysis" if err.key == "dt" else "ground_motion"
            raise InputError(f"{err.message} (record {spec.file.name})", file=model.source,
                             key=f"{section}.{err.key}") from None
        raise err.located(file=spec.file) from None
    prov = dict(rec.provenance)
    if ag.size != nsteps + 1:  # pragma: no cover - guarded by ground_acceleration's contract
        raise InputError(f"record gives {ag.size} samples, expected {nsteps + 1}", file=spec.file)
    return ag, prov


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
        raw0 = integrate(system.without_contact(), ag, an.dt, an.nsteps, an.newmark)
    else:
        raw0 = raw
        raw0 = type(raw)(**{**raw.__dict__, "peak_displacement": np.full_like(raw.peak_displacement, np.nan)})
    return build_dataset(model, system, raw, raw0, ag, prov, __version__)
