"""Run a model: assemble, read the ground motion, integrate with and without pounding."""

from __future__ import annotations

import functools
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import xarray as xr

from .errors import InputError
from .integrate import integrate

__all__ = ["simulate", "prepare_ground_motion", "prepare_ground_motions", "run_inputs", "GroundMotions"]


def prepare_ground_motion(model):
    """Ground acceleration of the row's record on the analysis grid [m/s^2], shape (nsteps + 1,), and its provenance.

    Free vibration (no ``[ground_motion]``) gives zeros and provenance None.
    """
    an = model.analysis
    if model.ground_motion is None:
        return np.zeros(an.nsteps + 1), None
    return _prepare_record(model.ground_motion, model, "ground_motion")


def _prepare_record(spec, model, section):
    """A record (file or samples) on the model's analysis grid; errors name ``section``.<setting>."""
    an = model.analysis
    nsteps = an.nsteps
    if spec.samples is not None:
        return _prepare_samples(spec, an.dt, nsteps, section)
    try:
        st = spec.file.stat()
    except OSError:
        raise InputError("record file not found", file=spec.file, key=f"{section}.file") from None
    key = (str(spec.file), st.st_mtime_ns, st.st_size, spec.trace, spec.units, spec.calibration, spec.scale,
           spec.baseline, spec.format, spec.dt, an.dt, nsteps)
    try:
        ag, prov = _read_prepared(*key)
    except _SettingError as err:
        where = section if err.section == "ground_motion" else err.section
        raise InputError(f"{err.message} (record {err.record})", file=model.source,
                         key=f"{where}.{err.key}") from None
    return ag.copy(), dict(prov)


@dataclass
class GroundMotions:
    """The ground motions of a run on the analysis grid.

    Attributes
    ----------
    rows : ndarray, shape (nm, nt)
        Distinct ground accelerations [m/s^2]; row 0 is the row's record (zeros without one).
    row_of : ndarray, shape (nb,)
        The row under each building, left to right.
    provenance : dict or None
        The row's record's provenance (``motion.record.on_analysis_grid``).
    per_building : list of (dict or None)
        Each building's own motion (its record's provenance, delay, filter steps), None for the row's.
    """

    rows: np.ndarray
    row_of: np.ndarray
    provenance: dict | None
    per_building: list

    @property
    def uniform(self) -> bool:
        return self.rows.shape[0] == 1

    def dof_motion(self, system) -> np.ndarray:
        """The ground-motion row of every DOF of ``system``, shape (n,)."""
        return self.row_of[system.dof_building].astype(np.int64)


def run_inputs(model):
    """What a run integrates: the assembled row, its DOFs on their buildings' ground motions, and the motions.

    Validates and assembles once (``Model.assembled``); shared by :func:`simulate`
    and the study worker.  Returns (SystemArrays, GroundMotions).
    """
    return _run_inputs(model)[1:]


def _run_inputs(model):
    """(what the model keeps for its content, system, motions): :func:`run_inputs` with ``Model.kept()``."""
    kept = model.kept()
    system = kept["system"]
    motions = prepare_ground_motions(model)
    if not motions.uniform:
        system = replace(system, dof_motion=motions.dof_motion(system))
    return kept, system, motions


# Newmark's substeps on the general driver: no step longer than NEWMARK_THETA / omega_hi (see newmark_substeps)
NEWMARK_THETA = 0.2
MAX_NEWMARK_SUBSTEPS = 8


