"""The package's ``njit``: numba's, with one specialisation per argument type, not per value.

When a compiled function calls another, numba types the call with the arguments as they stand
at the call site, and a constant (``m_act = 0`` before the first impact, ``transposed=True``)
is typed as its literal value: the callee is compiled once for ``Literal[int](0)`` and again
for ``int64``.  On a fresh install that doubled the compile of a dozen of the integrator's
functions (about 5 s of the first run's 45 s, ``python -m benchmarks.startup``).  This
dispatcher types every call with the arguments' plain types (``numba.types.unliteral``), so
each function compiles once per argument type; LLVM still folds the constants where it
inlines the callee.  Nothing in the package dispatches on a literal value.

It is numba's CPU dispatcher (``numba.core.registry.CPUDispatcher``, the class
``numba.njit`` builds) with one method overridden; the options are numba's.
"""

from __future__ import annotations

from numba.core import config, types
from numba.core.registry import CPUDispatcher


class _Dispatcher(CPUDispatcher):
    """``CPUDispatcher`` whose calls from compiled code are typed without literal values."""

    def get_call_template(self, args, kws):
        args = tuple(types.unliteral(a) for a in args)
        kws = {k: types.unliteral(v) for k, v in kws.items()}
        return super().get_call_template(args, kws)


def njit(*, cache: bool = True, **options):
    """Decorator: compile ``nopython`` like ``numba.njit(cache=cache, **options)``.

    Parameters
    ----------
    cache : bool
        Keep the compiled code on disk (numba's cache, ``NUMBA_CACHE_DIR``).
    **options
        numba target options (``inline``, ``fastmath``, ...).
    """

    def wrap(func):
        if config.DISABLE_JIT:  # NUMBA_DISABLE_JIT=1, as numba.njit honours it
            return func
        disp = _Dispatcher(py_func=func, locals={}, targetoptions=dict(options, nopython=True))
        if cache:
            disp.enable_caching()
        return disp

    return wrap
