"""A compiled function whose Python form raises where its machine code does not (for ``test_first_use.py``)."""

import math

from seispound._jit import njit


@njit(cache=True)
def root(x):
    """sqrt(x): NaN below zero as machine code (numba's ``math.sqrt``); Python's ``math.sqrt`` raises ValueError."""
    return math.sqrt(x)
