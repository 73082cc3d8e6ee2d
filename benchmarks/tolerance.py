"""Is ``[analysis] tolerance`` honest?  ``python -m benchmarks.tolerance [--quick] [--json PATH]``.

A run given ``tolerance`` (and no ``contact_substeps``) chooses its contact substeps from an
error estimate on an isolated impact of each of its laws (``seispound.accuracy``).  The promise
is that the relative error of the peak pounding force and of the peak floor response is at most
the tolerance.  This benchmark checks the promise against a converged reference on rows and
pairs covering every law, strong and weak pounding, the canonical row, a row of four
10-storey buildings with gaps at every floor and a yielding row (the general driver).

For each case
* the reference: the same model with ``contact_substeps = 1024`` given explicitly, at the
  model's ``dt`` or, where that is not converged, a fraction of it (``REFERENCE_DT_DIVISOR``:
  the yielding pair at dt / 16); its convergence is checked against 512 and 2048 substeps and
  against a quarter of its step (at 1024), all peaks taken on the model's analysis instants;
* at each tolerance 0.1 %, 1 % and 5 %: ``simulate(model, twin=False, tolerance=tol)``,
  its chosen substeps and estimate (the result's ``contact_substeps`` and
  ``contact_error_estimate``), and the relative errors against the reference of
  (a) the peak pounding force: of the largest peak over the gaps, and the worst over the gaps
      whose reference peak is at least ``SIGNIFICANT`` (10 %) of the largest;
  (b) the peak floor response: the worst over the floors of the peak |absolute acceleration| and
      of the peak |displacement|, both over the model's analysis instants (the histories; the
      result's ``peak_acceleration`` is that very maximum);
  "within" when all four are at most the tolerance;
* where each miss comes from (:func:`locate`): the approach velocity of the worst gap's peak impact,
  and the contact force on the worst floor at the instant of its peak;
* the cost: ``--repeat`` (5) rounds of warm runs of the whole ``simulate(model, twin=False,
  tolerance=tol)``, one per tolerance in each round (in a shuffled order); the median time, and the
  median over the rounds of its ratio to the same round's 1 % run; the integration steps taken (the result's
  ``integrator_stats``), which no load changes; and, apart, the one-off cost of the error
  estimate in a fresh process (``seispound.accuracy`` keeps its isolated impacts for the
  process, so warm runs do not pay it).

``--quick`` runs two short strong-pounding pairs (Hd, LVe; 6 s), two repeats: a smoke run.
``--figure PATH`` draws error reached vs tolerance asked, and time and steps vs tolerance;
``--markdown`` prints the tables of ``docs/tolerance.md``.
"""

from __future__ import annotations

import argparse
import json
import math
import statistics
import sys
import time
import warnings
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
TOLERANCES = (0.001, 0.01, 0.05)
REFERENCE_SUBSTEPS = 1024
#: the reference's substep checks: half and twice its substeps
CHECK_SUBSTEPS = (512, 2048)
#: a gap counts in the "significant gaps" force error when its reference peak is at least this share of the largest
SIGNIFICANT = 0.10
#: a reference is converged when its checks differ by at most this (a tenth of the tightest tolerance)
CONVERGED = 1e-4
#: the reference's step is the model's dt / this; 1 unless its check against dt / 4 was not converged.
#: The yielding pair (general driver: Newmark between impacts, error ~ (omega h)^2) differed by 0.23 % in
#: its floor accelerations between dt and dt / 4; at dt / 16 it differs from dt / 64 by 0.003 %.
REFERENCE_DT_DIVISOR = {"yielding_pair.toml": 16,
                        # the held-out set's first run took this one's reference at dt, which its own check
                        # flagged (0.20 % from dt / 4): rerun with the yielding pair's divisor
                        "held-out yielding pair, El Centro 270": 16}

#: contact stiffness per law: linear laws [N/m], Hertz-type [N/m^1.5]
STIFFNESS = {"LVe": 1.5e8, "MLVe": 1.5e8, "NIVe": 2.75e9, "Hd": 2.75e9, "LHC": 1.5e8}
RESTITUTION = 0.65
LAWS = ("LVe", "MLVe", "NIVe", "Hd", "LHC")


