"""The flag-shaped, self-centring storey law (``integrate._flag``) through the material protocol.

Kinds: closed form (the flag's branches drawn from its geometry, the energy a full cycle dissipates,
2 beta H (A - dy) for an amplitude A >= (1 + beta) dy, derived in the test's docstring); the law's own energy
function against the work done on a random walk (dissipation never decreases: a consistency check of the
derived recoverable energy); the return map over one long step against a fine walk (the exactness claimed for
a monotone step, zero crossings included); the protocol's trial/commit contract; the free flight's path along a
step's cubic (``_material.flag_path``) against a fine walk of the law (the path's pieces claimed exact), and its
slope changes against cases whose corners are placed by hand.
"""

import numpy as np
import pytest

from seispound.contact.codes import N_PAR
from seispound.errors import InputError
from seispound.integrate._flag import flag_kept_elastic, flag_window
from seispound.integrate._material import N_STATE, flag_path, material_commit, material_energy, material_trial
from seispound.storey import StoreyLaw
from seispound.storey import codes as C

K, DY, ALPHA = 2e7, 0.01, 0.05
KH = (1 - ALPHA) * K  # the hysteretic force's stiffness
H = KH * DY  # its strength


def _par(beta, alpha=ALPHA):
    law = StoreyLaw(kind="flag", yield_drift=DY, post_yield_ratio=alpha, energy_dissipation=beta)
    law.validate(1)
    return law.kernel_rows([K], N_PAR)[1]


def _walk(par, drifts):
    """Forces, tangents, the work done along the drifts (each move committed) and the recoverable energies."""
    committed, trial = np.zeros((1, N_STATE)), np.zeros((1, N_STATE))
    f, kt, work, stored, prev_f, prev_d = [], [], [0.0], [], 0.0, 0.0
    for d in drifts:
        force, tangent, _ = material_trial(C.FLAG, par, committed, trial, 0, d, 0.0)
        material_commit(committed, trial, 0)
        work.append(work[-1] + 0.5 * (force + prev_f) * (d - prev_d))
        stored.append(material_energy(C.FLAG, par, committed, 0, d))
        f.append(force)
        kt.append(tangent)
        prev_f, prev_d = force, d
    return np.array(f), np.array(kt), np.array(work[1:]), np.array(stored), committed


def _flag_loop(d_up, d_down, amp, beta):
    """The closed-form flag (written from its geometry, apart from the law): loading from zero to amp, then
    unloading from amp to zero.  Loading: k d to dy, then alpha k d + H.  Unloading: k (d - amp) down from the
    upper branch until h has dropped by beta H, then the lower branch alpha k d + (1 - beta) H, then k d below
    (1 - beta) dy."""
    up = np.where(d_up <= DY, K * d_up, ALPHA * K * d_up + H)
    top = ALPHA * K * amp + H
    drop = amp - beta * DY  # where the unloading line meets the lower branch (beta H / KH = beta dy)
    low = (1 - beta) * DY
    down = np.where(d_down >= drop, top + K * (d_down - amp),
                    np.where(d_down >= low, ALPHA * K * d_down + (1 - beta) * H, K * d_down))
    return up, down


@pytest.mark.parametrize("beta", [0.0, 0.4, 1.0])
def test_one_excursion_draws_the_flag(beta):
    amp = 3 * DY
    d_up, d_down = np.linspace(0, amp, 301)[1:], np.linspace(amp, 0, 301)[1:]
    f, _, _, _, _ = _walk(_par(beta), np.concatenate([d_up, d_down]))
    up, down = _flag_loop(d_up, d_down, amp, beta)
    err = max(np.abs(f[:300] - up).max(), np.abs(f[300:] - down).max()) / H
    print(f"MEASURED flag beta {beta}: largest difference from the drawn flag {err:.1e} H")
    assert err < 5e-15  # measured 1.8e-15 H: round-off
    assert f[-1] == 0.0  # back at zero drift, at zero force: self-centring
    # the mirror image
    g, _, _, _, _ = _walk(_par(beta), -np.concatenate([d_up, d_down]))
    assert np.abs(g + f).max() < 3e-15 * H


