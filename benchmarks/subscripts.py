"""What numba's negative-index wraparound costs a loop over a DOF range lo..hi-1.

``python -m benchmarks.subscripts`` times, in one process (medians of 7
interleaved rounds), the Newmark predictor loop and the L D L^T tridiagonal
solve of the kernel written three ways: over ``range(n)``, over
``range(lo, hi)`` with signed (int64) subscripts, and over ``range(lo, hi)``
with ``np.uint64`` subscripts, as the kernel's ranged helpers do
(``_UNSIGNED`` in ``seispound/integrate/_kernel.py``).  numba wraps negative
subscripts around (``x[-1]`` is the last entry); for ``range(n)`` LLVM proves
the index non-negative and drops the test, for a runtime ``lo`` it cannot, and
the test keeps the elementwise loop from being vectorised.
"""

from __future__ import annotations

import time

import numpy as np
from numba import njit


@njit(cache=True)
def _predictor_whole(n, v, a, Av, Vv, beta, h, gamma, reps):
    for _ in range(reps):
        for i in range(n):
            Av[i] = -v[i] / (beta * h) - (0.5 / beta - 1.0) * a[i]
            Vv[i] = (1.0 - gamma / beta) * v[i] + h * (1.0 - 0.5 * gamma / beta) * a[i]


@njit(cache=True)
def _predictor_signed(lo, hi, v, a, Av, Vv, beta, h, gamma, reps):
    for _ in range(reps):
        for i in range(lo, hi):
            Av[i] = -v[i] / (beta * h) - (0.5 / beta - 1.0) * a[i]
            Vv[i] = (1.0 - gamma / beta) * v[i] + h * (1.0 - 0.5 * gamma / beta) * a[i]


@njit(cache=True)
def _predictor_unsigned(lo, hi, v, a, Av, Vv, beta, h, gamma, reps):
    for _ in range(reps):
        for i in range(np.uint64(lo), np.uint64(hi)):
            Av[i] = -v[i] / (beta * h) - (0.5 / beta - 1.0) * a[i]
            Vv[i] = (1.0 - gamma / beta) * v[i] + h * (1.0 - 0.5 * gamma / beta) * a[i]


@njit(cache=True)
def _solve_signed(L, b, x, lo, hi, reps):
    for _ in range(reps):
        x[lo] = b[lo]
        for i in range(lo + 1, hi):
            x[i] = b[i] - L[i, 1] * x[i - 1]
        x[hi - 1] *= L[hi - 1, 2]
        for i in range(hi - 2, lo - 1, -1):
            x[i] = x[i] * L[i, 2] - L[i + 1, 1] * x[i + 1]


@njit(cache=True)
def _solve_unsigned(L, b, x, lo, hi, reps):
    one = np.uint64(1)
    ulo = np.uint64(lo)
    uhi = np.uint64(hi)
    top = uhi - np.uint64(2)
    for _ in range(reps):
        x[ulo] = b[ulo]
        for i in range(ulo + one, uhi):
            x[i] = b[i] - L[i, one] * x[i - one]
        x[uhi - one] *= L[uhi - one, 2]
        for k in range(uhi - ulo - one):
            i = top - k
            x[i] = x[i] * L[i, 2] - L[i + one, one] * x[i + one]


def _rounds(fns, rounds=7):
    for f in fns.values():
        f()
    t = {k: [] for k in fns}
    for _ in range(rounds):
        for k, f in fns.items():
            t0 = time.perf_counter()
            f()
            t[k].append(time.perf_counter() - t0)
    return {k: float(np.median(v)) for k, v in t.items()}


def main() -> int:
    print("ns per DOF per pass (medians of 7 interleaved rounds)")
    print(f"{'DOFs':>5} {'loop':>10} {'range(n)':>9} {'signed':>8} {'unsigned':>9} {'signed/unsigned':>16}")
    rng = np.random.default_rng(0)
    for n in (40, 400):
        v, a, Av, Vv, b, x = (rng.random(n) for _ in range(6))
        L = rng.random((n, 3))
        reps = 4_000_000 // n
        t = _rounds({"whole": lambda: _predictor_whole(n, v, a, Av, Vv, 0.25, 0.005, 0.5, reps),
                     "signed": lambda: _predictor_signed(0, n, v, a, Av, Vv, 0.25, 0.005, 0.5, reps),
                     "unsigned": lambda: _predictor_unsigned(0, n, v, a, Av, Vv, 0.25, 0.005, 0.5, reps)})
        ns = {k: t[k] / (reps * n) * 1e9 for k in t}
        print(f"{n:5d} {'predictor':>10} {ns['whole']:9.2f} {ns['signed']:8.2f} {ns['unsigned']:9.2f} "
              f"{ns['signed'] / ns['unsigned']:16.2f}")
        x2 = np.empty(n)
        _solve_signed(L, b, x, 0, n, 1)
        _solve_unsigned(L, b, x2, 0, n, 1)
        assert np.array_equal(x, x2)
        t = _rounds({"signed": lambda: _solve_signed(L, b, x, 0, n, reps),
                     "unsigned": lambda: _solve_unsigned(L, b, x, 0, n, reps)})
        ns = {k: t[k] / (reps * n) * 1e9 for k in t}
        print(f"{n:5d} {'solve':>10} {'':>9} {ns['signed']:8.2f} {ns['unsigned']:9.2f} "
              f"{ns['signed'] / ns['unsigned']:16.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