@dataclass(frozen=True)
class Case:
    """One benchmark case: a name, what it stands for, and how to build its model."""

    name: str
    what: str
    build: object  # () -> seispound Model

    def model(self):
        return self.build()


def _record(name: str, scale: float):
    from seispound.model.spec import GroundMotionSpec
    from seispound.motion.catalogue import bundled_path

    return GroundMotionSpec(file=bundled_path(name), units="g", scale=scale)


def _row(title, specs, gap, law_name, record, scale, duration, dt=0.005, restitution=RESTITUTION):
    """A row of uniform shear buildings (``benchmarks.peer.cases.BuildingSpec``) with one gap size at every
    common floor of neighbours (equal storey heights: the lower neighbour's every floor)."""
    from seispound.contact import make_law
    from seispound.model.spec import Analysis, Model
    from seispound.structure import Gap

    law = make_law(law_name, stiffness=STIFFNESS[law_name], restitution=restitution)
    gaps = [Gap((a.name, b.name), gap) for a, b in zip(specs, specs[1:])]
    return Model(title, [b.building() for b in specs], gaps, law, Analysis(dt, duration),
                 ground_motion=_record(record, scale))


def _file(name):
    from seispound import load_model

    return lambda: load_model(REPO / "models" / name)


def cases(quick: bool = False) -> list[Case]:
    """The benchmark's cases (``quick``: two short strong pairs)."""
    from benchmarks.peer.cases import PAIR, ROW4

    if quick:
        return [Case(f"quick pair 3+5 {law}", f"3+5 pair, {law}, 0.5 cm gap, El Centro 180 x 1.5, 6 s",
                     lambda law=law: _row(f"quick {law}", PAIR, 0.005, law, "elcentro_180", 1.5, 6.0))
                for law in ("Hd", "LVe")]
    out = []
    for law in LAWS:  # strong: a 0.5 cm gap under 1.5 x El Centro 180 (about 130 impacts)
        out.append(Case(f"strong pair {law}", f"3+5 pair, {law}, 0.5 cm gap, El Centro 180 x 1.5, 20 s",
                        lambda law=law: _row(f"strong {law}", PAIR, 0.005, law, "elcentro_180", 1.5, 20.0)))
    for law in LAWS:  # weak: a 3.5 cm gap under El Centro 270 (5 impacts, on 2 of the 3 gap elements)
        out.append(Case(f"weak pair {law}", f"3+5 pair, {law}, 3.5 cm gap, El Centro 270 x 1, 20 s",
                        lambda law=law: _row(f"weak {law}", PAIR, 0.035, law, "elcentro_270", 1.0, 20.0)))
    out.append(Case("two_buildings.toml", "4+8 pair, Hd, 2 cm gap, El Centro 180, 30 s (models/)",
                    _file("two_buildings.toml")))
    out.append(Case("row_of_three.toml", "canonical row 8, 12, 6 storeys, Hd, 2 cm, El Centro 180, 40 s (models/)",
                    _file("row_of_three.toml")))
    out.append(Case("row of four NIVe",
                    "4 x 10 storeys (T1 1.0, 0.8, 1.25, 0.9 s), NIVe, 2 cm gaps at every floor, Corralitos 000, 20 s",
                    lambda: _row("row of four", ROW4, 0.02, "NIVe", "corralitos_000", 1.0, 20.0)))
    out.append(Case("yielding_pair.toml", "3+5 yielding pair (bilinear, Bouc-Wen), Hd, 2 cm, El Centro 180 x 2, "
                    "15 s, general driver (models/)", _file("yielding_pair.toml")))
    # added after the first run, in which the row of four (NIVe, Corralitos) missed 0.1 % and 1 %: is it the
    # law, the record or the row?  Every law under Corralitos 000 and under El Centro 180.
    for rec, short, full in (("corralitos_000", "Corralitos", "Corralitos 000"),
                             ("elcentro_180", "El Centro", "El Centro 180")):
        for law in LAWS:
            if (law, rec) == ("NIVe", "corralitos_000"):
                continue
            out.append(Case(f"row of four {law}, {short}",
                            f"the row of four, {law}, {full}, 20 s (added after the first run)",
                            lambda law=law, rec=rec: _row("row of four", ROW4, 0.02, law, rec, 1.0, 20.0)))
    return out


