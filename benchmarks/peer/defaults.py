"""seispound at its defaults against OpenSeesPy at equal accuracy: the whole call, and what bounds the ratio.

``python -m benchmarks.peer.defaults [--repeat 5] [--only TEXT] [--out docs/peer_defaults.json]``; then
``python -m benchmarks.peer.report`` writes the section "At the defaults" of ``docs/peer.md``.
``--quick``: a smoke run (the pair for 4 s, OpenSees' reference at 2.5e-4 s, one repeat).

seispound gets nothing but the model and the record: the peer case's buildings, gaps and law
(``benchmarks.peer.cases``), the record as samples in memory (after the peer cases' zero sample),
the analysis step equal to the record's own step, and no ``contact_substeps`` and no tolerance,
so that ``simulate(model, twin=False)`` picks its contact substeps from the default tolerance
(1 %) and checks the run by rerunning it with every step twice as long (``simulation.run_row``).
Its peak pounding force is checked against the reference (OpenSees at its finest step,
6.25e-5 s, as in ``benchmarks.peer.userpath``; seispound's own fine run, 1 ms / 256 contact
substeps, is reported beside it).  OpenSeesPy runs at the coarsest of 5, 2, 1 and 0.5 ms whose
peak force, and that of every finer step of its grid, lies within 1 % of its own reference
(``userpath.coarsest_stable_within``); it is timed as in ``userpath`` (``wipe``, model build,
``Path`` series from memory, ``analyze``, no recorders).

Timed, the two programs alternating in one process (each seispound call right after an OpenSees
one, so that every call finds the caches as the other program left them), medians of ``--repeat``:

* ``simulate(model, twin=False)`` at the defaults (the headline);
* the same call with the contact substeps the check ended at given in the model (one run, no
  check), so that the check's overhead shows;
* ``integrate`` alone at the settings of the run the check ended at (the kernel);
* one instrumented default call, whose parts are timed by wrappers around the functions
  ``simulate`` calls: each integration (the final one, the check's others), the peak comparison,
  validation/assembly with the record's preparation (``_run_inputs``), the plausibility checks,
  the result Dataset (``build_dataset``), and the rest;
* the first call a user makes with a new model in a process (numba's kernels already loaded):
  a newly built model, the record's preparation and the isolated-impact estimates not yet kept.

The ratio OpenSees / seispound is then recomputed with each part removed from the instrumented call.
"""

from __future__ import annotations

import argparse
import functools
import json
import statistics
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from .cases import PAIR, ROW4, PeerCase, kobe_nis090
from .opensees import run_opensees
from .userpath import WITHIN, coarsest_stable_within, time_opensees

OPENSEES_STEPS = (5e-3, 2e-3, 1e-3, 5e-4, 2.5e-4, 1.25e-4, 6.25e-5)
#: the steps OpenSees may be timed at (the issue's); finer ones only refine its reference
OPENSEES_PICKABLE = (5e-3, 2e-3, 1e-3, 5e-4)
#: seispound's own converged run: analysis step [s], contact substeps
SEISPOUND_FINE = (0.001, 256)


def cases(duration: float = 20.0) -> list[PeerCase]:
    """The issue's cases (the pair with a 1 cm gap under El Centro 180, NIVe and LVe; the row of four
    10-storey buildings with 2 cm gaps under 1.5 x El Centro 180 for 30 s), then the rest of
    ``benchmarks.peer.userpath``'s cases."""
    kobe = kobe_nis090()
    return [
        PeerCase("pair 3+5, El Centro 180, NIVe", PAIR, 0.01, "NIVe", "elcentro_180", duration),
        PeerCase("pair 3+5, El Centro 180, LVe", PAIR, 0.01, "LVe", "elcentro_180", duration),
        PeerCase("row of four 10-storey, El Centro 180 x1.5, 30 s, NIVe", ROW4, 0.02, "NIVe", "elcentro_180",
                 30.0, scale=1.5),
        PeerCase("pair 3+5, El Centro 180 x2, 5 mm gap, 40 s, NIVe", PAIR, 0.005, "NIVe", "elcentro_180",
                 2 * duration, scale=2.0),
        PeerCase("row of four 10-storey, El Centro 180, NIVe", ROW4, 0.02, "NIVe", "elcentro_180", duration),
        PeerCase("row of four 10-storey, Kobe NIS090 x1.5, NIVe", ROW4, 0.02, "NIVe", kobe, duration, scale=1.5),
    ]


