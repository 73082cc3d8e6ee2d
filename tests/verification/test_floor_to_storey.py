"""A floor striking the columns of a storey: momentum, energy and restitution of the impact, and the limit
where the heights coincide.

A one-storey body A (floor at 4.5 m) approaches B, whose floors stand at 3 m and 6 m: A strikes B's second
storey half way up (w = 0.5).  The storey springs are 1 N/m, so over the impact the three masses are free
and the closed forms of a two-body impact hold at the contact point, where B's apparent mass is
1 / ((1 - w)^2 / m1 + w^2 / m2) (an impulse J there changes v1 by (1 - w) J / m1 and v2 by w J / m2):

* total momentum mA vA + m1 v1 + m2 v2 is conserved;
* B's floors take the impulse in the ratio (1 - w)/m1 : w/m2;
* the contact point separates at e times the approach velocity (LVe with tension: exact for two bodies);
* the kinetic energy lost is mu (1 - e^2) v0^2 / 2 with mu = mA m_app / (mA + m_app).
"""

import numpy as np
import pytest

from seispound.contact import make_law
from seispound.integrate import integrate
from seispound.structure import Building, Gap, NoDamping, assemble

MA, M1, M2, V0, E = 2.0e4, 1.0e5, 6.0e4, 0.5, 0.6


def _row(height_a=4.5, law=None, levels="lower"):
    a = Building("A", [MA], [1.0], [height_a], NoDamping(), initial_velocity=V0)
    b = Building("B", [M1, M2], [1.0, 1.0], [3.0, 3.0], NoDamping())
    law = law or make_law("LVe", stiffness=5e8, restitution=E, tension=True)
    return assemble([a, b], [Gap(("A", "B"), size=1e-3, law=law, levels=levels)])


def _run(system, t_end=0.05, dt=1e-4):
    n = int(round(t_end / dt))
    return integrate(system, np.zeros(n + 1), dt, n)


def test_impact_against_a_storey_conserves_momentum_and_loses_the_closed_form_energy():
    system = _row()
    (link,) = system.links
    assert link.kind == "floor-to-storey" and link.right_floor == 2
    assert link.right_weight == pytest.approx(0.5, rel=1e-14)  # measured: 0.5 exactly
    raw = _run(system)
    assert raw.driver == "general"
    assert raw.impacts["t0"].size == 1
    w = 0.5
    m_app = 1.0 / ((1 - w) ** 2 / M1 + w ** 2 / M2)
    mu = MA * m_app / (MA + m_app)
    m = system.mass
    v = raw.velocity[-1]  # long after the impact (it lasts ~ pi sqrt(mu / k) = 11 ms)
    p0, p1 = MA * V0, float(m @ v)
    ke0, ke1 = 0.5 * MA * V0 ** 2, 0.5 * float(m @ (v * v))
    lost = 0.5 * mu * (1 - E ** 2) * V0 ** 2
    dv1, dv2 = v[1], v[2]
    e_sim = raw.impacts["vout"][0] / raw.impacts["v0"][0]
    print(f"MEASURED impact on a storey: momentum {p1 / p0 - 1:+.1e}, energy lost {(ke0 - ke1) / lost - 1:+.1e} of "
          f"the closed form, impulse split {dv1 * M1 / (dv2 * M2):.6f} (1 expected; {dv1 * M1 / (dv2 * M2) - 1:+.1e}), "
          f"restitution {e_sim:.6f} ({e_sim / E - 1:+.1e}); apparent-mass weight {link.right_weight!r}")
    # measured: momentum -8.9e-9 (the 1 N/m storey springs over the run), energy lost -2.7e-5 of the closed
    # form, impulse split +2.8e-9, restitution +2.4e-5; the weight 0.5 exactly
    assert abs(p1 / p0 - 1) <= 2.5e-8
    assert abs((ke0 - ke1) / lost - 1) <= 7e-5
    assert abs(dv1 * M1 / (dv2 * M2) - 1) <= 8e-9  # (1 - w)/w = 1 here
    assert abs(e_sim / E - 1) <= 6e-5


def test_elastic_impact_against_a_storey_keeps_the_energy():
    raw = _run(_row(law=make_law("Hertz", stiffness=5e9)))
    m = _row().mass
    v = raw.velocity[-1]
    ke0, ke1 = 0.5 * MA * V0 ** 2, 0.5 * float(m @ (v * v))
    print(f"MEASURED elastic impact on a storey: kinetic energy {ke1 / ke0 - 1:+.2e}")
    assert abs(ke1 / ke0 - 1) <= 3.5e-6  # measured -1.34e-6


def test_heights_coinciding_is_the_floor_to_floor_gap():
    """A's floor 0.1 mm above B's first floor (w = 3.3e-5 on storey 2) against exactly level with it."""
    level = _run(_row(height_a=3.0))
    near = _run(_row(height_a=3.0001))
    assert _row(height_a=3.0).links[0].kind == "floor-to-floor"
    assert _row(height_a=3.0001).links[0].kind == "floor-to-storey"
    dv = float(np.abs(near.velocity - level.velocity).max() / np.abs(level.velocity).max())
    df = float(abs(near.peak_force[0] / level.peak_force[0] - 1))
    print(f"MEASURED heights 0.1 mm apart against coinciding: velocities {dv:.1e}, peak force {df:.1e}")
    assert dv <= 5e-5 and df <= 1.5e-5  # measured 1.8e-5 and 5.6e-6


def test_levels_choose_the_elements():
    a = Building("A", [1e5] * 3, [1e8] * 3, [4.5] * 3, NoDamping())
    b = Building("B", [1e5] * 6, [1e8] * 6, [3.0] * 6, NoDamping())
    law = make_law("Hd", stiffness=2.75e9, restitution=0.65)
    kinds = {lv: [(l.height, l.kind) for l in assemble([a, b], [Gap(("A", "B"), 0.01, law, levels=lv)]).links]
             for lv in ("floors", "lower", "all")}
    assert kinds["floors"] == [(9.0, "floor-to-floor")]
    assert [h for h, _ in kinds["lower"]] == [4.5, 9.0, 13.5]
    assert [h for h, _ in kinds["all"]] == [3.0, 4.5, 6.0, 9.0, 12.0, 13.5]
    assert [k for _, k in kinds["all"]].count("floor-to-floor") == 1
