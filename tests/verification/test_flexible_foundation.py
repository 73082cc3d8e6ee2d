"""Flexible foundations: the assembled system against closed forms and an independent formulation.

* Eigenvalues: the package's DOFs are floor displacements relative to the free field (diagonal mass,
  storeys on three DOFs); the textbook formulation (Chopra, Dynamics of Structures, Ch. 20 / Wolf 1985,
  Sec. 2.2) takes them relative to the foundation (coupled mass, diagonal soil springs).  Both are
  written here, the second by hand, and their eigenvalues must agree to round-off.
* The fundamental period against Veletsos & Meek's flexible-base period (Veletsos & Meek 1974;
  ASCE 7-22 Eq. 19.2-3): T~ = T sqrt(1 + k/k_x + k h^2/k_theta), exact for a massless foundation.
* Free vibration through the general driver against the exact solution of the linear ODE
  (matrix exponential of the state matrix), undamped and with the soil's dashpots.
* The cone impedances against the closed forms of Gazetas (1991) for a disk.
"""

import math

import numpy as np
import pytest
from scipy.linalg import eigh, expm

from seispound.foundation import Foundation, Footing, Soil, cone_impedances
from seispound.integrate import integrate
from seispound.structure import Building, NoDamping, RayleighDamping, assemble
from tests.verification._helpers import uniform_stiffness

M, H = 1e5, 3.0


def _relative_formulation(masses, stiffness, heights, m0, inertia, kx, kt):
    """M, K in coordinates (x_1..x_N relative to the rigid base, u0, theta): coupled mass, diagonal soil."""
    n = len(masses)
    z = np.cumsum(heights)
    Mr = np.zeros((n + 2, n + 2))
    for i in range(n):
        r = np.zeros(n + 2)  # total displacement of floor i = x_i + u0 + z_i theta
        r[i], r[n], r[n + 1] = 1.0, 1.0, z[i]
        Mr += masses[i] * np.outer(r, r)
    Mr[n, n] += m0
    Mr[n + 1, n + 1] += inertia
    Kr = np.zeros((n + 2, n + 2))
    for i in range(n):
        Kr[i, i] += stiffness[i]
        if i > 0:
            Kr[i - 1, i - 1] += stiffness[i]
            Kr[i, i - 1] -= stiffness[i]
            Kr[i - 1, i] -= stiffness[i]
    Kr[n, n] = kx
    Kr[n + 1, n + 1] = kt
    return Mr, Kr


def _building(n, m0, inertia, kx, kt, cx=0.0, ct=0.0, damping=None, floor_inertia=0.0):
    k = uniform_stiffness(M, n, 0.1 * n)
    f = Foundation(mass=m0, rotary_inertia=inertia, floor_rotary_inertia=floor_inertia, sway_stiffness=kx,
                   sway_damping=cx, rocking_stiffness=kt, rocking_damping=ct)
    return Building("A", [M] * n, [k] * n, [H] * n, damping or NoDamping(), foundation=f), k


# round-off (measured 8.9e-16, 8.9e-16, 3.0e-14), so ~10x: it varies with LAPACK / the CPU
@pytest.mark.parametrize("n, limit", [(1, 1e-14), (3, 1e-14), (8, 3e-13)])
def test_eigenvalues_equal_the_relative_formulation(n, limit):
    b, k = _building(n, 0.3 * M * n, 0.1 * M * n * (n * H) ** 2, 5e8, 2e10, floor_inertia=2e5)
    Ma, _, Ka = assemble([b], []).matrices()
    w2 = eigh(Ka, Ma, eigvals_only=True)
    Mr, Kr = _relative_formulation([M] * n, [k] * n, [H] * n, 0.3 * M * n, 0.1 * M * n * (n * H) ** 2 + n * 2e5,
                                   5e8, 2e10)
    w2r = eigh(Kr, Mr, eigvals_only=True)
    err = np.abs(w2 / w2r - 1).max()
    print(f"MEASURED {n} storeys on a foundation: eigenvalues against the relative formulation {err:.1e}")
    assert err <= limit


