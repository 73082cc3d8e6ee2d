"""SDOF free vibration: the kernel against the closed forms of the Newmark-beta method.

References
----------
* Newmark, N.M. (1959) A method of computation for structural dynamics, ASCE J Eng
  Mech Div 85(EM3):67-94.
* Chopra, A.K., Dynamics of Structures, 4th ed. (2012), Sec. 5.4-5.5: period
  elongation of the average-acceleration method (Fig. 5.5.2) and absence of
  numerical damping (Fig. 5.5.1); Sec. 2.2: logarithmic decrement.
* Hughes, T.J.R., The Finite Element Method (1987), Sec. 9.1.3-9.1.4:
  amplification matrix of the Newmark family, spectral radius, algorithmic
  damping for gamma > 1/2 with beta = (gamma + 1/2)^2 / 4.

For undamped free vibration, average acceleration (beta = 1/4, gamma = 1/2) is
the trapezoidal rule applied to (u, v), i.e. the Cayley transform of a
skew-symmetric (in the energy norm) operator: the discrete energy
w^2 u_n^2 + v_n^2 is conserved exactly and the step-to-step rotation angle is
Omega = 2 arctan(w dt / 2).  With u_0 = 0, v_0 = V the discrete solution is
therefore exactly u_n = (V / w) sin(n Omega), of period
T_bar = 2 pi dt / Omega = 2 pi dt / (2 arctan(w dt / 2)).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from seispound.integrate import Newmark, integrate
from seispound.structure import Building, NoDamping, RayleighDamping, assemble

MASS = 1000.0  # kg
PERIOD = 1.0  # s
OMEGA = 2.0 * math.pi / PERIOD
V0 = 0.1  # m/s


def sdof(damping=None):
    k = MASS * OMEGA**2
    return assemble([Building("S", [MASS], [k], [3.0], damping or NoDamping(), initial_velocity=V0)], [])


def run(dt, t_end, newmark=None, damping=None):
    nsteps = int(round(t_end / dt))
    return integrate(sdof(damping), np.zeros(nsteps + 1), dt, nsteps, newmark or Newmark(), scheme="newmark")


def zero_crossings(t, u):
    """Upward and downward zero crossings (t > 0), each located on the cubic through 4 neighbouring samples."""
    out = []
    for k in np.nonzero(np.sign(u[:-1]) * np.sign(u[1:]) < 0)[0]:
        ks = np.arange(k - 1, k + 3)
        ks = ks[(ks >= 0) & (ks < u.size)]
        p = np.polyfit(t[ks] - t[k], u[ks], ks.size - 1)
        out.append(t[k] + brentq(lambda s: np.polyval(p, s), 0.0, t[k + 1] - t[k], xtol=1e-15))
    return np.array(out)


def newmark_period(dt):
    """Closed-form period of average acceleration, T_bar = 2 pi dt / (2 arctan(w dt / 2)) (Chopra Sec. 5.5)."""
    return 2.0 * math.pi * dt / (2.0 * math.atan(OMEGA * dt / 2.0))


def amplification_matrix(dt, beta, gamma, xi=0.0):
    """Newmark amplification matrix A of the state (u, v, a): x_{n+1} = A x_n (Hughes 1987, Sec. 9.1.3).

    Built from the three defining relations (unit mass, free vibration)
    a_{n+1} + 2 xi w v_{n+1} + w^2 u_{n+1} = 0,
    u_{n+1} = u_n + dt v_n + dt^2 ((1/2 - beta) a_n + beta a_{n+1}),
    v_{n+1} = v_n + dt ((1 - gamma) a_n + gamma a_{n+1}).
    """
    w = OMEGA
    lhs = np.array([[w * w, 2 * xi * w, 1.0],
                    [1.0, 0.0, -beta * dt * dt],
                    [0.0, 1.0, -gamma * dt]])
    rhs = np.array([[0.0, 0.0, 0.0],
                    [1.0, dt, (0.5 - beta) * dt * dt],
                    [0.0, 1.0, (1.0 - gamma) * dt]])
    return np.linalg.solve(lhs, rhs)


@pytest.mark.parametrize("ratio", [0.05, 0.1])
def test_average_acceleration_is_the_closed_form_discrete_solution(ratio):
    """u_n = (V/w) sin(n Omega), Omega = 2 arctan(w dt/2): exact to round-off over 10 periods."""
    dt = ratio * PERIOD
    r = run(dt, 10 * PERIOD)
    n = np.arange(r.time.size)
    big_omega = 2.0 * math.atan(OMEGA * dt / 2.0)
    exact = V0 / OMEGA * np.sin(n * big_omega)
    err = np.max(np.abs(r.displacement[:, 0] - exact)) / (V0 / OMEGA)
    print(f"MEASURED sdof dt/T={ratio}: max |u - (V/w) sin(n Omega)| / (V/w) = {err:.2e}")
    assert err <= 5e-13, err  # measured 4.8e-14 / 2.4e-14: round-off, so ~10x (it varies with the CPU)
    # the continuous closed form V/w sin(w t) is NOT reproduced: the phase drifts
    cont = V0 / OMEGA * np.sin(OMEGA * r.time)
    assert np.max(np.abs(r.displacement[:, 0] - cont)) / (V0 / OMEGA) > 0.1


# limit on |T_meas / T_bar - 1| (the error of the interpolated crossings): measured -5.9e-9 and -5.5e-7
@pytest.mark.parametrize("ratio, chopra_fig_552, limit", [(0.05, (0.007, 0.009), 1.5e-8),
                                                          (0.1, (0.030, 0.034), 1e-6)])
def test_period_elongation(ratio, chopra_fig_552, limit):
    """Period from interpolated zero crossings = T_bar to 1e-6 or better; elongation as in Chopra Fig. 5.5.2.

    The crossings are located on a cubic through four samples; over 50 periods the
    interpolation error of the first and last crossing is < 1e-7 of the span
    (10 periods leave ~1.2e-6 at dt/T = 0.1, so 50 are used).
    """
    dt = ratio * PERIOD
    r = run(dt, 52.0 * PERIOD)
    z = zero_crossings(r.time, r.displacement[:, 0])
    assert z.size >= 100
    measured = 2.0 * (z[-1] - z[0]) / (z.size - 1)
    t_bar = newmark_period(dt)
    elongation = measured / PERIOD - 1.0
    print(f"MEASURED sdof dt/T={ratio}: T_meas/T_bar - 1 = {measured / t_bar - 1.0:.2e}, "
          f"elongation {elongation:.6f} (formula {math.pi * ratio / math.atan(math.pi * ratio) - 1.0:.6f}, "
          f"difference {elongation - (math.pi * ratio / math.atan(math.pi * ratio) - 1.0):.2e})")
    assert abs(measured / t_bar - 1.0) <= limit, (measured, t_bar)
    # formula: T_bar/T = pi (dt/T) / arctan(pi dt/T); leading term (w dt)^2 / 12
    # measured -5.9e-9 / -5.7e-7 (the same crossing error, times T_bar / T)
    formula = math.pi * ratio / math.atan(math.pi * ratio) - 1.0
    assert abs(elongation - formula) <= (1.5e-8 if ratio == 0.05 else 1.5e-6)
    assert abs(elongation / ((OMEGA * dt) ** 2 / 12.0) - 1.0) < 0.05
    lo, hi = chopra_fig_552  # read off Chopra Fig. 5.5.2 (average acceleration curve)
    assert lo <= elongation <= hi


@pytest.mark.parametrize("ratio", [0.05, 0.1, 0.5])
def test_no_numerical_damping(ratio):
    """Average acceleration: w^2 u^2 + v^2 = V^2 at every step to round-off (Chopra Fig. 5.5.1: no amplitude decay)."""
    dt = ratio * PERIOD
    r = run(dt, 10 * PERIOD)
    u = r.displacement[:, 0]
    v = r.velocity[:, 0]
    amp = np.sqrt(u**2 + (v / OMEGA) ** 2) / (V0 / OMEGA)
    e = r.energy
    ke_drift = np.max(np.abs(e[:, 1] + e[:, 2] - 0.5 * MASS * V0**2)) / (0.5 * MASS * V0**2)
    print(f"MEASURED sdof dt/T={ratio}: amplitude drift {np.max(np.abs(amp - 1.0)):.2e}, "
          f"kinetic + strain energy drift {ke_drift:.2e}")
    # round-off (measured up to 4.9e-14 and 9.9e-14), so ~10x: it varies with the CPU
    assert np.max(np.abs(amp - 1.0)) <= 5e-13
    # kernel energy bookkeeping agrees: kinetic + strain constant
    assert ke_drift <= 1e-12


@pytest.mark.parametrize("ratio", [0.05, 0.1])
def test_numerical_damping_gamma_06(ratio):
    """gamma = 0.6, beta = (gamma + 1/2)^2 / 4 = 0.3025: decay per cycle = rho^(2 pi / Theta).

    rho e^(+-i Theta) are the complex eigenvalues of the Newmark amplification
    matrix (Hughes 1987, Sec. 9.1.4).  The kernel's (u, v, a) must follow
    x_{n+1} = A x_n; its decay is measured (i) by Prony's two-term linear
    prediction u_{n+1} = p1 u_n + p2 u_{n-1} (rho = sqrt(-p2), cos Theta = p1 / (2 rho))
    and (ii) by successive interpolated positive peaks.
    """
    beta, gamma = 0.3025, 0.6
    dt = ratio * PERIOD
    r = run(dt, 20 * PERIOD, Newmark(beta=beta, gamma=gamma))
    A = amplification_matrix(dt, beta, gamma)
    lam = np.linalg.eigvals(A)
    lam = lam[np.argmax(np.abs(lam.imag))]
    rho, theta = abs(lam), abs(np.angle(lam))
    assert rho < 1.0
    decay_exact = rho ** (2.0 * math.pi / theta)  # amplitude ratio per (numerical) cycle
    # (0) the kernel follows the amplification matrix
    x = np.column_stack([r.displacement[:, 0], r.velocity[:, 0], r.acceleration[:, 0]])
    scale = np.abs(x).max(axis=0)
    print(f"MEASURED sdof gamma=0.6 dt/T={ratio}: kernel against x_(n+1) = A x_n "
          f"{np.max(np.abs((x[1:] - x[:-1] @ A.T) / scale)):.2e}")
    assert np.max(np.abs((x[1:] - x[:-1] @ A.T) / scale)) <= 1.5e-14  # measured 1.4e-15: round-off, ~10x
    # (i) Prony
    u = r.displacement[:, 0]
    k = np.nonzero((u[1:-1] > u[:-2]) & (u[1:-1] >= u[2:]) & (u[1:-1] > 0))[0] + 1
    peaks = u[k] + (u[k + 1] - u[k - 1]) ** 2 / (8.0 * (2.0 * u[k] - u[k - 1] - u[k + 1]))
    p, *_ = np.linalg.lstsq(np.column_stack([u[1:-1], u[:-2]]), u[2:], rcond=None)
    rho_m = math.sqrt(-p[1])
    theta_m = math.acos(p[0] / (2.0 * rho_m))
    decay_prony = rho_m ** (2.0 * math.pi / theta_m)
    print(f"MEASURED sdof gamma=0.6 dt/T={ratio}: decay/cycle exact {decay_exact:.6f}, "
          f"Prony {decay_prony:.6f}, peaks {(peaks[-1] / peaks[0]) ** (1.0 / (peaks.size - 1)):.6f}; Prony / exact - 1 "
          f"{decay_prony / decay_exact - 1.0:.2e}, peaks / exact - 1 "
          f"{(peaks[-1] / peaks[0]) ** (1.0 / (peaks.size - 1)) / decay_exact - 1.0:.2e}")
    assert abs(decay_prony / decay_exact - 1.0) <= 3e-14  # measured 2.8e-15: round-off, ~10x
    # (ii) interpolated peaks (parabola through the 3 samples around each maximum)
    j = peaks.size - 1
    decay_peaks = (peaks[-1] / peaks[0]) ** (1.0 / j)
    # the parabola through three samples: measured -5.8e-7 (dt/T = 0.05), 1.3e-4 (0.1)
    assert abs(decay_peaks / decay_exact - 1.0) <= (1.5e-6 if ratio == 0.05 else 3.5e-4)
    # and it is a real decay: several percent per cycle at these steps
    assert decay_exact < (0.995 if ratio == 0.05 else 0.98)


def test_rayleigh_damped_logarithmic_decrement():
    """Rayleigh damping with modes [1, 1] and ratio 5 %: logarithmic decrement gives 5 % +- 0.1 % at dt/T = 0.01.

    delta = (1/j) ln(u_i / u_{i+j}) = 2 pi xi / sqrt(1 - xi^2), xi = delta / sqrt(4 pi^2 + delta^2)
    (Chopra Eq. 2.2.7-2.2.8); peaks located by a parabola through three samples.
    """
    dt = 0.01 * PERIOD
    r = run(dt, 12 * PERIOD, damping=RayleighDamping(ratio=0.05, modes=(1, 1)))
    u = r.displacement[:, 0]
    k = np.nonzero((u[1:-1] > u[:-2]) & (u[1:-1] >= u[2:]) & (u[1:-1] > 0))[0] + 1
    peaks = u[k] + (u[k + 1] - u[k - 1]) ** 2 / (8.0 * (2.0 * u[k] - u[k - 1] - u[k + 1]))
    assert peaks.size >= 10
    j = peaks.size - 1
    dec = math.log(peaks[0] / peaks[-1]) / j
    xi = dec / math.sqrt(4.0 * math.pi**2 + dec**2)
    print(f"MEASURED sdof Rayleigh 5%: log-decrement xi = {xi:.6f} (xi - 0.05 = {xi - 0.05:.2e}, "
          f"xi / 0.05 - 1 = {xi / 0.05 - 1.0:.2e})")
    assert abs(xi - 0.05) <= 1e-4, xi  # measured -3.3e-5 (the scheme's own damping, xi_bar below)
    assert abs(xi / 0.05 - 1.0) <= 1e-3, xi  # 5 % +- 0.1 % of 5 % (measured -6.6e-4)
    # tighter: the discrete scheme's own damping ratio, from the eigenvalues of A
    lam = np.linalg.eigvals(amplification_matrix(dt, 0.25, 0.5, xi=0.05))
    lam = lam[np.argmax(np.abs(lam.imag))]
    xi_bar = -math.log(abs(lam)) / math.hypot(math.log(abs(lam)), abs(np.angle(lam)))
    print(f"MEASURED sdof Rayleigh 5%: discrete-scheme xi_bar = {xi_bar:.6f}, xi - xi_bar = {xi - xi_bar:.2e}")
    assert abs(xi - xi_bar) <= 4e-8, (xi, xi_bar)  # measured 1.3e-8 (the peaks' parabola)