def newmark_substeps(model, system) -> int:
    """Substeps per analysis step that make the general driver's Newmark steps accurate at the model's dt.

    The general driver (yielding storeys, foundations, floor-to-storey gaps) steps by Newmark's
    average acceleration rule, whose error grows as (omega h)^2 (period elongation
    (omega h)^2 / 12 per cycle; Chopra, Dynamics of Structures, Sec. 5.5): floor accelerations
    follow every mode of the storeys, so the step is set by the highest natural frequency
    omega_hi of the fixed-base buildings (storey springs and floor masses; rods' axial and
    foundation modes left out).  The rule omega_hi h <= NEWMARK_THETA = 0.2 rad is calibrated,
    not derived: on the 5 + 8 storey pair of ``benchmarks.physics_accuracy`` the floor-acceleration
    NE against a 0.5 ms reference was 1.2-1.3 % at omega_hi h = 0.33 (NE ~ 0.115 (omega_hi h)^2),
    so 0.2 puts it near 0.45 %, under the 0.5 % asked.  A power of two (the contact substeps'
    grid), at most MAX_NEWMARK_SUBSTEPS; 1 on the fast driver (its steps are exact between
    impacts).  A tolerance below the default (0.01) scales the rule's 0.2 rad by sqrt(tolerance /
    0.01), up to MAX_TOLERANCE_NEWMARK substeps; a looser one keeps it.
    """
    from .integrate.newmark import general_driver_needed
    from .model.analysis import DEFAULT_TOLERANCE

    if not general_driver_needed(system, model.analysis.scheme):
        return 1

    # a tolerance finer than the default asks a smaller omega h, as the error's (omega h)^2 falls
    tol = model.analysis.tolerance
    theta = NEWMARK_THETA * min(1.0, (tol / DEFAULT_TOLERANCE) ** 0.5)
    most = MAX_NEWMARK_SUBSTEPS if tol >= DEFAULT_TOLERANCE else MAX_TOLERANCE_NEWMARK
    w_hi = max(float(b.modes()[0].max()) for b in model.buildings)
    n = 1
    while n < most and w_hi * model.analysis.dt / n > theta:
        n *= 2
    return n


# the longest contact substep: CONTACT_THETA / omega_max (see contact_step)
CONTACT_THETA = 0.4


def contact_step(system) -> float:
    """Longest contact substep [s]: CONTACT_THETA / omega_max of the row's linear part.

    Contact substeps are 1 / ``contact_substeps`` of the impact's duration, which follows the
    contact stiffness, not the row: rod floors put axial modes of hundreds of Hz to kHz into
    the buildings, which those substeps step by Newmark with omega h near 1. omega_max is
    bounded by Gershgorin's theorem on M^-1 K (lumped masses: omega_max^2 <= max_i sum_j
    |K_ij| / m_i; Golub & Van Loan 2013, Thm. 7.2.1), cheap and never below the true value.
    CONTACT_THETA = 0.4 is calibrated, not derived: on the rod-floor pair of
    ``benchmarks.physics_accuracy`` (4 segments, 220 Hz axial modes) the floor-acceleration NE
    at 5 ms against a 0.5 ms run was 2.47 % without the limit, 0.11 % at 0.4 and 0.03 % at 0.2
    (at 3.7 and 9.6 times the cost); with every physics together 1.61 % -> 0.29 %.  For storeys
    alone the limit is longer than the impact's substeps, so ordinary rows are unchanged (unless
    very stiff springs, a foundation on 1e14 N/m, set omega_max).  The kernel never lets it ask
    more than ``_contact.MAX_SUBSTEP_FACTOR`` (4) times an impact's substeps.
    """
    k, i, j, m = (np.asarray(x, float) for x in (system.el_k, system.el_i, system.el_j, system.mass))
    i, j = i.astype(np.int64), j.astype(np.int64)
    row = np.zeros(m.size)
    np.add.at(row, i, np.abs(k) * np.where(j >= 0, 2.0, 1.0))
    np.add.at(row, j[j >= 0], 2.0 * np.abs(k[j >= 0]))
    w2 = np.max(row / m, initial=0.0)
    return CONTACT_THETA / np.sqrt(w2) if w2 > 0 else np.inf