@pytest.mark.parametrize("beta", [0.3, 1.0])
def test_a_full_cycle_dissipates_the_flags_area(beta):
    """Half a cycle's loop lies between the loading path (k d to dy, then H) and the unloading path (the drop of
    beta H at k, the lower branch, the origin's line) in h = F - alpha k d: over [(1 - beta) dy, dy] the area
    is K dy^2 beta^2 / 2, over [dy, A - beta dy] beta H (A - dy - beta dy), over [A - beta dy, A] K beta^2 dy^2 / 2:
    beta H (A - dy) in all; a full cycle twice that."""
    amp = 3 * DY
    path = np.concatenate([np.linspace(0, amp, 3001)[1:], np.linspace(amp, -amp, 6001)[1:],
                           np.linspace(-amp, 0, 3001)[1:]])
    f, _, work, stored, _ = _walk(_par(beta), path)
    closed = 2 * beta * H * (amp - DY)
    err = abs(work[-1] - closed) / closed
    print(f"MEASURED flag cycle beta {beta}: dissipated {work[-1]:.6g} J, closed form {closed:.6g} J, "
          f"relative difference {err:.1e}")
    assert err < 2e-14  # measured 3.4e-15 and 5.7e-15: the walk's grid holds every corner, so the work is exact
    assert abs(f[-1]) < 1e-9 * H and abs(stored[-1]) < 1e-9 * H * DY  # back at rest, nothing stored


def test_recoverable_energy_leaves_a_dissipation_that_never_decreases():
    # a random walk of moves of about 0.25 dy, each walked in 40 substeps (the trapezoidal work of a substep
    # across a corner of the flag errs by about K (dy / 160)^2, 1e-4 H dy): over no move may the work done
    # fall short of the change in recoverable energy (beyond that trapezoidal error)
    rng = np.random.default_rng(5)
    coarse = np.concatenate([[0.0], np.cumsum(rng.normal(0.0, 0.25 * DY, 600))])
    fine = np.concatenate([np.linspace(a, b, 41)[1:] for a, b in zip(coarse[:-1], coarse[1:])])
    _, _, work, stored, _ = _walk(_par(0.6), fine)
    dissipated = (work - stored)[39::40]
    steps = np.diff(np.concatenate([[0.0], dissipated]))
    print(f"MEASURED flag random walk: most negative dissipation over a move {steps.min():.1e} J "
          f"(H dy = {H * DY:.4g} J; total {dissipated[-1]:.4g} J)")
    assert steps.min() > -1e-4 * H * DY  # measured -6.6e-2 J, 3.5e-5 H dy
    assert dissipated[-1] > 10 * H * DY and np.abs(coarse).max() > 2 * DY


@pytest.mark.parametrize("start, end", [(2.5, -1.7), (2.5, 0.3), (0.5, -2.2), (-2.8, 2.0)])
def test_one_long_step_equals_the_fine_walk(start, end):
    par = _par(0.7)
    lead = np.linspace(0, start, 400)[1:] * DY
    _, _, _, _, committed = _walk(par, lead)
    trial = np.zeros((1, N_STATE))
    f_one, _, _ = material_trial(C.FLAG, par, committed, trial, 0, end * DY, 0.0)
    f_fine, _, _, _, _ = _walk(par, np.concatenate([lead, np.linspace(start, end, 800)[1:] * DY]))
    assert abs(f_one - f_fine[-1]) < 1e-12 * H


def test_zero_dissipation_is_nonlinear_elastic_and_the_window_matches_the_law():
    rng = np.random.default_rng(7)
    drifts = np.cumsum(rng.normal(0.0, 0.4 * DY, 400))
    f, _, _, _, _ = _walk(_par(0.0), drifts)
    assert np.abs(f - (ALPHA * K * drifts + np.clip(KH * drifts, -H, H))).max() < 1e-9 * H
    # inside its window a storey's force is k d - c; a trial kept elastic lies in it
    par = _par(0.5)
    committed, trial = np.zeros((1, N_STATE)), np.zeros((1, N_STATE))
    kept = 0
    for d in drifts:
        lo, hi, c = flag_window(par, committed, 0)
        probe = d + rng.normal(0.0, 0.5 * DY)
        fp, ktp, _ = material_trial(C.FLAG, par, committed, trial, 0, probe, 0.0)
        if flag_kept_elastic(par, committed, 0, probe, ktp):
            kept += 1
            assert lo <= probe <= hi and abs(fp - (K * probe - c)) < 1e-9 * H
        elif lo < probe < hi:
            raise AssertionError("a trial inside the window was not kept")
        material_trial(C.FLAG, par, committed, trial, 0, d, 0.0)
        material_commit(committed, trial, 0)
    assert 50 < kept < 390


