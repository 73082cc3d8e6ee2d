"""How long one diagnosis takes: ``python -m benchmarks.diagnose.speed [--families none,inelastic-storey] [--forms]``.

The issue's case: a two-building recording of 30 s at 200 Hz (every floor's acceleration and
both roofs' displacements, 1 % noise), made by the independent generator (``generate.py``),
one case per family.  Timed: the whole ``diagnose`` call as a user makes it (reading the
model, recording and channel map, numerics check, recalibration, every hypothesis, the
report, the augmented model and the figure).  Target: under 60 s each on this machine.

``--progress``: diagnose's progress lines, each with its time, on stderr (where a search's time goes: the
recalibration, each form's short fits and polish, the polishes left out).

``--drivers``: where the general driver's time goes: ``integrate`` alone (no Observer, no result) on the
base row with each driver, the same row with its gap opened to 1 m (free flight throughout), and the
forms that run on the general driver, at their null points, alternating in one process.

``--forms``: instead, the cost of one simulation of each hypothesis form on the family
``none``'s case (what a search pays per evaluation): ``Observer.simulate`` of the form's
augmented model at its null point, after one untimed call, median of ``--repeat`` rounds that
simulate every form once each, alternating in one process (the machine drifts by 20-50 % within
minutes), next to the base model's.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

from .generate import write_case


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--families", default="none,inelastic-storey,spatially-varying-input")
    ap.add_argument("--seed", type=int, default=31)
    ap.add_argument("--forms", action="store_true", help="time one simulation per hypothesis form")
    ap.add_argument("--drivers", action="store_true",
                    help="time the integrator alone on the base row (both drivers, with and without contact) "
                         "and on the general driver's forms")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--progress", action="store_true", help="diagnose's progress lines, with their times, on stderr")
    args = ap.parse_args(argv)
    if args.forms:
        return _forms(args.seed, args.repeat)
    if args.drivers:
        return _drivers(args.seed, args.repeat)
    from seispound.diagnose import diagnose

    from .generate import FAMILIES

    unknown = sorted(set(args.families.split(",")) - set(FAMILIES))
    if unknown:
        ap.error(f"--families: unknown {', '.join(unknown)} (one of {', '.join(FAMILIES)})")
    with tempfile.TemporaryDirectory() as tmp:
        for fam in args.families.split(","):
            f = Path(tmp) / fam
            key = write_case(f, fam, args.seed, duration=30.0, buildings=2)
            t0 = time.perf_counter()
            d = diagnose(f / "model.toml", [f / "recording.mseed"], channels=f / "channels.toml",
                         report=f / "report.json", figure=f / "fig.png", progress=args.progress)
            wall = time.perf_counter() - t0
            print(f"{fam}: 2 buildings ({key['impacts']} impacts), 30 s at 200 Hz: diagnose {wall:.1f} s "
                  f"({'under' if wall < 60 else 'OVER'} 60 s); named {[x['physics'] for x in d.left_out] or 'nothing'}"
                  f", NE {d.ne_before:.4f} -> {d.ne_after:.4f}", flush=True)
    return 0


def _case_none(tmp, seed):
    """The family ``none``'s case in folder tmp: (its folder, the model's table with 32 contact substeps,
    the channels, the trials), as ``diagnose`` reads them."""
    import tomllib

    from seispound.calibrate.api import load_inputs

    f = Path(tmp) / "none"
    write_case(f, "none", seed, duration=30.0, buildings=2)
    model, chans, trials = load_inputs(f / "model.toml", [f / "recording.mseed"], f / "channels.toml", None)
    data = tomllib.loads(model.text)
    data.setdefault("analysis", {}).setdefault("contact_substeps", 32)
    return f, data, chans, trials


def _forms(seed, repeat) -> int:
    from seispound.calibrate.observe import Observer
    from seispound.diagnose.hypotheses import REGISTRY

    from ..timing import warm_medians

    with tempfile.TemporaryDirectory() as tmp:
        f, data, chans, trials = _case_none(tmp, seed)

        forms = [("base row", data, [], 0)]
        for hyp in REGISTRY:
            for k, form in enumerate(hyp.forms):
                try:
                    table, specs, null = hyp.augment(data, k)
                except ValueError as err:  # a form that does not apply to this case (``diagnose`` leaves it out too)
                    print(f"  {hyp.name} / {form.__name__.lstrip('_')}: left out ({err})")
                    continue
                forms.append((f"{hyp.name} / {form.__name__.lstrip('_')}", table, list(null.items()), len(specs)))
        observers = []
        for label, table, overrides, _ in forms:
            obs = Observer(table, f, chans, trials)
            obs.simulate(overrides)  # compiled and warm
            observers.append(obs)
        # every form in each round (the machine's drift between forms cancels), each on its second run
        ts = warm_medians({k: (lambda o=obs, ov=form[2]: o.simulate(ov))
                           for k, (obs, form) in enumerate(zip(observers, forms))}, repeat)
        base = ts[0]
        print(f"one simulation, 2 buildings, 30 s at 200 Hz, median of {repeat} rounds over every form:")
        print(f"  base row: {1e3 * base:.1f} ms ({len(observers[0].impact_times[0])} impacts)")
        for k, (label, _, _, p) in enumerate(forms[1:], 1):
            m = ts[k]
            print(f"  {label}: {1e3 * m:.1f} ms ({m / base:.1f} x the base row), {p} parameters", flush=True)
    return 0


def _drivers(seed, repeat) -> int:
    import copy

    from seispound.calibrate.observe import Observer
    from seispound.diagnose.hypotheses import REGISTRY
    from seispound.integrate import integrate
    from seispound.simulation import newmark_substeps, run_inputs

    from ..timing import warm_medians

    with tempfile.TemporaryDirectory() as tmp:
        f, data, chans, trials = _case_none(tmp, seed)
        apart = copy.deepcopy(data)
        for g in apart["gap"]:
            g["size"] = 1.0
        cases = [("base row, fast", data, [], "fast"), ("base row, general", data, [], "general"),
                 ("gap open, fast", apart, [], "fast"), ("gap open, general", apart, [], "general")]
        for hyp in REGISTRY:
            for k, form in enumerate(hyp.forms):
                try:
                    table, _, null = hyp.augment(data, k)
                except ValueError as err:  # a form that does not apply to this case
                    print(f"  {hyp.name} / {form.__name__.lstrip('_')}: left out ({err})")
                    continue
                cases.append((f"{hyp.name} / {form.__name__.lstrip('_')}", table, list(null.items()), "auto"))
        runs = []
        for label, table, overrides, driver in cases:
            m = Observer(table, f, chans, trials).model_for(trials[0], overrides)
            an = m.analysis
            system, motions = run_inputs(m)
            args = (system, motions.rows, an.dt, an.nsteps, an.newmark)
            kw = dict(substeps=newmark_substeps(m, system), driver=driver)
            raw = integrate(*args, **kw)  # compiled and warm
            if driver == "auto" and raw.driver != "general":
                continue
            runs.append((label, args, kw, raw.stats))
        ts = warm_medians({k: (lambda a=args, k_=kw: integrate(*a, **k_)) for k, (_, args, kw, _) in enumerate(runs)},
                          repeat)
        base = ts[0]
        print(f"integrate alone, 2 buildings, 30 s at 200 Hz, median of {repeat} alternating rounds:")
        for k, (label, _, _, st) in enumerate(runs):
            m = ts[k]
            print(f"  {label:48s} {1e3 * m:7.2f} ms  {m / base:5.2f} x  steps {st['steps']:6d} "
                  f"({st['free_flight_steps']} in free flight), DOF-steps {st['dof_steps']}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
