"""The contact compliance G = B^T K_hat^-1 B and the contact share of a step, K_hat^-1 B F.

A located step has a step size of its own, so its factor is new; the kernel
then takes G from the semiseparable inverse of the tridiagonal K_hat
(``_inverse_diagonals``, ``_compliance_tridiagonal``) and K_hat^-1 B F from one
sparse solve (``_subtract_contact``), instead of a Woodbury column per closed
gap.  Each is checked here against a dense
``numpy.linalg.inv`` of K_hat assembled independently from the storey springs.
The banded path (any bandwidth, Woodbury columns throughout) is checked against
the tridiagonal one on a whole pounding run.
"""

from dataclasses import replace

import numpy as np
import pytest

from seispound.contact import make_law
from seispound.integrate import integrate
from seispound.integrate._linear import (
    SEMISEPARABLE_GAPS, _compliance_tridiagonal, _factor, _inverse_diagonals, _subtract_contact,
)
from seispound.structure import Building, Gap, RayleighDamping, assemble

BETA, GAMMA = 0.25, 0.5


def _row(storeys, seed=0):
    """Buildings of the given storey counts with random floor masses and storey stiffnesses."""
    rng = np.random.default_rng(seed)
    bs = []
    for b, ns in enumerate(storeys):
        bs.append(Building(f"B{b}", list(rng.uniform(0.5e5, 2e5, ns)), list(rng.uniform(1e7, 5e8, ns)),
                           [3.0] * ns, RayleighDamping(0.05, (1, 2) if ns > 1 else (1, 1))))
    gaps = [Gap((a.name, c.name), 0.02) for a, c in zip(bs, bs[1:])]
    return assemble(bs, gaps, make_law("LVe", stiffness=2e8, restitution=0.65))


def _dense_khat(s, h):
    """K_hat = (1/(beta h^2) + gamma/(beta h) a0) M + (1 + gamma/(beta h) a1) K, assembled densely."""
    # the assembly's dense matrices; the kernel factors its own banded K_hat from the element arrays
    cm, cc = 1.0 / (BETA * h * h), GAMMA / (BETA * h)
    return s.stiffness_matrix() + cc * s.damping_matrix() + np.diag(cm * s.mass)


def _factored(s, h):
    p = int(s.bandwidth)
    L = np.empty((s.n_dof, p + 2))
    assert _factor(h, BETA, GAMMA, s.mass, s.dof_a0, s.el_i, s.el_j, s.el_k, s.el_a1, p, L)
    sig, Sd = np.empty(s.n_dof), np.empty(s.n_dof)
    _inverse_diagonals(L, p, sig, Sd)
    return p, L, sig, Sd


def _scratch(ng, n):
    k = 2 * ng
    return (np.empty(k, np.int64), np.empty(k, np.int64), np.empty(k, np.int64), np.empty(k), np.empty((k, k)))


# dt and a deep contact substep: K_hat^-1 decays by ~0.05 per floor at the first,
# by ~1e-6 at the second, where the far entries underflow
@pytest.mark.parametrize("h", [0.005, 0.005 / 256])
@pytest.mark.parametrize("storeys", [(8, 5, 13), (1, 1, 1), (40, 40)])
def test_semiseparable_inverse_matches_a_dense_inverse(storeys, h):
    s = _row(storeys)
    p, L, sig, Sd = _factored(s, h)
    Kinv = np.linalg.inv(_dense_khat(s, h))
    assert np.allclose(Sd, np.diag(Kinv), rtol=1e-13, atol=0)
    # every entry a <= b from the ratio products, cross-building ones exactly zero
    n = s.n_dof
    scale = np.abs(np.diag(Kinv)).max()
    for a in range(n):
        prod = 1.0
        for b in range(a, n):
            if b > a:
                prod *= sig[b]
            assert abs(Sd[b] * prod - Kinv[a, b]) <= 1e-12 * scale, (a, b)


@pytest.mark.parametrize("h", [0.005, 0.005 / 256])
@pytest.mark.parametrize("storeys,m", [((8, 5, 13), 1), ((8, 5, 13), 2), ((8, 5, 13), 5),
                                       ((40, 40), 7), ((1, 1, 1), 2)])