def heldout_cases() -> list[Case]:
    """Cases outside the development set above, written down before the tolerance's rule (the run checked
    by two substep counts) was first run on them, and run once: other records, other e, the yielding
    pair under another record."""
    from benchmarks.peer.cases import PAIR, ROW4

    out = []
    for rec, scale, full in (("corralitos_090", 1.0, "Corralitos 090"), ("elcentro_270", 1.5, "El Centro 270 x 1.5")):
        for law in ("NIVe", "Hd", "LVe"):
            out.append(Case(f"held-out row of four {law}, {full}", f"the row of four, {law}, {full}, 20 s",
                            lambda law=law, rec=rec, scale=scale: _row("row of four", ROW4, 0.02, law, rec, scale,
                                                                       20.0)))
    for law in ("Hd", "LHC"):
        for e in (0.4, 0.85):
            out.append(Case(f"held-out pair {law}, e = {e}", f"3+5 pair, {law}, e = {e}, 1 cm gap, Corralitos 090, 20 s",
                            lambda law=law, e=e: _row(f"pair {law}", PAIR, 0.01, law, "corralitos_090", 1.0, 20.0,
                                                      restitution=e)))

    def yielding():
        model = _file("yielding_pair.toml")()
        model.ground_motion = _record("elcentro_270", 2.0)
        return model

    out.append(Case("held-out yielding pair, El Centro 270", "models/yielding_pair.toml under El Centro 270 x 2",
                    yielding))
    return out


# -- running and measuring ---------------------------------------------------------------------------------

def _with(model, *, substeps=None, dt=None):
    an = model.analysis
    nm = an.newmark if substeps is None else replace(an.newmark, contact_substeps=substeps)
    return replace(model, analysis=replace(an, newmark=nm, dt=an.dt if dt is None else dt))


def _simulate(model, **kw):
    from seispound import simulate

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # plausibility notes (a 2 x record ...): not what is measured here
        return simulate(model, twin=False, **kw)


def peaks(ds, every: int = 1) -> dict:
    """The peaks compared: per gap (over every substep) and per floor (over every ``every``-th analysis instant),
    with what locates them (the impacts; each floor's history, and the contact force on it from its
    floor-to-floor gaps)."""
    present = np.isfinite(ds["acceleration"].values[0])  # (building, floor): the floors there are
    acc = ds["acceleration"].values[::every][:, present]
    disp = np.abs(ds["displacement"].values[::every][:, present])
    names = list(ds["building"].values)
    b, f = np.nonzero(present)
    floors = [f"{names[i]}/{j + 1}" for i, j in zip(b, f)]
    force = ds["pounding_force"].values[::every]
    on_floor = np.zeros((force.shape[1], len(floors)))  # contact force on each floor per unit gap force
    for g in range(force.shape[1]):
        if str(ds["gap_kind"].values[g]) != "floor-to-floor":
            continue
        lf, rf = int(ds["gap_left_floor"].values[g]), int(ds["gap_right_floor"].values[g])
        on_floor[g, floors.index(f"{ds['gap_left'].values[g]}/{lf}")] = -1.0  # compression pushes left apart
        on_floor[g, floors.index(f"{ds['gap_right'].values[g]}/{rf}")] = 1.0
    return dict(force=np.asarray(ds["peak_pounding_force"].values, float),
                acceleration=np.abs(acc).max(axis=0), displacement=disp.max(axis=0),
                impacts=int(ds["impact_count"].values.sum()), floors=floors, acc_history=acc,
                contact_on_floor=force @ on_floor, closed=(force > 0).any(axis=1),
                gap_label=[f"{l}-{r} floor {lf}" for l, r, lf in zip(ds["gap_left"].values, ds["gap_right"].values,
                                                                     ds["gap_left_floor"].values)],
                gap_law=[str(x) for x in ds["gap_law"].values],
                impact=dict(gap=ds["impact_gap"].values, force=ds["impact_peak_force"].values,
                            v0=ds["impact_approach_velocity"].values, onset=ds["impact_onset"].values),
                time=ds["time"].values[::every])


