"""Variants read reusing what did not change, against read afresh: ``python -m benchmarks.reuse [--repeat 5]``.

A fit's evaluations and a study's runs are variants of one model (``seispound/model/parts.py``):
read with ``Parts``, a variant validates and lays out only the buildings whose tables changed.
Timed on the paths a user calls, alternating the off switch (``parts.REUSE``) in one process:

1. ``calibrate`` as ``benchmarks.calibration`` runs it (two buildings of 4 and 8 storeys, 30 s at
   200 Hz, six parameters): the whole call, medians of ``repeat`` each way, and per simulation;
2. a study run as ``benchmarks.study_scale`` times it (a 2 + 3 storey pair, 30 s at 5 ms, the axes
   records x laws x gap sizes x storey stiffness; ``study.worker.run_one`` with its twin at hand):
   the median of 101 runs spread over the study, each way, ``repeat`` times.

Both ways give the same results to the last bit (``tests/model/test_parts.py``).
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
import warnings
from pathlib import Path


def _calibrate(folder: Path):
    from .calibration import timed

    seconds, res = timed(folder)
    return seconds, res.evaluations


def _study_runs(study, idx, twins):
    from seispound.study.worker import run_one

    times = []
    for i in idx:
        t0 = time.perf_counter()
        run_one(study, i, twins[study.twin_key(i)])
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main(argv=None) -> int:
    from seispound.model import parts
    from seispound.study.spec import load_study
    from seispound.study.worker import twin_task

    from .calibration import setup
    from .study_scale import write_study

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        setup(folder)
        study = load_study(write_study(folder, 1000))
        idx = list(range(0, study.n_runs, study.n_runs // 101))[:101]
        twins = {study.twin_key(i): twin_task(study, i) for i in idx}
        _calibrate(folder)  # numba's cache, the record reader
        cal = {True: [], False: []}
        runs = {True: [], False: []}
        for _ in range(args.repeat):
            for reuse in (True, False):
                parts.REUSE = reuse
                cal[reuse].append(_calibrate(folder))
                runs[reuse].append(_study_runs(study, idx, twins))
        parts.REUSE = True
    for reuse in (True, False):
        t = statistics.median(c[0] for c in cal[reuse])
        n = cal[reuse][0][1]
        print(f"calibrate, {'reused' if reuse else 'afresh'}: {t:.3f} s, {n} simulations, "
              f"{1e3 * t / n:.2f} ms each; study run: {1e3 * statistics.median(runs[reuse]):.3f} ms")
    c_on = statistics.median(c[0] for c in cal[True])
    c_off = statistics.median(c[0] for c in cal[False])
    print(f"ratio afresh / reused: calibrate {c_off / c_on:.2f}, study run "
          f"{statistics.median(runs[False]) / statistics.median(runs[True]):.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
