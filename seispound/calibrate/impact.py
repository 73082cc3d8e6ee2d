"""The seed paper's procedure for impact tests (Khatiwada & Chouw, Sec. 4), as one function and command.

For every trial (one impact of two pendulum bodies, recorded force and displacements) and
every contact law:

1. the first positive pulse of the recorded force: the samples around its peak above 2 % of
   it (above the sensor noise), its start carried back to zero along its rising slope (later
   oscillations are the bodies' internal vibration, which a lumped model cannot follow);
2. the approach velocity and the coefficient of restitution from the two displacement
   channels: velocities by least-squares lines through the displacements just before the
   pulse and just after it (each window twice the pulse's length), e = -(v1' - v2') / (v1 - v2)
   (the seed takes them from the post-impact displacements the same way);
3. the law's stiffness such that the simulated peak force equals the recorded peak (Brent's
   method on log k), the model's bodies released touching with the measured velocities and
   the law's damping set from that e;
4. the normalised error NE = ||F_sim - F_rec||_2 / ||F_rec||_2 (seed Eq. 10) over that pulse,
   the simulation aligned on the pulse's start (its zero crossing, interpolated).
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .._blas import single_threaded
from ..errors import InputError

__all__ = ["ImpactStudy", "impact_study", "first_pulse", "velocity_at", "SEED_LAWS"]

SEED_LAWS = ("LVe", "MLVe", "NIVe", "Hd", "LHC")
_HERTZ_LIKE = {"NIVe", "Hd", "Hertz", "Hertzdamp", "HC"}


def first_pulse(force, dt, threshold=0.02):
    """(i0, i1, t_start): the first positive pulse around the recorded peak and the time it began [s].

    The pulse runs over the samples i0..i1 above ``threshold`` x its peak (a level above the
    sensor noise, so that noise before the contact is not taken for it); its start is the
    upward crossing of that level, linear between samples, carried back to zero along the
    same slope.
    """
    f = np.asarray(force, float)
    k = int(np.argmax(f))
    if f[k] <= 0:
        raise InputError("the force never becomes positive", key="force")
    level = threshold * f[k]
    i0 = k
    while i0 > 0 and f[i0 - 1] > level:
        i0 -= 1
    i1 = k
    while i1 < f.size - 1 and f[i1 + 1] > level:
        i1 += 1
    if i0 > 0:
        slope = (f[i0] - f[i0 - 1]) / dt
        t_level = (i0 - 1) * dt + (level - f[i0 - 1]) / slope
        t_start = t_level - level / slope
    else:
        t_start = 0.0
    return i0, i1, t_start


def velocity_at(x, dt, lo, hi):
    """Slope [m/s] of the least-squares line through samples lo..hi-1 of the displacement x."""
    lo, hi = max(lo, 0), min(hi, len(x))
    if hi - lo < 3:
        raise InputError("too few displacement samples around the impact to estimate a velocity", key="displacement")
    t = np.arange(lo, hi) * dt
    return float(np.polyfit(t, np.asarray(x[lo:hi], float), 1)[0])


@dataclass
class LawFit:
    law: str
    stiffness: float
    ne: float
    time: np.ndarray  # s, from the pulse's start, at the recording's samples
    force: np.ndarray  # N, simulated


@dataclass
class TrialFit:
    name: str
    velocity: float  # approach velocity [m/s]
    restitution: float
    peak_force: float  # recorded [N]
    time: np.ndarray  # s from the pulse's start
    force: np.ndarray  # recorded first pulse [N]
    laws: dict = field(default_factory=dict)  # law -> LawFit


def _stiffness_units(law: str) -> str:
    """The units of a law's stiffness, from the law's own parameter description (N/m, N/m^1.5 ...)."""
    from ..contact import get_law

    units = {p.name: p.units for p in get_law(law).describe_params()}
    return units.get("stiffness", "?")


@dataclass
class ImpactStudy:
    """Per trial and law: stiffness, NE, simulated pulse (``trials``); ``table()`` and ``figure()``."""

    trials: list
    laws: tuple

    def table(self) -> str:
        """A markdown table like the seed's Table 1 (NE per law), with e and the fitted stiffnesses."""
        head = "| trial | velocity (m/s) | e | " + " | ".join(f"NE {law}" for law in self.laws) + " | best |"
        lines = [head, "|" + "---|" * (4 + len(self.laws))]
        for t in self.trials:
            ne = [t.laws[law].ne for law in self.laws]
            best = self.laws[int(np.argmin(ne))]
            lines.append(f"| {t.name} | {t.velocity:.3f} | {t.restitution:.3f} | "
                         + " | ".join(f"{x:.2%}" for x in ne) + f" | {best} |")
        lines.append("")
        lines.append("| trial | " + " | ".join(f"k {law} [{_stiffness_units(law)}]" for law in self.laws) + " |")
        lines.append("|" + "---|" * (1 + len(self.laws)))
        for t in self.trials:
            lines.append(f"| {t.name} | " + " | ".join(f"{t.laws[law].stiffness:.4g}" for law in self.laws) + " |")
        return "\n".join(lines)

    def mean_ne(self) -> dict:
        return {law: float(np.mean([t.laws[law].ne for t in self.trials])) for law in self.laws}

    def figure(self, path, trials=None):
        """Measured against simulated force of every law (the seed's Fig. 7), one panel per trial."""
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        chosen = self.trials if trials is None else [t for t in self.trials if t.name in trials]
        n = len(chosen)
        cols = min(n, 4)
        rows = math.ceil(n / cols)
        fig, axes = plt.subplots(rows, cols, figsize=(3.6 * cols, 2.8 * rows), squeeze=False)
        for ax, t in zip(axes.flat, chosen):
            ax.plot(1e3 * t.time, t.force / 1e3, "k", lw=2, label="measured")
            for law in self.laws:
                lf = t.laws[law]
                ax.plot(1e3 * lf.time, lf.force / 1e3, lw=1, label=f"{law} (NE {lf.ne:.0%})")
            ax.set_title(f"{t.name}: {t.velocity:.3f} m/s", fontsize=9)
            ax.set_xlabel("time from contact [ms]")
            ax.set_ylabel("force [kN]")
            ax.legend(fontsize=6)
        for ax in list(axes.flat)[n:]:
            ax.axis("off")
        fig.tight_layout()
        fig.savefig(path, dpi=120, format="png")
        plt.close(fig)