def test_compliance_and_contact_share_match_dense_algebra(storeys, m, h):
    """G and Du - K_hat^-1 B F for m closed gaps chosen at random, some sharing a floor DOF."""
    s = _row(storeys, seed=m)
    rng = np.random.default_rng(100 + m)
    p, L, sig, Sd = _factored(s, h)
    Kinv = np.linalg.inv(_dense_khat(s, h))
    act = rng.choice(s.n_gap, size=m, replace=False).astype(np.int64)
    gi, gj = s.gap_i.astype(np.int64), s.gap_j.astype(np.int64)
    B = np.zeros((s.n_dof, m))
    B[gi[act], np.arange(m)] += 1.0
    B[gj[act], np.arange(m)] -= 1.0
    G_ref = B.T @ Kinv @ B

    G = np.empty((s.n_gap, s.n_gap))
    _compliance_tridiagonal((0, m, act), gi, gj, (sig, Sd), G, _scratch(s.n_gap, s.n_dof))
    assert np.allclose(G[:m, :m], G_ref, rtol=1e-12, atol=1e-12 * np.abs(G_ref).max())
    # the same gaps as a group further down the list (the kernel's groups): the same block there
    off = s.n_gap - m
    shifted = np.r_[np.zeros(off, np.int64), act]
    G2 = np.full((s.n_gap, s.n_gap), np.nan)
    _compliance_tridiagonal((off, s.n_gap, shifted), gi, gj, (sig, Sd), G2, _scratch(s.n_gap, s.n_dof))
    assert np.array_equal(G2[off:, off:], G[:m, :m])
    assert np.isnan(G2[:off, :]).all() and np.isnan(G2[:, :off]).all()  # nothing written outside it

    # the blocks each gap links (the buildings' DOFs are contiguous, in row order)
    starts = np.r_[0, np.cumsum(storeys)]
    blk = np.searchsorted(starts, np.arange(s.n_dof), side="right") - 1
    lo = np.minimum(starts[blk[gi]], starts[blk[gj]]).astype(np.int64)
    hi = np.maximum(starts[blk[gi] + 1], starts[blk[gj] + 1]).astype(np.int64)
    F = rng.uniform(1e4, 1e6, m)
    Du0 = rng.normal(size=s.n_dof) * 1e-3
    Du = Du0.copy()
    _subtract_contact(L, p, m, act, gi, gj, lo, hi, F, np.empty(s.n_dof), Du)
    ref = Du0 - Kinv @ (B @ F)
    assert np.allclose(Du, ref, rtol=0, atol=1e-13 * np.abs(Kinv @ (B @ F)).max() + 1e-18)


@pytest.mark.parametrize("case", ["row_of_three", "tall_row"])
def test_banded_path_reproduces_the_tridiagonal_one_on_a_pounding_run(case):
    """The same row declared with half bandwidth 2: Woodbury columns throughout, no
    semiseparable shortcut.  Histories agree to round-off, impact counts exactly.

    The tall row (three 20-storey buildings, 1 cm gaps) closes SEMISEPARABLE_GAPS
    or more gaps at once, so its located steps take the shortcut.
    """
    from seispound import load_model
    from seispound.motion import read_record
    from seispound.motion.catalogue import bundled_path
    from seispound.simulation import prepare_ground_motion
    from tests._models import REPO

    n = 1200  # 6 s: the first impacts
    if case == "row_of_three":
        model = load_model(REPO / "models" / "row_of_three.toml")
        s = assemble(model.buildings, model.gaps, model.contact)
        ag, _ = prepare_ground_motion(model)
        ag, dt = ag[..., :n + 1], model.analysis.dt
    else:
        s = _row((20, 20, 20), seed=3)
        s = replace(s, gap_size=np.full(s.n_gap, 0.01))
        rec = read_record(bundled_path("elcentro_180"))
        dt = 0.005
        ag = np.interp(np.arange(n + 1) * dt, np.arange(rec.acceleration.size) * rec.dt, rec.acceleration)
    tri = integrate(s, ag, dt, n)
    band = integrate(replace(s, bandwidth=2), ag, dt, n)
    assert tri.impacts["gap"].size > 10
    if case == "tall_row":
        assert (tri.force > 0).sum(axis=1).max() >= SEMISEPARABLE_GAPS
    assert np.array_equal(tri.impacts["gap"], band.impacts["gap"])
    assert tri.stats["steps"] == band.stats["steps"]
    scale = np.abs(tri.displacement).max()
    assert np.abs(tri.displacement - band.displacement).max() <= 1e-9 * scale
    assert np.abs(tri.force - band.force).max() <= 1e-7 * np.abs(tri.force).max()
