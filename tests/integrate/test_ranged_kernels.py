"""The kernel's ranged helpers (one building, or a run of buildings, inside a row) against dense algebra.

Multi-rate stepping factors, solves and steps only the buildings that take a
substep, so these helpers run on a DOF range lo..hi-1 that starts inside the
row.  They index with np.uint64 subscripts (``_UNSIGNED`` in the kernel: numba's
negative-index wraparound made the signed versions 2.3-4.6 times slower), so
each is checked here on ranges that start at 0, in the middle and at the end
of a row, against numpy on the densely assembled matrices.
"""

from __future__ import annotations

import numpy as np
import pytest

from seispound.contact import make_law
from seispound.integrate import _linear as K
from seispound.integrate.modal import dof_blocks
from seispound.integrate.newmark import _element_blocks
from seispound.structure import Gap, assemble
from tests.verification._helpers import shear_building

BETA, GAMMA = 0.25, 0.5


@pytest.fixture(scope="module")
def row():
    """Three buildings of 4, 7 and 3 storeys with different periods, two gaps."""
    bs = [shear_building("A", 4, 0.45), shear_building("B", 7, 0.8), shear_building("C", 3, 0.3)]
    s = assemble(bs, [Gap(("A", "B"), 0.01), Gap(("B", "C"), 0.01)], make_law("Hd", stiffness=2.75e9,
                                                                                restitution=0.65))
    starts, el_start = _element_blocks(s)
    assert starts.tolist() == [0, 4, 11, 14]
    return s, starts, el_start


def _khat(s, h):
    cm, cc = 1.0 / (BETA * h * h), GAMMA / (BETA * h)
    return s.stiffness_matrix() + cc * s.damping_matrix() + np.diag(cm * s.mass)


RANGES = [(0, 1), (1, 2), (2, 3), (0, 2), (1, 3), (0, 3)]  # first and last building of each run


@pytest.mark.parametrize("b0, b1", RANGES)
def test_factor_and_solve_on_a_run_of_buildings_match_the_dense_solve(row, b0, b1):
    s, starts, el_start = row
    lo, hi = int(starts[b0]), int(starts[b1])
    h = 0.005 / 8
    L = np.full((s.n_dof, s.bandwidth + 2), np.nan)  # rows outside the run must stay untouched
    assert K._factor_range(h, (BETA, GAMMA), (s.mass, s.dof_a0, s.el_i, s.el_j, s.el_k, s.el_a1), s.bandwidth, L,
                           (lo, hi, int(el_start[b0]), int(el_start[b1])))
    assert np.all(np.isnan(L[:lo])) and np.all(np.isnan(L[hi:]))
    b = np.random.default_rng(b0 + 3 * b1).standard_normal(s.n_dof)
    x = np.full(s.n_dof, np.nan)
    K._solve_range(L, s.bandwidth, b, x, lo, hi)
    A = _khat(s, h)[lo:hi, lo:hi]
    expect = np.linalg.solve(A, b[lo:hi])
    assert np.max(np.abs(x[lo:hi] - expect)) <= 1e-12 * np.max(np.abs(expect))
    assert np.all(np.isnan(x[:lo])) and np.all(np.isnan(x[hi:]))


@pytest.mark.parametrize("b0, b1", RANGES)
def test_internal_forces_on_a_run_of_buildings_match_k_u_and_c_v(row, b0, b1):
    s, starts, el_start = row
    lo, hi = int(starts[b0]), int(starts[b1])
    rng = np.random.default_rng(7 + b0 + 3 * b1)
    u, v = rng.standard_normal(s.n_dof) * 1e-2, rng.standard_normal(s.n_dof) * 1e-1
    fs = np.full(s.n_dof, np.nan)
    fd = np.full(s.n_dof, np.nan)
    K._internal_range((s.mass, s.dof_a0, s.el_i, s.el_j, s.el_k, s.el_a1), u, v, fs, fd,
                      (lo, hi, int(el_start[b0]), int(el_start[b1])))
    # the run's rows only: its buildings are not coupled to the others by any storey
    ks = (s.stiffness_matrix() @ u)[lo:hi]
    cs = (s.damping_matrix() @ v)[lo:hi]
    assert np.max(np.abs(fs[lo:hi] - ks)) <= 1e-12 * np.max(np.abs(ks))
    assert np.max(np.abs(fd[lo:hi] - cs)) <= 1e-12 * np.max(np.abs(cs))
    assert np.all(np.isnan(fs[:lo])) and np.all(np.isnan(fs[hi:]))


def test_woodbury_columns_of_the_second_gap_match_the_dense_inverse(row):
    """Gap B|C links the buildings from DOF starts[1] on: its columns start inside the row."""
    s, starts, _ = row
    h = 0.005 / 4
    L = np.empty((s.n_dof, s.bandwidth + 2))
    assert K._factor(h, BETA, GAMMA, s.mass, s.dof_a0, s.el_i, s.el_j, s.el_k, s.el_a1, s.bandwidth, L)
    lo, hi = int(starts[1]), int(starts[3])
    # a gap at every floor level the neighbours share: the first one of B|C
    g = int(np.flatnonzero(np.minimum(s.gap_i, s.gap_j) >= lo)[0])
    W = np.full((s.n_gap, s.n_dof), np.nan)
    K._woodbury_columns(L, s.bandwidth, W, np.array([g]), 1, lo, hi, s.gap_i, s.gap_j)
    bvec = np.zeros(s.n_dof)
    bvec[s.gap_i[g]], bvec[s.gap_j[g]] = 1.0, -1.0
    expect = np.linalg.solve(_khat(s, h), bvec)
    assert np.max(np.abs(W[g, lo:hi] - expect[lo:hi])) <= 1e-12 * np.max(np.abs(expect))
    assert np.max(np.abs(expect[:lo])) <= 1e-15 * np.max(np.abs(expect))  # A is not coupled to the gap
    assert np.all(np.isnan(W[:g])) and np.all(np.isnan(W[g, :lo]))


def _blocks_by_hand(n, el_i, el_j):
    """Block starts by the definition: DOF d ends a block when no element couples a DOF <= d to one > d."""
    starts = [0]
    for d in range(n - 1):
        if not any(min(i, j) <= d < max(i, j) for i, j in zip(el_i, el_j) if j >= 0):
            starts.append(d + 1)
    return starts + [n]


def test_dof_blocks_match_their_definition_on_rows_with_joined_and_grounded_elements():
    rng = np.random.default_rng(3)
    for _ in range(200):
        n = int(rng.integers(1, 30))
        ne = int(rng.integers(0, 40))
        el_i = rng.integers(0, n, ne)
        el_j = np.where(rng.random(ne) < 0.3, -1, rng.integers(0, n, ne))
        got = dof_blocks(n, el_i, el_j)
        assert got.dtype == np.int64
        assert got.tolist() == _blocks_by_hand(n, el_i, el_j)