def errors(run: dict, ref: dict) -> dict:
    """Relative errors of ``run``'s peaks against ``ref``'s (see the module docstring)."""
    f, fr = run["force"], ref["force"]
    big = fr.max() if fr.size else 0.0
    out = dict(force_largest=abs(f.max() / big - 1.0) if big > 0 else 0.0)
    sig = fr >= SIGNIFICANT * big if big > 0 else np.zeros(fr.shape, bool)
    out["force_gaps"] = float(np.max(np.abs(f[sig] / fr[sig] - 1.0))) if sig.any() else 0.0
    out["acceleration"] = float(np.max(np.abs(run["acceleration"] / ref["acceleration"] - 1.0)))
    out["displacement"] = float(np.max(np.abs(run["displacement"] / ref["displacement"] - 1.0)))
    out["worst"] = max(out.values())
    out["worst_of"] = max(("force_largest", "force_gaps", "acceleration", "displacement"), key=out.get)
    return out


def locate(run: dict, ref: dict, masses=None) -> dict:
    """Where the worst force and floor errors are, and what they come with.

    The worst gap (of those >= SIGNIFICANT of the largest peak): its share of the largest peak, and the impact
    that gives its peak in each run: the approach velocities' relative difference dv/v and the onset shift.  A
    self-similar impact's peak force goes as v0^(2 p / (p + 1)) (p the law's exponent: v0 for the linear laws,
    v0^1.2 for the Hertz-type ones), so (2 p / (p + 1)) dv/v is the part of the force error the approach alone
    explains.  The worst floor acceleration: its floor, the instants of its peak, whether a gap was closed
    at the reference's instant (a contact spike sampled at an analysis instant), and at that instant the
    difference of the floor's acceleration and of the contact force on the floor over its mass
    (``masses``: per floor, in the order of ``floors``): their ratio is the share the contact force carries.
    """
    from seispound.contact import get_law

    out = {}
    f, fr = run["force"], ref["force"]
    if fr.size and fr.max() > 0:
        sig = np.flatnonzero(fr >= SIGNIFICANT * fr.max())
        g = int(sig[np.argmax(np.abs(f[sig] / fr[sig] - 1.0))])
        p = get_law(ref["gap_law"][g]).exponent

        def at_peak(x):
            sel = np.flatnonzero(x["impact"]["gap"] == g)
            if sel.size == 0:
                return math.nan, math.nan
            i = sel[np.argmax(x["impact"]["force"][sel])]
            return float(x["impact"]["v0"][i]), float(x["impact"]["onset"][i])

        (v, t), (vr, tr) = at_peak(run), at_peak(ref)
        dv = v / vr - 1.0
        out["gap"] = dict(gap=g, where=ref["gap_label"][g], share=float(fr[g] / fr.max()),
                          error=float(f[g] / fr[g] - 1.0), v0_error=dv, explained_by_v0=2 * p / (p + 1) * dv,
                          onset_shift_s=t - tr, impacts_ref=int((ref["impact"]["gap"] == g).sum()))
    k = int(np.argmax(np.abs(run["acceleration"] / ref["acceleration"] - 1.0)))
    i = int(np.argmax(np.abs(ref["acc_history"][:, k])))  # the reference's instant of that floor's peak
    j = int(np.argmax(np.abs(run["acc_history"][:, k])))
    da = run["acc_history"][i, k] - ref["acc_history"][i, k]  # the difference at the reference's instant
    dfc = run["contact_on_floor"][i, k] - ref["contact_on_floor"][i, k]  # of the contact force on the floor
    out["floor"] = dict(floor=ref["floors"][k], error=float(run["acceleration"][k] / ref["acceleration"][k] - 1.0),
                        time_ref=float(ref["time"][i]), time_run=float(run["time"][j]),
                        in_contact_ref=bool(ref["closed"][i]), contact_on_floor_ref=bool(ref["contact_on_floor"][i, k]),
                        accel_diff=float(da), contact_force_diff=float(dfc))
    if masses is not None:
        out["floor"]["contact_share"] = float(dfc / masses[k] / da) if da else math.nan
    return out