# measured +1.3e-8 (the formula is exact for a massless foundation), +2.5e-3, +6.5e-3, +1.4e-2
@pytest.mark.parametrize("m0_ratio, bound", [(1e-6, 3e-8), (0.2, 6e-3), (0.5, 0.015), (1.0, 0.02)])
def test_one_storey_period_equals_veletsos_meek(m0_ratio, bound):
    """T~/T = 1.18; the formula is exact for a massless foundation, and a foundation as heavy as the
    floor (with rotary inertia m0 h^2 / 4) lengthens the period by 1.4 % more."""
    kx, kt = 2e9, 1.8e10
    b, k = _building(1, m0_ratio * M, m0_ratio * 0.25 * M * H * H, kx, kt)
    Ma, _, Ka = assemble([b], []).matrices()
    T = 2 * math.pi / math.sqrt(eigh(Ka, Ma, eigvals_only=True)[0])
    T_vm = 2 * math.pi * math.sqrt(M / k) * math.sqrt(1 + k / kx + k * H * H / kt)
    print(f"MEASURED foundation mass {m0_ratio:g} m: period {T:.6f} s, Veletsos-Meek {T_vm:.6f} s "
          f"({T / T_vm - 1:+.1e})")
    assert abs(T / T_vm - 1) <= bound


def test_multistorey_period_within_two_percent_of_veletsos_meek():
    """Five storeys: VM on the first mode's equivalent oscillator (effective mass, height, stiffness)."""
    n, kx, kt = 5, 3e8, 2e10
    b, k = _building(n, 0.1 * M * n, 0.02 * M * n * (n * H) ** 2, kx, kt)
    w, phi = b.modes()
    p = phi[:, 0]
    m_star = (M * p.sum()) ** 2 / (M * (p * p).sum())
    h_star = (M * p * b.floor_heights).sum() / (M * p).sum()
    k_star = m_star * w[0] ** 2
    T_vm = 2 * math.pi / w[0] * math.sqrt(1 + k_star / kx + k_star * h_star ** 2 / kt)
    Ma, _, Ka = assemble([b], []).matrices()
    T = 2 * math.pi / math.sqrt(eigh(Ka, Ma, eigvals_only=True)[0])
    print(f"MEASURED 5 storeys: flexible-base period {T:.4f} s (fixed {2 * math.pi / w[0]:.4f} s), "
          f"Veletsos-Meek {T_vm:.4f} s ({T / T_vm - 1:+.2%})")
    assert T > 1.1 * 2 * math.pi / w[0]  # the soil matters here
    assert abs(T / T_vm - 1) <= 0.008  # measured +0.33 %


