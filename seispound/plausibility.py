"""Plausibility guards: input that runs but is probably not what the engineer meant.

A run whose input is legal but implausible (a record in cm/s^2 declared as g,
an analysis step coarser than the record, a duration beyond the record's end,
neighbours whose floors mostly do not face each other) finishes with a
:class:`Finding` for each such fact.  ``simulate`` issues each finding as a
:class:`PlausibilityWarning`, stores the list in the result's
``attrs["plausibility"]`` (JSON) and the ``run`` summary prints it; a finding
marked ``refuse`` stops the run before any work unless ``force=True``
(``seispound run --force``).

Thresholds, and why:

* PGA above 3 g refuses unless forced: horizontal ground accelerations above
  about 3 g have been recorded only exceptionally (Tohoku 2011, K-NET MYG004
  Tsukidate: 2.7 g; Iwate-Miyagi 2008, KiK-net IWTH25: 4.36 g as a
  three-component vector sum, Aoi et al. 2008, Science 322:727), so more than
  that is almost always a units mistake (a record in cm/s^2 read as g is
  981 times too strong).
* An analysis step coarser than T / 10 of a mode needed for 90 % of the
  effective modal mass warns: the average-acceleration method's period error
  is (omega dt)^2 / 12, 3.3 % at dt = T / 10 (Chopra, Dynamics of Structures,
  Sec. 5.5; Bathe 1996, Sec. 9.4.2), and 90 % mass participation is the
  usual criterion for the modes that matter (ASCE 7-22, Sec. 12.9.1.1).
* Fewer than half of the lower neighbour's floors at a common level warns:
  the row then pounds mostly floor against storey (columns), which the model
  does not represent.
"""

from __future__ import annotations

import json
import math
import warnings
from dataclasses import dataclass

import numpy as np

from .errors import InputError

__all__ = ["Finding", "PlausibilityWarning", "PGA_LIMIT_G", "check_before_run", "check_model", "check_after_run",
           "issue", "to_json"]

#: Peak ground acceleration [g] above which a record is refused unless forced.
PGA_LIMIT_G = 3.0
#: Steps per period of the highest mode that matters below which a warning is given.
STEPS_PER_PERIOD = 10.0
#: Share of the effective modal mass the modes that matter must reach.
MASS_SHARE = 0.90
#: Share of the lower neighbour's floors that must face a floor of the other.
LEVEL_SHARE = 0.5

G = 9.80665


class PlausibilityWarning(UserWarning):
    """A legal but implausible input or outcome (the message says what was done)."""


@dataclass(frozen=True)
class Finding:
    """One plausibility finding.

    Attributes
    ----------
    code : str
        Stable identifier: ``pga``, ``decimated``, ``coarse_step``, ``zero_padded``,
        ``floor_levels``, ``velocity_ratio``.
    message : str
        One sentence for the engineer: what was found and what was done.
    key : str
        The model key it concerns (``ground_motion.units``, ``analysis.dt`` ...).
    refuse : bool
        True if the run is refused unless forced.
    advisory : bool
        True for what is expected and no error (impact velocity ratios outside
        [0, 1]): stored with the result and printed as a note by the run
        summary, never raised as a warning.
    """

    code: str
    message: str
    key: str = ""
    refuse: bool = False
    advisory: bool = False


def check_before_run(model, provenance: dict | None, ground_acceleration=None, *,
                     model_findings=None) -> list[Finding]:
    """Findings on a model and its prepared record, before integrating.

    Parameters
    ----------
    model : Model
        A validated model.
    provenance : dict or None
        Provenance of the prepared ground motion (``prepare_ground_motion``);
        None for free vibration.
    ground_acceleration : array_like, shape (nt,), optional
        The prepared ground acceleration [m/s^2]; its peak stands in for the
        record's PGA if the provenance does not state it.
    model_findings : sequence of Finding, optional
        :func:`check_model` of this model, if the caller kept it (they depend on the model alone).

    Returns
    -------
    list of Finding
    """
    found = []
    if provenance:
        prov = dict(provenance)
        if prov.get("pga") is None and ground_acceleration is not None:
            prov["pga"] = float(np.max(np.abs(ground_acceleration), initial=0.0))
        found += _record_findings(model, prov)
    return found + list(check_model(model) if model_findings is None else model_findings)


