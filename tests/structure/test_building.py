"""Shear buildings, Rayleigh damping, gap elements at common levels and the assembled system."""

from __future__ import annotations

import math

import numpy as np
import pytest

from seispound import InputError
from seispound.contact import Hd, LVe
from seispound.contact.codes import N_PAR
from seispound.structure import Building, Gap, NoDamping, RayleighDamping, assemble
from seispound.structure.gap import expand_gap


def uniform(name, n, m=2.0e5, k=3.0e8, h=3.0, damping=None):
    return Building(name=name, floor_masses=[m] * n, storey_stiffness=[k] * n, storey_heights=[h] * n,
                    damping=damping or RayleighDamping(0.05))


# -- natural frequencies ------------------------------------------------------------------------
@pytest.mark.parametrize("n", [1, 2, 5, 12])
def test_uniform_building_frequencies_closed_form(n):
    m, k = 2.0e5, 3.0e8
    w, phi = uniform("U", n, m, k).modes()
    r = np.arange(1, n + 1)
    # fixed-free uniform chain: w_r = 2 sqrt(k/m) sin((2r - 1) pi / (2 (2N + 1)))
    w_exact = 2 * np.sqrt(k / m) * np.sin((2 * r - 1) * np.pi / (2 * (2 * n + 1)))
    np.testing.assert_allclose(w, w_exact, rtol=1e-10, atol=0)
    # mass-normalised mode shapes
    np.testing.assert_allclose(phi.T @ np.diag([m] * n) @ phi, np.eye(n), atol=1e-10)


def test_five_storey_numbers():
    w, _ = uniform("U", 5, 1.0, 1.0).modes()
    # 2 sin((2r-1) pi / 22): 0.28463, 0.83083, 1.30972, 1.68251, 1.91899
    np.testing.assert_allclose(w, [0.284630, 0.830830, 1.309721, 1.682507, 1.918986], atol=2e-6)
    b = uniform("U", 5, 1.0e5, 1.0e8)
    assert b.periods[0] == pytest.approx(2 * math.pi / (2 * math.sqrt(1e3) * math.sin(math.pi / 22)), rel=1e-10)
    assert np.all(np.diff(b.periods) < 0)


def test_stiffness_matrix_is_the_shear_building_tridiagonal():
    b = Building("S", [1.0, 2.0, 3.0], [10.0, 20.0, 30.0], [3.0, 3.0, 4.0])
    K = b.stiffness_matrix()
    np.testing.assert_array_equal(K, [[30.0, -20.0, 0.0], [-20.0, 50.0, -30.0], [0.0, -30.0, 30.0]])
    np.testing.assert_array_equal(b.mass_matrix(), np.diag([1.0, 2.0, 3.0]))
    np.testing.assert_array_equal(b.floor_heights, [3.0, 6.0, 10.0])


# -- Rayleigh damping -----------------------------------------------------------------------------
@pytest.mark.parametrize("modes", [(1, 2), (1, 3), (2, 5), (1, 5)])
@pytest.mark.parametrize("ratio", [0.02, 0.05, 0.1])
def test_rayleigh_ratio_exact_at_the_anchor_modes(modes, ratio):
    b = Building("R", [1.0e5, 1.2e5, 0.9e5, 1.0e5, 0.8e5], [2.0e8, 1.8e8, 1.6e8, 1.5e8, 1.2e8],
                 [4.0, 3.0, 3.0, 3.0, 3.0], damping=RayleighDamping(ratio, modes))
    a0, a1 = b.rayleigh_coefficients()
    w, phi = b.modes()
    ratios = a0 / (2 * w) + a1 * w / 2
    i, j = modes
    assert ratios[i - 1] == pytest.approx(ratio, rel=1e-12)
    assert ratios[j - 1] == pytest.approx(ratio, rel=1e-12)
    # between the anchors the ratio is lower, outside it is higher
    for r in range(1, 6):
        if i < r < j:
            assert ratios[r - 1] < ratio
        elif r > j or r < i:
            assert ratios[r - 1] > ratio
    # C = a0 M + a1 K is diagonalised by the modes with 2 ratio_n w_n on the diagonal
    C = b.damping_matrix()
    np.testing.assert_allclose(C, a0 * b.mass_matrix() + a1 * b.stiffness_matrix(), rtol=1e-14)
    Cm = phi.T @ C @ phi
    np.testing.assert_allclose(np.diag(Cm), 2 * ratios * w, rtol=1e-10)
    np.testing.assert_allclose(Cm - np.diag(np.diag(Cm)), 0.0, atol=1e-10 * np.abs(Cm).max())