def run_row(model, system, rows, *, scheme=None, store_history=True, limit_contact_step=True):
    """Integrate an assembled row with the model's analysis settings: the one call every run makes.

    ``simulate`` (the run and its twin), the study worker, a fit's evaluation and the impact
    procedure all integrate through here, so the step, the scheme, the general driver's
    substeps (:func:`newmark_substeps`) and the contact substeps (:func:`contact_substeps`) are
    decided once.  ``scheme`` overrides the model's.  ``limit_contact_step`` False leaves the
    contact substeps at 1 / ``contact_substeps`` of each impact's duration (:func:`contact_step`
    not applied): a fit's evaluations do, since the limit made a diagnosis with rod-floor forms 11
    times slower (docs/performance.md).

    When the contact substeps are the tolerance's (the model does not give them) and the row
    pounds, the run is checked by two substep counts (:func:`_meet_tolerance`) and refined until
    its peaks meet the tolerance.  Returns the kernel's RawResult, its ``stats`` holding
    ``newmark_substeps``, ``contact_step``, ``contact_substeps``, ``contact_error_estimate``,
    ``peak_error_estimate`` and ``tolerance_runs``.
    """
    an = model.analysis
    nm, estimate = contact_substeps(model)
    steps = (nm, newmark_substeps(model, system), contact_step(system) if limit_contact_step else np.inf)

    def run(settings):
        n_cs, n_nm, h_c = settings
        raw = integrate(system, rows, an.dt, an.nsteps, n_cs, scheme=scheme or an.scheme,
                        store_history=store_history, substeps=n_nm, contact_step=h_c)
        raw.stats.update(newmark_substeps=n_nm if raw.driver == "general" else 1, contact_step=float(h_c),
                         contact_substeps=int(n_cs.contact_substeps))
        return raw

    raw = run(steps)
    peak_estimate, runs = float("nan"), 1
    if an.newmark.contact_substeps is None and raw.impacts["gap"].size:
        raw, steps, peak_estimate, runs = _meet_tolerance(run, raw, steps, an.tolerance)
        estimate = impact_error_of(model, steps[0].contact_substeps)
        if not peak_estimate <= an.tolerance:
            import warnings

            from .plausibility import PlausibilityWarning

            warnings.warn(f"{model.source or model.title}: the tolerance {an.tolerance:g} was not reached: at "
                          f"{steps[0].contact_substeps} contact substeps, the most it takes, the peaks still moved by "
                          f"{peak_estimate:.2g} from the run at half the steps (analysis.tolerance)",
                          PlausibilityWarning, stacklevel=2)
    raw.stats.update(contact_error_estimate=estimate, peak_error_estimate=peak_estimate, tolerance_runs=runs)
    return raw


#: the finest settings the tolerance may ask for: contact substeps, Newmark substeps per analysis step
MAX_CONTACT_SUBSTEPS, MAX_TOLERANCE_NEWMARK = 512, 64


def _meet_tolerance(run, raw, steps, tolerance):
    """(run, settings, estimated relative error of its peaks, runs made): refined until the peaks meet ``tolerance``.

    Two substep counts: the same row with every step the tolerance sets twice as long (contact
    substeps halved, the contact-step limit and the general driver's Newmark substeps
    doubled) gives, by Richardson's extrapolation, the error of the finer run's peaks,
    err = |q(h) - q(2h)| / (2^p - 1) over :func:`peak_values`, taken at p = 1 (err = the change
    itself; derived here).  The steps are second order (Newmark's average acceleration rule,
    Chopra Sec. 5.4), but a row's peaks come out of hundreds of impacts, and until the steps are
    fine enough that the sequence of impacts no longer changes they converge more slowly: on the
    row of four 10-storey buildings of ``benchmarks.tolerance`` (NIVe, El Centro) the worst peak's
    error went 2.62, 1.50, 0.53, 0.16 % as the steps halved (orders 0.8, 1.5, 1.75), and p = 2
    would have taken the 1.50 % run for 0.49 %.  While the estimate is above the tolerance,
    every step is halved and the row run again, the last run becoming the coarse one, up to
    MAX_CONTACT_SUBSTEPS.  (The isolated impact's estimate, which also sees a peak force
    that converges unevenly, met the tolerance at the first settings and only falls from there.)
    """
    coarse = run(_scaled(steps, 0.5))
    runs = 2
    while True:
        estimate = _peak_change(raw, coarse)
        if raw.stats["steps"] == coarse.stats["steps"] and estimate == 0.0:
            estimate = np.inf  # the coarse run could not be coarser (its substeps were the analysis step): no check
        finest = steps[0].contact_substeps >= MAX_CONTACT_SUBSTEPS
        if estimate <= tolerance or finest:
            return raw, steps, estimate, runs
        coarse, steps = raw, _scaled(steps, 2.0)
        raw = run(steps)
        runs += 1


