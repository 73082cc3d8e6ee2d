"""The general driver's profile (envelope) factor and the DOF order that keeps a foundation's envelope small.

Kinds:
- ``_factor_profile`` / ``_solve_profile`` against numpy's dense solve (an independent implementation) on
  a random arrowhead matrix, the pattern of a building numbered floors first, foundation last;
- ``structure.band.profile_order`` on a building on soil: its floors come out tridiagonal;
- ``linear_forces`` with the listed off-band entries against the dense K u + C v in the new order
  (an independent assembly, ``SystemArrays.matrices``);
- a regression guard, not a verification: the same run with the renumbering switched off agrees to
  round-off carried through the impacts.
"""

from pathlib import Path

import numpy as np
import pytest

import seispound as sp
from seispound.integrate import newmark
from seispound.integrate._elements import linear_bands, linear_forces
from seispound.integrate._linear import _factor_profile, _solve_profile
from seispound.integrate.transition import components
from seispound.structure.band import _profile_cost, envelope, profile_order

REPO = Path(__file__).resolve().parents[2]


def _arrowhead(n_blocks, size, border, rng):
    """A block-diagonal SPD matrix whose blocks are tridiagonal with ``border`` full last rows."""
    n = n_blocks * size
    A = np.zeros((n, n))
    for b in range(n_blocks):
        o = b * size
        for i in range(size):
            A[o + i, o + i] = 4.0 + rng.random()
            if i:
                A[o + i, o + i - 1] = A[o + i - 1, o + i] = -1.0 + 0.1 * rng.random()
        for r in range(size - border, size):
            for j in range(size - border):
                A[o + r, o + j] = A[o + j, o + r] = 0.3 * rng.normal()
            A[o + r, o + r] += size
    return A


def _band(A, first, p):
    n = A.shape[0]
    L = np.zeros((n, p + 2))
    for i in range(n):
        for j in range(max(first[i], i - p), i + 1):
            L[i, i - j] = A[i, j]
    return L


def test_profile_factor_solves_as_numpy_does():
    rng = np.random.default_rng(11)
    A = _arrowhead(2, 9, 2, rng)
    n = A.shape[0]
    first = np.array([np.flatnonzero(A[i, :i + 1])[0] for i in range(n)], np.int64)
    p = int(np.max(np.arange(n) - first))
    L = _band(A, first, p)
    assert _factor_profile(L, p, first, 0, n)
    b = rng.normal(size=n)
    x = np.empty(n)
    _solve_profile(L, p, first, b, x, 0, n)
    ref = np.linalg.solve(A, b)
    err = np.abs(x - ref).max() / np.abs(ref).max()
    # one building alone (lo..hi): the other's rows take no part
    y = np.zeros(n)
    rhs = np.zeros(n)
    rhs[9:] = b[9:]
    _solve_profile(L, p, first, rhs, y, 9, n)
    err_block = np.abs(y[9:] - np.linalg.solve(A[9:, 9:], b[9:])).max() / np.abs(ref).max()
    print(f"MEASURED profile solve against numpy: {err:.1e}, one block {err_block:.1e}")
    assert err <= 6e-16 and err_block <= 6e-16  # measured 2.1e-16: round-off
    assert np.all(y[:9] == 0.0)
    # a matrix that is not positive definite is refused
    L = _band(A - 20.0 * np.eye(n), first, p)
    assert not _factor_profile(L, p, first, 0, n)


def _soil_model(duration=20.0):
    m = sp.load_model(REPO / "models" / "two_buildings.toml")
    from seispound.foundation import Footing, Foundation, Soil

    m.buildings[1].foundation = Foundation(mass=2e5, rotary_inertia=2e6, floor_rotary_inertia=5e5,
                                           soil=Soil(200.0, 1900.0, 0.3), footing=Footing(width=15.0, length=15.0))
    m.buildings[1].validate()
    m.analysis.duration = duration
    m.__dict__.pop("_assembled", None)
    return m


