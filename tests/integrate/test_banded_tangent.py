"""The general driver's banded-tangent Newton (``_general_solve._newton_tangent``) against its dense
condensed Newton (``_newton._newton``, ``tangent=False``): the off switch.

Both iterate on the same condensed residual of the active elements' forces to the same tolerance
(rtol 1e-10 of the largest force); the tangent path solves each Newton update through the banded
T = A + B K_t B^T (with the closed gaps by Woodbury) instead of the dense I + K_t G.  So they are the
same discrete solution and differ by round-off and the Newton tolerance: a regression guard on the
algebra (an identity), not a verification of the physics (that is ``tests/verification``).
"""

import copy
import warnings

import numpy as np
import pytest

from seispound import load_model
from seispound.integrate import integrate
from seispound.simulation import _run_inputs
from seispound.storey import StoreyLaw
from tests._models import REPO


def _row(kind):
    m = load_model(REPO / "models" / "row_of_three.toml")
    m.analysis.duration = 10.0
    for b in m.buildings:
        b.storey_law = (StoreyLaw(kind="bilinear", yield_drift=0.01, post_yield_ratio=0.05) if kind == "bilinear"
                        else StoreyLaw(kind="bouc-wen", yield_drift=0.01, post_yield_ratio=0.05, n=2.0))
        b.validate()
    m.__dict__.pop("_assembled", None)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        _, system, motions = _run_inputs(m)
    return system, motions, m.analysis


def _rel(a, b):
    return float(np.abs(a - b).max() / max(np.abs(b).max(), 1e-300))


@pytest.mark.parametrize("kind", ["bilinear", "bouc-wen"])
def test_banded_tangent_equals_the_dense_condensed_newton(kind):
    system, motions, an = _row(kind)
    # every step on the physical path (no hysteretic free flight), where the two Newton iterations run
    runs = {tan: integrate(system, motions.rows, an.dt, an.nsteps, an.newmark, tangent=tan, hysteretic_flight=False)
            for tan in (True, False)}
    a, b = runs[True], runs[False]
    assert a.driver == "general" and a.impacts["t0"].size > 10  # storeys with history and pounding
    errs = {k: _rel(getattr(a, k), getattr(b, k)) for k in ("displacement", "acceleration", "force", "energy")}
    errs["storey_force"] = _rel(a.storey_force, b.storey_force)
    print(f"MEASURED {kind}: banded tangent vs dense condensed", {k: f"{v:.1e}" for k, v in errs.items()},
          "impacts", a.impacts["t0"].size)
    # measured on the canonical row, 10 s: at most 5.2e-13 (bilinear, contact force), 1.3e-13 (Bouc-Wen)
    assert max(errs.values()) <= 1.5e-12, errs
    np.testing.assert_array_equal(a.impacts["gap"], b.impacts["gap"])
    assert a.stats["iterations"] == b.stats["iterations"]