def _scaled(steps, factor):
    """The settings with every step the tolerance sets divided by ``factor`` (2: twice as fine; 0.5: coarse)."""
    nm, n_nm, h_c = steps
    n_cs = max(int(round(nm.contact_substeps * factor)), 2)
    n_nm = min(max(int(round(n_nm * factor)), 1), MAX_TOLERANCE_NEWMARK)
    return replace(nm, contact_substeps=n_cs), n_nm, h_c / factor


def peak_values(raw) -> list:
    """What the tolerance speaks of, as arrays: the peak pounding force of every gap element whose peak
    is at least a tenth of the largest, and every DOF's peak displacement and absolute acceleration
    at least 1e-3 of the largest."""
    f = np.asarray(raw.peak_force, float)
    u = np.asarray(raw.peak_displacement, float)
    a = np.abs(raw.acceleration).max(axis=0) if raw.acceleration.size else np.zeros(0)
    return [f, 0.1 * f.max(initial=0.0)], [u, 1e-3 * u.max(initial=0.0)], [a, 1e-3 * a.max(initial=0.0)]


def _peak_change(fine, coarse) -> float:
    """Largest relative change of :func:`peak_values` from ``coarse`` to ``fine`` [-]."""
    worst = 0.0
    for (q1, floor), (q0, _) in zip(peak_values(fine), peak_values(coarse)):
        keep = q1 >= floor
        if keep.any() and floor > 0:
            worst = max(worst, float(np.max(np.abs(q1[keep] - q0[keep]) / q1[keep])))
    return worst


def impact_error_of(model, n) -> float:
    """The isolated-impact estimate at ``n`` substeps for the row's laws (``seispound.accuracy``)."""
    from .accuracy import impact_error

    return max((impact_error(law, int(n)) for law in _laws(model)), default=0.0)


def _laws(model) -> list:
    """The contact laws of the row's gaps (a gap's own, else the model's), each once."""
    laws = {id(law): law for law in (g.law or model.contact for g in model.gaps) if law is not None}
    return list(laws.values())


def contact_substeps(model):
    """(Newmark settings with the contact substeps set, the estimated relative error of an impact).

    Given substeps (``[analysis] contact_substeps``) win, with no estimate (NaN); otherwise the
    fewest that meet ``[analysis] tolerance`` on an isolated impact of each of the row's laws
    (:func:`seispound.accuracy.choose_contact_substeps`), never fewer than Newmark's stability
    asks for the contact stiffness.  :func:`run_row` checks the run itself and refines from there.
    """
    from .accuracy import choose_contact_substeps

    nm = model.analysis.newmark
    if nm.contact_substeps is not None:
        return nm, float("nan")
    n, estimate = choose_contact_substeps(_laws(model), model.analysis.tolerance)
    limit = nm.stability_limit()
    if np.isfinite(limit):
        n = max(n, int(np.ceil(1.0 / (2.0 * limit) + 1e-12)))
    return replace(nm, contact_substeps=n), estimate


def prepare_ground_motions(model) -> GroundMotions:
    """The row's record and each building's own motion (``[[building]] ground_motion``) on the analysis grid.

    A building's motion is the row's record (or its own file) delayed and low-passed
    (:func:`seispound.motion.spatial.variant`); motions equal to one already
    prepared share its row, so a zero delay without a filter is the uniform case.
    """
    from .motion.spatial import variant

    ag, prov = prepare_ground_motion(model)
    rows, row_of, per_building = [ag], [], []
    for b, m in zip(model.buildings, model.building_motions()):
        if m is None:
            row_of.append(0)
            per_building.append(None)
            continue
        key = f"building.{b.name}.ground_motion"
        base, bprov = (ag, prov) if m.record is None else _prepare_record(m.record, model, key)
        if m.record is not None and m.weight != 1.0:  # the row's record and w times its own's difference from it
            base = m.weight * base + (1.0 - m.weight) * ag
        own = bprov.get("dt_original") if isinstance(bprov, dict) else None  # the record's step: its arrival
        samples, steps = variant(base, model.analysis.dt, m.delay, m.lowpass, m.lowpass_order, key=key,
                                 rise=float(own) if own else 0.0)
        same = [r for r, x in enumerate(rows) if np.array_equal(x, samples)]
        if same:
            row_of.append(same[0])
        else:
            rows.append(samples)
            row_of.append(len(rows) - 1)
        per_building.append({"record": bprov if m.record is not None else "the row's record",
                             "weight": m.weight if m.record is not None else 0.0, "delay_s": m.delay,
                             "lowpass_hz": m.lowpass, "lowpass_order": m.lowpass_order, "steps": steps})
    return GroundMotions(np.vstack(rows), np.asarray(row_of, np.int64), prov, per_building)