@single_threaded  # (its fits: _blas.py)
def impact_study(model, trials, channels, laws=SEED_LAWS, progress=False) -> ImpactStudy:
    """Run the seed's procedure (module docstring) on every trial for every law.

    Parameters
    ----------
    model : Model or path
        Two 1-DoF bodies joined by one gap element (``models/slab_pendulum.toml``); its law
        and stiffness are replaced per law.
    trials : path or list of Trial
    channels : path or list of Channel
        One force channel and one displacement channel per body.
    """
    import os
    import tomllib

    from ..model import load_model
    from .api import load_trials
    from .channels import load_channels

    if isinstance(model, (str, os.PathLike)):
        model = load_model(model)
    src = getattr(model, "source", None)
    names = [b.name for b in model.buildings]
    if len(names) != 2:
        raise InputError(f"the seed's procedure needs two bodies; the model has {len(names)} buildings",
                         file=src, key="building")
    n_gap = model.assembled().n_gap
    if n_gap != 1:
        raise InputError(f"the seed's procedure needs two single-floor bodies joined by one gap element; the model "
                         f"has {n_gap} (a multi-storey row: use calibrate or diagnose)", file=src, key="gap")
    chans = load_channels(channels, model) if isinstance(channels, (str, os.PathLike)) else list(channels)
    tri = load_trials(trials, chans) if isinstance(trials, (str, os.PathLike)) else list(trials)
    forces = [c for c in chans if c.quantity == "force"]
    disps = [c for c in chans if c.quantity == "displacement"]
    if len(forces) != 1:
        raise InputError(f"the seed's procedure needs one force channel, the channel map has {len(forces)}",
                         file=channels if isinstance(channels, (str, os.PathLike)) else None, key="channel")
    by_body = {c.building: c for c in disps if c.floor == 1}
    if set(by_body) != set(names):
        raise InputError(f"give one displacement channel (floor 1) for each body: {', '.join(names)}", key="channel")
    data = tomllib.loads(model.text)
    out = []
    for trial in tri:
        rec = trial.recording
        f = rec.data[forces[0].id]
        i0, i1, t_start = first_pulse(f, rec.dt)
        w = max(2 * (i1 - i0 + 1), 10)
        v = {b: (velocity_at(rec.data[by_body[b].id], rec.dt, i0 - w, i0),
                 velocity_at(rec.data[by_body[b].id], rec.dt, i1 + 1, i1 + 1 + w)) for b in names}
        left, right = names
        v0 = v[left][0] - v[right][0]
        e = -(v[left][1] - v[right][1]) / v0
        if not (v0 > 0 and 0.0 < e <= 1.0):
            raise InputError(f"from its displacements the approach velocity is {v0:.4g} m/s and the restitution "
                             f"{e:.4g}: not an impact of {left} on {right}", key=f"trial.{trial.name}")
        t_rec = np.arange(i0, i1 + 1) * rec.dt - t_start
        tf = TrialFit(trial.name, v0, e, float(f.max()), t_rec, f[i0:i1 + 1].copy())
        for law in laws:
            tf.laws[law] = _fit_law(data, model, law, e, {b: v[b][0] for b in names}, tf, rec.dt)
            if progress:
                import sys

                print(f"\r  {trial.name} {law}: NE {tf.laws[law].ne:.2%}    ", end="", file=sys.stderr, flush=True)
        out.append(tf)
    if progress:
        import sys

        print(file=sys.stderr)
    return ImpactStudy(out, tuple(laws))


