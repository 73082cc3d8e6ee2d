"""Distributed-mass floors and bodies (axial rods) against closed forms.

* the first free-free axial frequency c / 2L (c = sqrt(EA L / m)) and its O(1/N^2) convergence;
* Saint-Venant's impact of two elastic rods (Goldsmith 1960, Impact, Sec. 3.3; Graff 1975, Wave Motion in
  Elastic Solids, Sec. 2.4): equal rods stay in contact 2L/c at the force rho c A v0 / 2 and exchange
  their velocities (e = 1); a short rod striking a long one (same material and section) leaves the long one
  with the mean velocity v0 L_short / L_long and itself at rest (e = L_short / L_long), after 2 L_short / c;
* a floor whose mass gathers toward one face (linear density 1 + g (x/L - 1/2)): the free-free axial modes of
  EA u'' + omega^2 rho(x) u = 0 are Airy functions (Abramowitz & Stegun 1964, 10.4; the reduction derived
  here): u = A Ai(z) + B Bi(z), z = -(kappa beta)^(1/3) (x + alpha / beta), kappa = omega^2 rho_0 / EA,
  rho / rho_0 = alpha + beta x; u'(0) = u'(L) = 0 gives Ai'(z_0) Bi'(z_L) - Ai'(z_L) Bi'(z_0) = 0;
* the lumped limit: a very stiff rod floor moves as the lumped floor (uniform or tapered);
* an attachment on a joint: the free-free two-mass mode omega^2 = k_j (1/m + 1/m_a).
"""

import math

import numpy as np
import pytest
from scipy.linalg import eigh
from scipy.optimize import brentq
from scipy.special import airy

from seispound.contact import make_law
from seispound.floor import Attachment, RodFloor
from seispound.integrate import integrate
from seispound.structure import Building, Gap, NoDamping, RayleighDamping, assemble
from tests.verification._helpers import el_centro

MASS_PER_LENGTH, EA = 100.0, 1e8  # kg/m, N: c = 1000 m/s
C = math.sqrt(EA / MASS_PER_LENGTH)


def _body(name, length, segments, v0=0.0, attachment=None):
    """A free body: one 'storey' of 1 N/m (a pendulum's restoring force is negligible over an impact)."""
    rod = RodFloor(segments=segments, length=length, axial_stiffness=EA, attachment=attachment)
    return Building(name, [MASS_PER_LENGTH * length], [1.0], [1.0], NoDamping(), initial_velocity=v0,
                    floor_model=rod)


def test_first_axial_frequency_converges_to_c_over_2L():
    errs = []
    for n in (4, 8, 16, 32):
        M, _, K = assemble([_body("A", 1.0, n)], []).matrices()
        w = np.sqrt(np.abs(eigh(K, M, eigvals_only=True)))
        errs.append(w[1] / (2 * math.pi) / (C / 2.0) - 1)
    print("MEASURED first axial frequency against c/2L, N = 4, 8, 16, 32:", ", ".join(f"{e:+.1e}" for e in errs))
    assert abs(errs[-1]) <= 5e-4  # measured -4.0e-4: the lumped rod's O(1/N^2) error at N = 32
    assert all(3.9 <= errs[k] / errs[k + 1] <= 4.1 for k in range(3))  # O(1/N^2), from below
    assert all(e < 0 for e in errs)


def _airy_first_axial_hz(g, length=1.0):
    """The first nonzero free-free axial frequency [Hz] of a rod of linear density rho_0 (1 + g (x/L - 1/2))."""
    alpha, beta = 1.0 - g / 2.0, g / length

    def det(omega):
        c = np.cbrt(omega ** 2 * MASS_PER_LENGTH / EA * beta)
        z0, z1 = -c * (alpha / beta), -c * (length + alpha / beta)
        _, a0, _, b0 = airy(z0)
        _, a1, _, b1 = airy(z1)
        return a0 * b1 - a1 * b0

    w0 = math.pi * C / length  # the uniform rod's; the tapered one's lies within a few per cent of it
    return brentq(det, 0.7 * w0, 1.3 * w0, xtol=1e-14, rtol=1e-14) / (2.0 * math.pi)