def test_rayleigh_default_modes():
    assert uniform("U", 4).damping.modes == (1, 2)
    assert uniform("V", 1).damping.modes == (1, 1)


def test_one_storey_building_gets_the_ratio_in_its_only_mode():
    m, k, ratio = 3.0e4, 5.0e7, 0.07
    b = Building("One", [m], [k], [3.5], damping=RayleighDamping(ratio))
    a0, a1 = b.rayleigh_coefficients()
    w = math.sqrt(k / m)
    assert a0 / (2 * w) + a1 * w / 2 == pytest.approx(ratio, rel=1e-12)
    assert (a0, a1) == (pytest.approx(ratio * w, rel=1e-12), pytest.approx(ratio / w, rel=1e-12))
    c = b.damping_matrix()[0, 0]
    assert c == pytest.approx(2 * ratio * math.sqrt(k * m), rel=1e-12)


def test_no_damping():
    b = Building("N", [1.0, 1.0], [1.0, 1.0], [3.0, 3.0], damping=NoDamping())
    assert b.rayleigh_coefficients() == (0.0, 0.0)
    np.testing.assert_array_equal(b.damping_matrix(), 0.0)
    assert Building("Z", [1.0], [1.0], [3.0], damping=RayleighDamping(0.0)).rayleigh_coefficients() == (0.0, 0.0)


@pytest.mark.parametrize("kw, key", [
    (dict(floor_masses=[1.0, 0.0]), "building.X.floor_masses"),
    (dict(floor_masses=[1.0, -1.0]), "building.X.floor_masses"),
    (dict(storey_stiffness=[1.0, float("nan")]), "building.X.storey_stiffness"),
    (dict(storey_stiffness=[1.0, 1.0, 1.0]), "building.X.storey_stiffness"),
    (dict(storey_heights=[3.0]), "building.X.storey_heights"),
    (dict(storey_heights=[3.0, 0.0]), "building.X.storey_heights"),
    (dict(initial_velocity=[0.1, 0.2, 0.3]), "building.X.initial_velocity"),
    (dict(damping=RayleighDamping(0.05, (1, 3))), "building.X.damping.modes"),
    (dict(damping=RayleighDamping(0.05, (0, 2))), "building.X.damping.modes"),
    (dict(damping=RayleighDamping(1.2)), "building.X.damping.ratio"),
])
def test_building_validation(kw, key):
    args = dict(name="X", floor_masses=[1.0, 1.0], storey_stiffness=[1.0, 1.0], storey_heights=[3.0, 3.0])
    args.update(kw)
    with pytest.raises(InputError) as info:
        Building(**args)
    assert info.value.key == key


# -- gap elements ------------------------------------------------------------------------------------
def test_gaps_only_at_common_levels():
    a = Building("A", [1e5] * 4, [1e8] * 4, [3.0, 3.0, 3.0, 3.0])  # floors at 3, 6, 9, 12 m
    b = Building("B", [1e5] * 3, [1e8] * 3, [3.0, 3.0, 6.0])  # floors at 3, 6, 12 m
    links = expand_gap(Gap(("A", "B"), 0.05, levels="floors"), 0, [a, b], Hd(2.75e9, 0.65))
    # common levels: 3 m (A1-B1), 6 m (A2-B2), 12 m (A4-B3); A3 at 9 m has no partner
    assert [(l.left_floor, l.right_floor, l.height) for l in links] == [(1, 1, 3.0), (2, 2, 6.0), (4, 3, 12.0)]
    # by default (level roofs: every floor of both) A3 strikes B's third storey half way up
    default = expand_gap(Gap(("A", "B"), 0.05), 0, [a, b], Hd(2.75e9, 0.65))
    assert [(l.left_floor, l.right_floor, l.right_weight, l.kind) for l in default] == [
        (1, 1, 1.0, "floor-to-floor"), (2, 2, 1.0, "floor-to-floor"), (3, 3, 0.5, "floor-to-storey"),
        (4, 3, 1.0, "floor-to-floor")]
    assert all(l.size == 0.05 and (l.left, l.right) == (0, 1) and l.gap_index == 0 for l in links)
    # either order of the pair gives the same elements
    rev = expand_gap(Gap(("B", "A"), 0.05, levels="floors"), 0, [a, b], Hd(2.75e9, 0.65))
    assert [(l.left_floor, l.right_floor) for l in rev] == [(1, 1), (2, 2), (4, 3)]


