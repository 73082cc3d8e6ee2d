"""Score ``diagnose`` on the outside suite: ``python -m benchmarks.diagnose.score_suite CASES [--markdown F]``.

``CASES`` holds the case folders and ``key.json`` of ``benchmarks.diagnose.suite`` and the
``results.json`` that ``benchmarks.diagnose.run`` wrote.  The key is read only here.  Scored
against the issue's targets, each rate with its 95 % Wilson interval (Wilson 1927; the score
interval, which stays inside [0, 1] and holds at small counts):

* right physics named first over the effect cases (single effects, two effects, impact tests):
  the first named is one of the case's labels (target >= 90 %);
* both effects named on the two-effect cases;
* false alarms: any physics named on a control (target: upper bound < 10 %);
* instrument faults found (the faulty channel reported);
* the gap closed: (NE as given - NE after) / (NE as given - the noise's NE) >= 80 % in at least
  80 % of the effect cases (the noise's NE is the NE of the model that made the data);
* quantities: each identified quantity of a named physics within 15 % of the generator's; apart, the
  same count over the quantities the report reads as measurements (not marked ``form_limited``: their
  physics's fit within ``diagnose.api.FORM_LIMITED`` times the noise);
* the Brier score of the probabilities: per case and hypothesis, the probability of a named
  physics (0 when it is not named) against whether it was concealed.
"""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

from .run import EFFECTS

Z95 = 1.959964


def wilson(k: int, n: int) -> tuple[float, float]:
    """95 % Wilson score interval of a proportion k / n."""
    if n == 0:
        return float("nan"), float("nan")
    p = k / n
    c = Z95 * Z95 / n
    mid = (p + c / 2) / (1 + c)
    half = Z95 * math.sqrt(p * (1 - p) / n + c / (4 * n)) / (1 + c)
    return max(0.0, mid - half), min(1.0, mid + half)


def _truth(q, physics, name):
    """The generator's value of one of our quantity names, or None (no counterpart)."""
    b = name.split(":")[0]
    per = q.get("buildings", {}).get(b, {})
    if physics == "soil-structure-interaction" and "period on the foundation" in name:
        return per.get("first_period_s")
    if physics == "distributed-mass" and "first axial frequency" in name:
        return per.get("first_axial_hz")
    if physics == "distributed-mass" and "centre of mass" in name:
        return per.get("centre_of_mass")
    if physics == "inelastic-storey" and name.endswith("yield drift"):
        return per.get("yield_drift")
    if physics == "velocity-dependent-restitution" and name.startswith("e at an impact velocity of"):
        return q.get("e_at_0.1" if "0.1 m/s" in name else "e_at_0.5")
    if physics == "spatially-varying-input" and name.endswith("delay of its ground motion"):
        return per.get("delay_s")
    return None


def score(key: dict, results: dict) -> dict:
    cases = [c for c in results if c in key]
    effect = [c for c in cases if key[c]["labels"][0] not in ("none", "instrument-fault")]
    two = [c for c in effect if len(key[c]["labels"]) > 1]
    control = [c for c in cases if key[c]["labels"] == ["none"]]
    fault = [c for c in cases if key[c]["labels"] == ["instrument-fault"]]
    first = {c: (results[c]["named"] or ["none"])[0] for c in cases}
    right = sum(first[c] in key[c]["labels"] for c in effect)
    both = sum(set(key[c]["labels"]) <= set(results[c]["named"]) for c in two)
    alarms = sum(bool(results[c]["named"]) for c in control)
    found = sum(bool(results[c].get("fault")) for c in fault)
    closed = {}
    for c in effect:
        r = results[c]
        gap = r["ne_before"] - r["noise_ne"]
        closed[c] = (r["ne_before"] - r["ne_after"]) / gap if gap > 0 else float("nan")
    closing = sum(v >= 0.8 for v in closed.values())
    within, compared, rows = 0, 0, []
    sound_within, sound = 0, 0
    for c in effect:
        for physics, qs in results[c].get("quantities", {}).items():
            if physics not in key[c]["labels"]:
                continue
            for q in qs:
                truth = _truth(key[c]["quantities"], physics, q["name"])
                if truth is None or q.get("stderr") is None or not truth:
                    continue
                err = q["value"] / truth - 1.0
                compared += 1
                within += abs(err) <= 0.15
                limited = q.get("form_limited")
                if not limited:
                    sound += 1
                    sound_within += abs(err) <= 0.15
                rows.append((c, q["name"], q["value"], truth, err, limited))
    brier, nb = 0.0, 0
    for c in cases:
        for h in EFFECTS:
            p = (results[c].get("probability") or {}).get(h) or 0.0
            o = 1.0 if h in key[c]["labels"] else 0.0
            brier += (p - o) ** 2
            nb += 1
    return {"effect_cases": len(effect), "right_first": right, "right_interval": wilson(right, len(effect)),
            "two_effect_cases": len(two), "both_named": both, "control_cases": len(control), "false_alarms": alarms,
            "false_alarm_interval": wilson(alarms, len(control)), "fault_cases": len(fault), "faults_found": found,
            "gap_closed_80": closing, "gap_interval": wilson(closing, len(effect)), "closed": closed,
            "quantities_within_15": within, "quantities_compared": compared, "quantity_rows": rows,
            "measured_within_15": sound_within, "measured_compared": sound,
            "brier": brier / nb if nb else float("nan"), "brier_pairs": nb}


