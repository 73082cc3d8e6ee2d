"""Run ``diagnose`` on generated concealed-effect cases and score it: ``python -m benchmarks.diagnose.run CASES``.

``CASES`` is a folder written by ``benchmarks.diagnose.generate`` (case folders and
``key*.json``).  Each case is diagnosed exactly as a user would (model, recording and channel
map from the folder; the key is read only to score).  Cases run ``--jobs`` at a time in
separate processes.  Written: ``CASES/results.json`` (per case: label, named, NE before and
after, seconds) and, with ``--markdown``, the scored tables:

* the confusion matrix: true label (the family; ``wrong-parameters`` is a control whose label
  is ``none``) against the physics named first (``none`` when nothing is named);
* the right physics named first, over the effect cases (target >= 90 %);
* the false-alarm rate: physics claimed on a control (target <= 10 %);
* NE after / NE before over the effect cases (target <= 0.5 in every case).
"""

from __future__ import annotations

import argparse
import json
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

EFFECTS = ("distributed-mass", "velocity-dependent-restitution", "soil-structure-interaction", "inelastic-storey",
           "spatially-varying-input")


def run_case(folder: str, jobs: int | None = None) -> dict:
    """Diagnose one case folder as a user would; the report goes to ``folder/report.json``.

    An impact test (``trials.toml`` in the folder) is diagnosed from its trials file.
    ``jobs``: diagnose's own processes (default: the machine's CPUs; 1 when cases run side by side)."""
    from seispound.diagnose import diagnose

    f = Path(folder)
    t0 = time.perf_counter()
    trials = f / "trials.toml"
    recordings = None if trials.exists() else [f / "recording.mseed"]
    d = diagnose(f / "model.toml", recordings, channels=f / "channels.toml", trials=trials if trials.exists() else None,
                 report=f / "report.json", output=f / "diagnosed.toml", progress=False, jobs=jobs)
    return _result(d.report(), time.perf_counter() - t0)


def _result(report: dict, seconds: float) -> dict:
    """A case's line of ``results.json`` from its diagnosis report (``Diagnosis.report()``)."""
    return {"named": [x["physics"] for x in report["left_out"]], "ne_before": report["fit"]["before"],
            "ne_after": report["fit"]["after"], "seconds": seconds, "noise_ne": report["noise_ne"],
            "hypotheses": {k: v.get("ne") for k, v in report["hypotheses"].items()},
            "probability": {x["physics"]: x.get("probability") for x in report["left_out"]},
            "quantities": {x["physics"]: x.get("quantities", []) for x in report["left_out"]},
            "fault": (report["instrument_fault"] or {}).get("channel"), "kept_as_given": report["kept_as_given"],
            "recalibrated_ne": report["numerics"].get("recalibrated_ne")}


def collected(root: Path, todo: list, key_time: float) -> dict:
    """Results of the cases in ``todo`` whose diagnosis finished in a run that stopped before recording them.

    A run's pool finishes the cases it has started when another case raises; each wrote its
    ``report.json`` (after the set's key, so not left from an earlier set).  Their seconds are the
    diagnosis's own, without reading the case."""
    out = {}
    for c in todo:
        f = root / c / "report.json"
        if f.exists() and f.stat().st_mtime > key_time:
            rep = json.loads(f.read_text())
            out[c] = _result(rep, rep["seconds"])
    return out


def score(key: dict, results: dict) -> dict:
    """Rates against the issue's targets, from ``key`` (generator answers) and ``results`` (per case)."""
    effect = [c for c in results if key[c]["label"] != "none"]
    control = [c for c in results if key[c]["label"] == "none"]
    first = {c: (results[c]["named"] or ["none"])[0] for c in results}
    right = sum(first[c] in key[c].get("labels", [key[c]["label"]]) for c in effect)  # two-effect cases: either
    alarms = sum(first[c] != "none" for c in control)
    halved = sum(results[c]["ne_after"] <= 0.5 * results[c]["ne_before"] for c in effect)
    return {"effect_cases": len(effect), "right_first": right, "control_cases": len(control), "false_alarms": alarms,
            "ne_halved": halved}