@pytest.mark.parametrize("centre", [0.4, 0.62])
def test_tapered_rod_first_axial_frequency_is_the_airy_root(centre):
    g = 12.0 * (centre - 0.5)
    exact = _airy_first_axial_hz(g)
    errs = []
    for n in (50, 100, 200):
        rod = RodFloor(segments=n, length=1.0, axial_stiffness=EA, centre_of_mass=centre)
        shares = rod.node_shares()
        x = np.linspace(0.0, 1.0, n + 1)
        assert abs(shares.sum() - 1.0) <= 1e-14
        assert abs(shares @ x - centre) <= abs(g) / (20 * n ** 2)  # the lumped centroid: measured g / (24 N^2) off
        errs.append(rod.first_axial_omega(MASS_PER_LENGTH) / (2 * math.pi) / exact - 1)
    print(f"MEASURED tapered rod (centre of mass {centre}) against the Airy root {exact:.2f} Hz, N = 50, 100, 200: "
          + ", ".join(f"{e:+.1e}" for e in errs))
    assert abs(errs[-1]) <= 3e-5  # measured -1.2e-5 and -1.3e-5, the lumped rod's O(1/N^2): uniform -(pi/N)^2/24 = -1.0e-5 at N = 200
    assert 3.5 <= errs[0] / errs[1] <= 4.5 and 3.5 <= errs[1] / errs[2] <= 4.5


def _impact(l1, l2, n1, n2, v0=0.1, dt=1e-5):
    """Rod 1 (left) at v0 strikes rod 2 at rest; the contact spring equals one segment (EA N / L): the
    interface is one more segment, so the discrete rods do not chatter."""
    law = make_law("LVe", stiffness=EA * n1 / l1, restitution=1.0)
    system = assemble([_body("A", l1, n1, v0), _body("B", l2, n2)], [Gap(("A", "B"), 1e-9, law)])
    nsteps = int(round(3.0 * l2 / C / dt))
    raw = integrate(system, np.zeros(nsteps + 1), dt, nsteps)
    b = system.dof_building
    v = raw.velocity[-1]
    V = [float(system.mass[b == k] @ v[b == k] / system.mass[b == k].sum()) for k in (0, 1)]
    imp = raw.impacts
    episode = float(imp["t0"][-1] + imp["dur"][-1] - imp["t0"][0])
    mid = (raw.time > imp["t0"][0] + 0.2 * episode) & (raw.time < imp["t0"][0] + 0.8 * episode)
    return dict(e=(V[1] - V[0]) / v0, V=V, duration=episode, force=float(raw.force[mid, 0].mean()), n=imp["t0"].size)


# limits on the mean force's error and the striker's final velocity / v0: measured -0.17 % and 5.4e-3 (N = 100),
# +0.29 % and 3.5e-3 (N = 200)
@pytest.mark.parametrize("n, force_limit, v_limit", [(100, 4.5e-3, 0.015), (200, 7.5e-3, 0.01)])
def test_saint_venant_equal_rods(n, force_limit, v_limit):
    got = _impact(1.0, 1.0, n, n)
    plateau = MASS_PER_LENGTH * C * 0.1 / 2  # rho c A v0 / 2
    print(f"MEASURED equal rods, N = {n}: contact {got['duration'] / (2.0 / C) - 1:+.2%} of 2L/c, mean force "
          f"{got['force'] / plateau - 1:+.2%} of rho c A v0/2, e = {got['e']:.4f} (1), {got['n']} contact(s); "
          f"striker's velocity {got['V'][0] / 0.1:+.2e} of v0")
    assert abs(got["duration"] / (2.0 / C) - 1) <= 0.01  # measured +0.64 % (N = 100), +0.86 % (N = 200)
    assert abs(got["force"] / plateau - 1) <= force_limit
    assert abs(got["e"] - 1) <= 0.015  # measured 1 - e = 0.0109 (N = 100), 0.0069 (N = 200)
    assert abs(got["V"][0]) <= v_limit * 0.1  # the striker stops