def test_levels_match_within_tolerance_only():
    a = Building("A", [1.0] * 2, [1.0] * 2, [3.0, 3.0])
    b = Building("B", [1.0] * 2, [1.0] * 2, [3.0 + 1e-9, 3.0])  # 1 nm: the same level
    c = Building("C", [1.0] * 2, [1.0] * 2, [3.001, 3.0])  # 1 mm apart: different levels
    assert len(expand_gap(Gap(("A", "B"), 0.0), 0, [a, b], Hd(1.0, 0.5))) == 2
    with pytest.raises(InputError) as info:
        expand_gap(Gap(("A", "C"), 0.0, levels="floors"), 0, [a, c], Hd(1.0, 0.5))
    assert info.value.key == "gap.1.between"
    # by default A's floors (the lower roof) strike C's storeys just below C's floors
    links = expand_gap(Gap(("A", "C"), 0.0), 0, [a, c], Hd(1.0, 0.5))
    assert [l.kind for l in links] == ["floor-to-storey"] * 2
    assert links[0].right_weight == pytest.approx(3.0 / 3.001)


def test_size_list_per_level():
    a = Building("A", [1e5] * 4, [1e8] * 4, [3.0] * 4)
    b = Building("B", [1e5] * 3, [1e8] * 3, [3.0, 3.0, 6.0])
    links = expand_gap(Gap(("A", "B"), [0.01, 0.02, 0.04], levels="floors"), 2, [a, b], Hd(2.75e9, 0.65))
    assert [l.size for l in links] == [0.01, 0.02, 0.04]
    assert all(l.gap_index == 2 for l in links)
    with pytest.raises(InputError) as info:
        expand_gap(Gap(("A", "B"), [0.01, 0.02], levels="floors"), 2, [a, b], Hd(2.75e9, 0.65))
    assert info.value.key == "gap.3.size" and "3" in info.value.message


@pytest.mark.parametrize("gap, key", [
    (Gap(("A", "B"), -0.01), "gap.1.size"),
    (Gap(("A", "B"), [0.02, -1e-6]), "gap.1.size"),
    (Gap(("A", "B"), float("nan")), "gap.1.size"),
    (Gap(("A", "B"), "wide"), "gap.1.size"),
    (Gap(("A", "C"), 0.02), "gap.1.between"),  # not neighbours
    (Gap(("A", "Q"), 0.02), "gap.1.between"),  # unknown building
    (Gap(("A", "A"), 0.02), "gap.1.between"),
    (Gap(("A",), 0.02), "gap.1.between"),
])
def test_gap_errors(gap, key):
    row = [uniform("A", 2), uniform("B", 2), uniform("C", 2)]
    with pytest.raises(InputError) as info:
        expand_gap(gap, 0, row, Hd(2.75e9, 0.65))
    assert info.value.key == key
    assert key in str(info.value)
    with pytest.raises(InputError) as info:
        assemble(row, [gap], Hd(2.75e9, 0.65))
    assert info.value.key == key


def test_gap_without_law():
    with pytest.raises(InputError) as info:
        assemble([uniform("A", 2), uniform("B", 2)], [Gap(("A", "B"), 0.02)], None)
    assert info.value.key == "gap.1.law"


