"""No analysis step jumps over an impact; onsets are located in time, not at step ends.

References: average-acceleration Newmark = trapezoidal rule, which conserves
w^2 u^2 + v^2 exactly for an undamped SDOF for ANY step size (Chopra, Dynamics
of Structures, Sec. 5.5; Hughes 1987, Sec. 9.1), including the shortened steps
that land on an event.  Hence the approach velocity at the onset of a contact at
u = g is exactly v0 = sqrt(V^2 - w^2 g^2), whatever the phase error.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from seispound.contact import make_law
from seispound.integrate import integrate
from seispound.structure import Building, Gap, NoDamping, assemble

MASS = 1000.0


def one_storey(name, w, v0=0.0):
    return Building(name, [MASS], [MASS * w * w], [3.0], NoDamping(), initial_velocity=v0)


# limit on |v0 / v_exact - 1|: measured -4.6e-12, -9.2e-8, -5.0e-12
@pytest.mark.parametrize("overlap, limit", [(1e-4, 1.5e-11), (1e-5, 2.5e-7), (1e-6, 1.5e-11)])
def test_grazing_contact_inside_one_step_is_detected(overlap, limit):
    """Gap = V/w - overlap: the striker's excursion passes the gap for a few ms inside one 50 ms step.

    T = 1.1 s, V = 0.1 m/s: the maximum V/w = 17.5 mm is reached at t ~ 0.277 s, i.e.
    inside the step (0.25, 0.30); neither step end is in contact.  The overlap
    lasts 2 sqrt(2 overlap / (V w)) = 11.8 ms, 3.7 ms and 1.2 ms (exact ODE) for
    the three cases.
    """
    T, V, dt = 1.1, 0.1, 0.05
    w = 2.0 * math.pi / T
    gap = V / w - overlap
    system = assemble([one_storey("A", w, V), one_storey("B", w)], [Gap(("A", "B"), gap)],
                      make_law("Hd", stiffness=1e10, restitution=0.65))
    r = integrate(system, np.zeros(13), dt, 12)
    # no step END is in contact: the contact would be invisible on the output grid
    delta = r.displacement[:, 0] - r.displacement[:, 1] - gap
    assert np.all(delta[r.time <= 0.25 + 1e-12] < 0.0)
    imp = r.impacts
    assert imp["gap"].size == 1, f"grazing contact of {overlap} m missed"
    t0, dur = imp["t0"][0], imp["dur"][0]
    assert 0.25 < t0 and t0 + dur < 0.30  # closes and reopens within one analysis step
    v_exact = math.sqrt(V * V - (w * gap) ** 2)  # energy conservation of the trapezoidal rule
    print(f"MEASURED grazing overlap {overlap:g} m: t0 = {t0:.6f} s, dur = {1e3 * dur:.3f} ms, "
          f"v0 = {imp['v0'][0]:.6e} (exact {v_exact:.6e}, {imp['v0'][0] / v_exact - 1:+.1e})")
    assert imp["v0"][0] == pytest.approx(v_exact, rel=limit)
    assert imp["vout"][0] > 0.0


@pytest.mark.parametrize("dt", [0.05, 0.013])
def test_free_flight_onset_time(dt):
    """Very soft storeys (w = 1e-3 rad/s): onset at t = gap / (vA - vB) to 1e-10 s, approach velocity exact.

    With springs, delta = (vA - vB)/w sin(w t) - gap, so the exact onset is
    asin(gap w / (vA - vB)) / w = gap / v (1 + (w gap / v)^2 / 6 + ...): here
    the spring correction is 4.9e-11 s and the Newmark phase error O((w dt)^2) is
    below 1e-12 s: the onset equals the exact one with springs to round-off.
    """
    w = 1e-3
    va, vb, gap = 0.1, -0.05, 0.01
    system = assemble([one_storey("A", w, va), one_storey("B", w, vb)], [Gap(("A", "B"), gap)],
                      make_law("LVe", stiffness=1e8, restitution=0.5))
    n = int(math.ceil(0.2 / dt))
    r = integrate(system, np.zeros(n + 1), dt, n)
    imp = r.impacts
    assert imp["gap"].size >= 1
    t_free = gap / (va - vb)
    t_spring = math.asin(gap * w / (va - vb)) / w
    err = abs(imp["t0"][0] - t_free)
    print(f"MEASURED free flight dt={dt}: onset {imp['t0'][0]!r} s, |t0 - gap/v| = {err:.1e} s, "
          f"|t0 - t_spring| = {abs(imp['t0'][0] - t_spring):.1e} s, v0 "
          f"{imp['v0'][0] / ((va - vb) * math.cos(w * t_spring)) - 1:+.1e}")
    assert err <= 1e-10  # measured 4.9e-11 s: the spring correction
    # measured 1.4e-17 / 2.8e-17 s and 2.2e-16 / 3.3e-16: round-off, ~10x
    assert abs(imp["t0"][0] - t_spring) <= 3e-16
    assert imp["v0"][0] == pytest.approx((va - vb) * math.cos(w * t_spring), rel=3e-15)
    # the analysis step containing the onset is not an output-grid event: t0 is off the grid
    assert abs(t_free / dt - round(t_free / dt)) > 1e-3


def test_impact_between_two_output_steps_is_resolved():
    """A full LVe impact (2.4 ms) inside one 50 ms analysis step still gives e (substeps inside the step)."""
    w = 1e-3
    va, gap = 0.1, 0.0104  # onset at 0.104 s, end ~0.1064 s: both inside the step (0.10, 0.15)
    system = assemble([one_storey("A", w, va), one_storey("B", w)], [Gap(("A", "B"), gap)],
                      make_law("LVe", stiffness=1e8, restitution=0.5))
    r = integrate(system, np.zeros(5), 0.05, 4)
    imp = r.impacts
    assert imp["gap"].size == 1
    assert 0.10 < imp["t0"][0] and imp["t0"][0] + imp["dur"][0] < 0.15
    assert np.all(r.force[:, 0] == 0.0)  # never seen on the output grid ...
    print(f"MEASURED impact inside one step: e {imp['vout'][0] / imp['v0'][0] / 0.5 - 1:+.1e} of 0.5, momentum "
          f"{r.velocity[-1].sum() / va - 1:+.1e}")
    assert imp["vout"][0] / imp["v0"][0] == pytest.approx(0.5, rel=2.5e-3)  # ... yet fully resolved (8.6e-4)
    # momentum: m vA = m (uA' + uB') after the impact (equal masses, negligible springs)
    assert r.velocity[-1].sum() == pytest.approx(va, rel=5e-8)  # measured -2.0e-8