@functools.lru_cache(maxsize=32)
def _read_prepared(file, mtime_ns, size, trace, units, calibration, scale, baseline, fmt, rec_dt, dt, nsteps):
    """Read and prepare a record once per (file version, settings): studies rerun the same record."""
    from .motion.record import read_record

    path = Path(file)
    stage = "ground_motion"  # a "dt" that does not fit is the record's own while reading, the analysis's after
    try:
        rec = read_record(path, trace=trace, units=units, calibration=calibration, scale=scale, format=fmt,
                          dt=rec_dt)
        stage = "analysis"
        rec = _to_grid(rec, baseline, dt, nsteps)
        ag = np.array(rec.acceleration)
    except InputError as err:
        if err.key in ("units", "trace", "calibration", "scale", "baseline", "dt", "format"):
            # a setting of the model file that does not fit the record
            section = stage if err.key == "dt" else "ground_motion"
            raise _SettingError(err.message, section, err.key, path.name) from None
        raise err.located(file=path) from None
    ag.setflags(write=False)
    return ag, dict(rec.provenance)


def _to_grid(rec, baseline, dt, nsteps):
    """Baseline-corrected (if asked), then resampled, cut or zero-padded to the analysis grid: each step in
    the provenance (:func:`seispound.motion.record.on_analysis_grid`)."""
    from .motion.record import on_analysis_grid

    if baseline is not None:
        rec = rec.baseline_corrected(order=baseline)
    return on_analysis_grid(rec, dt, nsteps * dt)


def _prepare_samples(spec, dt, nsteps, section="ground_motion"):
    """A ground motion given in memory (GroundMotionSpec.from_array / from_trace) on the analysis grid.

    Kept per (samples, settings, grid), as a file's record is (``_read_prepared``): a study or a
    fit reruns the same samples.
    """
    samples = np.ascontiguousarray(spec.samples, dtype=float)
    try:
        ag, prov = _samples_prepared(samples.tobytes(), spec.dt, spec.units, spec.calibration, spec.scale,
                                     spec.source, spec.baseline, dt, nsteps)
    except InputError as err:
        raise InputError(err.message, file=err.file, key=f"{section}.{err.key}") from None
    return ag.copy(), _copy_tree(prov)


def _copy_tree(x):
    """A copy of nested dicts and lists (the provenance), sharing their immutable leaves: a caller may add to
    its copy, never to the kept one; ``copy.deepcopy``'s generality cost five times as much."""
    if isinstance(x, dict):
        return {k: _copy_tree(v) for k, v in x.items()}
    if isinstance(x, list):
        return [_copy_tree(v) for v in x]
    return x


@functools.lru_cache(maxsize=32)
def _samples_prepared(data, rec_dt, units, calibration, scale, source, baseline, dt, nsteps):
    """(read-only acceleration, provenance) of samples (their bytes) on the analysis grid."""
    from .motion.record import record_from_samples

    rec = record_from_samples(np.frombuffer(data), rec_dt, units=units, calibration=calibration, scale=scale,
                              source=source or "numpy array")
    rec = _to_grid(rec, baseline, dt, nsteps)
    ag = np.array(rec.acceleration)
    ag.setflags(write=False)
    return ag, dict(rec.provenance)