def reference(model, name: str) -> dict:
    """The converged reference of ``model`` (1024 substeps, at dt / REFERENCE_DT_DIVISOR) with its peaks, and its
    checks: 512 and 2048 substeps, and a quarter of its step; ``converged`` when all are within CONVERGED."""
    every = REFERENCE_DT_DIVISOR.get(name, 1)
    ref_dt = model.analysis.dt / every
    t0 = time.perf_counter()
    ds = _simulate(_with(model, substeps=REFERENCE_SUBSTEPS, dt=ref_dt))
    seconds = time.perf_counter() - t0
    ref = peaks(ds, every)
    checks = {n: errors(peaks(_simulate(_with(model, substeps=n, dt=ref_dt)), every), ref) for n in CHECK_SUBSTEPS}
    quarter = errors(peaks(_simulate(_with(model, substeps=REFERENCE_SUBSTEPS, dt=ref_dt / 4)), 4 * every), ref)
    # the error of the reference's substeps at the model's own step: what its dt alone costs
    at_dt = errors(peaks(_simulate(_with(model, substeps=REFERENCE_SUBSTEPS))), ref) if every > 1 else None
    worst_check = max([e["worst"] for e in checks.values()] + [quarter["worst"]])
    return dict(peaks=ref, dt=ref_dt, model_dt=model.analysis.dt, substeps=REFERENCE_SUBSTEPS, seconds=seconds,
                laws=sorted({str(x) for x in ds["gap_law"].values}), driver=ds.attrs["driver"],
                newmark_substeps=int(ds.attrs["newmark_substeps"]), n_gap=int(ds.sizes["gap"]),
                gaps_hit=int((ref["force"] > 0).sum()), check_substeps={str(n): e for n, e in checks.items()},
                check_dt=quarter, check_dt_value=ref_dt / 4, worst_check=worst_check,
                converged=bool(worst_check <= CONVERGED), model_dt_error=at_dt)


def estimate_cost(model, tol: float) -> float:
    """Seconds the error estimate costs a fresh process (``seispound.accuracy`` keeps its impacts per process)."""
    from seispound import accuracy

    saved = dict(accuracy._OUTCOMES), dict(accuracy._ERRORS)
    accuracy._OUTCOMES.clear()
    accuracy._ERRORS.clear()
    laws = [g.law or model.contact for g in model.gaps]
    t0 = time.perf_counter()
    accuracy.choose_contact_substeps([law for law in laws if law is not None], tol)
    seconds = time.perf_counter() - t0
    for kept, was in zip((accuracy._OUTCOMES, accuracy._ERRORS), saved):
        kept.clear()
        kept.update(was)
    return seconds


def measure(case: Case, tolerances=TOLERANCES, repeat: int = 5) -> dict:
    """The reference, and per tolerance: substeps, estimate, errors, cost."""
    model = case.model()
    ref = reference(model, case.name)
    masses = np.concatenate([np.asarray(b.floor_masses, float) for b in model.buildings])  # in peaks' floor order
    runs = {}
    for tol in tolerances:
        ds = _simulate(model, tolerance=tol)
        p = peaks(ds)
        runs[tol] = dict(tolerance=tol, substeps=int(ds.attrs["contact_substeps"]),
                         substeps_from=ds.attrs["contact_substeps_from"],
                         estimate=float(ds.attrs["contact_error_estimate"]),
                         peak_estimate=float(ds.attrs.get("peak_error_estimate", math.nan)),
                         runs=int(ds.attrs.get("tolerance_runs", 1)),
                         attr_tolerance=float(ds.attrs["tolerance"]), impacts=p["impacts"], **errors(p, ref["peaks"]),
                         located=locate(p, ref["peaks"], masses), estimate_s=estimate_cost(model, tol),
                         steps=int(json.loads(ds.attrs["integrator_stats"])["steps"]))
        runs[tol]["error_over_estimate"] = runs[tol]["worst"] / runs[tol]["estimate"]
        runs[tol]["error_over_peak_estimate"] = (runs[tol]["worst"] / runs[tol]["peak_estimate"]
                                                 if runs[tol]["peak_estimate"] > 0 else math.nan)
        runs[tol]["within"] = bool(runs[tol]["worst"] <= tol)
    times = {tol: [] for tol in tolerances}
    order = np.random.default_rng(0)
    for _ in range(repeat):  # interleaved, in a new order each round: a load that comes and goes hits all alike
        for tol in order.permutation(tolerances).tolist():
            t0 = time.perf_counter()
            _simulate(model, tolerance=tol)
            times[tol].append(time.perf_counter() - t0)
    base = times.get(0.01)
    for tol in tolerances:
        runs[tol]["seconds"] = statistics.median(times[tol])
        # the median over the rounds of the time over the same round's 1 % run: a load that lasts a round
        # slows both (the ratio of the medians mixes rounds)
        runs[tol]["cost_ratio"] = statistics.median(t / b for t, b in zip(times[tol], base)) if base else math.nan
        runs[tol]["steps_ratio"] = runs[tol]["steps"] / runs[0.01]["steps"] if 0.01 in runs else math.nan
    ref_out = {k: v for k, v in ref.items() if k != "peaks"}
    ref_out["impacts"] = ref["peaks"]["impacts"]
    return dict(case=case.name, what=case.what, reference=ref_out, runs=[runs[t] for t in tolerances])


