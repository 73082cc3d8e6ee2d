"""The peak-oriented storey law through the material protocol: hand-derived points of its loops, exactness of
a move split into pieces, its recoverable energy, and its validation.

Kind: closed form (the points below are derived here from the law's rules: Clough & Johnston 1966, Takeda et
al. 1970 with Otani's 1974 unloading stiffness, Roufaiel & Meyer's 1987 pinch point), and properties.
"""

import numpy as np
import pytest

from seispound.contact.codes import N_PAR
from seispound.errors import InputError
from seispound.integrate._material import N_STATE, material_commit, material_energy, material_trial
from seispound.storey import StoreyLaw
from seispound.storey import codes as C

K, DY, ALPHA = 1e7, 0.01, 0.05
FY = K * DY


def _par(beta_u=0.0, pinching=0.0):
    law = StoreyLaw(kind="peak-oriented", yield_drift=DY, post_yield_ratio=ALPHA, unloading_exponent=beta_u,
                    pinching=pinching)
    law.validate(1)
    codes, par = law.kernel_rows([K], N_PAR)
    assert codes[0] == C.PEAK_ORIENTED
    return par


def _walk(par, drifts):
    """The force [N] after each committed move to the next drift, and the tangents; the final state."""
    committed, trial = np.zeros((1, N_STATE)), np.zeros((1, N_STATE))
    f, kt = np.zeros(len(drifts)), np.zeros(len(drifts))
    for i, x in enumerate(drifts):
        f[i], kt[i], _ = material_trial(C.PEAK_ORIENTED, par, committed, trial, 0, x, 0.0)
        material_commit(committed, trial, 0)
    return f, kt, committed


def test_clough_cycle_at_hand_derived_points():
    # 0 -> 2 dy: the backbone, Fy + alpha k dy; unloading at k reaches zero force at 2 dy - (1 + alpha) dy;
    # reloading aims at the other side's yield point (-dy, -Fy); then the backbone to -2 dy; back to +2 dy
    # aimed at the first peak (2 dy, (1 + alpha) Fy) from the zero-force point -(1 - alpha) dy
    f, kt, st = _walk(_par(), np.array([2.0, 1.5, 0.5, -1.0, -2.0, -0.5, 0.0, 2.0]) * DY)
    f2 = (1 + ALPHA) * FY
    d0 = 2 * DY - f2 / K
    k_re = FY / (d0 + DY)
    d0b = -d0
    k_back = f2 / (2 * DY - d0b)
    expected = [f2, f2 - 0.5 * K * DY, -k_re * (d0 - 0.5 * DY), -FY, -f2, k_back * (-0.5 * DY - d0b),
                k_back * (0.0 - d0b), f2]
    np.testing.assert_allclose(f, expected, rtol=1e-12, atol=1e-9 * FY)
    np.testing.assert_allclose(kt[[0, 1, 2, 4, 6]], [ALPHA * K, K, k_re, ALPHA * K, k_back], rtol=1e-12)
    assert st[0, 2] == pytest.approx(2 * DY) and st[0, 3] == pytest.approx(-2 * DY)  # the excursions