def _fit_law(data, model, law, e, v_before, tf, dt_rec) -> LawFit:
    """Stiffness of ``law`` matching the recorded peak force; its pulse and NE."""
    from scipy.optimize import brentq

    mass = [float(np.sum(b.floor_masses)) for b in model.buildings]
    meff = mass[0] * mass[1] / (mass[0] + mass[1])
    v0, fpk = tf.velocity, tf.peak_force
    # a first guess from the undamped closed forms: linear F = v0 sqrt(k m), Hertz F = k^(2/5) (5 m v0^2 / 4)^(3/5)
    k0 = (fpk ** 2.5 / (1.25 * meff * v0 * v0) ** 1.5) if law in _HERTZ_LIKE else (fpk / v0) ** 2 / meff
    duration = 4.0 * (tf.time[-1] + dt_rec)

    def run(k):
        d = copy.deepcopy(data)
        d["contact"] = {"law": law, "stiffness": float(k), "restitution": float(e)}
        d.setdefault("analysis", {})
        d["analysis"].update(dt=dt_rec / 4.0, duration=duration)
        d["analysis"].setdefault("contact_substeps", 200)
        d.pop("ground_motion", None)
        for b in d["building"]:
            b["initial_velocity"] = v_before[b["name"]]
        for g in d.get("gap", []):
            g["size"] = 0.0
            for key in ("law", "stiffness", "restitution", "tension", "damping_constant", "exponent"):
                g.pop(key, None)
        from ..model.toml_loader import parse_model
        from ..simulation import run_inputs, run_row

        m = parse_model(d, base=Path(model.source).parent if model.source else Path("."))
        system, motions = run_inputs(m)
        return run_row(m, system, motions.rows, scheme="newmark")

    def excess(logk):
        return float(run(math.exp(logk)).peak_force[0]) - fpk

    lo, hi = math.log(k0 / 30.0), math.log(k0 * 30.0)
    while excess(lo) > 0:
        lo -= math.log(30.0)
    while excess(hi) < 0:
        hi += math.log(30.0)
    k = math.exp(brentq(excess, lo, hi, xtol=1e-10, rtol=1e-8))
    raw = run(k)
    sim = np.interp(tf.time, raw.time, raw.force[:, 0], left=0.0, right=0.0)
    ne = float(np.linalg.norm(sim - tf.force) / np.linalg.norm(tf.force))
    return LawFit(law, k, ne, tf.time, sim)