# -- report ----------------------------------------------------------------------------------------------

def _pct(x):
    if not math.isfinite(x):
        return "-"
    return f"{100 * x:.3g}%" if x >= 1e-5 else ("0" if x == 0 else f"{100 * x:.1e}%")


def _spread(xs) -> str:
    return f"{statistics.median(xs):.2f} ({min(xs):.2f}-{max(xs):.2f})"


def _failures(report: dict) -> list:
    return [(c, r) for c in report["cases"] for r in c["runs"] if not r["within"]]


def markdown(report: dict) -> str:
    lines = ["| case | tolerance | substeps (runs) | impact estimate | peaks estimate | force err (largest) | "
             "force err (gaps >= 10 %) | floor accel err | floor disp err | within? | error / peaks estimate | "
             "cost vs 1 % | steps vs 1 % | impacts (ref) |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for c in report["cases"]:
        for r in c["runs"]:
            lines.append(f"| {c['case']} | {_pct(r['tolerance'])} | {r['substeps']} ({r.get('runs', 1)}) | "
                         f"{_pct(r['estimate'])} | {_pct(r.get('peak_estimate', math.nan))} | "
                         f"{_pct(r['force_largest'])} | {_pct(r['force_gaps'])} | {_pct(r['acceleration'])} | "
                         f"{_pct(r['displacement'])} | {'yes' if r['within'] else '**no**'} | "
                         f"{r.get('error_over_peak_estimate', math.nan):.2g} | {r['cost_ratio']:.2f} | "
                         f"{r['steps_ratio']:.2f} | {r['impacts']} ({c['reference']['impacts']}) |")
    lines += ["", "| tolerance | cases within | worst error / tolerance | cost vs 1 %: median (range) | "
                  "steps vs 1 %: median (range) | one-off estimate vs the run: median (range) |",
              "|---|---|---|---|---|---|"]
    for i, tol in enumerate(report["tolerances"]):
        rs = [c["runs"][i] for c in report["cases"]]
        cost, steps = [r["cost_ratio"] for r in rs], [r["steps_ratio"] for r in rs]
        est = [r["estimate_s"] / r["seconds"] for r in rs]
        lines.append(f"| {_pct(tol)} | {sum(r['within'] for r in rs)} of {len(rs)} | "
                     f"{max(r['worst'] for r in rs) / tol:.2f} | {_spread(cost)} | {_spread(steps)} | {_spread(est)} |")
    lines += ["", "| case | tolerance | worst | worst gap (share of largest peak) | its error | approach "
                  "velocity dv/v | part explained by dv/v | onset shift | worst floor accel | at t (ref) | "
                  "a gap at that floor closed then | share of the accel difference from the contact force |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for c, r in _failures(report):
        g, fl = r["located"].get("gap"), r["located"]["floor"]
        gap = (f"{g['where']} ({g['share']:.2f}) | {g['error'] * 100:+.3g}% | {g['v0_error'] * 100:+.3g}% | "
               f"{g['explained_by_v0'] * 100:+.3g}% | {g['onset_shift_s'] * 1e3:+.2g} ms") if g else "- | - | - | - | -"
        share = fl.get("contact_share", math.nan)
        lines.append(f"| {c['case']} | {_pct(r['tolerance'])} | {r['worst_of']} | {gap} | {fl['floor']} "
                     f"{fl['error'] * 100:+.3g}% | {fl['time_ref']:.3f} s | "
                     f"{'yes' if fl['contact_on_floor_ref'] else 'no'} | {share:.2f} |")
    lines += ["", "| case | driver | model dt | reference dt | gaps hit / gaps | 1024 vs 512 substeps | "
                  "1024 vs 2048 | reference dt vs its quarter | converged? |",
              "|---|---|---|---|---|---|---|---|---|"]
    for c in report["cases"]:
        ref = c["reference"]
        chk = [ref["check_substeps"][str(n)] for n in CHECK_SUBSTEPS] + [ref["check_dt"]]
        lines.append(f"| {c['case']} | {ref['driver']} | {ref['model_dt'] * 1e3:g} ms | {ref['dt'] * 1e3:g} ms | "
                     f"{ref['gaps_hit']} / {ref['n_gap']} | "
                     + " | ".join(f"{_pct(e['worst'])} ({e['worst_of']})" for e in chk)
                     + f" | {'yes' if ref['converged'] else '**no**'} |")
    for c in report["cases"]:
        e = c["reference"]["model_dt_error"]
        if e:
            lines.append(f"\n{c['case']}: 1024 substeps at the model's dt ({c['reference']['model_dt'] * 1e3:g} ms) "
                         f"against the reference: force (largest) {_pct(e['force_largest'])}, force (gaps) "
                         f"{_pct(e['force_gaps'])}, floor accel {_pct(e['acceleration'])}, floor disp "
                         f"{_pct(e['displacement'])}.")
    return "\n".join(lines)


def text(report: dict) -> str:
    head = (f"{'case':26s} {'tol':>6s} {'n':>4s} {'estimate':>9s} {'F max':>8s} {'F gaps':>8s} {'acc':>8s} "
            f"{'disp':>8s} {'within':>6s} {'err/est':>7s} {'ms':>8s} {'cost':>6s}")
    lines = [head]
    for c in report["cases"]:
        ref = c["reference"]
        for r in c["runs"]:
            lines.append(f"{c['case'][:26]:26s} {r['tolerance']:6.3f} {r['substeps']:4d} {_pct(r['estimate']):>9s} "
                         f"{_pct(r['force_largest']):>8s} {_pct(r['force_gaps']):>8s} {_pct(r['acceleration']):>8s} "
                         f"{_pct(r['displacement']):>8s} {'yes' if r['within'] else 'NO':>6s} "
                         f"{r['error_over_estimate']:7.2g} {1e3 * r['seconds']:8.1f} {r['cost_ratio']:6.2f}")
        lines.append(f"{'':26s} reference: {ref['substeps']} substeps at dt {ref['dt']:g} s ({ref['driver']}), "
                     f"{ref['impacts']} impacts; "
                     + ", ".join(f"vs {n}: {_pct(ref['check_substeps'][str(n)]['worst'])}" for n in CHECK_SUBSTEPS)
                     + f", vs dt/4: {_pct(ref['check_dt']['worst'])}")
    return "\n".join(lines)


def _group(name: str) -> str:
    for g in ("strong pair", "weak pair", "row of four", "quick"):
        if name.startswith(g):
            return g
    return name


def figure(report: dict, path) -> None:
    """Error reached vs tolerance asked (log-log, with error = tolerance), cost and steps vs tolerance."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    fig, (ax, bx, cx) = plt.subplots(1, 3, figsize=(15, 5.2))
    tols = np.array(report["tolerances"])
    groups = list(dict.fromkeys(_group(c["case"]) for c in report["cases"]))
    colour = {g: plt.cm.tab10(i % 10) for i, g in enumerate(groups)}
    marker = dict(zip(LAWS, "os^Dv"))
    n = len(report["cases"])
    for i, c in enumerate(report["cases"]):
        t = np.array([r["tolerance"] for r in c["runs"]]) * (1.0 + 0.25 * (i - n / 2) / n)  # spread the points
        law = c["reference"]["laws"][0] if len(c["reference"]["laws"]) == 1 else ""
        style = dict(color=colour[_group(c["case"])], marker=marker.get(law, "x"), ls="-", lw=0.7, ms=5, alpha=0.85)
        ax.loglog(t, [max(r["worst"], 1e-7) for r in c["runs"]], **style)
        bx.semilogx(t, [r["cost_ratio"] for r in c["runs"]], **style)
        cx.semilogx(t, [r["steps_ratio"] for r in c["runs"]], **style)
    ax.loglog(tols, tols, "k--", lw=1.3)
    ax.set_xlabel("tolerance asked")
    ax.set_ylabel("error reached: worst of peak force and floor peaks")
    ax.set_title("error against the converged reference")
    bx.set_xlabel("tolerance asked")
    bx.set_ylabel(f"time / time at 1 %  (median over {report['repeat']} rounds of warm runs)")
    bx.set_title("cost of simulate(model, twin=False, tolerance=...)")
    cx.set_xlabel("tolerance asked")
    cx.set_ylabel("integration steps / steps at 1 %")
    cx.set_title("steps taken (independent of load)")
    for x in (ax, bx, cx):
        x.grid(True, which="both", alpha=0.3)
        x.set_xticks(tols, [f"{100 * t:g} %" for t in tols])
    for x in (bx, cx):
        x.axhline(1.0, color="k", lw=0.6)
    handles = [Line2D([], [], color=colour[g], lw=2, label=g) for g in groups]
    handles += [Line2D([], [], color="grey", marker=m, ls="", label=law) for law, m in marker.items()]
    handles.append(Line2D([], [], color="k", ls="--", label="error = tolerance"))
    fig.legend(handles=handles, fontsize=8, loc="lower center", ncol=len(handles), frameon=False)
    fig.tight_layout(rect=(0, 0.06, 1, 1))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def run(quick: bool = False, repeat: int = 5, only=None, progress=None, heldout: bool = False) -> dict:
    import seispound

    out = []
    for case in (heldout_cases() if heldout else cases(quick)):
        if only and not any(s.lower() in case.name.lower() for s in only):
            continue
        out.append(measure(case, repeat=repeat))
        if progress:
            progress(f"{case.name}: done")
    return dict(benchmark="tolerance", set="held-out" if heldout else "development", quick=quick, repeat=repeat, tolerances=list(TOLERANCES),
                reference_substeps=REFERENCE_SUBSTEPS, check_substeps=CHECK_SUBSTEPS, significant=SIGNIFICANT,
                converged=CONVERGED, seispound=seispound.__file__, python=sys.version.split()[0], cases=out)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.tolerance", description=__doc__.splitlines()[0],
                                 epilog="Cases: " + "; ".join(c.name for c in cases()))
    ap.add_argument("--quick", action="store_true", help="two short strong pairs, two repeats (a smoke run)")
    ap.add_argument("--repeat", type=int, default=None, help="timed repeats per tolerance (default 5; quick 2)")
    ap.add_argument("--case", action="append", help="run only cases whose name contains this (repeatable)")
    ap.add_argument("--json", metavar="PATH", help="write the report as JSON to PATH ('-': stdout)")
    ap.add_argument("--figure", metavar="PATH", help="draw the figure to PATH (PNG)")
    ap.add_argument("--markdown", action="store_true", help="print the markdown tables of docs/tolerance.md")
    ap.add_argument("--heldout", action="store_true", help="the held-out cases (run once, after the rule was frozen)")
    args = ap.parse_args(argv)
    repeat = args.repeat or (2 if args.quick else 5)
    report = run(args.quick, repeat, args.case, progress=lambda s: print(s, file=sys.stderr, flush=True),
                 heldout=args.heldout)
    if args.json == "-":
        print(json.dumps(report, indent=1))
    else:
        print(markdown(report) if args.markdown else text(report))
        if args.json:
            Path(args.json).write_text(json.dumps(report, indent=1) + "\n")
    if args.figure:
        figure(report, args.figure)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
