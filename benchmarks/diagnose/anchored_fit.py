"""How far a yielding form can fit a diagnosed case from a given start:
``python -m benchmarks.diagnose.anchored_fit CASE [--form K] [--start anchor:MU | generator] [--base nominal|recalibrated]
[--pinch P] [--stages]``.

``CASE`` is a case folder that ``benchmarks.diagnose.run`` has diagnosed (its ``report.json`` holds the
recalibrated base values); ``--start generator`` reads the yield drifts from the suite's ``key.json`` beside it.
The form (``--form``: 0 Bouc-Wen, 1 bilinear, 2 degrading and pinching, as ``hypotheses/inelastic.py`` orders
them) is added to the model at its null point, each building's yield drift set from the start:

* ``anchor:MU``: the search's own anchored start (``api._yield_anchors``: the elastic model's peak storey
  deformation over the ductility MU, on the chosen base values);
* ``generator``: the generator's yield drifts (a development check, never a start the search has).

Then, by default, one least-squares fit of the form's own parameters together with the base parameters
``diagnose`` recalibrates (``api._base_specs``, the masses held as the report holds them), with
``diagnose``'s tolerance and finite-difference step and at most ``--budget`` simulations; with
``--stages``, the search's own two stages instead: the short fit of the form's own parameters with the base
held (``api._short``), then the polish, own parameters and then jointly (``api._polish``).  Printed: the NE
reached and the simulations.  Used for docs/diagnose.md, "What bounds the pinched Clough misses".
"""

from __future__ import annotations

import argparse
import copy
import json
import time
import tomllib
from pathlib import Path


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.diagnose.anchored_fit")
    ap.add_argument("case", type=Path)
    ap.add_argument("--form", type=int, default=2)
    ap.add_argument("--start", default="anchor:4", help="anchor:MU or generator")
    ap.add_argument("--base", choices=("nominal", "recalibrated"), default="nominal")
    ap.add_argument("--pinch", type=float, default=None, help="the degrading form's pinching at the start")
    ap.add_argument("--budget", type=int, default=500)
    ap.add_argument("--stages", action="store_true", help="the search's short fit and polish instead of one fit")
    args = ap.parse_args(argv)

    from seispound.calibrate.api import load_inputs
    from seispound.calibrate.fit import calibrate_observer, parse_fit
    from seispound.calibrate.observe import Observer
    from seispound.diagnose import api
    from seispound.diagnose.hypotheses import REGISTRY
    from seispound.model.paths import get_value, set_value

    case = args.case
    report = json.loads((case / "report.json").read_text())
    model, chans, trials = load_inputs(case / "model.toml", [case / "recording.mseed"], case / "channels.toml", None)
    chans = api._responses(chans)  # the channels diagnose fits
    data = tomllib.loads(model.text)
    an = data.setdefault("analysis", {})  # the step and contact substeps diagnose ran at (its numerics)
    an["dt"], an["contact_substeps"] = report["numerics"]["dt"], report["numerics"]["contact_substeps"]
    held = set(report.get("held_as_given", {}))
    base_params = [p for p in parse_fit(api._base_specs(data), data) if p.path not in held]
    joint = [f"{p.path}={p.lo!r}:{p.hi!r}" for p in base_params]
    hyp = next(h for h in REGISTRY if h.name == "inelastic-storey")
    aug, specs, null = hyp.augment(data, args.form)
    start = dict(null)
    if args.base == "recalibrated":  # the base values as the recalibration left them (factors on the lists)
        for p in base_params:
            start[p.path] = p.value_at(get_value(aug, p.path), report["recalibrated"][p.path])
    if args.start == "generator":
        key = json.loads((case.parent / "key.json").read_text())[case.name]
        for b, q in key["quantities"]["buildings"].items():
            start[f"building.{b}.storey_law.yield_drift"] = q["yield_drift"]
    else:
        mu = float(args.start.split(":")[1])
        if mu not in api.DUCTILITIES:
            ap.error(f"--start anchor:MU: MU is one of the search's ductilities {api.DUCTILITIES}")
        anchors = api._yield_anchors(data, specs, [dict(start)], case, trials)[api.DUCTILITIES.index(mu)][1]
        start.update({k: v for k, v in anchors.items() if k.endswith(".yield_drift")})
    if args.pinch is not None:
        start["building.*.storey_law.pinching"] = args.pinch
    drifts = {k.split(".")[1]: round(v, 5) for k, v in start.items() if k.endswith(".yield_drift")}
    t0 = time.perf_counter()
    if args.stages:
        fit, _, _ = api._short(aug, specs, start, case, chans, trials)
        print(f"short fit of the form's own parameters: NE {fit.ne_mean_after:.4f} ({fit.evaluations} simulations)")
        fit = api._polish([fit.model_text], specs, joint + specs, case, chans, trials, 400, False, True)
        label = "then polished (own parameters, then jointly)"
    else:
        table = copy.deepcopy(aug)
        for path, value in start.items():
            set_value(table, path, value)
        params = parse_fit(joint + specs, table)
        fit = calibrate_observer(Observer(table, case, chans, trials), params, progress=False,
                                 max_evaluations=args.budget, tolerance=api.TOLERANCE, step_fraction=api.STEP)
        label = "one joint fit"
    print(f"{case.name}, form {args.form}, start {args.start} (yield drifts {drifts}), {args.base} base: {label}, "
          f"NE {fit.ne_mean_after:.4f} ({fit.evaluations} simulations, {time.perf_counter() - t0:.0f} s)")
    print("  " + ", ".join(f"{q} {v['value']:.4g}" for q, v in fit.parameters.items()))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
