"""Same-process A/B timing of the integrator against an earlier commit.

``python -m benchmarks.ab REF [--model models/row_of_three.toml] [--repeat 7] [--simulate]``

The package as it was at git ``REF`` is exported to a temporary folder under the
name ``seispound_ref`` (its absolute ``seispound.`` imports rewritten) and
imported next to the working tree's ``seispound``.  Both integrate the same
assembled row and record, alternately, after compilation; reported are the
medians of each and their ratio (working tree / REF), for the pounding run and
for the no-pounding twin, plus the largest difference of their displacement
histories.  Timing both in one process removes the machine's drift between
runs, which is larger than the 5 % a refactoring must stay within.

Both sides compile afresh, into a temporary numba cache: code loaded from numba's cache can run at
another speed than the same code compiled in the process (the general driver's kernel about 15 %
slower on ``models/yielding_pair.toml``, the fast driver's not measurably; docs/performance.md), so
a REF compiled afresh against a working tree loaded from its cache would time the cache, not the
change.  ``--cache DIR`` keeps both sides' cache (and REF's export) in DIR: run twice, and the
second run times both as loaded from the cache, the path a user takes.
"""

from __future__ import annotations

import argparse
import importlib
import inspect
import io
import os
import re
import statistics
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]


def export_reference(ref: str, folder: Path) -> None:
    """Write the package at ``ref`` to folder/seispound_ref (imports renamed)."""
    blob = subprocess.run(["git", "-C", str(REPO), "archive", ref, "seispound"], check=True,
                          capture_output=True).stdout
    with tarfile.open(fileobj=io.BytesIO(blob)) as tar:
        tar.extractall(folder, filter="data")
    src = folder / "seispound"
    for path in src.rglob("*.py"):
        text = path.read_text(encoding="utf-8")
        path.write_text(re.sub(r"\bseispound\.", "seispound_ref.", text), encoding="utf-8")
    src.rename(folder / "seispound_ref")


def _runner(pkg, model_path, scheme=None):
    model = pkg.load_model(model_path)
    system = model.assembled() if hasattr(model, "assembled") else None
    if system is None:
        system = importlib.import_module(pkg.__name__ + ".structure").assemble(
            model.buildings, model.gaps, model.contact)
    ag, _ = importlib.import_module(pkg.__name__ + ".simulation").prepare_ground_motion(model)
    integrate = importlib.import_module(pkg.__name__ + ".integrate").integrate
    an = model.analysis
    twin = system.without_contact()
    kw = {} if scheme is None else {"scheme": scheme}
    return (lambda: integrate(system, ag, an.dt, an.nsteps, an.newmark, **kw),
            lambda: integrate(twin, ag, an.dt, an.nsteps, an.newmark, **kw))


def _simulate_runner(pkg, model_path):
    """The whole path a user calls: ``simulate(model)`` (with its twin) and ``simulate(model, twin=False)``."""
    model = pkg.load_model(model_path)
    return (lambda: pkg.simulate(model), lambda: pkg.simulate(model, twin=False))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("ref", help="git commit or branch to compare against")
    ap.add_argument("--model", default=str(REPO / "models" / "row_of_three.toml"))
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--simulate", action="store_true",
                    help="time the whole simulate(model) (with and without its twin) instead of integrate()")
    ap.add_argument("--stat", choices=("median", "min"), default="median",
                    help="statistic of the repeats (min: the least disturbed run, for a busy machine)")
    ap.add_argument("--scheme", choices=("exact", "newmark"),
                    help="integration scheme of both sides (REF's only if it has schemes; default: each default)")
    ap.add_argument("--cache", metavar="DIR",
                    help="keep REF's export and both sides' numba cache in DIR: a second run with the same DIR times "
                         "both sides as loaded from numba's cache, as a user runs them")
    args = ap.parse_args(argv)
    if "numba" in sys.modules:
        raise SystemExit("benchmarks.ab: run it in a fresh process (numba must read NUMBA_CACHE_DIR first)")
    with tempfile.TemporaryDirectory() as scratch:
        tmp = args.cache or scratch
        Path(tmp).mkdir(parents=True, exist_ok=True)
        os.environ["NUMBA_CACHE_DIR"] = str(Path(tmp) / "numba-cache")  # both sides compile afresh (or cached)
        if not (args.cache and (Path(tmp) / "seispound_ref").is_dir()):
            export_reference(args.ref, Path(tmp))
        sys.path.insert(0, tmp)
        ref = importlib.import_module("seispound_ref")
        new = importlib.import_module("seispound")
        # the scheme goes to REF too when its integrate() knows it (older commits are Newmark throughout)
        ref_integrate = importlib.import_module("seispound_ref.integrate").integrate
        ref_knows = "scheme" in inspect.signature(ref_integrate).parameters
        if args.simulate:
            runs = {"ref": _simulate_runner(ref, args.model), "new": _simulate_runner(new, args.model)}
        else:
            runs = {"ref": _runner(ref, args.model, args.scheme if ref_knows else None),
                    "new": _runner(new, args.model, args.scheme)}
        out = {name: (pound(), twin()) for name, (pound, twin) in runs.items()}  # compile, and compare
        u = [out[k][0]["displacement"].values if args.simulate else out[k][0].displacement for k in ("new", "ref")]
        diff = float(np.nanmax(np.abs(u[0] - u[1])))
        times = {(name, part): [] for name in runs for part in (0, 1)}
        for _ in range(args.repeat):
            for name, fns in runs.items():
                for part, fn in enumerate(fns):
                    t0 = time.perf_counter()
                    fn()
                    times[name, part].append(time.perf_counter() - t0)
    stat = statistics.median if args.stat == "median" else min
    print(f"model {args.model}; {args.stat} of {args.repeat}, alternating, one process")
    labels = ("simulate(model)", "simulate(twin=False)") if args.simulate else ("pounding run", "no-pounding twin")
    for part, label in enumerate(labels):
        r = stat(times["ref", part])
        n = stat(times["new", part])
        print(f"  {label:17s} {args.ref}: {1e3 * r:8.2f} ms   working tree: {1e3 * n:8.2f} ms   ratio {n / r:.3f}")
    print(f"  largest displacement difference (pounding run): {diff:.3g} m")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