def check_model(model) -> list[Finding]:
    """The findings that depend on the model alone: the analysis step against the modes, and floors that face
    a storey of the neighbour with no gap element."""
    return _step_findings(model) + _level_findings(model)


def _record_findings(model, prov: dict) -> list[Finding]:
    out = []
    pga = prov.get("pga")
    if pga is not None and pga > PGA_LIMIT_G * G:
        units = prov.get("units", "?")
        out.append(Finding(
            "pga", f"the record's PGA is {pga / G:.4g} g ({pga:.4g} m/s2), above {PGA_LIMIT_G:g} g, "
                   f"beyond almost every recorded ground motion; its units were taken as {units!r}: a record in cm/s2 "
                   "declared as g is 981 times too strong. Check ground_motion.units and scale "
                   "(--force / force=True runs it anyway)", key="ground_motion.units", refuse=True))
    if prov.get("decimated"):
        f_hi = prov.get("highest_resolved_frequency")
        out.append(Finding(
            "decimated", f"the analysis step {model.analysis.dt:g} s is coarser than the record's step "
                         f"{prov.get('dt_record', float('nan')):g} s: the record was decimated with an anti-alias "
                         f"low-pass, so the ground motion holds frequencies up to {f_hi:.3g} Hz only",
            key="analysis.dt"))
    pad = prov.get("zero_padded_from")
    if pad is not None:
        end = model.analysis.nsteps * model.analysis.dt
        out.append(Finding(
            "zero_padded", f"the analysis lasts {end:g} s but the record ends at {pad:g} s: it was zero-padded, "
                           f"so the last {end - pad:.4g} s are free vibration", key="analysis.duration"))
    return out


def _step_findings(model) -> list[Finding]:
    """The analysis step against the shortest period among the modes needed for 90 % of the mass.

    Newmark: the period error (w dt)^2 / 12 of average acceleration (Chopra Fig. 5.5.2).  The exact
    scheme (classically damped buildings of at most MAX_MODAL_BLOCK storeys) has none between impacts,
    but a sinusoid of period T sampled every dt can show a peak too low by up to 1 - cos(pi dt / T).
    """
    from .integrate.modal import MAX_MODAL_BLOCK

    dt = model.analysis.dt
    worst = None
    for b in model.buildings:
        w, phi = b.modes()
        m = b.floor_masses
        gamma = phi.T @ m  # participation factors of mass-normalised modes (Chopra Eq. 13.2.3)
        share = np.cumsum(gamma ** 2) / m.sum()  # effective modal mass share (Chopra Eq. 13.2.14)
        k = int(np.searchsorted(share, MASS_SHARE - 1e-12)) + 1
        t_k = 2 * math.pi / w[min(k, w.size) - 1]
        if worst is None or t_k < worst[0]:
            worst = (t_k, b.name, min(k, w.size))
    if worst is None or dt <= worst[0] / STEPS_PER_PERIOD:
        return []
    t_k, name, k = worst
    head = (f"dt = {dt:g} s is {t_k / dt:.3g} steps per period of building {name}'s mode {k} "
            f"(T = {t_k:.3g} s), a mode needed for {MASS_SHARE:.0%} of its mass: ")
    if model.analysis.scheme == "exact" and all(b.n_floors <= MAX_MODAL_BLOCK for b in model.buildings):
        # the exact scheme has no period error between impacts; the peaks are still read at the samples
        under = (1.0 - math.cos(math.pi * dt / t_k)) * 100
        return [Finding(
            "coarse_step", head + f"the exact scheme integrates it without period error, but results are sampled "
                                  f"at dt, so its peak can be under-read by up to {under:.2g} %; use dt <= "
                                  f"{t_k / STEPS_PER_PERIOD:.3g} s for peak accelerations", key="analysis.dt")]
    err = (2 * math.pi * dt / t_k) ** 2 / 12 * 100
    return [Finding(
        "coarse_step", head + f"its period comes out about {err:.2g} % long (Newmark); use dt <= "
                              f"{t_k / STEPS_PER_PERIOD:.3g} s", key="analysis.dt")]


