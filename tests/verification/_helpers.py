"""Shared fixtures of the verification suite: the El Centro record and the test buildings.

The record is read here with a ten-line parser (not with ``seispound.motion``) so
that the verification does not depend on the package's own reader.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from benchmarks.peer.cases import uniform_storey_stiffness
from seispound.structure import Building, NoDamping, RayleighDamping

G = 9.80665  # standard gravity [m/s^2] (PEER AT2 records are in g)
RECORD = Path(__file__).resolve().parents[2] / "ground_motions" / "RSN6_IMPVALL.I_I-ELC180-hor1.AT2"


def read_at2(path=RECORD):
    """(dt [s], acceleration [m/s^2]) of a PEER AT2 file: 4 header lines, then values in g."""
    lines = Path(path).read_text().splitlines()
    header = lines[3].upper().replace(",", " ")
    npts = int(header.split("NPTS=")[1].split()[0])
    dt = float(header.split("DT=")[1].split()[0])
    acc = np.array(" ".join(lines[4:]).split(), dtype=float)
    assert acc.size == npts
    return dt, acc * G


def el_centro(t_end, dt):
    """El Centro 1940 (RSN6, 180 deg) ground acceleration on the grid k dt, k = 0..round(t_end/dt) [m/s^2].

    The record (dt = 0.01 s) is interpolated linearly, which is exactly how the
    kernel and the closed-form references see the excitation between samples.
    """
    rdt, acc = read_at2()
    nsteps = int(round(t_end / dt))
    t = np.arange(nsteps + 1) * dt
    return np.interp(t, np.arange(acc.size) * rdt, acc), nsteps


def uniform_stiffness(mass, n, period):
    """Storey stiffness [N/m] of a uniform n-storey shear building with fundamental period ``period``.

    The formula (omega_1 = 2 sqrt(k/m) sin(pi / (2 (2n + 1)))) lives in one place,
    ``benchmarks.peer.cases.uniform_storey_stiffness``, shared with the benchmarks.
    """
    return uniform_storey_stiffness(mass, n, period)


def shear_building(name, n, period, mass=1e5, ratio=0.05, modes=(1, 2), height=3.0, v0=0.0):
    """Uniform n-storey building with floor mass ``mass`` [kg] and fundamental period ``period`` [s]."""
    k = uniform_stiffness(mass, n, period)
    damping = RayleighDamping(ratio=ratio, modes=modes) if ratio > 0 else NoDamping()
    return Building(name, [mass] * n, [k] * n, [height] * n, damping, initial_velocity=v0)


def pendulum(name, mass, v0=0.0, length=1.5, g=9.81):
    """A suspended slab as a one-storey 'building' of stiffness m g / L (seed Sec. 3 test rig)."""
    return Building(name, [mass], [mass * g / length], [1.0], NoDamping(), initial_velocity=v0)


def lve_peak_force(k, meff, v0, xi, points=200001):
    """Peak force [N] of an LVe two-body impact, closed form (seed Eqs. 1-3): delta = v0/w_d exp(-xi w t)
    sin(w_d t), F = k delta + 2 xi w m_eff delta', its maximum over ``points`` instants of the contact."""
    w = math.sqrt(k / meff)
    wd = w * math.sqrt(1.0 - xi * xi)
    t = np.linspace(0.0, math.pi / wd, points)
    decay = np.exp(-xi * w * t)
    delta = v0 / wd * decay * np.sin(wd * t)
    rate = v0 * decay * (np.cos(wd * t) - xi * w / wd * np.sin(wd * t))
    return float(np.max(k * delta + 2.0 * xi * w * meff * rate))


def storeys_against_twin(name, building, k, twin, dy, flight):
    """Displacement NE [-] of one yielding building under El Centro x 2 (10 s) at dt 5 and 2.5 ms against
    ``twin(k, a0, a1, t, ag) -> (displacements, largest drift)`` (k [N/m]: every storey's stiffness), flying
    free or on the physical path; each run's storeys must yield past 2 dy [m] and fly free in more than a fifth
    of the steps exactly when asked."""
    from seispound.integrate import integrate
    from seispound.structure import assemble

    a0, a1 = building.rayleigh_coefficients()
    errs = []
    for dt in (0.005, 0.0025):
        ag, nsteps = el_centro(10.0, dt)
        ag = 2.0 * ag
        raw = integrate(assemble([building], []), ag, dt, nsteps, free_flight=flight)
        assert (raw.stats["free_flight_steps"] > nsteps // 5) == flight
        u_ref, peak = twin(k, a0, a1, np.arange(nsteps + 1) * dt, ag)
        errs.append((np.linalg.norm(raw.displacement - u_ref, axis=0) / np.linalg.norm(u_ref, axis=0)).max())
        print(f"MEASURED {name} building, flight {flight}, dt {dt}, scheme {raw.scheme}: displacement NE "
              f"{errs[-1]:.2e}; largest drift {peak / dy:.2f} dy; free-flight steps "
              f"{raw.stats['free_flight_steps']} of {nsteps}")
        assert peak > 2.0 * dy  # the storeys yield well past their yield drift
    return errs