def test_saint_venant_short_rod_strikes_long_one():
    got = [_impact(0.5, 1.0, n, 2 * n) for n in (50, 100, 200)]
    errs = [g["e"] / 0.5 - 1 for g in got]
    print("MEASURED short on long rod, N_short = 50, 100, 200: e against L_short/L_long "
          + ", ".join(f"{e:+.2%}" for e in errs) + f"; contact {got[-1]['duration'] / (1.0 / C) - 1:+.2%} of "
          "2 L_short / c")
    assert abs(errs[-1]) <= 0.015  # measured +1.39 %: the discrete rods' error at N_short = 200
    assert abs(errs[2]) < abs(errs[1]) < abs(errs[0])  # converging
    assert abs(got[-1]["duration"] / (1.0 / C) - 1) <= 0.025  # measured +2.01 %


@pytest.mark.parametrize("centre", [0.5, 0.62])
def test_stiff_rod_floors_move_as_lumped_floors(centre):
    dt, (ag, nsteps) = 0.005, el_centro(6.0, 0.005)
    law = make_law("Hd", stiffness=2.75e9, restitution=0.65)

    def row(rod):
        a = Building("A", [1e5] * 4, [1.3092e8] * 4, [3.0] * 4, RayleighDamping(0.05, (1, 2)), floor_model=rod)
        b = Building("B", [1e5] * 8, [1.1593e8] * 8, [3.0] * 8, RayleighDamping(0.05, (1, 2)))
        return assemble([a, b], [Gap(("A", "B"), 0.02, law)])

    lumped = integrate(row(None), ag, dt, nsteps, driver="general")  # as the rod row steps
    rod = row(RodFloor(segments=4, length=20.0, axial_stiffness=1e15, centre_of_mass=centre))  # above 100 kHz
    stiff = integrate(rod, ag, dt, nsteps)  # no modal basis (non-classical): the general driver, exact
    assert stiff.driver == "general" and stiff.scheme == "exact"
    u = stiff.displacement @ rod.outputs.sensor.T
    err = float(np.abs(u - lumped.displacement).max() / np.abs(lumped.displacement).max())
    df = float(abs(stiff.peak_force.max() / lumped.peak_force.max() - 1))
    print(f"MEASURED stiff rod floors against lumped ones: displacement {err:.2e}, peak force {df:.2e}")
    assert err <= 2e-7 and df <= 1.25e-6  # measured 8.4e-8 and 5.2e-7


def test_attachment_joint_mode():
    m_a, k_j = 15.0, 2e6
    body = Building("A", [400.0], [1.0], [1.0], NoDamping(),
                    floor_model=RodFloor(segments=1, length=1.0, axial_stiffness=1e14,
                                         attachment=Attachment(mass=m_a, joint_stiffness=k_j)))
    other = Building("B", [400.0], [1.0], [1.0], NoDamping())
    system = assemble([body, other], [Gap(("A", "B"), 0.01, make_law("Hd", stiffness=1e9, restitution=0.8))])
    M, _, K = system.matrices()
    w2 = np.sort(eigh(K, M, eigvals_only=True))
    exact = k_j * (1 / 400.0 + 1 / m_a)
    joint = w2[np.argmin(np.abs(w2 - exact))]
    print(f"MEASURED joint mode: {joint / exact - 1:+.2e} of k_j (1/m + 1/m_a)")
    assert abs(joint / exact - 1) <= 1.2e-8  # measured -4.4e-9 (the rod's finite stiffness)
    # the gap acts on the attachment (the right face faces B), with the whole body's mass in the law
    assert system.gap_i[0] == int(np.flatnonzero(system.dof_kind == 4)[0])