def _level_findings(model) -> list[Finding]:
    """Floors below the lower roof that face a storey of the neighbour with no gap element there.

    ``levels = "floors"``: floors at levels the other has no floor at, when they are most of them
    (the model then lets no floor strike a storey); ``levels = "lower"``: the taller neighbour's
    floors that face a storey of the lower one (``levels = "all"`` adds them).
    """
    from .structure.gap import HEIGHT_TOLERANCE

    out = []
    index = {b.name: b for b in model.buildings}
    for gi, gap in enumerate(model.gaps):
        pair = [index.get(n) for n in gap.between]
        if None in pair or gap.levels == "all":
            continue
        heights = {b.name: b.floor_heights for b in pair}
        roof = min(z[-1] for z in heights.values()) + HEIGHT_TOLERANCE
        facing, shared = [], None
        for b, other in (pair, pair[::-1]):
            z = heights[b.name]
            h = z[z <= roof]
            match = np.any(np.abs(heights[other.name][None, :] - h[:, None]) <= HEIGHT_TOLERANCE, axis=1)
            shared = h[match] if shared is None else shared
            facing.append((b, other, np.flatnonzero(~match) + 1, h[~match], h.size))
        most = max(f[4] for f in facing)
        key = f"gap.{gi + 1}.levels"
        if gap.levels == "lower":
            lower = min(pair, key=lambda b: b.floor_heights[-1])
            missed = [f for f in facing if f[0] is not lower and f[2].size]
            if missed:
                b, o, fl, hs, _ = missed[0]
                out.append(Finding("floor_levels", f"{pair[0].name}|{pair[1].name}: {b.name}'s floors "
                                   f"{', '.join(f'{f} ({x:g} m)' for f, x in zip(fl, hs))} face a storey of "
                                   f"{o.name} and have no gap element (levels = \"lower\": {o.name}'s floors "
                                   "only); levels = \"all\" adds them", key=key))
            continue
        if shared.size >= LEVEL_SHARE * most:
            continue
        faces = "; ".join(f"{b.name}'s floors {', '.join(f'{f} ({x:g} m)' for f, x in zip(fl, hs))} face a storey "
                          f"of {o.name}" for b, o, fl, hs, _ in facing if fl.size)
        out.append(Finding(
            "floor_levels", f"{pair[0].name}|{pair[1].name}: only {shared.size} of the floor levels below the lower "
                            f"roof are shared ({most} floors in the taller count); gap elements at "
                            f"{', '.join(f'{x:g}' for x in shared) or 'none'} m only. {faces}: levels = \"floors\" "
                            "lets no floor strike a storey (\"lower\" or \"all\" do)", key=key))
    return out


def check_after_run(ds) -> list[Finding]:
    """Findings on a finished run's result Dataset (impacts whose velocity ratio lies outside [0, 1])."""
    if ds.sizes.get("impact", 0) == 0:
        return []
    r = np.asarray(ds.variables["impact_velocity_ratio"].values, float)
    out_of = np.isfinite(r) & ((r < 0.0) | (r > 1.0))
    if not out_of.any():
        return []
    lo, hi = float(np.nanmin(r)), float(np.nanmax(r))
    return [Finding(
        "velocity_ratio", f"{int(out_of.sum())} of {r.size} impacts have a separation/approach velocity ratio "
                          f"outside [0, 1] (range {lo:.3g} to {hi:.3g}); this is expected, not an error: the floors "
                          "belong to buildings whose storey forces and other contacts act during the impact, so "
                          "this ratio (impact_velocity_ratio) is not the contact law's restitution e",
        key="contact.restitution", advisory=True)]


def issue(findings, *, force: bool, file=None) -> None:
    """Raise InputError for the first refusing finding (unless ``force``); warn for every finding that is not
    advisory."""
    for f in findings:
        if f.refuse and not force:
            raise InputError(f.message, file=file, key=f.key)
    for f in findings:
        if not f.advisory:
            warnings.warn(f.message, PlausibilityWarning, stacklevel=4)  # the caller of simulate (via _simulate)


def to_json(findings) -> str:
    """The findings as a JSON list of {code, message, key, refuse} (stored in ``attrs["plausibility"]``)."""
    return json.dumps([dict(vars(f)) for f in findings])  # a Finding's fields are flat: no asdict deep copy