def quick_cases() -> list[PeerCase]:
    """A smoke run: the pair under the first 4 s of El Centro (a few impacts)."""
    return [PeerCase("quick pair 3+5, El Centro 180, 4 s, NIVe", PAIR, 0.01, "NIVe", "elcentro_180", 4.0)]


def default_model(case: PeerCase, substeps: int | None = None, dt: float | None = None):
    """The case as a user gives it: the record (after the zero sample) as samples in memory, the analysis step
    the record's own, nothing else set (``substeps``: contact substeps given in the model; ``dt``: another step)."""
    from seispound.integrate import Newmark
    from seispound.model.spec import GroundMotionSpec
    from seispound.motion import read_record

    rec = read_record(case.record_path(), scale=case.scale)
    acc = np.concatenate([[0.0], np.asarray(rec.acceleration)])
    model = case.model(dt or rec.dt, Newmark(contact_substeps=substeps))
    return replace(model, ground_motion=GroundMotionSpec.from_array(acc, rec.dt, units="m/s2", name=case.record))


def simulate_timed(model):
    """(seconds, Dataset) of ``simulate(model, twin=False)``."""
    import seispound as sp

    t0 = time.perf_counter()
    ds = sp.simulate(model, twin=False)
    return time.perf_counter() - t0, ds


# -- the parts of one call -------------------------------------------------------------------------------------

#: (module, attribute, part): the functions ``simulate`` reaches through a module attribute at call time
PARTS = (
    ("seispound.simulation", "_run_inputs", "validation, assembly, record"),
    ("seispound.simulation", "contact_substeps", "substeps from the law"),
    ("seispound.simulation", "impact_error_of", "substeps from the law"),
    ("seispound.simulation", "_peak_change", "check: peak comparison"),
    ("seispound.simulation", "_check_finite", "finite check"),
    ("seispound.plausibility", "check_model", "plausibility"),
    ("seispound.plausibility", "check_before_run", "plausibility"),
    ("seispound.plausibility", "check_after_run", "plausibility"),
    ("seispound.plausibility", "issue", "plausibility"),
    ("seispound.plausibility", "to_json", "plausibility"),
    ("seispound.results", "build_dataset", "Dataset"),
)


def simulate_split(model) -> tuple[float, dict, list, object]:
    """One default call with its parts timed: (total seconds, seconds per part, the integrations as
    [(contact substeps, Newmark substeps, contact step limit, seconds)], Dataset).

    Wrappers around the module attributes ``simulate`` reads (``PARTS``) and around ``integrate`` in
    ``seispound.simulation``; each adds one ``perf_counter`` pair (about 0.1 us)."""
    import importlib

    import seispound.simulation as sim

    parts: dict = {}
    runs: list = []
    saved = []

    def wrap(mod, name, part):
        f = getattr(mod, name)
        saved.append((mod, name, f))

        @functools.wraps(f)
        def timed(*a, **k):
            t0 = time.perf_counter()
            try:
                return f(*a, **k)
            finally:
                parts[part] = parts.get(part, 0.0) + time.perf_counter() - t0
        setattr(mod, name, timed)

    f_int = sim.integrate

    def integrate_timed(system, rows, dt, nsteps, newmark, **k):
        t0 = time.perf_counter()
        raw = f_int(system, rows, dt, nsteps, newmark, **k)
        runs.append((int(newmark.contact_substeps), int(k.get("substeps") or 1), float(k.get("contact_step")),
                     time.perf_counter() - t0))
        return raw

    try:
        for modname, name, part in PARTS:
            wrap(importlib.import_module(modname), name, part)
        saved.append((sim, "integrate", f_int))
        sim.integrate = integrate_timed
        total, ds = simulate_timed(model)
    finally:
        for mod, name, f in reversed(saved):
            setattr(mod, name, f)
    return total, parts, runs, ds


def kernel_timed(model, settings, contact: bool = True) -> float:
    """Wall time of ``integrate`` alone at ``settings`` = (contact substeps, Newmark substeps, contact step
    limit) with histories, as ``run_row`` calls it (after validation, assembly and the record's preparation);
    ``contact`` False: the row with its gaps disabled (the no-pounding twin's system)."""
    from seispound.integrate import integrate
    from seispound.simulation import run_inputs

    system, motions = run_inputs(model)
    if not contact:
        system = system.without_contact()
    an = model.analysis
    nm = replace(an.newmark, contact_substeps=settings[0])
    t0 = time.perf_counter()
    integrate(system, motions.rows, an.dt, an.nsteps, nm, scheme=an.scheme, store_history=True,
              substeps=settings[1], contact_step=settings[2])
    return time.perf_counter() - t0


