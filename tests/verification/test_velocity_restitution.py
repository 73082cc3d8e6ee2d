"""Velocity-dependent restitution: free two-body impacts from v0 = 0.01 to 2 m/s.

Two bodies of 110 and 109 kg (the seed's slabs with their pounding elements) on
springs of 100 s period (free bodies to 1e-6 during a millisecond impact),
touching at t = 0, the striker arriving at v0.  The simulated restitution is
the catalogue's vout / v0.  Closed forms for two free bodies (see
test_impact_restitution.py for their derivation):

* LVe with tension, Hd and LHC return exactly the e their damping was set
  from, for any mass and any exponent; so with e given as a function of the
  approach velocity, every impact must return e(v0).
* HC (Hunt & Crossley 1975, fixed damping constant c): zeta = 3/2 c k for
  every impact, so seed Eq. 8 read backwards gives e(v0) exactly
  (e with s(e) = 3/2 c v0; ``restitution_from_s``).  It is checked against a
  root of Eq. 8 found here with scipy's brentq (the reference twin's own solver).
* MLVe and NIVe miss their target e even at constant e (Mahmoud 2008's damping
  ratio is approximate; Jankowski 2005's too): their deviations from e(v0) are
  measured and printed (docs/verification.md tabulates them), not asserted.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
import pytest

from seispound.contact import ExponentialRestitution, make_law
from seispound.integrate import Newmark, integrate
from seispound.structure import Building, Gap, NoDamping, assemble

M1, M2 = 110.0, 109.0
V0S = (0.01, 0.03, 0.1, 0.3, 1.0, 2.0)
FORM = ExponentialRestitution(e0=0.9, e_inf=0.4, v_c=0.5)
K_LINEAR, K_HERTZ = 1e8, 1e9


def _body(name, mass, v0=0.0):
    return Building(name, [mass], [mass * (2 * math.pi / 100.0) ** 2], [1.0], NoDamping(), initial_velocity=v0)


@lru_cache(maxsize=None)
def impact(law, v0, **params):
    contact = make_law(law, **dict(params))
    system = assemble([_body("A", M1, v0), _body("B", M2)], [Gap(("A", "B"), 0.0)], contact)
    dt = 1e-3
    n = 60
    r = integrate(system, np.zeros(n + 1), dt, n, Newmark(contact_substeps=64))
    imp = r.impacts
    assert imp["gap"].size == 1, imp
    return imp["vout"][0] / imp["v0"][0], imp["e"][0], imp["v0"][0]


def _params(law):
    k = K_LINEAR if law in ("LVe", "MLVe", "LHC") else K_HERTZ
    return dict(stiffness=k, restitution=FORM)


@pytest.mark.parametrize("law", ["LVe", "Hd", "LHC"])
def test_every_impact_returns_e_of_its_approach_velocity(law):
    worst, used = 0.0, 0.0
    for v0 in V0S:
        e_sim, e_used, v_app = impact(law, v0, **_params(law))
        target = float(FORM(v_app))
        used = max(used, abs(e_used / target - 1))
        assert e_used == pytest.approx(target, rel=1e-14)  # the catalogue keeps the e used (measured: equal)
        worst = max(worst, abs(e_sim / target - 1.0))
    print(f"MEASURED {law}: e(v0) = {FORM!r}, worst |e_sim / e(v0) - 1| over v0 = {V0S}: {worst:.2e}; "
          f"catalogue e against e(v0) {used:.1e}")
    assert worst <= 8e-4  # measured 2.7e-4 (LVe), 3.1e-4 (Hd), 3.3e-4 (LHC)


def _hc_exact(c, v0):
    """e from seed Eq. 8, (1 + e) = x ln((x + 1) / (x - e)) with x = k / (zeta v0) = 1 / (3/2 c v0), by brentq.

    f(e) = x ln((x + 1) / (x - e)) - (1 + e) is negative at e = 0 and positive
    at e = min(1, x) (the branch x > e of the physical root).
    """
    from scipy.optimize import brentq

    x = 1.0 / (1.5 * c * v0)
    top = min(1.0, x * (1.0 - 1e-12))
    return brentq(lambda e: x * math.log((x + 1.0) / (x - e)) - (1.0 + e), 1e-12, top, xtol=1e-15, rtol=1e-15)


def test_hunt_crossley_restitution_falls_with_approach_velocity():
    c = 0.4  # s/m
    rows, used = [], 0.0
    for v0 in V0S:
        e_sim, e_used, v_app = impact("HC", v0, stiffness=K_HERTZ, damping_constant=c)
        exact = _hc_exact(c, v_app)
        rows.append((v0, e_sim, exact))
        used = max(used, abs(e_used / exact - 1))
        assert e_used == pytest.approx(exact, rel=3e-12)  # measured <= 3.3e-13 (two root solvers), ~10x
        assert e_sim == pytest.approx(exact, rel=5e-4)  # measured <= 2.1e-4
    print("MEASURED HC c = 0.4 s/m: v0, e_sim, e_exact: " + "; ".join(f"{a:g} {b:.5f} {x:.5f}" for a, b, x in rows)
          + f"; worst e_sim / e_exact - 1 {max(abs(b / x - 1) for _, b, x in rows):.2e}, catalogue e {used:.1e}")
    assert rows[0][1] > 0.99 and rows[-1][1] < 0.6  # e ~ 1 - c v0 at low speed, falling


@pytest.mark.parametrize("law", ["MLVe", "NIVe"])
def test_mlve_and_nive_deviations_are_measured(law):
    """Printed for the table in docs/verification.md.  MLVe is checked against its closed form at e(v0)
    (approach-only damped oscillator, ``e_mlve`` of test_impact_restitution.py); NIVe has none, and its
    deviation is only bounded (it still dissipates: 0 < e_sim < 1)."""
    from .test_impact_restitution import e_mlve

    devs, cf = [], 0.0
    for v0 in V0S:
        e_sim, e_used, v_app = impact(law, v0, **_params(law))
        devs.append(e_sim / e_used - 1.0)
        if law == "MLVe":
            cf = max(cf, abs(e_sim / e_mlve(e_used) - 1))
            assert e_sim == pytest.approx(e_mlve(e_used), rel=6e-4)  # measured <= 2.2e-4
        assert 0.0 < e_sim < 1.0
    print(f"MEASURED {law}: e_sim / e(v0) - 1 at v0 = {V0S}: " + ", ".join(f"{d:+.3f}" for d in devs)
          + (f"; worst against the closed form {cf:.2e}" if law == "MLVe" else ""))