@pytest.mark.parametrize("field, value", [("energy_dissipation", 1.5), ("energy_dissipation", -0.1)])
def test_bad_parameters_are_refused(field, value):
    law = StoreyLaw(kind="flag", yield_drift=DY, post_yield_ratio=ALPHA, **{field: value})
    with pytest.raises(InputError, match=field):
        law.validate(1)
    with pytest.raises(InputError, match=field):
        StoreyLaw(kind="bilinear", yield_drift=DY, **{field: 0.5}).validate(1)


def _path_case(par, lead, cubic):
    """flag_path from the state the drifts ``lead`` leave, along d0 + ca t + cb t^2 + cc t^3, and the fine walk's
    h [N] at the cubic's middle and end (20 000 moves, each committed)."""
    _, _, _, _, committed = _walk(par, lead)
    d0, ca, cb, cc = lead[-1], *cubic
    out = flag_path(par, 0, committed, d0, ca, cb, cc)
    tau = np.linspace(0.0, 1.0, 20001)[1:]
    f, _, _, _, _ = _walk(par, np.concatenate([lead, d0 + tau * (ca + tau * (cb + tau * cc))]))
    d_mid, d_end = d0 + 0.5 * (ca + 0.5 * (cb + 0.5 * cc)), d0 + ca + cb + cc
    h_walk = (f[len(lead) + 9999] - ALPHA * K * d_mid, f[-1] - ALPHA * K * d_end)
    return out, h_walk


# (the lead's end in dy, the cubic's (ca, cb, cc) in dy, whether the force bends inside a monotonic piece)
PATHS = [
    (3.0, (0.9, -0.6, -0.1), False),  # on the upper branch, out to 3.34 dy, back inside the flag to 3.2 dy
    (3.0, (0.3, 0.1, 0.0), False),  # on the upper branch throughout
    (3.0, (-1.0, 0.0, 0.0), True),  # unloads at k, meets the lower branch at 2.4 dy
    (2.0, (0.5, 0.0, 0.0), True),  # inside the flag after unloading, loads onto the upper branch at 2.6 dy
    (0.5, (0.3, 0.0, 0.0), False),  # on the origin's line, stays within dy
    (0.5, (-1.0, 0.0, 0.0), False),  # on the origin's line through zero drift
]


@pytest.mark.parametrize("start, cubic, bends", PATHS)
def test_the_free_flights_path_follows_the_law_along_a_cubic(start, cubic, bends):
    par = _par(0.6)
    lead = np.concatenate([np.linspace(0, start + 0.4, 300)[1:], np.linspace(start + 0.4, start, 100)[1:]]) * DY
    if start > 2.5:  # the cases on the upper branch end loading
        lead = np.linspace(0, start, 300)[1:] * DY
    (zm, z1, pm, p1, bent, h1), (hm_walk, h1_walk) = _path_case(par, lead, np.array(cubic) * DY)
    # measured: the end within 1.4e-12 H of the walk (its round-off over 20 000 moves), the middle 2.6e-15 H
    print(f"MEASURED flag path from {start} dy: end {abs(h1 - h1_walk) / H:.1e} H, middle "
          f"{abs(zm * KH - hm_walk) / H:.1e} H, bends {bent}")
    assert abs(h1 - h1_walk) < 4e-12 * H and abs(z1 * KH - h1) < 1e-12 * H
    assert bent == bends
    if not bends:  # the middle on its piece's line
        assert abs(zm * KH - hm_walk) < 1e-14 * H and pm in (0.0, 1.0) and p1 in (0.0, 1.0)
