"""Closed gaps that share no building are solved as separate groups; simultaneous events switch together.

K_hat is block diagonal over the buildings, so G = B^T K_hat^-1 B is block
diagonal over groups of gaps whose buildings do not overlap, and the contact
Newton iteration splits into one small system per group (O(sum m_c^3) instead
of O(m^3) when many floors are in contact at once).  Checked here against the
dense inverse (the premise), against the single pair (copies of a pair in one
row must move exactly like the pair), and against the reference twin (two
different pairs whose impacts come at different times).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sl

from seispound.contact import make_law
from seispound.integrate import Newmark, integrate
from seispound.integrate._contact import _group_contacts
from seispound.integrate.newmark import gap_blocks
from seispound.structure import Gap, assemble
from tests.reference_twin import RefGap, RefLaw, shear_matrices, simulate_reference
from tests.verification._helpers import el_centro, read_at2, shear_building

K_HD, E_HD = 2.75e9, 0.65


def _law():
    return make_law("Hd", stiffness=K_HD, restitution=E_HD)


def test_groups_are_sorted_maximal_and_uncoupled_in_the_dense_inverse():
    # a row of five buildings (4, 6, 3, 5, 2 storeys) with a gap between each neighbour pair
    bs = [shear_building(f"B{i}", n, 0.1 * n) for i, n in enumerate((4, 6, 3, 5, 2))]
    gaps = [Gap((a.name, b.name), 0.01) for a, b in zip(bs, bs[1:])]
    system = assemble(bs, gaps, _law())
    lo, hi = gap_blocks(system, system.gap_i, system.gap_j)  # as the front end passes them
    h, beta, gamma = 0.001, 0.25, 0.5
    K_hat = system.stiffness_matrix() + gamma / (beta * h) * system.damping_matrix() + np.diag(
        system.mass / (beta * h * h))
    B = np.zeros((system.n_dof, system.n_gap))
    B[system.gap_i, np.arange(system.n_gap)] = 1.0
    B[system.gap_j, np.arange(system.n_gap)] = -1.0
    G = B.T @ np.linalg.solve(K_hat, B)
    rng = np.random.default_rng(7)
    n_split = 0
    for trial in range(200):
        m = int(rng.integers(1, system.n_gap + 1))
        act = rng.permutation(system.n_gap)[:m].astype(np.int64)
        chosen = set(act.tolist())
        off = np.empty(system.n_gap + 1, np.int64)
        nc = _group_contacts(m, act, lo, hi, off)
        assert set(act.tolist()) == chosen  # a permutation of the closed gaps
        assert off[0] == 0 and off[nc] == m and np.all(np.diff(off[:nc + 1]) > 0)
        assert np.all(np.diff(lo[act]) >= 0)  # sorted by block start
        for c in range(nc):
            grp = act[off[c]:off[c + 1]]
            # maximal: within a group the block ranges chain without a break
            reach = hi[grp[0]]
            for g in grp[1:]:
                assert lo[g] < reach
                reach = max(reach, hi[g])
            # uncoupled: nothing of G links this group to the others
            rest = np.setdiff1d(act, grp)
            assert np.all(G[np.ix_(grp, rest)] == 0.0)
            if c + 1 < nc:
                assert reach <= lo[act[off[c + 1]]]
        n_split += nc > 1
    assert n_split > 20  # the random sets did exercise more than one group


def _pairs(k, periods=((0.5, 0.8),), storeys=(5, 8), gap=0.01):
    """k pairs A_p | B_p of storeys[0] and storeys[1] floors, a gap only inside each pair."""
    bs, gaps = [], []
    for p in range(k):
        ta, tb = periods[p % len(periods)]
        a = shear_building(f"A{p}", storeys[0], ta)
        b = shear_building(f"B{p}", storeys[1], tb)
        bs += [a, b]
        gaps.append(Gap((a.name, b.name), gap))
    return assemble(bs, gaps, _law())


@pytest.fixture(scope="module")
def copies():
    ag, nsteps = el_centro(10.0, 0.005)
    return {k: integrate(_pairs(k), ag, 0.005, nsteps, scheme="newmark") for k in (1, 2, 4)}


def test_copies_of_a_pair_move_exactly_like_the_pair(copies):
    one = copies[1]
    n1, g1 = one.displacement.shape[1], one.force.shape[1]
    assert one.impacts["gap"].size >= 20
    for k in (2, 4):
        r = copies[k]
        assert r.impacts["gap"].size == k * one.impacts["gap"].size
        for p in range(k):
            u = r.displacement[:, p * n1:(p + 1) * n1]
            f = r.force[:, p * g1:(p + 1) * g1]
            np.testing.assert_allclose(u, one.displacement, rtol=0, atol=1e-12 * np.abs(one.displacement).max())
            np.testing.assert_allclose(f, one.force, rtol=0, atol=1e-10 * one.force.max())
            np.testing.assert_allclose(r.peak_force[p * g1:(p + 1) * g1], one.peak_force, rtol=1e-10)


def test_copies_cost_the_attempts_of_one_pair(copies):
    # every event of one copy happens at the same instant in the others; they switch
    # together, so 2 and 4 copies take exactly the steps and redone steps of one pair
    s1, s2, s4 = (copies[k].stats for k in (1, 2, 4))
    print(f"MEASURED copies: steps {s1['steps']} / {s2['steps']} / {s4['steps']}, "
          f"redone {s1['rejected']} / {s2['rejected']} / {s4['rejected']} (1, 2, 4 pairs)")
    assert s1["rejected"] > 50  # events were located
    for s in (s2, s4):
        assert (s["steps"], s["rejected"]) == (s1["steps"], s1["rejected"])


def test_two_different_pairs_against_the_reference_twin():
    """Pairs with impacts at different times: twin peaks within 1-2 %.

    dt = 1 ms: these stiff low buildings (T1 = 0.25-0.45 s) need it for the
    first-floor impacts, whose force depends on the free-flight phase error
    (6 % at dt = 5 ms, with the kernel of before the groups as well).
    """
    t_end = 5.0
    system = _pairs(2, periods=((0.3, 0.45), (0.4, 0.25)), storeys=(3, 4), gap=0.005)
    ag, nsteps = el_centro(t_end, 0.001)
    r = integrate(system, ag, 0.001, nsteps)
    a0, b0, a1, b1 = (shear_building(n, s, t) for n, s, t in
                      (("A0", 3, 0.3), ("B0", 4, 0.45), ("A1", 3, 0.4), ("B1", 4, 0.25)))
    mats = [shear_matrices(x.floor_masses, x.storey_stiffness, *x.rayleigh_coefficients()) for x in (a0, b0, a1, b1)]
    m = np.concatenate([x[0] for x in mats])
    K = sl.block_diag(*[x[1] for x in mats])
    C = sl.block_diag(*[x[2] for x in mats])
    gaps = [RefGap(int(i), int(j), 0.005, RefLaw("Hd", K_HD, E_HD)) for i, j in zip(system.gap_i, system.gap_j)]
    rdt, acc = read_at2()
    tr = np.arange(acc.size) * rdt
    twin = simulate_reference(m, K, C, gaps, lambda t: np.interp(t, tr, acc), t_end, np.zeros(m.size),
                              rtol=1e-9, breakpoints=tr[tr < t_end])
    # both pairs pound, and not in lockstep
    first = [r.impacts["t0"][np.isin(r.impacts["gap"], np.arange(3 * p, 3 * p + 3))].min() for p in (0, 1)]
    assert abs(first[0] - first[1]) > 0.01
    active = twin.peak_force > 0
    du = np.max(np.abs(r.peak_displacement / twin.peak_displacement - 1.0))
    df = np.max(np.abs(r.peak_force[active] / twin.peak_force[active] - 1.0))
    print(f"MEASURED two pairs vs twin: impacts {r.impacts['gap'].size} / {twin.impacts['gap'].size}, "
          f"peak displacement error {du:.2e}, peak force error {df:.2e}")
    assert r.impacts["gap"].size == twin.impacts["gap"].size >= 10
    assert np.array_equal(r.peak_force > 0, active)
    assert du <= 0.01
    assert df <= 0.02


@pytest.mark.parametrize("substeps", [4, 32])
def test_stored_forces_obey_the_law_at_the_stored_state_with_several_floors_in_contact(substeps):
    """F = F_law(delta, rate) at every stored step inside an impact, to 1e-6 of the largest force.

    The Newton iteration solves for all the forces of a group at once because
    a force at one floor changes the penetration at the others (G has
    off-diagonal terms within a group).  Solving each gap on its own would
    leave each force consistent with a penetration that the other forces then
    change by G_qr F_r: measured 1.9e-4 (32 substeps) and 5.9e-3 (4 substeps)
    of the largest force.  The bound: Newton stops at rtol = 1e-10 of the
    largest residual term, which inside a 1e-4 s substep is the inertia term
    m v / (beta h) ~ 1e9 N, so up to ~0.1-1 N, a few 1e-7 of the 2.8 MN peak
    (measured 2.0e-7 at 32 substeps, 2.7e-9 at 4).
    """
    law = _law()
    system = _pairs(1, periods=((0.5, 0.8),), storeys=(5, 8), gap=0.01)
    ag, nsteps = el_centro(8.0, 0.005)
    r = integrate(system, ag, 0.005, nsteps, newmark=Newmark(contact_substeps=substeps))
    imp = r.impacts
    fmax = r.peak_force.max()
    worst, checked, together = 0.0, 0, 0
    closed_at = np.zeros(r.time.size, int)
    for g, t0, v0, dur in zip(imp["gap"], imp["t0"], imp["v0"], imp["dur"]):
        inside = (r.time > t0) & (r.time < t0 + dur)
        closed_at += inside
        i, j = system.gap_i[g], system.gap_j[g]
        delta = r.displacement[inside, i] - r.displacement[inside, j] - system.gap_size[g]
        rate = r.velocity[inside, i] - r.velocity[inside, j]
        expected = law.force(delta, rate, v0, system.mass[i], system.mass[j])
        if inside.any():
            worst = max(worst, np.max(np.abs(r.force[inside, g] - expected)))
            checked += int(inside.sum())
    together = int(np.sum(closed_at >= 2))
    print(f"MEASURED substeps {substeps}: {checked} stored contact states, {together} steps with 2+ floors "
          f"in contact, worst |F - F_law| = {worst / fmax:.2e} of the largest force")
    assert checked > 50 and together > 10
    assert worst <= 1e-6 * fmax
