"""Freed memory kept for the next run: a run's large arrays from pages the process already holds.

Every run allocates its histories anew: the kernel's outputs, the floors' read-out of a row whose DOFs
are not its floors, the result's buffers and their temporaries.  glibc's allocator serves an array
above its mmap threshold (128 kB at start, raised to the largest such array freed so far) with fresh
pages from the kernel, and trims the heap's free top beyond twice that threshold, so a run may touch
its arrays' pages for the first time again, one page fault per 4 kB.  Measured in fresh processes
(``python -m benchmarks.page_faults``): a ``simulate`` of the canonical row with a flexible foundation
under one building took 5 489 faults and 50.4 ms with glibc's defaults, none and 40.7 ms with freed
memory kept; the plain canonical row 2 376 faults against none, yet the same time within 1 % (17 ms;
why its faults cost so much less was not measured).  A process that
has already freed larger arrays runs at the kept speed with the defaults as well (the threshold has
risen), so what this buys is that a run's speed does not depend on what the process did before.

:func:`keep_freed_memory` sets glibc's thresholds (``mallopt``; glibc manual, "Malloc Tunable
Parameters"): arrays up to MMAP_THRESHOLD come from the heap, and up to TRIM_THRESHOLD of free memory
stays at the heap's top for the next run instead of going back to the kernel.  Called once when the
package is imported; the environment variable ``SEISPOUND_KEEP_MEMORY=0`` leaves glibc's defaults, and
other C libraries (musl, macOS, Windows) are left as they are.  What it costs: a process keeps up to
TRIM_THRESHOLD of memory it freed (its resident size does not fall back after a peak below that).
"""

from __future__ import annotations

import ctypes
import ctypes.util
import os
import sys

__all__ = ["keep_freed_memory"]

# glibc's malloc.h: mallopt's parameter numbers
M_TRIM_THRESHOLD, M_MMAP_THRESHOLD = -1, -3
#: arrays up to this size [bytes] come from the heap (a 30 s record at 200 Hz on 100 DOFs is 4.8 MB)
MMAP_THRESHOLD = 32 << 20
#: free memory [bytes] kept at the heap's top before it is given back
TRIM_THRESHOLD = 128 << 20

_DONE: list = []


def keep_freed_memory() -> bool:
    """Set glibc's allocator to keep freed memory for the next run (module docstring); True if it was set.

    Idempotent; False where the C library is not glibc or ``SEISPOUND_KEEP_MEMORY=0``.
    """
    if _DONE:
        return _DONE[0]
    ok = False
    if sys.platform.startswith("linux") and os.environ.get("SEISPOUND_KEEP_MEMORY", "1") != "0":
        try:
            libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
            glibc = hasattr(libc, "gnu_get_libc_version")  # musl has a mallopt that does nothing
            ok = glibc and bool(libc.mallopt(M_MMAP_THRESHOLD, MMAP_THRESHOLD)) and bool(
                libc.mallopt(M_TRIM_THRESHOLD, TRIM_THRESHOLD))
        except (OSError, AttributeError):
            ok = False
    _DONE.append(ok)
    return ok
