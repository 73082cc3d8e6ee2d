"""One BLAS thread for the package's linear algebra.

The package's matrices are small or tall and thin: a row's transition maps (n up to a few
hundred), a fit's Jacobian (samples x parameters, parameters below 20).  On them a second
OpenBLAS thread does not help: it spins beside the caller and hands work back and forth, and
beside other work (diagnose's worker processes, a study's workers, a busy machine) it
competes for the cores.  Measured: a matrix exponential of 122 x 122 in 187 ms instead of
1.9 ms; the whole ``calibrate`` of ``benchmarks.calibration`` in 0.96 s instead of 0.37 s
(``python -m benchmarks.blas_threads``).

The same holds for the per-floor read-out of a row whose DOFs are not its floors (``results.floors``:
a few (steps x DOFs) by (DOFs x floors) products per run): a study of the 5 + 8 storey pair with soil
under one building, 200 runs on two workers, took 6.9 s with BLAS on its default threads against 4.4 s
on one (``python -m benchmarks.blas_threads --study``), the stores equal value for value.

``one_thread()`` (and the decorator ``single_threaded``) limits every loaded BLAS to one thread
for the duration of a ``with`` block and restores the caller's setting after it, through
``threadpoolctl`` (the maintained library scikit-learn uses for this).  Finding the loaded libraries is the slow part (about 1 ms), so it
is done once, after importing SciPy's linear algebra so that SciPy's own OpenBLAS is among them.
"""

from __future__ import annotations

import functools

__all__ = ["one_thread", "single_threaded"]

_CONTROLLER = None


def one_thread():
    """A context manager: every BLAS library loaded by NumPy and SciPy on one thread inside it."""
    global _CONTROLLER
    if _CONTROLLER is None:
        import scipy.linalg  # noqa: F401 (loads SciPy's BLAS, so that the controller sees it)
        from threadpoolctl import ThreadpoolController

        _CONTROLLER = ThreadpoolController()
    return _CONTROLLER.limit(limits=1, user_api="blas")


def single_threaded(func):
    """Decorator: ``func`` runs inside :func:`one_thread` (the package's fits, diagnosis and impact study)."""

    @functools.wraps(func)
    def wrapper(*args, **kwargs):
        with one_thread():
            return func(*args, **kwargs)

    return wrapper
