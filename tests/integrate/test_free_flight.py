"""Free-flight blocks (modal Newmark while every gap is open) against physical stepping.

Both paths are the same Newmark-beta recurrence (Bathe 1996, Sec. 9.4: direct
integration equals integration of all the mode equations) and differ only by
round-off.  Round-off can move a located event within the kernel's landing
window (LAND_TOL of the step's travel), so outputs are compared to LAND_TOL:
far above round-off, far below any modelling difference.
"""

from pathlib import Path

import dataclasses

import numpy as np
import pytest

from seispound import load_model
from seispound.contact import make_law
from seispound.integrate import integrate
from seispound.integrate._events import LAND_TOL
from seispound.simulation import prepare_ground_motion
from seispound.structure import Gap, assemble
from tests.verification._helpers import el_centro, shear_building

MODELS = Path(__file__).resolve().parents[2] / "models"
TOL = LAND_TOL


def rel(a, b):
    return np.max(np.abs(a - b)) / max(np.max(np.abs(b)), 1e-300)


def both(system, ag, dt, nsteps, newmark=None, store=True, scheme="newmark"):
    """The same run in free-flight blocks and stepped physically (Newmark throughout unless told otherwise)."""
    a = integrate(system, ag, dt, nsteps, newmark, store_history=store, free_flight=True, scheme=scheme)
    b = integrate(system, ag, dt, nsteps, newmark, store_history=store, free_flight=False, scheme=scheme)
    return a, b


def assert_same(a, b, energy_scale, energy_tol=TOL):
    assert a.impacts["gap"].tolist() == b.impacts["gap"].tolist()
    for key in ("t0", "v0", "vout", "fmax", "dur", "zeta"):
        x, y = a.impacts[key], b.impacts[key]
        assert np.allclose(x, y, rtol=TOL, atol=TOL * max(np.max(np.abs(y), initial=0.0), 1e-300)), key
    for name in ("displacement", "velocity", "acceleration", "force", "peak_displacement", "peak_force"):
        x, y = getattr(a, name), getattr(b, name)
        if np.any(y):
            assert rel(x, y) <= TOL, name
    assert np.max(np.abs(a.energy - b.energy)) <= energy_tol * energy_scale


@pytest.mark.parametrize("name", ["two_buildings.toml", "slab_pendulum.toml"])
def test_bundled_models_agree_with_physical_stepping(name):
    m = load_model(MODELS / name)
    an = m.analysis
    s = assemble(m.buildings, m.gaps, m.contact)
    ag, _ = prepare_ground_motion(m)
    a, b = both(s, ag, an.dt, an.nsteps, an.newmark)
    assert a.stats["free_flight_steps"] > 0 and b.stats["free_flight_steps"] == 0
    assert a.impacts["gap"].size > 0
    assert_same(a, b, np.max(np.abs(b.energy[:, 0])))


def test_row_of_three_and_its_twin_agree_with_physical_stepping():
    m = load_model(MODELS / "row_of_three.toml")
    s = assemble(m.buildings, m.gaps, m.contact)
    ag, _ = prepare_ground_motion(m)
    nsteps = 3000  # 15 s: dozens of impacts, several multi-floor contacts
    a, b = both(s, ag[:nsteps + 1], m.analysis.dt, nsteps, m.analysis.newmark)
    assert a.impacts["gap"].size >= 40
    assert_same(a, b, np.max(np.abs(b.energy[:, 0])))
    # the no-pounding twin: peaks only, every step in free flight
    a, b = both(s.without_contact(), ag[:nsteps + 1], m.analysis.dt, nsteps, m.analysis.newmark, store=False)
    assert a.stats["free_flight_steps"] == nsteps
    assert rel(a.peak_displacement, b.peak_displacement) <= TOL


def test_one_ground_motion_per_building():
    """Each building on its own base motion (dof_motion rows) in both paths."""
    bs = [shear_building("A", 5, 0.6), shear_building("B", 8, 1.0)]
    s = assemble(bs, [Gap(("A", "B"), 0.01)], make_law("LVe", stiffness=1e8, restitution=0.6))
    s = dataclasses.replace(s, dof_motion=np.array([0] * 5 + [1] * 8))
    ag1, nsteps = el_centro(12.0, 0.005)
    ag = np.vstack([ag1, 0.8 * np.roll(ag1, 4)])  # (gaps close on absolute positions: keep the grounds close)
    # (exact scheme: the blocks take the input work exactly, the physical path's steps by the
    # trapezoidal rule, so their energy terms differ by that rule's error, measured 5.6e-4)
    for scheme, energy_tol in (("newmark", TOL), ("exact", 1e-3)):
        a, b = both(s, ag, 0.005, nsteps, scheme=scheme)
        assert a.impacts["gap"].size > 0 and a.stats["free_flight_steps"] > 0
        assert_same(a, b, np.max(np.abs(b.energy[:, 0])), energy_tol)


def test_non_classical_damping_steps_physically():
    bs = [shear_building("A", 5, 0.6), shear_building("B", 8, 1.0)]
    s = assemble(bs, [Gap(("A", "B"), 0.01)], make_law("Hd", stiffness=2.75e9, restitution=0.65))
    a0 = s.dof_a0.copy()
    a0[2] *= 4.0
    s = dataclasses.replace(s, dof_a0=a0)
    ag, nsteps = el_centro(6.0, 0.005)
    r = integrate(s, ag, 0.005, nsteps, driver="fast")
    assert r.stats["free_flight_steps"] == 0 and r.stats["free_flight_blocks"] == 0
    assert r.scheme == "newmark"  # and the result says so
    # left to choose, the exact scheme takes such a row to the general driver's exact free flight
    auto = integrate(s, ag, 0.005, nsteps)
    assert auto.driver == "general" and auto.scheme == "exact" and auto.stats["free_flight_steps"] > 0
    # and the energy still balances (the check does not depend on the modes)
    e = r.energy
    assert abs(e[-1, 0] - e[-1, 1:].sum()) <= 1e-12 * e[:, 0].max()


def test_long_runs_keep_their_block_length_bounded():
    """A twin of 100 000 steps (~400 blocks): the block length stays at most nblk (it once doubled without bound)."""
    s = assemble([shear_building("A", 2, 0.3)], [])
    ag1, _ = el_centro(39.0, 0.01)
    nsteps = 100_000
    ag = np.resize(ag1, nsteps + 1)  # the record repeated: a long, busy excitation
    a = integrate(s, ag, 0.0004, nsteps, store_history=False)
    b = integrate(s, ag, 0.0004, nsteps, store_history=False, free_flight=False)
    assert a.stats["free_flight_steps"] == nsteps and a.stats["free_flight_blocks"] >= nsteps // 256
    assert rel(a.peak_displacement, b.peak_displacement) <= TOL
