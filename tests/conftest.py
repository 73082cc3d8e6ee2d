"""Session set-up of the test suite.

Run on two processes (``pytest -n 2``, README command 2), each worker would compile both of the
integrator's drivers into numba's cache on first use, at the same moment as the other (each
1-4 min on this machine). Instead, before its first test, the first worker compiles the fast
driver and the second the general one, each on a ten-step run of a bundled model, so that each
finds the other's machine code in the cache when its tests reach it. A plain ``pytest`` (no
workers) compiles on first use as before.

The suite compiles on first use rather than running the integrator as Python while it compiles
in the background (``seispound._first_use``; ``SEISPOUND_INTERPRET_SECONDS=0``): its tests call
the integrator thousands of times.
"""

from __future__ import annotations

import os
from pathlib import Path

# the suite compiles as numba does; tests/test_first_use.py runs the first use as Python in child processes
os.environ.setdefault("SEISPOUND_INTERPRET_SECONDS", "0")

_WARM = {"gw0": "two_buildings.toml", "gw1": "yielding_pair.toml"}  # fast driver; general driver


def pytest_sessionstart(session):
    model = _WARM.get(os.environ.get("PYTEST_XDIST_WORKER", ""))
    if model is None:
        return
    import seispound as sp
    from seispound.integrate import integrate
    from seispound.simulation import newmark_substeps, run_inputs

    m = sp.load_model(Path(__file__).resolve().parents[1] / "models" / model)
    system, motions = run_inputs(m)
    rows = motions.rows[:, :11]
    integrate(system, rows, m.analysis.dt, 10, m.analysis.newmark, substeps=newmark_substeps(m, system))
