"""One BLAS thread against the machine's default: ``python -m benchmarks.blas_threads [--repeat 5]``.

The package's fits, diagnosis and transition maps run their linear algebra on one BLAS thread
(``seispound/_blas.py``).  This times the whole ``calibrate`` of ``benchmarks.calibration`` (two
buildings of 4 and 8 storeys, 30 s at 200 Hz, three channels, six parameters) with that limit and
without it (BLAS on the threads it starts with, ``threadpoolctl.threadpool_info``), alternating in
one process, medians of ``repeat`` each way.  The fitted values agree to the last printed digit.

``--study`` times instead a study a user runs on every core: the 5 + 8 storey pair of
``benchmarks.physics_accuracy`` with soil under B (its floors read out through ``results.floors``'
products) under the two bundled El Centro components at 100 gap sizes, ``seispound study --workers
2``, each run a process of its own, alternating with BLAS on its default threads; the two stores are
compared value for value.
"""

from __future__ import annotations

import argparse
import contextlib
import statistics
import tempfile
import warnings
from functools import partial
from pathlib import Path


STUDY = """title = "soil pair: gap sizes"
model = "soil.toml"
[records]
bundled = ["elcentro_180", "elcentro_270"]
[[axis]]
name = "gap_size"
path = "gap.*.size"
range = {{ start = 0.005, stop = 0.05, num = {num} }}
"""
# one study in a process of its own; argv: folder, "one" or "default" (BLAS on the threads it starts with)
_RUN = """import contextlib, sys, time
import seispound._blas as b
if sys.argv[2] == "default":
    b.one_thread = contextlib.nullcontext
from seispound.cli import main
t = time.perf_counter()
rc = main(["study", sys.argv[1] + "/study.toml", "-o", sys.argv[1] + "/" + sys.argv[2] + ".h5", "--overwrite", "-q",
           "--workers", sys.argv[3]])
print(time.perf_counter() - t, rc)
"""


def study(repeat, workers=2, num=100):
    """Wall time [s] of the study (``--study``) each way, medians of ``repeat``, and the stores' largest difference."""
    import subprocess
    import sys

    import numpy as np

    from seispound.study import open_study

    from .physics_accuracy import CASES, _text

    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        (folder / "soil.toml").write_text(_text(CASES["soil and footing"], 0.005))
        (folder / "study.toml").write_text(STUDY.format(num=num))
        times = {"one": [], "default": []}
        for _ in range(repeat):
            for mode in times:
                for old in folder.glob(f"{mode}.h5*"):
                    old.unlink()
                out = subprocess.run([sys.executable, "-c", _RUN, str(folder), mode, str(workers)],
                                     capture_output=True, text=True, check=True).stdout.split()
                times[mode].append(float(out[0]))
        a, b = open_study(folder / "one.h5"), open_study(folder / "default.h5")
        diff = max((float(np.nanmax(np.abs(a[v].values - b[v].values), initial=0.0))
                    for v in a.data_vars if a[v].dtype.kind == "f"), default=0.0)
        runs = int(a.sizes["record"] * a.sizes["gap_size"])
    print(f"study of {runs} runs, soil pair, {workers} workers: one BLAS thread in the read-out "
          f"{statistics.median(times['one']):.2f} s ({', '.join(f'{t:.2f}' for t in times['one'])}); "
          f"BLAS on its default threads {statistics.median(times['default']):.2f} s "
          f"({', '.join(f'{t:.2f}' for t in times['default'])}); stores' largest difference {diff:g}")
    return 0


def main(argv=None) -> int:
    from threadpoolctl import threadpool_info

    import seispound._blas as blas
    from .calibration import setup, timed

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--study", action="store_true", help="time a study of the soil pair on two workers instead")
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    if args.study:
        return study(args.repeat)
    limited = blas.one_thread
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        setup(folder)

        run = partial(timed, folder)

        run()  # numba's cache, the record reader
        times = {True: [], False: []}
        last = {}
        for _ in range(args.repeat):
            for one in (True, False):
                blas.one_thread = limited if one else contextlib.nullcontext
                t, last[one] = run()
                times[one].append(t)
        blas.one_thread = limited
    threads = sorted({lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"})
    for one in (True, False):
        res = last[one]
        vals = ", ".join(f"{p['value']:.5g}" for p in res.parameters.values())
        print(f"calibrate, {'one BLAS thread' if one else f'BLAS on {threads} threads'}: "
              f"{statistics.median(times[one]):.3f} s ({res.evaluations} simulations); fitted {vals}")
    print(f"ratio: {statistics.median(times[False]) / statistics.median(times[True]):.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