def first_call_timed(case: PeerCase) -> float:
    """A user's first ``simulate`` of a new model in a process whose kernels are loaded: the model built
    afresh (nothing kept on it), the record's preparation and the isolated-impact estimates forgotten."""
    import seispound.accuracy as acc
    import seispound.simulation as sim

    model = default_model(case)
    acc._OUTCOMES.clear()
    sim._samples_prepared.cache_clear()
    sim._read_prepared.cache_clear()
    return simulate_timed(model)[0]


def check_changes(model, runs) -> list[dict]:
    """What the check saw: for each pair of its runs (in substeps, the finer against the coarser), the largest
    relative change of each kind of peak it compares (``simulation.peak_values``: every gap's peak force at
    least a tenth of the largest, every DOF's peak displacement and absolute acceleration at least 1e-3 of
    the largest), and of the largest peak force alone (the benchmark's measure).  Recomputed, not timed."""
    from seispound.integrate import integrate
    from seispound.simulation import peak_values, run_inputs

    system, motions = run_inputs(model)
    an = model.analysis
    raws = {}
    for r in sorted(runs, key=lambda r: r["contact_substeps"]):
        nm = replace(an.newmark, contact_substeps=r["contact_substeps"])
        raws[r["contact_substeps"]] = integrate(system, motions.rows, an.dt, an.nsteps, nm, scheme=an.scheme,
                                                substeps=r["newmark_substeps"], contact_step=r["contact_step"])
    out = []
    ns = sorted(raws)
    for coarse, fine in zip(ns, ns[1:]):
        row = dict(fine=fine, coarse=coarse)
        for kind, (q1, floor), (q0, _) in zip(("force", "displacement", "acceleration"), peak_values(raws[fine]),
                                             peak_values(raws[coarse])):
            keep = q1 >= floor
            row[kind] = float(np.max(np.abs(q1[keep] - q0[keep]) / q1[keep])) if keep.any() and floor > 0 else 0.0
        f1, f0 = raws[fine].peak_force.max(), raws[coarse].peak_force.max()
        row["largest_force"] = float(abs(f1 - f0) / f1)
        out.append(row)
    return out


# -- one case --------------------------------------------------------------------------------------------------

def opensees_grid(case: PeerCase, steps=OPENSEES_STEPS) -> list[dict]:
    """Peak pounding force of OpenSees at each step (binary recorders, not timed)."""
    rows = []
    for dt in steps:
        ag, n = case.ground(dt)
        t0 = time.perf_counter()
        try:
            r = run_opensees(case.model(dt), ag, dt, n)
        except RuntimeError as err:  # an unstable coarse step is reported, not picked
            rows.append(dict(dt=dt, failed=str(err)))
            continue
        rows.append(dict(dt=dt, peak_force=float(r.peak_force.max(initial=0.0)), impacts=int(r.impacts.sum()),
                         unconverged=int(r.unconverged_steps), seconds=time.perf_counter() - t0))
    return rows


