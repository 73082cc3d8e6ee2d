"""What keeping freed memory saves a run: ``python -m benchmarks.page_faults [--rounds 5] [--repeat 9]``.

``seispound._memory.keep_freed_memory`` sets glibc's allocator, process-wide, when the package is imported,
so the two settings run in separate child processes: one as the package is (freed memory kept), one with
``SEISPOUND_KEEP_MEMORY=0`` (glibc's defaults), alternating ``--rounds`` times.  Each child times the
whole ``simulate(model)`` (its twin included) of each case, each timed on the second of two runs in a row
(``timing.warm_medians``), medians of ``--repeat``, and counts the page faults the process took per
``simulate`` (``getrusage``'s minor faults).  Reported per case: the medians over the rounds of each
setting's time and faults, and the ratio of the times (kept / defaults).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
CASES = ("models/two_buildings.toml", "canonical row (models/row_of_three.toml)",
         "canonical row, flexible foundation under Middle")


def _models():
    import seispound as sp
    from benchmarks.physics import cases

    row = cases(sp.load_model(REPO / "models" / "row_of_three.toml"))
    return {CASES[0]: sp.load_model(REPO / "models" / "two_buildings.toml"), CASES[1]: row["plain"],
            CASES[2]: row["flexible foundation"]}


def _child(repeat: int) -> dict:
    import resource
    import warnings

    import seispound as sp
    from benchmarks.timing import warm_medians

    warnings.simplefilter("ignore")
    models = _models()
    out = {}
    for name, m in models.items():
        sp.simulate(m)
        f0 = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
        for _ in range(repeat):
            sp.simulate(m)
        faults = (resource.getrusage(resource.RUSAGE_SELF).ru_minflt - f0) / repeat
        out[name] = {"faults": faults}
    times = warm_medians({name: (lambda m=m: sp.simulate(m)) for name, m in models.items()}, repeat)
    for name in models:
        out[name]["seconds"] = times[name]
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.page_faults", description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=5, help="child processes per setting, alternating (default 5)")
    ap.add_argument("--repeat", type=int, default=9, help="simulations per case and child (default 9)")
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        print(json.dumps(_child(args.repeat)))
        return 0
    runs = {"kept": [], "defaults": []}
    for r in range(args.rounds):
        for setting in runs:
            # set either way: a caller's own SEISPOUND_KEEP_MEMORY must not turn the kept side into the defaults
            env = dict(os.environ, PYTHONPATH=str(REPO), SEISPOUND_KEEP_MEMORY="0" if setting == "defaults" else "1")
            res = subprocess.run([sys.executable, "-m", "benchmarks.page_faults", "--child", "--repeat",
                                  str(args.repeat)], cwd=REPO, env=env, capture_output=True, text=True)
            if res.returncode != 0:
                print(res.stderr, file=sys.stderr)
                return 1
            runs[setting].append(json.loads(res.stdout.strip().splitlines()[-1]))
            print(f"round {r + 1}/{args.rounds}: {setting} done", file=sys.stderr, flush=True)
    print(f"whole simulate(model) with its twin; medians over {args.rounds} child processes per setting, each the "
          f"median of {args.repeat}\n")
    print("| case | freed memory kept | glibc's defaults | kept / defaults | page faults per simulate (kept, defaults) |")
    print("|---|---:|---:|---:|---:|")
    for name in CASES:
        t = {s: statistics.median(r[name]["seconds"] for r in runs[s]) for s in runs}
        f = {s: statistics.median(r[name]["faults"] for r in runs[s]) for s in runs}
        print(f"| {name} | {1e3 * t['kept']:.2f} ms | {1e3 * t['defaults']:.2f} ms | {t['kept'] / t['defaults']:.2f} "
              f"| {f['kept']:.0f}, {f['defaults']:.0f} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
