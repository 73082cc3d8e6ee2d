"""The lean simulation path a fit calls: a model's mapped channels at the recording's sample times.

No Dataset is built and nothing is written: the row is assembled, integrated
(without its no-pounding twin), and only the mapped channels are read out of
the run, then interpolated linearly onto the recording's time grid (equal to
the analysis grid when the model's ``analysis.dt`` is the recording's).
"""

from __future__ import annotations

import copy
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError

__all__ = ["Trial", "Observer"]


@dataclass
class Trial:
    """One test: its recording, and the changes to the model that make it (initial velocities, another model)."""

    recording: object
    name: str = "trial"
    model_data: dict | None = None  # the model file's table (None: the calibration's model)
    base: Path | None = None  # folder the model's relative paths start from
    initial_velocity: dict | None = None  # building -> list of floor velocities [m/s]
    source: Path | None = None  # the trials file it was read from (named in errors)
    key: str = ""  # its table in that file (trial.2)


class Observer:
    """Simulate a model file's table with parameter overrides; return the mapped channels per trial.

    Parameters
    ----------
    model_data : dict
        The model file's table (``tomllib.loads(model.text)``).
    base : Path
        Folder of the model file (relative record paths start there).
    channels : list of Channel
    trials : list of Trial
    """

    def __init__(self, model_data, base, channels, trials):
        self.model_data = model_data
        self.base = Path(base)
        self.channels = channels
        self.trials = trials
        self.evaluations = 0
        self.impact_times = []
        self._substeps = None  # contact substeps the tolerance chose for the model as given, kept for the fit
        self._parts = None  # the buildings the evaluations share (model/parts.py)

    def _fixed_substeps(self, trial) -> int:
        """The contact substeps of every evaluation whose model does not give them: chosen once, from the
        model as given, so that a fitted e cannot move them (a fit's misfit must not jump between evaluations)."""
        if self._substeps is None:
            from ..simulation import contact_substeps

            data = copy.deepcopy(trial.model_data if trial.model_data is not None else self.model_data)
            self._substeps = int(contact_substeps(self._parse(trial, data))[0].contact_substeps)
        return self._substeps

    def _parse(self, trial, data, parts=None):
        from ..model.toml_loader import parse_model

        return parse_model(data, base=trial.base or self.base, parts=parts)

    def data_for(self, trial, overrides) -> dict:
        """The model table of ``trial`` with ``overrides`` [(path, value)] applied, its duration the recording's."""
        from ..model.paths import set_value

        data = copy.deepcopy(trial.model_data if trial.model_data is not None else self.model_data)
        for path, value in overrides:
            set_value(data, path, value)
        rec = trial.recording
        analysis = data.setdefault("analysis", {})
        analysis["duration"] = float((rec.npts - 1) * rec.dt)
        if "contact_substeps" not in analysis:
            analysis["contact_substeps"] = self._fixed_substeps(trial)
        for name, v in (trial.initial_velocity or {}).items():
            hit = [b for b in data.get("building", []) if b.get("name") == name]
            if not hit:
                have = ", ".join(str(b.get("name")) for b in data.get("building", []))
                raise InputError(f"unknown building {name!r} (the model has {have})", file=trial.source,
                                 key=f"{trial.key or 'trial.' + trial.name}.initial_velocity.{name}")
            hit[0]["initial_velocity"] = v
        return data

    def model_for(self, trial, overrides):
        return self._parse(trial, self.data_for(trial, overrides))

    def simulate(self, overrides) -> list[dict]:
        """Per trial: {trace id: simulated samples on the recording's grid}."""
        self.evaluations += 1
        self.impact_times = []  # per trial, the onset times [s] of the last simulation's impacts
        from ..model import parts

        if self._parts is None:
            self._parts = parts.Parts()
        # read as variants: the buildings an evaluation leaves unchanged are read and laid out once
        kept = self._parts if parts.REUSE else None
        return [self._one(t, self._parse(t, self.data_for(t, overrides), kept)) for t in self.trials]

    def _one(self, trial, model) -> dict:
        from ..results.floors import floor_view
        from ..simulation import run_inputs, run_row

        system, motions = run_inputs(model)
        raw = run_row(model, system, motions.rows, limit_contact_step=False)  # (its cost: run_row)
        self.impact_times.append(np.sort(raw.impacts.get("t0", np.zeros(0))))
        view, floors = floor_view(raw, system)
        t_rec = trial.recording.time
        # the recording's grid is the analysis grid (the model's dt is the recording's): no interpolation
        same = t_rec.size == raw.time.size and np.array_equal(t_rec, raw.time)
        out = {}
        names = [b.name for b in model.buildings]
        for ch in self.channels:
            if ch.quantity == "force":
                x = raw.force[:, ch.gap]
            elif ch.floor == 0:
                x = motions.rows[motions.row_of[names.index(ch.building)]]
            else:
                b = names.index(ch.building)
                x = _floor_history(ch, b, model, system, raw, view, floors)
            out[ch.id] = np.array(x, dtype=float) if same else np.interp(t_rec, raw.time, x)
        return out


def _floor_history(ch, b, model, system, raw, view, floors):
    """A floor channel's history on the analysis grid: at the floor's sensor, or at ``position`` on a rod."""
    col = int(np.flatnonzero((floors.dof_building == b) & (floors.dof_floor == ch.floor))[0])
    hist = {"acceleration": "acceleration", "velocity": "velocity", "displacement": "displacement"}[ch.quantity]
    if ch.position is None:
        return getattr(view, hist)[:, col]
    rod = model.buildings[b].floor_model
    nodes = system.outputs.nodes[col]
    x = ch.position * rod.segments
    p = min(int(np.floor(x)), rod.segments - 1)
    f = x - p
    h = getattr(raw, hist)
    return (1.0 - f) * h[:, nodes[p]] + f * h[:, nodes[p + 1]]
