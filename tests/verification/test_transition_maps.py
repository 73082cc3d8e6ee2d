"""The general driver's exact free-flight maps (``integrate/transition._exact_maps``) against an independent
solver: SciPy's Radau at rtol 1e-12 on M u'' + C u' + K u = -L g(t) + R c(t) with the input work integrated
alongside, one analysis step from random states; c constant (a bilinear storey's term) or quadratic in time
through its values at the step's start, middle and end (a Bouc-Wen storey's offset force).

Kind: independent implementation (a stiff implicit Runge-Kutta with its own right-hand side and quadrature).
Two buildings: light damping, and a dashpot that damps a mode by about e^-100 per step (a soil cone's).
"""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from seispound.integrate.transition import _exact_maps

H = 0.005  # [s]


def _building(rng, stiff):
    nb = 4
    M = np.diag(rng.uniform(1e4, 1e5, nb))
    k = rng.uniform(1e7, 5e7, nb)
    K = np.diag(k + np.r_[k[1:], 0.0]) - np.diag(k[1:], 1) - np.diag(k[1:], -1)
    C = 0.002 * K
    if stiff:  # -Re(lambda) h of about 100 for the damped mode
        C[0, 0] += 100.0 * M[0, 0] / H
    L = np.diag(M)[:, None] * np.ones((1, 2))  # two motion rows, each on every DOF
    L[:2, 1] = 0.0
    L[2:, 0] = 0.0
    R = np.zeros((nb, 1))
    R[0, 0], R[1, 0] = 1.0, -1.0  # a storey's constant term
    return M, C, K, L, R


def _radau(M, C, K, L, R, x0, g0, g1, c, cm=None, c1=None):
    nb = M.shape[0]
    Minv = np.linalg.inv(M)
    cm = c if cm is None else cm
    c1 = c if c1 is None else c1

    def load(t):  # Lagrange's quadratic through (0, c), (H/2, cm), (H, c1)
        s = t / H
        return c * 2.0 * (s - 0.5) * (s - 1.0) - cm * 4.0 * s * (s - 1.0) + c1 * 2.0 * s * (s - 0.5)

    def rhs(t, y):
        u, v = y[:nb], y[nb:2 * nb]
        g = g0 + (g1 - g0) * t / H
        return np.r_[v, Minv @ (-K @ u - C @ v - L @ g + R @ load(t)), -g @ L.T @ v]

    sol = solve_ivp(rhs, (0.0, H), np.r_[x0, 0.0], method="Radau", rtol=1e-12, atol=1e-18)
    return sol.y[:2 * nb, -1], sol.y[-1, -1]


@pytest.mark.parametrize("stiff", [False, True])
@pytest.mark.parametrize("quadratic", [False, True])
def test_exact_maps_match_an_implicit_runge_kutta(stiff, quadratic):
    rng = np.random.default_rng(7 + stiff)
    M, C, K, L, R = _building(rng, stiff)
    nb = M.shape[0]
    lam = np.linalg.eigvals(np.block([[np.zeros((nb, nb)), np.eye(nb)],
                                      [-np.linalg.solve(M, K), -np.linalg.solve(M, C)]]))
    decay = float(np.max(-lam.real) * H)
    assert decay > 50.0 if stiff else decay < 0.1
    P, G0, G1, Gc, Gq, Egx, Egg, Egc, Egq = _exact_maps(M, C, K, L, R, H, 0.25, 0.5, 1, quadratic)
    errs = []
    for _ in range(3):
        x0 = rng.normal(size=2 * nb) * np.r_[np.full(nb, 1e-2), np.full(nb, 1e-1)]
        g0, g1, c = rng.normal(size=2), rng.normal(size=2), rng.normal(size=1) * 1e4
        dq = rng.normal(size=2) * 1e4 if quadratic else np.zeros(2)  # [c(H/2) - c(0), c(H) - c(0)]
        x_ref, w_ref = _radau(M, C, K, L, R, x0, g0, g1, c, c + dq[:1], c + dq[1:])
        x1 = P[:2 * nb] @ x0 + G0[:2 * nb] @ g0 + G1[:2 * nb] @ g1 + Gc[:2 * nb] @ c + Gq[:2 * nb] @ dq
        g = np.r_[g0, g1]
        w = g @ Egx @ x0 + g @ Egg @ g + g @ Egc @ c + g @ Egq @ dq
        errs.append(max(np.abs(x1 - x_ref).max() / np.abs(x_ref).max(), abs(w - w_ref) / abs(w_ref)))
    print(f"MEASURED exact maps vs Radau, decay {decay:.3g} per step, quadratic load {quadratic}: "
          f"largest relative error {max(errs):.1e}")
    # measured: constant load 6.9e-15 and 8.1e-15; quadratic 9.0e-15 and 2.0e-14 (the stiff building)
    assert max(errs) <= (5e-14 if quadratic else 2e-14)
