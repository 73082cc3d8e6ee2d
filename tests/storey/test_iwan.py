"""Iwan's distributed-element storey law (``integrate._iwan``) through the material protocol.

Kinds: closed form (Masing's rules, which Iwan 1966 proves for the parallel-series model, and the energy a
full cycle dissipates in each elastic-perfectly-plastic slider, 4 k_i d_i (A - d_i)); the bilinear law of
the package at zero spread and no self-centring (a regression guard: two laws of one package); the
protocol's trial/commit contract.
"""

import numpy as np
import pytest

from seispound.contact.codes import N_PAR
from seispound.errors import InputError
from seispound.integrate._material import N_STATE, material_commit, material_energy, material_trial
from seispound.storey import StoreyLaw
from seispound.storey import codes as C

K, DY, ALPHA = 2e7, 0.01, 0.05


def _par(spread, centring, alpha=ALPHA):
    law = StoreyLaw(kind="iwan", yield_drift=DY, post_yield_ratio=alpha, yield_spread=spread,
                    self_centring=centring)
    law.validate(1)
    return law.kernel_rows([K], N_PAR)[1]


def _walk(par, drifts, code=C.IWAN):
    """Forces, tangents and the work done along the drifts (each move committed), from the virgin state."""
    committed, trial = np.zeros((1, N_STATE)), np.zeros((1, N_STATE))
    f, kt, work, prev_f, prev_d = [], [], 0.0, 0.0, 0.0
    for d in drifts:
        force, tangent, _ = material_trial(code, par, committed, trial, 0, d, 0.0)
        material_commit(committed, trial, 0)
        work += 0.5 * (force + prev_f) * (d - prev_d)  # exact for a piecewise-linear law on a fine walk
        f.append(force)
        kt.append(tangent)
        prev_f, prev_d = force, d
    return np.array(f), np.array(kt), work, committed


def _virgin(x, spread, centring, alpha=ALPHA):
    """The virgin curve at drift x >= 0, summed spring by spring (closed form)."""
    d = DY * 10.0 ** (spread * (2 * (np.arange(8) + 0.5) / 8 - 1))
    ki = (1 - centring) * (1 - alpha) * K / 8
    return alpha * K * x + centring * (1 - alpha) * K * min(x, DY) + ki * np.minimum(x, d).sum()


@pytest.mark.parametrize("spread", [0.0, 0.4, 1.0])
def test_unloading_branch_is_the_virgin_curve_scaled_by_two(spread):
    up = np.linspace(0.0, 3 * DY, 301)[1:]
    down = np.linspace(3 * DY, -3 * DY, 601)[1:]
    f, _, _, _ = _walk(_par(spread, 0.0), np.concatenate([up, down]))
    fr = f[up.size - 1]
    masing = np.array([fr - 2 * _virgin((3 * DY - d) / 2, spread, 0.0) for d in down])
    err = np.abs(f[up.size:] - masing).max() / (K * DY)
    print(f"MEASURED Iwan spread {spread}: largest difference from Masing's branch {err:.1e} Fy")
    assert err < 3e-15  # measured 8.7e-16 (round-off)
    assert np.abs(f[:up.size] - [_virgin(d, spread, 0.0) for d in up]).max() < 1e-12 * K * DY


def test_an_inner_loop_closes_where_it_started():
    # load to 3 dy, unload to -1 dy, reload to +0.5 dy (an inner loop), unload again: past -1 dy the law
    # continues on the outer branch (Masing's extended rules; the sliders are the memory)
    par = _par(0.6, 0.0)
    path = np.concatenate([np.linspace(0, 3, 301)[1:], np.linspace(3, -1, 401)[1:], np.linspace(-1, 0.5, 151)[1:],
                           np.linspace(0.5, -2.5, 301)[1:]]) * DY
    direct = np.concatenate([np.linspace(0, 3, 301)[1:], np.linspace(3, -2.5, 551)[1:]]) * DY
    f, _, _, _ = _walk(par, path)
    g, _, _, _ = _walk(par, direct)
    err = abs(f[-1] - g[-1]) / (K * DY)
    print(f"MEASURED Iwan inner loop: end force differs from the outer branch's by {err:.1e} Fy")
    assert err < 1e-15  # measured 0