def run_case(case: PeerCase, repeat: int, steps=OPENSEES_STEPS) -> dict:
    """OpenSees' grid and pick, seispound's default call and its parts, timed alternately."""
    med = statistics.median
    os_rows = opensees_grid(case, steps)
    good = [r for r in os_rows if "peak_force" in r]
    reference = good[-1]["peak_force"]
    halving = abs(good[-1]["peak_force"] - good[-2]["peak_force"]) / reference if len(good) > 1 else float("nan")
    os_pick = coarsest_stable_within(good, reference)
    if os_pick is None:  # none passes: its finest step, flagged
        os_pick = dict(good[-1], within=False)
    pickable = os_pick["dt"] in OPENSEES_PICKABLE

    model = default_model(case)
    _, ds = simulate_timed(model)  # untimed: the kept assembly, record and estimates as in a user's second call
    a = ds.attrs
    n_final = int(a["contact_substeps"])
    final = (n_final, int(a["newmark_substeps"]), float(a["contact_step_limit"]))
    peak = float(ds["peak_pounding_force"].max())
    _, ds_fine = simulate_timed(default_model(case, substeps=SEISPOUND_FINE[1], dt=SEISPOUND_FINE[0]))
    fine = float(ds_fine["peak_pounding_force"].max())
    single = default_model(case, substeps=n_final)
    _, ds_single = simulate_timed(single)
    t_os, t_sp, t_one, t_k, t_nc, t_split, t_first, split_parts, split_runs = [], [], [], [], [], [], [], [], []
    for _ in range(repeat):  # every seispound call right after an OpenSees one: each finds the same state
        t_os.append(time_opensees(case, os_pick["dt"]))
        t_sp.append(simulate_timed(model)[0])
        t_os.append(time_opensees(case, os_pick["dt"]))
        t_one.append(simulate_timed(single)[0])
        t_os.append(time_opensees(case, os_pick["dt"]))
        t_k.append(kernel_timed(model, final))
        t_nc.append(kernel_timed(model, final, contact=False))
        t_os.append(time_opensees(case, os_pick["dt"]))
        total, parts, runs, _ = simulate_split(model)
        t_split.append(total)
        split_parts.append(parts)
        split_runs.append(runs)
        t_os.append(time_opensees(case, os_pick["dt"]))
        t_first.append(first_call_timed(case))
    # each repeat's split: the final run's kernel, the check's other integrations, the Python around them
    # (the total less every integration) and its parts, the rest unaccounted; medians over the repeats
    n_runs = len(split_runs[0])
    i_final = max(i for i, r in enumerate(split_runs[0]) if r[0] == n_final)
    per_repeat = []
    for total, parts, runs in zip(t_split, split_parts, split_runs):
        kernels = [r[3] for r in runs]
        python = total - sum(kernels)
        row = dict(total=total, kernel_final=kernels[i_final], kernel_check=sum(kernels) - kernels[i_final],
                   python=python, **parts)
        row["rest (simulate's own lines)"] = python - sum(parts.values())
        per_repeat.append(row)
    keys = list(dict.fromkeys(k for row in per_repeat for k in row))
    split = {k: med(row.get(k, 0.0) for row in per_repeat) for k in keys}
    runs = [dict(contact_substeps=r[0], newmark_substeps=r[1], contact_step=r[2],
                 seconds=med(rr[i][3] for rr in split_runs), final=i == i_final)
            for i, r in enumerate(split_runs[0])]
    assert all(len(rr) == n_runs for rr in split_runs)
    kernel_final, kernel_check, python = split["kernel_final"], split["kernel_check"], split["python"]
    parts = {k: v for k, v in split.items() if k not in ("total", "kernel_final", "kernel_check", "python")}
    T_os, T_sp, T_split = med(t_os), med(t_sp), split["total"]
    # the removals are taken from the split call's own total, so that the parts add up to what they are taken from
    ratio = {
        "as is": T_os / T_sp,
        "as is (the split call)": T_os / T_split,
        "without the check's extra integrations": T_os / (T_split - kernel_check),
        "without the Python around the kernels": T_os / (T_split - python),
        "kernel of the final run only": T_os / kernel_final,
        "kernel of the cheapest run made (the check's coarse one)": T_os / min(r["seconds"] for r in runs),
        "single run at the final substeps (simulate, substeps given)": T_os / med(t_one),
        "integrate alone at the final settings": T_os / med(t_k),
        "first call with a new model": T_os / med(t_first),
    }
    for p, s in parts.items():
        ratio[f"without {p}"] = T_os / (T_split - s)
    return dict(
        case=case.name, duration=case.duration, record_dt=float(model.analysis.dt),
        reference_peak_force=reference, reference_dt=good[-1]["dt"], reference_last_halving=halving,
        opensees_grid=os_rows, opensees=os_pick, opensees_pick_in_issue_grid=pickable,
        seispound=dict(contact_substeps=n_final, tolerance_runs=int(a["tolerance_runs"]),
                       peak_error_estimate=float(a["peak_error_estimate"]),
                       contact_error_estimate=float(a["contact_error_estimate"]),
                       newmark_substeps=final[1], contact_step_limit=final[2], driver=a["driver"],
                       peak_force=peak, error=(peak - reference) / reference,
                       within=abs(peak - reference) <= WITHIN * reference, impacts=int(ds["impact_count"].sum()),
                       fine_peak_force=fine, error_vs_fine=(peak - fine) / fine,
                       single_run_peak_force=float(ds_single["peak_pounding_force"].max()),
                       single_run_error=(float(ds_single["peak_pounding_force"].max()) - reference) / reference,
                       single_run_same=bool(np.array_equal(ds_single["peak_pounding_force"].values,
                                                           ds["peak_pounding_force"].values)),
                       single_run_gap_peaks_differ=_largest_change(ds_single["peak_pounding_force"].values,
                                                                   ds["peak_pounding_force"].values)),
        opensees_s=T_os, seispound_s=T_sp, single_run_s=med(t_one), kernel_s=med(t_k), first_call_s=med(t_first),
        check_changes=check_changes(model, runs),
        split=dict(total_s=split["total"], kernel_final_s=kernel_final, kernel_check_s=kernel_check,
                   python_s=python, parts_s=parts, runs=runs),
        kernel_no_contact_s=med(t_nc), per_impact_s=(med(t_k) - med(t_nc)) / max(int(ds["impact_count"].sum()), 1),
        ratio=ratio, target_seispound_s=T_os / 100.0,
        fastest=dict(opensees_s=min(t_os), seispound_s=min(t_sp), split_total_s=min(t_split), kernel_s=min(t_k),
                     ratio=min(t_os) / min(t_sp)),  # the least disturbed repeats (the machine is shared)
        samples=dict(opensees=t_os, seispound=t_sp, single_run=t_one, kernel=t_k, kernel_no_contact=t_nc,
                     split_total=t_split,
                     first_call=t_first),
    )


