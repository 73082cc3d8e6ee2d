"""The nonlinear element protocol (trial from the committed state, commit, onset) for contact laws and the
bilinear storey law with kinematic hardening."""

import math

import numpy as np
import pytest

from seispound.contact import _scalar, make_law
from seispound.integrate._material import (B_ALPHA, B_FY, B_K, BILINEAR, N_STATE, ST_E, ST_ZETA, material_commit,
                                           material_onset, material_trial)

K, FY, ALPHA = 2.0e7, 1.0e5, 0.1  # N/m, N, -: yield deformation 5 mm


def _bilinear_par():
    par = np.zeros(8)
    par[B_K], par[B_FY], par[B_ALPHA] = K, FY, ALPHA
    return par


@pytest.mark.parametrize("law", ["LVe", "MLVe", "NIVe", "Hd", "LHC", "Hertzdamp", "HC"])
def test_contact_laws_through_the_protocol(law):
    params = dict(stiffness=1e9, damping_constant=0.3) if law == "HC" else dict(stiffness=1e9, restitution=0.6)
    contact = make_law(law, **params)
    code, par = contact.code, contact.kernel_params(100.0, 120.0)
    state = np.zeros(N_STATE)
    material_onset(code, par, 0.4, state)
    zeta, e = _scalar.onset_state(code, par, 0.4)
    assert (state[ST_ZETA], state[ST_E]) == (zeta, e)
    trial = np.empty((1, N_STATE))
    got = material_trial(code, par[None], state[None], trial, 0, 1e-4, 0.2)
    assert got == _scalar.contact_force(code, par, 1e-4, 0.2, zeta)
    assert np.array_equal(trial[0], state)  # contact laws carry no history within an impact


def _masing_reference(delta):
    """The bilinear law written as Masing's rule: from the last reversal (d_r, q_r) the hysteretic force is
    q_r + k (d - d_r), capped at +-fy, until the deformation turns again."""
    q = np.zeros(delta.size)
    d_r, q_r, direction = 0.0, 0.0, 0.0
    for i in range(1, delta.size):
        step = delta[i] - delta[i - 1]
        if step != 0.0 and np.sign(step) != direction:
            if direction != 0.0:
                d_r, q_r = delta[i - 1], q[i - 1]
            direction = np.sign(step)
        q[i] = min(max(q_r + K * (delta[i] - d_r), -FY), FY)
    return ALPHA * K * delta + (1.0 - ALPHA) * q


def test_bilinear_loops_under_imposed_cyclic_drift_equal_masing_rule():
    t = np.linspace(0.0, 4.0, 4001)
    delta = 0.004 * (1 + t) * np.sin(2 * math.pi * t)  # 4 mm growing to 20 mm: elastic, then yielding
    par = _bilinear_par()[None]  # the protocol takes tables, one row per element
    committed, trial = np.zeros((1, N_STATE)), np.zeros((1, N_STATE))
    force = np.zeros(t.size)
    for i in range(1, t.size):
        # a trial that is abandoned (a redone step) must leave no trace
        material_trial(BILINEAR, par, committed, trial, 0, 10.0 * delta[i], 0.0)
        force[i], kt, _ = material_trial(BILINEAR, par, committed, trial, 0, delta[i], 0.0)
        material_commit(committed, trial, 0)
        assert kt in (K, ALPHA * K)
    ref = _masing_reference(delta)
    print(f"MEASURED bilinear against Masing's rule: {np.abs(force - ref).max() / FY:.1e} of fy")
    assert np.abs(force - ref).max() <= 1e-9 * FY


def test_bilinear_dissipates_the_closed_form_per_cycle():
    """A symmetric cycle of amplitude A > dy: loop area (1 - alpha) 4 fy (A - dy), dy = fy / k."""
    A = 0.02
    t = np.linspace(0.0, 2.0, 200001)
    delta = A * np.sin(2 * math.pi * t)
    par = _bilinear_par()[None]
    committed, trial = np.zeros((1, N_STATE)), np.zeros((1, N_STATE))
    force = np.zeros(t.size)
    for i in range(1, t.size):
        force[i] = material_trial(BILINEAR, par, committed, trial, 0, delta[i], 0.0)[0]
        material_commit(committed, trial, 0)
    second = t >= 1.0  # the stabilised cycle
    area = np.sum(0.5 * (force[second][1:] + force[second][:-1]) * np.diff(delta[second]))
    closed = (1 - ALPHA) * 4 * FY * (A - FY / K)
    assert area == pytest.approx(closed, rel=1e-6)
