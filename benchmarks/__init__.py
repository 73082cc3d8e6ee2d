"""Benchmarks and peer comparisons (not part of the installed package).

Timings measure machine code: a first ``simulate`` here compiles (as numba does) rather than
running the integrator's Python source while it compiles in the background
(``seispound._first_use``), which ``benchmarks.startup`` measures on its own.
"""

import os

os.environ.setdefault("SEISPOUND_INTERPRET_SECONDS", "0")