def _largest_change(a, b) -> float:
    """Largest |a - b| / b over the gaps whose peak force b is at least a tenth of the largest."""
    a, b = np.asarray(a, float).ravel(), np.asarray(b, float).ravel()
    keep = b >= 0.1 * b.max(initial=0.0)
    return float(np.max(np.abs(a[keep] - b[keep]) / b[keep])) if keep.any() and b.max() > 0 else 0.0


def line(r: dict) -> str:
    s, sp = r["split"], r["seispound"]
    return (f"{r['case']}: OpenSees {r['opensees_s']:.3f} s at dt {r['opensees']['dt']:g}; seispound "
            f"{r['seispound_s'] * 1e3:.2f} ms ({sp['contact_substeps']} substeps, {sp['tolerance_runs']} runs, "
            f"error {sp['error']:+.2%}): {r['ratio']['as is']:.0f}x; single run {r['single_run_s'] * 1e3:.2f} ms, "
            f"kernel {r['kernel_s'] * 1e3:.2f} ms; split: final kernel {s['kernel_final_s'] * 1e3:.2f}, check "
            f"{s['kernel_check_s'] * 1e3:.2f}, Python {s['python_s'] * 1e3:.2f} ms")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.peer.defaults", description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=None, help="timed repeats per case (medians; default 5, 1 with --quick)")
    ap.add_argument("--duration", type=float, default=20.0,
                    help="s of record for the cases of benchmarks.peer.userpath (the row x1.5 runs 30 s)")
    ap.add_argument("--only", default=None, help="run the cases whose name contains this text")
    ap.add_argument("--quick", action="store_true",
                    help="smoke run: the pair for 4 s, OpenSees' reference at 2.5e-4 s, 1 repeat")
    ap.add_argument("--out", default="docs/peer_defaults.json")
    args = ap.parse_args(argv)
    if args.quick:
        todo, steps, repeat = quick_cases(), OPENSEES_STEPS[:5], args.repeat or 1
    else:
        todo, steps, repeat = cases(args.duration), OPENSEES_STEPS, args.repeat or 5
    simulate_timed(default_model(quick_cases()[0]))  # numba's kernels loaded before anything is timed
    rows = []
    t0 = time.perf_counter()
    for case in todo:
        if args.only and args.only not in case.name:
            continue
        r = run_case(case, repeat, steps)
        rows.append(r)
        print(line(r), flush=True)
    out = Path(args.out)
    out.write_text(json.dumps(dict(quick=args.quick, duration=args.duration, repeat=repeat, within=WITHIN,
                                   opensees_steps=list(steps), seispound_fine=list(SEISPOUND_FINE), cases=rows,
                                   seconds=time.perf_counter() - t0), indent=1))
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
