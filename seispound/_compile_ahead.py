"""``python -m seispound._compile_ahead``: compile package functions into numba's cache, in the background.

Started by :mod:`seispound._first_use` while a first run goes through a function's Python source.
Reads a pickled list of (module, name, argument types) on stdin and compiles each function for
those types at low priority; numba writes the machine code into its cache, where the next
process finds it.  One such process compiles at a time (a lock file in numba's cache directory):
a second waits, then finds in the cache what the first compiled.
"""

from __future__ import annotations

import contextlib
import os
import pickle
import sys
from importlib import import_module


@contextlib.contextmanager
def _lock(function):
    import fcntl

    from ._first_use import cache_dir

    with open(cache_dir(function) / "seispound-compile.lock", "a") as f:
        fcntl.flock(f, fcntl.LOCK_EX)
        yield


def main(argv=None) -> int:
    import argparse

    argparse.ArgumentParser(description=__doc__.splitlines()[0], epilog="reads its work on stdin").parse_args(argv)
    with contextlib.suppress(OSError):
        os.nice(10)  # the run in the foreground keeps its core
    from ._first_use import _cached

    for module, name, sig in pickle.load(sys.stdin.buffer):
        function = getattr(import_module(module), name)
        with _lock(function):
            if not _cached(function, sig):
                function.compile(sig)
    return 0


if __name__ == "__main__":
    sys.exit(main())
