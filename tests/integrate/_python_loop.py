"""Run cases of ``kernel_reference.cases`` through the time loop as Python (``NUMBA_DISABLE_JIT``).

``python -m tests.integrate._python_loop OUT.npz NAME:NSTEPS:DRIVER ...`` (a subprocess of
``test_driver.py``: numba reads ``NUMBA_DISABLE_JIT`` once, at import).  The borrowed-array
intrinsics run their Python forms (``_borrow._PYTHON``).
"""

from __future__ import annotations

import sys

import numpy as np

FIELDS = ("displacement", "velocity", "acceleration", "force", "energy", "peak_displacement", "peak_force")


def run(name: str, nsteps: int, driver: str):
    """The raw result of case ``name``'s first ``nsteps`` steps on ``driver``."""
    from seispound.integrate import integrate
    from tests.integrate.kernel_reference import cases

    system, ag, dt, _, kw = cases()[name]
    return integrate(system, ag[..., :nsteps + 1], dt, nsteps, driver=driver, **kw)


def main(out: str, specs: list[str]) -> None:
    saved = {}
    for spec in specs:
        name, nsteps, driver = spec.split(":")
        raw = run(name, int(nsteps), driver)
        for f in FIELDS:
            saved[f"{spec}/{f}"] = np.asarray(getattr(raw, f))
        saved[f"{spec}/t0"] = np.asarray(raw.impacts["t0"])
    np.savez(out, **saved)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2:])