def test_takeda_unloading_stiffness_and_the_pinch_point():
    beta_u, s = 0.4, 0.5
    # unloading from 3 dy at k (dy / 3 dy)^0.4
    f, kt, _ = _walk(_par(beta_u), np.array([3.0, 2.5]) * DY)
    ku = K * (1 / 3) ** beta_u
    assert f[1] == pytest.approx(f[0] - ku * 0.5 * DY, rel=1e-12) and kt[1] == pytest.approx(ku, rel=1e-12)
    # pinched: after 3 dy and a full unloading to -dy, reloading towards +3 dy passes the pinch point on the
    # target's unloading line at (1 - s) of the target force, then reaches the target itself
    ft = FY + ALPHA * K * 2 * DY
    d_pinch = 3 * DY - s * ft / ku
    f, kt, _ = _walk(_par(beta_u, s), np.array([3.0, 0.0, -1.0, -1.5]) * DY)
    # unloaded from -1.5 dy (negative side at k (dy / 1.5 dy)^0.4): zero force at d0
    fneg = f[-1]
    ku_neg = K * (1 / 1.5) ** beta_u
    d0 = -1.5 * DY - fneg / ku_neg
    f2, kt2, _ = _walk(_par(beta_u, s), np.array([3.0, 0.0, -1.0, -1.5, d0 / DY,
                                                   (d0 + 0.5 * (d_pinch - d0)) / DY, d_pinch / DY, 3.0]) * DY)
    assert f2[4] == pytest.approx(0.0, abs=1e-6 * FY)
    assert f2[5] == pytest.approx(0.5 * (1 - s) * ft, rel=1e-10)  # half way along the first line
    assert f2[6] == pytest.approx((1 - s) * ft, rel=1e-10)  # the pinch point
    assert f2[7] == pytest.approx(ft, rel=1e-10)  # the target
    assert kt2[7] == pytest.approx((ft - (1 - s) * ft) / (3 * DY - d_pinch), rel=1e-10)


def test_a_move_split_into_pieces_ends_where_the_whole_move_does():
    # rate independent and piecewise linear: one monotonic move and the same move in 97 committed pieces agree
    rng = np.random.default_rng(3)
    par = _par(0.4, 0.3)
    turns = np.concatenate([[0.0], rng.uniform(-4, 4, 12) * DY])
    coarse = _walk(par, turns[1:])[0]
    fine_path = np.concatenate([np.linspace(a, b, 98)[1:] for a, b in zip(turns[:-1], turns[1:])])
    fine = _walk(par, fine_path)[0][96::97]
    np.testing.assert_allclose(fine, coarse, rtol=1e-11, atol=1e-9 * FY)


def test_recoverable_energy_is_what_unloading_returns():
    par = _par(0.4)
    _, _, st = _walk(par, np.array([2.5, 2.2]) * DY)
    f = st[0, 0]
    # unload to zero force in small committed steps: the work returned is the recoverable energy
    ku = K * (1 / 2.5) ** 0.4
    d0 = 2.2 * DY - f / ku
    e = material_energy(C.PEAK_ORIENTED, par, st, 0, 2.2 * DY)
    path = np.linspace(2.2 * DY, d0, 201)
    forces = _walk(par, np.array([2.5 * DY, *path]))[0][1:]
    returned = -np.trapezoid(forces, path)
    assert e == pytest.approx(returned, rel=1e-9)
    assert e == pytest.approx(f * f / (2 * ku), rel=1e-12)


@pytest.mark.parametrize("fields, key", [
    ({"kind": "bilinear", "unloading_exponent": 0.4}, "unloading_exponent"),
    ({"kind": "peak-oriented", "unloading_exponent": 2.5}, "unloading_exponent"),
    ({"kind": "peak-oriented", "pinching": 1.0}, "pinching"),
    ({"kind": "bilinear", "pinching": 0.3}, "pinching"),
])
def test_invalid_fields_name_their_key(fields, key):
    with pytest.raises(InputError, match=key):
        StoreyLaw(yield_drift=DY, post_yield_ratio=ALPHA, **fields).validate(1, "storey_law")