def markdown(key: dict, results: dict) -> str:
    s = score(key, results)
    pct = lambda k, n: f"{k} of {n} ({100 * k / n:.0f} %)" if n else "none"  # noqa: E731
    iv = lambda t: f"95 % interval {100 * t[0]:.0f}-{100 * t[1]:.0f} %"  # noqa: E731
    cols = ("none",) + EFFECTS
    short = {"none": "none", "distributed-mass": "dist.", "velocity-dependent-restitution": "e(v)",
             "soil-structure-interaction": "SSI", "inelastic-storey": "inel.", "spatially-varying-input": "SVI"}
    lines = ["| family \\ named first | " + " | ".join(short[c] for c in cols) + " |", "|---" * (len(cols) + 1) + "|"]
    for fam in sorted({key[c]["family"] for c in results if c in key}):
        cs = [c for c in results if c in key and key[c]["family"] == fam]
        counts = [sum((results[c]["named"] or ["none"])[0] == col for c in cs) for col in cols]
        lines.append(f"| {fam} | " + " | ".join(str(n) if n else "." for n in counts) + " |")
    lines += ["",
              f"- right physics named first: {pct(s['right_first'], s['effect_cases'])}, {iv(s['right_interval'])}",
              f"- both effects named: {pct(s['both_named'], s['two_effect_cases'])}",
              f"- physics claimed on a control: {pct(s['false_alarms'], s['control_cases'])}, "
              f"{iv(s['false_alarm_interval'])}",
              f"- instrument faults found: {pct(s['faults_found'], s['fault_cases'])}",
              f"- at least 80 % of the gap to the noise closed: {pct(s['gap_closed_80'], s['effect_cases'])}, "
              f"{iv(s['gap_interval'])}",
              f"- identified quantities within 15 %: {pct(s['quantities_within_15'], s['quantities_compared'])}",
              f"- of them read as measurements (not marked form-limited): "
              f"{pct(s['measured_within_15'], s['measured_compared'])} within 15 %",
              f"- Brier score of the probabilities: {s['brier']:.3f} over {s['brier_pairs']} (case, hypothesis) pairs",
              "", "| case | form | labels | named | NE as given | NE after | noise NE | gap closed | seconds |",
              "|---|---|---|---|---|---|---|---|---|"]
    for c in sorted(c for c in results if c in key):
        k, r = key[c], results[c]
        g = s["closed"].get(c)
        lines.append(f"| {c} | {k['form']} | {', '.join(k['labels'])} | {', '.join(r['named']) or 'nothing'}"
                     f"{' (fault ' + r['fault'] + ')' if r.get('fault') else ''} | {r['ne_before']:.4f} | "
                     f"{r['ne_after']:.4f} | {r['noise_ne']:.4f} | {'-' if g is None else f'{100 * g:.0f} %'} | "
                     f"{r['seconds']:.0f} |")
    if s["quantity_rows"]:
        lines += ["", "| case | quantity | recovered | generator | error | form-limited (x noise) |",
                  "|---|---|---|---|---|---|"]
        lines += [f"| {c} | {n} | {v:.4g} | {t:.4g} | {100 * e:+.1f} % | {f'{lim:.1f}' if lim else '-'} |"
                  for c, n, v, t, e, lim in s["quantity_rows"]]
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("cases")
    ap.add_argument("--markdown", default="")
    args = ap.parse_args(argv)
    root = Path(args.cases)
    key = json.loads((root / "key.json").read_text())
    results = json.loads((root / "results.json").read_text())
    text = markdown(key, results)
    print(text)
    if args.markdown:
        Path(args.markdown).write_text(text + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