def test_a_foundation_is_numbered_after_its_floors():
    system = _soil_model().assembled()
    tab = system.element_tables()
    n = system.n_dof
    storeys = tab["ne_dof"][~tab["ne_gap"]]
    order = profile_order(n, components(tab, n), tab["ms_dof"], tab["le_dof"], storeys)
    assert order is not None
    new = np.empty(n, np.int64)
    new[order] = np.arange(n)
    ren = [np.where(x >= 0, new[np.maximum(x, 0)], -1) for x in (tab["ms_dof"], tab["le_dof"], storeys)]
    before, after = envelope(n, tab["ms_dof"], tab["le_dof"], storeys), envelope(n, *ren)
    floors = np.flatnonzero(system.dof_floor > 0)
    width = np.arange(n) - after
    print(f"MEASURED factor work sum w^2: {_profile_cost(before)} as assembled, {_profile_cost(after)} renumbered")
    assert _profile_cost(after) <= 0.6 * _profile_cost(before)  # measured 264 against 519
    assert np.all(width[new[floors]] <= 1)  # every floor row tridiagonal
    assert sorted(order[: system.n_dof - np.count_nonzero(system.dof_building == 1)]) == list(
        np.flatnonzero(system.dof_building == 0))  # each building keeps its block


def test_listed_entries_of_k_and_c_add_as_the_dense_product():
    system = _soil_model().assembled()
    row = newmark._general_row(system)
    tab, order = row["tab"], row["order"]
    n = system.n_dof
    bands = linear_bands(tuple(tab[k] for k in ("ms_dof", "ms_coef", "ms_val", "ms_a0", "le_dof", "le_coef", "le_k",
                                                          "le_c")), int(tab["p"]), n)
    M, C, K = (np.asarray(x)[np.ix_(order, order)] for x in system.matrices())
    rng = np.random.default_rng(5)
    u, v = rng.normal(size=n) * 1e-2, rng.normal(size=n) * 1e-1
    f = np.empty(n)
    linear_forces(bands, u, v, f)
    ref = K @ u + C @ v
    err = np.abs(f - ref).max() / np.abs(ref).max()
    print(f"MEASURED K u + C v with {bands[1].size} listed entries, {bands[0].shape[1]} dense diagonals: {err:.1e}")
    assert bands[1].size > 0 and bands[0].shape[1] < int(tab["p"]) + 1  # the list is used
    assert err <= 5e-16  # measured 1.5e-16


def test_the_renumbered_run_equals_the_run_in_the_rows_own_order(monkeypatch):
    m = _soil_model(duration=8.0)
    renumbered = sp.simulate(m, twin=False)
    assert m.assembled()._general_row["order"] is not None
    monkeypatch.setattr(newmark, "profile_order", lambda *a, **k: None)  # the off switch
    newmark._ORDERS.clear()
    m.__dict__.pop("_assembled", None)
    own = sp.simulate(m, twin=False)
    newmark._ORDERS.clear()
    assert int(own.sizes["impact"]) == int(renumbered.sizes["impact"]) > 5
    worst = max(float(np.abs(own[k] - renumbered[k]).max() / np.abs(own[k]).max())
                for k in ("displacement", "acceleration", "pounding_force"))
    print(f"MEASURED renumbered against own order, {int(own.sizes['impact'])} impacts: {worst:.1e}")
    assert worst <= 1.2e-11  # measured 4.6e-12 (round-off of the sums' order, carried through the impacts)


@pytest.mark.parametrize("writeable", [False, True])
def test_the_prepared_row_is_kept_only_on_a_frozen_system(writeable):
    system = _soil_model().assembled()
    if writeable:
        from dataclasses import replace

        system = replace(system, mass=system.mass.copy())
        assert system.mass.flags.writeable
    first = newmark._general_row(system)
    assert (newmark._general_row(system) is first) is (not writeable)
