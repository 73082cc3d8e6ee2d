"""The Bouc-Wen law's closed form along a monotonic move (``_material._bouc_wen_exact``, n = 1 and 2, no
degradation or pinching) against SciPy's ``solve_ivp`` on Wen's equation (kind: independent solver).

The reference integrates dz/d(delta) = 1 - |z/dy|^n (beta sgn(d(delta) z) + gamma) (Wen 1976, Eq. 2 with
A = 1, divided by the deformation's rate: the law is rate independent) with Radau at rtol 1e-12, split where z
crosses zero (the right-hand side's kink), from states that load, unload, cross zero and start above
saturation, for beta > gamma, beta = gamma and beta < gamma.  The tangent dz/d(total) is checked against a
central difference of the closed form, and the package's sub-increments (the path every other law takes)
against the same reference at their own, second-order accuracy.
"""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from seispound.integrate._material import BW_SUBINCREMENT, _bouc_wen_exact, bouc_wen_advance
from seispound.storey import StoreyLaw

DY = 0.01  # m


def _reference(z0, total, n, beta, gamma):
    """z after the deformation moves by ``total`` [m], Radau on Wen's equation, restarted where z crosses 0."""
    s = float(np.sign(total))

    def rhs(_, z):
        c = beta * (1.0 if s * z[0] >= 0.0 else -1.0) + gamma
        return [s * (1.0 - abs(z[0] / DY) ** n * c)]

    def cross(_, z):
        return z[0]

    cross.terminal = True
    cross.direction = s  # unloading runs z to zero in the move's direction, then loads on
    loading = z0 * s >= 0.0  # (from z = 0 too): no crossing ahead
    sol = solve_ivp(rhs, (0.0, abs(total)), [z0], method="Radau", rtol=1e-12, atol=1e-16 * DY,
                    events=None if loading else cross)
    if loading or sol.t_events[0].size == 0:
        return sol.y[0, -1]
    t = sol.t_events[0][0]
    sol = solve_ivp(rhs, (t, abs(total)), [0.0], method="Radau", rtol=1e-12, atol=1e-16 * DY)
    return sol.y[0, -1]


CASES = [  # (z0 / dy, total / dy): loading, unloading without and with a zero crossing, above saturation
    (0.0, 0.3), (0.2, 1.5), (0.9, 0.05), (0.6, -0.3), (0.6, -2.0), (-0.95, 3.0), (-0.3, -0.02), (0.0, -0.7),
    (1.05, 0.2), (-1.1, -0.4),
]
LAWS = [(0.5, 0.5), (0.75, 0.25), (0.25, 0.75), (0.9, 0.3)]


@pytest.mark.parametrize("n", [1.0, 2.0])
@pytest.mark.parametrize("beta,gamma", LAWS)
def test_closed_form_equals_wen_integrated_by_radau(n, beta, gamma):
    worst = 0.0
    for x0, u in CASES:
        z1 = _bouc_wen_exact(x0 * DY, 0.0, u * DY, DY, n, beta, gamma)[0]
        ref = _reference(x0 * DY, u * DY, n, beta, gamma)
        worst = max(worst, abs(z1 - ref) / DY)
    print(f"MEASURED n={n} beta={beta} gamma={gamma}: largest |z - Radau| {worst:.2e} dy")
    assert worst < 1.5e-14  # measured: at most 5.4e-15 dy


@pytest.mark.parametrize("n", [1.0, 2.0])
def test_tangent_is_the_derivative_of_the_closed_form(n):
    worst = 0.0
    for x0, u in CASES:
        h = 1e-7 * DY
        out = _bouc_wen_exact(x0 * DY, 0.0, u * DY, DY, n, 0.75, 0.25)
        up = _bouc_wen_exact(x0 * DY, 0.0, u * DY + h, DY, n, 0.75, 0.25)[0]
        dn = _bouc_wen_exact(x0 * DY, 0.0, u * DY - h, DY, n, 0.75, 0.25)[0]
        worst = max(worst, abs(out[2] - (up - dn) / (2 * h)))
    print(f"MEASURED n={n}: largest |dz/d(total) - central difference| {worst:.2e}")
    assert worst < 3e-9  # measured: at most 1.2e-9 (the difference quotient's own error)


def test_sub_increments_stay_within_their_error():
    """The trapezoidal sub-increments (degrading or pinching laws, other exponents) on the same moves at
    n = 1.5: their error, of the order of the sub-increment squared, against the same reference."""
    law = StoreyLaw(kind="bouc-wen", yield_drift=DY, post_yield_ratio=0.05, n=1.5)
    par = law.kernel_rows([2e7], 44)[1][:1].copy()
    worst = 0.0
    for x0, u in CASES:
        z1 = bouc_wen_advance(par, 0, x0 * DY, 0.0, u * DY)[0]
        worst = max(worst, abs(z1 - _reference(x0 * DY, u * DY, 1.5, par[0, 4], par[0, 5])) / DY)
    print(f"MEASURED n=1.5, sub-increments of {BW_SUBINCREMENT} dy: largest |z - Radau| {worst:.2e} dy")
    assert worst < 5e-5  # measured: 1.6e-5 dy


def test_a_state_beyond_the_law_falls_back_to_the_sub_increments():
    """Unloading from beyond sqrt(1 / (gamma - beta)) dy (gamma > beta) the slope is negative: z would move away
    from zero, which no closed form above covers; the closed form says so (NaN) and the sub-increments take it."""
    assert np.isnan(_bouc_wen_exact(-1.5 * DY, 0.0, 0.1 * DY, DY, 2.0, 0.25, 0.75)[0])
    law = StoreyLaw(kind="bouc-wen", yield_drift=DY, post_yield_ratio=0.05, n=2.0, beta=0.25, gamma=0.75)
    par = law.kernel_rows([2e7], 44)[1][:1].copy()
    z1 = bouc_wen_advance(par, 0, -1.5 * DY, 0.0, 0.1 * DY)[0]
    ref = _reference(-1.5 * DY, 0.1 * DY, 2.0, 0.25, 0.75)
    print(f"MEASURED a state beyond the law: sub-increments {abs(z1 - ref) / DY:.1e} dy from Radau")
    assert np.isfinite(z1) and abs(z1 - ref) < 2.5e-6 * DY  # measured: 8.1e-7 dy