@pytest.mark.parametrize("centring", [0.0, 0.5])
def test_a_full_cycle_dissipates_what_the_sliders_do(centring):
    spread, amp = 0.5, 2.0 * DY
    par = _par(spread, centring)
    path = np.concatenate([np.linspace(0, amp, 2001)[1:], np.linspace(amp, -amp, 4001)[1:],
                           np.linspace(-amp, amp, 4001)[1:]])
    first, _, w0, st0 = _walk(par, path[:2000])
    f, _, work, st = _walk(par, path)
    stored0 = material_energy(C.IWAN, par, st0, 0, amp)
    stored1 = material_energy(C.IWAN, par, st, 0, amp)
    dissipated = (work - w0) - (stored1 - stored0)
    d = DY * 10.0 ** (spread * (2 * (np.arange(8) + 0.5) / 8 - 1))
    ki = (1 - centring) * (1 - ALPHA) * K / 8
    closed = (4 * ki * d * np.maximum(amp - d, 0.0)).sum()
    err = abs(dissipated - closed) / closed
    print(f"MEASURED Iwan cycle, self-centring {centring}: dissipated {dissipated:.6g} J, closed form "
          f"{closed:.6g} J, relative difference {err:.1e}")
    assert err < 1.5e-7  # measured 4.6e-8: the trapezoidal work over the moves in which a slider yields
    assert abs(f[-1] - first[-1]) < 1e-9 * K * DY  # the cycle closes


def test_no_spread_no_centring_is_the_bilinear_law():
    rng = np.random.default_rng(3)
    drifts = np.cumsum(rng.normal(0.0, 0.4 * DY, 400))
    f, kt, _, _ = _walk(_par(0.0, 0.0), drifts)
    law = StoreyLaw(kind="bilinear", yield_drift=DY, post_yield_ratio=ALPHA)
    law.validate(1)
    g, _, _, _ = _walk(law.kernel_rows([K], N_PAR)[1], drifts, C.BILINEAR)
    assert np.abs(f - g).max() < 1e-9 * K * DY
    assert np.abs(f).max() > 1.5 * K * DY * ALPHA + K * DY * (1 - ALPHA)  # it yields well past fy


def test_tangent_is_k_exactly_while_elastic_and_the_trial_leaves_the_committed_state():
    par = _par(0.5, 0.3)
    committed, trial = np.zeros((1, N_STATE)), np.zeros((1, N_STATE))
    d0 = DY * 10.0 ** (-0.5 * 7 / 8)  # the first slider's yield drift
    f, kt, _ = material_trial(C.IWAN, par, committed, trial, 0, 0.9 * d0, 0.0)
    assert kt == K and f == pytest.approx(0.9 * d0 * K, rel=1e-14)
    f, kt, _ = material_trial(C.IWAN, par, committed, trial, 0, 2.0 * DY, 0.0)
    assert kt < K and np.all(committed == 0.0) and np.any(trial != 0.0)


def test_self_centring_narrows_the_loop_and_brings_the_drift_back():
    path = np.concatenate([np.linspace(0, 3, 301)[1:], np.linspace(3, 0, 301)[1:]]) * DY
    residual = [_walk(_par(0.3, c), path)[0][-1] for c in (0.0, 0.8)]
    # at zero drift after the excursion the hysteretic sliders pull back: less force left with self-centring
    assert abs(residual[1]) < 0.35 * abs(residual[0])


@pytest.mark.parametrize("field, value", [("yield_spread", 1.5), ("self_centring", 1.0), ("yield_spread", -0.1)])
def test_bad_parameters_are_refused(field, value):
    law = StoreyLaw(kind="iwan", yield_drift=DY, post_yield_ratio=ALPHA, **{field: value})
    with pytest.raises(InputError, match=field):
        law.validate(1)
    with pytest.raises(InputError, match=field):
        StoreyLaw(kind="bilinear", yield_drift=DY, **{field: 0.5}).validate(1)
