"""The general driver (``_general.py``: every law through the material protocol, coefficient-vector
elements, Newton on the condensed forces) against the fast one on rows both take.

The fast driver is run with every optimisation off that the general one lacks (Newmark throughout, no
free flight, single-rate), so the two integrate the same discrete equations; they differ only in the
order of floating-point operations and, through it, in where inside its tolerance (1e-7 of a step's
travel) an event lands.
"""

import numpy as np
import pytest

from seispound.integrate import integrate
from tests.integrate.kernel_reference import cases

CASES = cases()
NAMES = ["pair-LVe", "pair-LVe-clamped", "pair-Hd", "pair-NIVe", "pair-MLVe", "row3-Hd", "pair-Hd-twin",
         "pair-Hd-linear-acceleration"]


def _rel(a, b):
    return float(np.abs(a - b).max() / max(np.abs(b).max(), 1e-300))


@pytest.mark.parametrize("name", NAMES)
def test_general_driver_equals_the_fast_one(name):
    system, ag, dt, nsteps, kw = CASES[name]
    newmark = kw.get("newmark")
    fast = integrate(system, ag, dt, nsteps, newmark=newmark, scheme="newmark", free_flight=False, multirate=False)
    general = integrate(system, ag, dt, nsteps, newmark=newmark, driver="general")
    assert general.driver == "general" and fast.driver == "fast"
    errs = {k: _rel(getattr(general, k), getattr(fast, k))
            for k in ("displacement", "velocity", "acceleration", "energy", "peak_displacement")}
    if np.any(fast.force):
        errs["force"] = _rel(general.force, fast.force)
    print(f"MEASURED {name}: general vs fast", {k: f"{v:.1e}" for k, v in errs.items()})
    assert max(errs.values()) <= 1e-7, errs
    np.testing.assert_array_equal(general.impacts["gap"], fast.impacts["gap"])
    np.testing.assert_allclose(general.impacts["t0"], fast.impacts["t0"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(general.impacts["e"], fast.impacts["e"], rtol=1e-9)


def test_driver_choice_follows_the_row():
    system, ag, dt, nsteps, _ = CASES["pair-Hd"]
    assert not system.needs_general_driver
    assert integrate(system, ag[:21], dt, 20).driver == "fast"
    with pytest.raises(ValueError, match="driver must be"):
        integrate(system, ag[:21], dt, 20, driver="slow")