# displacement NE at dt = 0.1 ms, Newmark: measured 2.4e-4 (undamped), 2.7e-6 (with dashpots)
@pytest.mark.parametrize("scheme", ["newmark", "exact"])
@pytest.mark.parametrize("dashpots, limit", [(False, 6e-4), (True, 7e-6)])
def test_free_vibration_equals_the_matrix_exponential(dashpots, limit, scheme):
    """Three storeys on a foundation (modes 2.7-23.5 Hz), released with floor velocities; 1 s.

    Closed form: e^(A t) x0.  Newmark's steps (every step physical or its free-flight map, which composes
    the same steps) converge at second order; the exact scheme's free flight (one matrix exponential
    per building and step, ``integrate/transition.py``) is exact to round-off at any step.
    """
    n = 3
    cx, ct = (3e6, 8e7) if dashpots else (0.0, 0.0)
    b, _ = _building(n, 0.3 * M * n, 0.05 * M * n * (n * H) ** 2, 5e8, 2e10, cx, ct,
                     damping=RayleighDamping(0.05, (1, 2)) if dashpots else None)
    b.initial_velocity = np.array([0.1, 0.2, 0.3])
    system = assemble([b], [])
    Ma, Ca, Ka = system.matrices()
    nd = system.n_dof
    A = np.block([[np.zeros((nd, nd)), np.eye(nd)], [-np.linalg.solve(Ma, Ka), -np.linalg.solve(Ma, Ca)]])
    errs = []
    for dt in (2e-4, 1e-4):
        nsteps = int(round(1.0 / dt))
        raw = integrate(system, np.zeros(nsteps + 1), dt, nsteps, scheme=scheme)
        assert raw.driver == "general" and raw.stats["free_flight_steps"] == nsteps
        t = np.arange(nsteps + 1) * dt
        y = np.array([expm(A * tk) @ np.concatenate([system.u0, system.v0]) for tk in t[::50]])
        ne = np.linalg.norm(raw.displacement[::50] - y[:, :nd], axis=0) / np.linalg.norm(y[:, :nd], axis=0)
        errs.append(ne.max())
        e = raw.energy
        balance = np.abs(e[:, 0] - e[:, 1:].sum(axis=1)).max() / e[0, 0]
        print(f"MEASURED free vibration on a foundation ({scheme}, dashpots {dashpots}), dt {dt:g}: displacement NE "
              f"{ne.max():.1e} (worst DOF), energy balance {balance:.1e}")
        assert balance <= 3e-11  # measured up to 2.7e-12: round-off, ~10x
    if scheme == "exact":
        assert max(errs) <= 1e-11  # measured 8.6e-14 .. 1.2e-12: round-off, ~10x
        return
    assert errs[1] <= limit  # Newmark's period error on the 23.5 Hz mode, 1.2e-4 rad per cycle
    assert errs[0] / errs[1] >= 3.5  # second order (measured 4.0, 4.1)


def test_cone_impedances_of_a_disk_equal_gazetas():
    soil = Soil(shear_wave_velocity=200.0, density=1900.0, poisson=0.3)
    r = 5.0
    got = cone_impedances(soil, Footing(radius=r))
    G = 1900.0 * 200.0 ** 2  # the closed forms below are reproduced exactly (measured 0); rel 1e-14: a few ulps
    vp = 200.0 * math.sqrt(2 * 0.7 / 0.4)
    square = cone_impedances(soil, Footing(width=2 * r, length=2 * r))
    soft = cone_impedances(Soil(200.0, 1900.0, 0.45), Footing(radius=r))
    pairs = [(got["sway_stiffness"], 8 * G * r / (2 - 0.3)),
             (got["rocking_stiffness"], 8 * G * r ** 3 / (3 * (1 - 0.3))),
             (got["sway_damping"], 1900.0 * 200.0 * math.pi * r * r),
             (got["rocking_damping"], 1900.0 * vp * math.pi * r ** 4 / 4),
             (square["sway_stiffness"], 8 * G * math.sqrt(4 * r * r / math.pi) / 1.7),
             (soft["trapped_rotary_inertia"], 1.2 * (0.45 - 1 / 3) * 1900.0 * math.pi * r ** 5 / 4)]
    print("MEASURED cone impedances against Gazetas / Wolf: " + ", ".join(f"{a / b - 1:.1e}" for a, b in pairs))
    assert got["sway_stiffness"] == pytest.approx(8 * G * r / (2 - 0.3), rel=1e-14)  # Gazetas 1991, Table 1
    assert got["rocking_stiffness"] == pytest.approx(8 * G * r ** 3 / (3 * (1 - 0.3)), rel=1e-14)
    assert got["sway_damping"] == pytest.approx(1900.0 * 200.0 * math.pi * r * r, rel=1e-14)
    assert got["rocking_damping"] == pytest.approx(1900.0 * vp * math.pi * r ** 4 / 4, rel=1e-14)
    assert got["trapped_rotary_inertia"] == 0.0
    assert square["sway_stiffness"] == pytest.approx(8 * G * math.sqrt(4 * r * r / math.pi) / 1.7, rel=1e-14)
    assert soft["trapped_rotary_inertia"] == pytest.approx(1.2 * (0.45 - 1 / 3) * 1900.0 * math.pi * r ** 5 / 4,
                                                           rel=1e-14)