# -- assembly -------------------------------------------------------------------------------------------
@pytest.fixture
def row():
    a = Building("A", [1.0e5, 1.1e5, 0.9e5, 1.0e5], [1.3e8, 1.2e8, 1.1e8, 1.0e8], [3.0] * 4,
                 damping=RayleighDamping(0.05, (1, 2)))
    b = Building("B", [2.0e5] * 6, [2.0e8] * 6, [3.0] * 6, damping=RayleighDamping(0.03, (1, 3)),
                 initial_velocity=0.1)
    c = Building("C", [5.0e4] * 2, [6.0e7] * 2, [3.0, 6.0], damping=NoDamping())
    gaps = [Gap(("A", "B"), [0.01, 0.02, 0.03, 0.04]), Gap(("C", "B"), 0.0, law=LVe(5e7, 0.5))]
    return [a, b, c], gaps


def test_assembly_dof_numbering(row):
    buildings, gaps = row
    s = assemble(buildings, gaps, Hd(2.75e9, 0.65))
    assert s.n_dof == 12
    np.testing.assert_array_equal(s.dof_building, [0] * 4 + [1] * 6 + [2] * 2)
    np.testing.assert_array_equal(s.dof_floor, [1, 2, 3, 4, 1, 2, 3, 4, 5, 6, 1, 2])
    np.testing.assert_array_equal(s.mass, np.concatenate([b.floor_masses for b in buildings]))
    np.testing.assert_array_equal(s.v0, [0.0] * 4 + [0.1] * 6 + [0.0] * 2)
    np.testing.assert_array_equal(s.u0, 0.0)
    # gaps: A-B at 3, 6, 9, 12 m; B-C at 3 m and 9 m (C's floors at 3 and 9 m)
    assert s.n_gap == 6
    np.testing.assert_array_equal(s.gap_i, [0, 1, 2, 3, 4, 6])
    np.testing.assert_array_equal(s.gap_j, [4, 5, 6, 7, 10, 11])
    np.testing.assert_array_equal(s.gap_size, [0.01, 0.02, 0.03, 0.04, 0.0, 0.0])
    assert [l.law.name for l in s.links] == ["Hd"] * 4 + ["LVe"] * 2
    np.testing.assert_array_equal(s.gap_law, [Hd.code] * 4 + [LVe.code] * 2)
    # effective mass of each colliding pair
    from seispound.contact import _scalar as S

    m = s.mass
    np.testing.assert_allclose(s.gap_par[:, S.P_MEFF], m[s.gap_i] * m[s.gap_j] / (m[s.gap_i] + m[s.gap_j]),
                               rtol=1e-15)
    np.testing.assert_array_equal(s.without_contact().gap_law, 0)
    np.testing.assert_array_equal(s.gap_law, [Hd.code] * 4 + [LVe.code] * 2)  # the original is untouched


def test_assembled_matrices_are_the_building_blocks(row):
    buildings, gaps = row
    s = assemble(buildings, gaps, Hd(2.75e9, 0.65))
    K, C = s.stiffness_matrix(), s.damping_matrix()
    assert s.bandwidth == 1
    starts = np.cumsum([0] + [b.n_floors for b in buildings])
    for bi, b in enumerate(buildings):
        blk = slice(starts[bi], starts[bi + 1])
        np.testing.assert_allclose(K[blk, blk], b.stiffness_matrix(), rtol=1e-15, atol=0)
        np.testing.assert_allclose(C[blk, blk], b.damping_matrix(), rtol=1e-12, atol=1e-12 * np.abs(C).max())
    # nothing couples different buildings; K and C are symmetric and tridiagonal
    same = s.dof_building[:, None] == s.dof_building[None, :]
    assert np.all(K[~same] == 0) and np.all(C[~same] == 0)
    idx = np.arange(s.n_dof)
    far = np.abs(idx[:, None] - idx[None, :]) > 1
    assert np.all(K[far] == 0) and np.all(C[far] == 0)
    np.testing.assert_array_equal(K, K.T)
    np.testing.assert_allclose(C, C.T, rtol=0, atol=0)
    # ground elements: one per building (the first storey)
    assert np.sum(s.el_j < 0) == 3


def test_single_building_has_no_gaps():
    s = assemble([uniform("Solo", 3)], [])
    assert s.n_gap == 0 and s.gap_par.shape == (0, N_PAR)
    assert s.bandwidth == 1
    np.testing.assert_allclose(s.stiffness_matrix(), uniform("Solo", 3).stiffness_matrix())