def test_unloading_never_flatter_than_the_peaks_secant_so_every_loop_dissipates():
    # alpha 0.23 and beta_u 0.9 at a ductility of 10: Takeda's k (1/10)^0.9 = 0.126 k is below the secant
    # F_m / d_m = k (0.23 + 0.77 / 10) = 0.307 k, and below alpha k its loops would make energy
    law = StoreyLaw(kind="peak-oriented", yield_drift=DY, post_yield_ratio=0.23, unloading_exponent=0.9)
    law.validate(1)
    par = law.kernel_rows([K], N_PAR)[1]
    f, kt, _ = _walk(par, np.array([10.0, 9.0]) * DY)
    assert kt[1] == pytest.approx(K * (0.23 + 0.77 / 10), rel=1e-12)
    # cycles of growing amplitude: the work done on the storey over each closed cycle is positive
    cyc = np.concatenate([np.linspace(0, a, 60)[1:] for a in (10, -10, 10, -12, 12, 0)]) * DY
    forces = _walk(par, cyc)[0]
    work = np.diff(cyc) * 0.5 * (forces[1:] + forces[:-1])
    assert work.sum() > 0.0
    bounds = np.flatnonzero(np.isin(np.round(cyc / DY, 9), (10, -10, -12, 12)))
    per_cycle = [work[a:b].sum() for a, b in zip(bounds[:-2:2], bounds[2::2])]
    assert min(per_cycle) > 0.0


def _path_by_walking(par, committed, cubic):
    """The force [N] at the middle and the end of delta(tau) = d0 + ca tau + cb tau^2 + cc tau^3 and the end's
    tangent [N/m], walked through the material protocol from ``committed`` in 4000 pieces (rate independent:
    exact to round-off at the pieces' ends)."""
    ca, cb, cc = cubic
    fine = np.linspace(0.0, 1.0, 4001)[1:]
    st, trial = committed.copy(), np.zeros_like(committed)
    f, kt = np.zeros(fine.size), np.zeros(fine.size)
    for i, x in enumerate(committed[0, 1] + fine * (ca + fine * (cb + fine * cc))):
        f[i], kt[i], _ = material_trial(C.PEAK_ORIENTED, par, st, trial, 0, x, 0.0)
        material_commit(st, trial, 0)
    return f[1999], f[-1], kt[-1]


@pytest.mark.parametrize("start, cubic, bends", [
    (0.3, (0.4, 0.0, 0.0), False),  # virgin, elastic both ways: never bends
    (-0.5, (1.0, 1.2, -1.6), False),  # virgin, through zero force and a turning point, inside +-dy
    (0.5, (1.0, 0.0, 0.0), True),  # virgin to 1.5 dy: yields at dy
    (2.5, (0.3, -0.6, 0.0), False),  # on the backbone at 2.5 dy, on along it, unloading after a turning point
], ids=["elastic", "through-zero-and-turning", "yields", "backbone-then-unloading"])
def test_the_flight_path_follows_the_protocol_and_reports_its_bends(start, cubic, bends):
    """``peak_oriented_path`` (the free-flight step's view of the law) against the protocol walked in 4000
    pieces: the end force, z at the middle and the end (z = delta - (k delta - f) / ((1 - alpha) k)), and the
    slopes where the path does not bend (closed form: the law is piecewise linear)."""
    from seispound.integrate._material import peak_oriented_path

    par = _par(0.4, 0.3)
    committed = _walk(par, np.array([start]) * DY)[2]  # (beyond dy: on the backbone)
    d0 = start * DY
    ca, cb, cc = (c * DY for c in cubic)
    zm, z1, pm, p1, bent, f1, dpos, dneg = peak_oriented_path(par, 0, committed, d0, ca, cb, cc)
    assert bent == bends
    fm_ref, f1_ref, kt_ref = _path_by_walking(par, committed, (ca, cb, cc))
    assert f1 == pytest.approx(f1_ref, abs=1e-10 * FY)
    if not bends:
        scale = (1.0 - ALPHA) * K
        dm, d1 = d0 + 0.5 * ca + 0.25 * cb + 0.125 * cc, d0 + ca + cb + cc
        assert zm == pytest.approx(dm - (K * dm - fm_ref) / scale, abs=1e-10 * DY)
        assert z1 == pytest.approx(d1 - (K * d1 - f1_ref) / scale, abs=1e-10 * DY)
        assert p1 == pytest.approx(1.0 - (K - kt_ref) / scale, abs=1e-12)
    assert dpos >= DY and dneg <= -DY