def markdown(key: dict, results: dict) -> str:
    s = score(key, results)
    cols = ("none",) + EFFECTS
    short = {"none": "none", "distributed-mass": "dist.", "velocity-dependent-restitution": "e(v)",
             "soil-structure-interaction": "SSI", "inelastic-storey": "inel.", "spatially-varying-input": "SVI"}
    lines = ["| true \\ named first | " + " | ".join(short[c] for c in cols) + " |",
             "|---" * (len(cols) + 1) + "|"]
    for fam in ("none", "wrong-parameters") + EFFECTS:
        cases = [c for c in results if key[c]["family"] == fam]
        if not cases:
            continue
        counts = [sum((results[c]["named"] or ["none"])[0] == col for c in cases) for col in cols]
        lines.append(f"| {fam} | " + " | ".join(str(n) if n else "." for n in counts) + " |")
    lines += ["", f"- right physics named first: {s['right_first']} of {s['effect_cases']} effect cases",
              f"- physics claimed on a control (false alarm): {s['false_alarms']} of {s['control_cases']}",
              f"- NE after at most half of NE before: {s['ne_halved']} of {s['effect_cases']} effect cases", "",
              "| case | family | strength | effect NE | named | NE as given | NE after | seconds |",
              "|---|---|---|---|---|---|---|---|"]
    for c in sorted(results):
        k, r = key[c], results[c]
        eff = f"{k['effect_ne']:.3f}" if "effect_ne" in k else "-"
        lines.append(f"| {c} | {k['family']} | {k['strength']} | {eff} | {', '.join(r['named']) or 'nothing'} | "
                     f"{r['ne_before']:.4f} | {r['ne_after']:.4f} | {r['seconds']:.0f} |")
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("cases")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--only", default="", help="comma-separated case names (default: all in key.json)")
    ap.add_argument("--markdown", default="", help="write the scored tables here")
    ap.add_argument("--collect", action="store_true",
                    help="score the cases a stopped run finished (their report.json) instead of running them again")
    args = ap.parse_args(argv)
    root = Path(args.cases)
    key = {}
    for f in sorted(root.glob("key*.json")):  # key.json, and key-NNN.json of generators run side by side
        key.update(json.loads(f.read_text()))
    names = [c for c in (args.only.split(",") if args.only else sorted(key))]
    out = root / "results.json"
    results = json.loads(out.read_text()) if out.exists() else {}
    todo = [c for c in names if c not in results]
    if args.collect:
        found = collected(root, todo, min(f.stat().st_mtime for f in root.glob("key*.json")))
        results.update(found)
        out.write_text(json.dumps(results, indent=1))
        todo = [c for c in todo if c not in found]
        print(f"collected {len(found)} finished cases from their reports", flush=True)
    t0 = time.perf_counter()
    with ProcessPoolExecutor(max_workers=args.jobs) as pool:
        futures = {pool.submit(run_case, str(root / c), 1 if args.jobs > 1 else None): c for c in todo}
        for i, fut in enumerate(as_completed(futures), 1):
            c = futures[fut]
            try:
                results[c] = fut.result()
            except Exception as exc:  # one case's failure is reported and the others go on; it stays to do
                print(f"[{i}/{len(todo)}] {c}: FAILED, {type(exc).__name__}: {exc}", flush=True)
                continue
            out.write_text(json.dumps(results, indent=1))
            r = results[c]
            print(f"[{i}/{len(todo)}] {c} {key[c].get('form', key[c]['family'])}: named {r['named'] or 'nothing'}, NE "
                  f"{r['ne_before']:.4f} -> {r['ne_after']:.4f} in {r['seconds']:.0f} s", flush=True)
    print(f"wall {time.perf_counter() - t0:.0f} s for {len(todo)} cases", flush=True)
    done = {c: results[c] for c in names if c in results}
    print(json.dumps(score(key, done)))
    if args.markdown:
        Path(args.markdown).write_text(markdown(key, done) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
