"""The general driver (``_general.py``: every law through the material protocol, coefficient-vector
elements, Newton on the condensed forces) against the fast one on rows both take.

The fast driver is run with every optimisation off that the general one lacks (Newmark throughout, no
free flight, single-rate), so the two integrate the same discrete equations; they differ only in the
order of floating-point operations and, through it, in where inside its tolerance (1e-7 of a step's
travel) an event lands.  The general driver runs with its free flight on (the Newmark substeps composed
into one map per building, ``integrate/transition.py``) and off: both integrate those equations.
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


@pytest.mark.parametrize("free_flight", [False, True])
@pytest.mark.parametrize("name", NAMES)
def test_general_driver_equals_the_fast_one(name, free_flight):
    system, ag, dt, nsteps, kw = CASES[name]
    newmark = kw.get("newmark")
    fast = integrate(system, ag, dt, nsteps, newmark=newmark, scheme="newmark", free_flight=False, multirate=False)
    general = integrate(system, ag, dt, nsteps, newmark=newmark, driver="general", scheme="newmark",
                        free_flight=free_flight)
    assert general.driver == "general" and fast.driver == "fast"
    beta_gamma = (newmark.beta, newmark.gamma) if newmark else (0.25, 0.5)
    assert (general.stats["free_flight_steps"] > 0) == (free_flight and beta_gamma == (0.25, 0.5))
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


def test_exact_free_flight_equals_the_modal_one():
    """Two formulations of the exact step for a piecewise-linear ground acceleration: the general
    driver's state transition of each building (one matrix exponential, ``transition.py``) and the fast
    driver's modes (Nigam & Jennings' closed form per mode, ``_exact.py``), on a row that never pounds."""
    system, ag, dt, nsteps, kw = CASES["pair-Hd-twin"]
    fast = integrate(system, ag, dt, nsteps, scheme="exact")
    general = integrate(system, ag, dt, nsteps, scheme="exact", driver="general")
    assert general.stats["free_flight_steps"] == nsteps and general.scheme == "exact"
    errs = {k: _rel(getattr(general, k), getattr(fast, k))
            for k in ("displacement", "velocity", "acceleration", "energy", "peak_displacement")}
    print("MEASURED exact free flight, transition vs modes:", {k: f"{v:.1e}" for k, v in errs.items()})
    assert max(errs.values()) <= 1e-11, errs
