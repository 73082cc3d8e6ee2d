"""One BLAS thread against the machine's default: ``python -m benchmarks.blas_threads [--repeat 5]``.

The package's fits, diagnosis and transition maps run their linear algebra on one BLAS thread
(``seispound/_blas.py``).  This times the whole ``calibrate`` of ``benchmarks.calibration`` (two
buildings of 4 and 8 storeys, 30 s at 200 Hz, three channels, six parameters) with that limit and
without it (BLAS on the threads it starts with, ``threadpoolctl.threadpool_info``), alternating in
one process, medians of ``repeat`` each way.  The fitted values agree to the last printed digit.
"""

from __future__ import annotations

import argparse
import contextlib
import statistics
import tempfile
import warnings
from functools import partial
from pathlib import Path


def main(argv=None) -> int:
    from threadpoolctl import threadpool_info

    import seispound._blas as blas
    from .calibration import setup, timed

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
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