class _SettingError(Exception):
    """A model-file setting that does not fit the record (re-raised against the model file)."""

    def __init__(self, message, section, key, record):
        super().__init__(message)
        self.message, self.section, self.key, self.record = message, section, key, record


def simulate(model, *, twin: bool = True, force: bool = False, tolerance: float | None = None) -> xr.Dataset:
    """Simulate ``model`` and return its result Dataset (schema in :mod:`seispound.results.schema`).

    The no-pounding twin (all gaps disabled, same record and settings) runs
    automatically and gives the denominator of ``amplification``.

    Parameters
    ----------
    model : Model
    twin : bool
        Run the no-pounding twin (default True).  Without it the amplification is NaN.
    force : bool
        Run even when a plausibility guard would refuse (a PGA above 3 g ...;
        :mod:`seispound.plausibility`).  Findings are still warned about and stored.
    tolerance : float, optional
        The relative error accepted on the peak pounding force and the peak floor response, in
        (0, 0.5]; replaces ``[analysis] tolerance`` (default 0.01) for this run.  The contact
        substeps are chosen from it unless the model gives them (:func:`contact_substeps`).

    Raises
    ------
    InputError
        Invalid or refused input (one line naming file and key).
    IntegrationError
        Newton did not converge, or the state became non-finite (the message names the time).
    """
    from ._first_use import interpret_first_use

    if tolerance is not None:  # a copy of the model with its analysis' tolerance replaced
        model = replace(model, analysis=replace(model.analysis, tolerance=tolerance))
    with interpret_first_use():  # a first use after installing runs as Python while numba compiles (_first_use)
        return _simulate(model, twin, force)


def _simulate(model, twin, force):
    from . import __version__
    from .plausibility import check_after_run, check_before_run, check_model, issue, to_json
    from .results import build_dataset
    from .results.schema import Layout

    kept, system, motions = _run_inputs(model)  # validated as the file reader validates, assembled once
    if "model_findings" not in kept:
        kept["model_findings"] = tuple(check_model(model))
    ag, prov = motions.rows[0], motions.provenance
    findings = check_before_run(model, prov, ag, model_findings=kept["model_findings"])
    for i, own in enumerate(motions.per_building):  # a building's own record is checked as the row's is
        if own is not None and isinstance(own["record"], dict):
            findings += check_before_run(model, own["record"], motions.rows[motions.row_of[i]], model_findings=())
    issue(findings, force=force, file=model.source)
    an = model.analysis
    raw = run_row(model, system, motions.rows)
    _check_finite(raw, an.dt)
    raw0 = None
    if twin:  # with histories: its peak accelerations, drifts and storey shears (results/peaks.py)
        raw0 = run_row(model, system.without_contact(), motions.rows)
        _check_finite(raw0, an.dt, what="the no-pounding twin")
    if "layout" not in kept:
        kept["layout"] = Layout(model, system)
    ds = build_dataset(model, system, raw, raw0, ag, prov, __version__, motions=motions, layout=kept["layout"])
    after = check_after_run(ds)
    issue(after, force=True)
    ds.attrs["plausibility"] = to_json(findings + after)
    return ds


def _check_finite(raw, dt, what="the run"):
    """Stop with the first time at which the state or energy balance is not finite.

    A diverging integration must not end as a result: non-finite energies or
    peaks raise IntegrationError naming the time.  The energy terms are sums
    over every DOF of u, v and the ground input, so a NaN or inf anywhere in the
    state shows in the energy row of that instant and every later one.
    """
    from .integrate import IntegrationError

    if np.isfinite(raw.energy).all() and np.isfinite(raw.peak_displacement).all() and np.isfinite(raw.peak_force).all():
        return
    rows = np.isfinite(raw.energy).all(axis=1)  # a reduction along rows costs a vector operation per row: only here
    bad = int(np.argmin(rows)) if not rows.all() else raw.energy.shape[0] - 1
    t = float(raw.time[bad]) if raw.time.size > bad else float("nan")
    raise IntegrationError(f"{what} diverged: the state or energy balance is not finite at t = {t:.6g} s "
                           f"(dt = {dt:g} s); check the step, the Newmark parameters and the model's units")
