"""The contact duration of two rods in Saint-Venant impact: why the lumped chain is off 2L/c, and that it converges.

Kinds: independent solver (the package against the exact-in-time modal solution of the same lumped
chain, written here with scipy's ``eigh_tridiagonal``) and closed form (derived here: the interface mode and the
Airy delay of the unloading front).  The set-up is ``_impact`` of test_rod_floors.py: two free rods
(100 kg/m, EA = 1e8 N, c = 1000 m/s), each cut in N segments (masses m/N inside, m/2N at the faces,
springs EA N / L; Cook et al. 2002, Sec. 11.3), the striker at v0 = 0.1 m/s, the contact spring equal
to the striker's segment stiffness.  Saint-Venant (Goldsmith 1960, Impact, Sec. 3.3; Graff 1975, Wave
Motion in Elastic Solids, Sec. 2.4): contact 2 L_striker / c at the force P = rho c A v0 / 2.

What sets the discrete duration (derived here, checked below):

1. The interface mode.  The two face half-masses m/2 joined by the contact spring k are a light
   defect in the chain: an antisymmetric mode u_j = (-r)^j u_0 (j from the face) exists above the
   chain's cut-off 2 omega_0 (omega_0 = sqrt(k / m) = N c / L).  Interior nodes: m w^2 = k (2 + r + 1/r);
   face node: (m/2) w^2 = k (3 + r) (the contact spring stretches twice u_0).  Hence 1/r - r = 4,
   r = sqrt5 - 2, w = sqrt(2 + 2 sqrt5) omega_0 = 2.5440 omega_0.  The impact's initial velocity (v0 on
   the striker) has the antisymmetric part v0/2; its projection on the mode (sum m_j phi_j v_j /
   sum m_j phi_j^2, geometric series) is (v0/2)(1 - r)^2/(1 + r^2) = (v0/2)(1 - 1/sqrt5), so the
   contact force rings at w with amplitude A = k v0 (1 - 1/sqrt5) / w = P 2 (1 - 1/sqrt5) /
   sqrt(2 + 2 sqrt5) = 0.4346 P (sqrt(k m) = rho c A), the same for every N: it does not go away as
   the mesh is refined; only its period, 2 pi / w = 1.235 / N of 2L/c, shrinks.  The contact ends
   where a trough of this ringing first reaches zero.
2. The Airy delay of the unloading front.  The chain's dispersion w = 2 omega_0 sin(kappa/2)
   (Brillouin 1946, Wave Propagation in Periodic Structures, Ch. 1; recalled, not read here) is
   w ~ omega_0 (kappa - kappa^3/24) for long waves, so a step front that has travelled n segments
   is smeared into S(X) = int_X^inf Ai, X = (n - omega_0 t) (8 / (omega_0 t))^(1/3) (stationary phase at the
   inflection of the dispersion; derived).  Without the interface mode, the bonded chain's contact
   force drops at 2N segments from +P to -P for equal rods (the bonded free-free rod of length 2L,
   half of it moving: an antisymmetric square wave) and crosses zero where S = 1/2; for a short rod on
   a long one it drops from +P to 0 (the short rod is left at rest, unstressed) and first reaches zero
   where S = 1.  Both give a delay a N^(-2/3) of 2 L_striker / c with a = x 4^(-1/3) / 2, x from
   int_{-x}^0 Ai = 1/6 (a = 0.1290) or 2/3 (a = 0.4360) (scipy.special.itairy here).
3. The time step.  Newmark's average acceleration keeps the ringing's amplitude but slows its phase
   by (w h)^2 / 12 per radian (the trapezoidal rule's period elongation); at the default 32 substeps
   per impact estimate (on the grid dt / 2^k) w h is 1.3-2.5 in the cases below, so
   the package's contact ends at another trough than the exact chain's (jumps of a fraction of the
   ringing period); with w h small it converges to the exact chain at second order.

So there is no fixed offset such as (N+1)/N 2L/c: the lumped chain's duration converges to 2L/c
(errors halve per doubling of N over N = 100-400), and the package's duration converges to the
chain's at second order in the substep.  The numbers of test_rod_floors.py are explained: at the
defaults the package's first contact is within a ringing period of the exact chain's, and its
"duration" is the episode from the first touch to the last separation, which for N = 200 equal rods
and for the short rod at N = 100 and 200 includes a second contact after the first separation (the package's
episodes: equal N = 100 +0.64 %, N = 200 +0.86 %; short on long N = 200 +2.01 %; their first
contacts +0.64 %, +0.26 %, +1.26 %; the exact chain's +0.73 %, +0.38 %, +1.02 %).
"""

import math

import numpy as np
import pytest
from scipy.linalg import eigh, eigh_tridiagonal
from scipy.optimize import brentq
from scipy.special import itairy

from seispound.contact import make_law
from seispound.integrate import Newmark, integrate
from seispound.structure import Gap, assemble
from tests.verification.test_rod_floors import EA, MASS_PER_LENGTH, _body

C = math.sqrt(EA / MASS_PER_LENGTH)  # 1000 m/s
V0, DT = 0.1, 1e-5
PLATEAU = MASS_PER_LENGTH * C * V0 / 2  # rho c A v0 / 2
R = math.sqrt(5.0) - 2.0
W_INTERFACE = math.sqrt(2.0 + 2.0 * math.sqrt(5.0))  # / omega_0
A_INTERFACE = 2.0 * (1.0 - 1.0 / math.sqrt(5.0)) / W_INTERFACE  # / P
EQUAL, SHORT = (1.0, 1.0, 1), (0.5, 1.0, 2)  # (L striker, L struck, N struck / N striker)


def _system(l1, l2, n1, n2):
    law = make_law("LVe", stiffness=EA * n1 / l1, restitution=1.0)
    return assemble([_body("A", l1, n1, V0), _body("B", l2, n2)], [Gap(("A", "B"), 1e-9, law)])


def _package(l1, l2, n1, n2, substeps=32):
    """The package's impact (as test_rod_floors._impact, substeps per impact estimate free): its catalogue."""
    nsteps = int(round(3.0 * l2 / C / DT))
    raw = integrate(_system(l1, l2, n1, n2), np.zeros(nsteps + 1), DT, nsteps, Newmark(contact_substeps=substeps))
    return raw.impacts


class _Chain:
    """The two rods bonded at the contact spring, written here: exact modal solution from touching at t = 0."""

    def __init__(self, l1, l2, n1, n2):
        masses, springs = [], []
        for length, n in ((l1, n1), (l2, n2)):
            share = np.full(n + 1, 1.0 / n)
            share[[0, -1]] = 0.5 / n
            masses.append(MASS_PER_LENGTH * length * share)
            springs.append(np.full(n, EA * n / length))
        self.k = EA * n1 / l1
        m = np.concatenate(masses)
        ks = np.concatenate([springs[0], [self.k], springs[1]])
        # K phi = w^2 M phi with K tridiagonal, M diagonal: the symmetric tridiagonal M^-1/2 K M^-1/2
        s = 1.0 / np.sqrt(m)
        w2, psi = eigh_tridiagonal((np.r_[ks, 0.0] + np.r_[0.0, ks]) * s * s, -ks * s[:-1] * s[1:])
        phi = psi * s[:, None]
        self.w = np.sqrt(np.clip(w2, 0.0, None))
        q = phi.T @ (m * np.r_[np.full(n1 + 1, V0), np.zeros(n2 + 1)])  # modal velocities
        self.coef = self.k * (phi[n1] - phi[n1 + 1]) * q  # force = sum coef sin(w t) / w
        self.omega0 = n1 * C / l1
        self.period = 2.0 * math.pi / (W_INTERFACE * self.omega0)
        self.T = 2.0 * l1 / C

    def force(self, t, without_interface_mode=False):
        t = np.atleast_1d(np.asarray(t, float))
        live = self.w > 1e-6 * self.omega0  # the rigid mode does not stretch the contact spring
        if without_interface_mode:
            live &= self.w < 2.0001 * self.omega0  # the one mode above the cut-off
        return np.sin(np.outer(t, self.w[live])) @ (self.coef[live] / self.w[live])

    def first_separation(self, without_interface_mode=False):
        """First zero of the contact force, on a grid of 1/20 of the interface period, refined by brentq."""
        t = np.arange(0.02 * self.T, 1.5 * self.T, self.period / 20.0)
        f = self.force(t, without_interface_mode)
        k = int(np.flatnonzero(f < 0.0)[0])
        return brentq(lambda s: self.force(s, without_interface_mode)[0], t[k - 1], t[k], xtol=1e-15)


def _airy_delay(step_fraction):
    """a of the delay a N^(-2/3): x with int_{-x}^0 Ai = step_fraction - 1/3, a = x 4^(-1/3) / 2."""
    x = brentq(lambda s: itairy(s)[2] - (step_fraction - 1.0 / 3.0), 0.0, 2.3)
    return x * 4.0 ** (-1.0 / 3.0) / 2.0


@pytest.mark.parametrize("n", [25, 100])
def test_interface_mode_of_the_assembled_rods(n):
    """The assembled rods plus the contact spring: their top mode is the interface mode, frequency
    sqrt(2 + 2 sqrt5) N c / L, and the impact rings the contact force at 2 (1 - 1/sqrt5) / sqrt(2 + 2 sqrt5) P."""
    system = _system(1.0, 1.0, n, n)
    M, _, K = system.matrices()
    i, j, k = int(system.gap_i[0]), int(system.gap_j[0]), EA * n
    inner = [d for d in np.flatnonzero(K[i]) if d != i and K[i, d] < -1.0]  # the striker's node next to the face
    assert len(inner) == 1
    K[i, i] += k
    K[j, j] += k
    K[i, j] -= k
    K[j, i] -= k
    w2, phi = eigh(K, M)
    w = math.sqrt(w2[-1])
    amp = k * abs(phi[i, -1] - phi[j, -1]) * abs(phi[:, -1] @ M @ system.v0) / w
    next_w = math.sqrt(w2[-2]) / (n * C)
    decay = phi[inner[0], -1] / phi[i, -1]  # u_1 / u_0 = -r
    err_w, err_a = w / (n * C) / W_INTERFACE - 1, amp / PLATEAU / A_INTERFACE - 1
    print(f"MEASURED interface mode, N = {n}: omega / (N c / L) {w / (n * C):.6f} (closed form {W_INTERFACE:.6f}, "
          f"{err_w:+.1e}), next {next_w:.6f} (cut-off 2); force amplitude / P {amp / PLATEAU:.6f} "
          f"(closed form {A_INTERFACE:.6f}, {err_a:+.1e}); u_1 / u_0 {decay:.6f} "
          f"(-r = {-R:.6f}, {decay / -R - 1:+.1e})")
    assert abs(err_w) <= 4e-12 and abs(err_a) <= 4e-12  # measured 1.2e-12 (the 1 N/m storeys), 8e-14
    assert abs(decay / -R - 1) <= 2e-15  # measured 6.7e-16
    assert next_w <= 2.0 + 1e-9  # the only mode above the cut-off (the next is the chain's pi-mode, at 2)


@pytest.mark.parametrize("n", [25, 100])
def test_package_converges_to_the_exact_chain_at_second_order(n):
    """Equal rods: the package's first contact against the chain's exact-in-time modal solution, as the
    contact substep halves (1024, 2048, 4096 substeps per impact estimate)."""
    exact = _Chain(1.0, 1.0, n, n).first_separation()
    errs = [(_package(1.0, 1.0, n, n, s)["dur"][0] - exact) / (2.0 / C) for s in (1024, 2048, 4096)]
    ratios = [errs[0] / errs[1], errs[1] / errs[2]]
    print(f"MEASURED rods N = {n}: exact chain {exact / (2.0 / C) - 1:+.4%} of 2L/c; package - exact, of 2L/c, at "
          f"1024/2048/4096 substeps: {errs[0]:+.2e} {errs[1]:+.2e} {errs[2]:+.2e}, ratios {ratios[0]:.3f} "
          f"{ratios[1]:.3f}")
    assert all(abs(r - 4.0) <= 0.004 for r in ratios)  # measured 4.000-4.001: second order
    assert abs(errs[2]) <= {25: 3e-6, 100: 1.5e-5}[n]  # measured 1.4e-6, 6.5e-6


def test_exact_chain_converges_to_saint_venant():
    """The exact lumped chain, N = 100, 200, 400: the duration error halves per doubling of N, for equal
    rods and for the short rod; without the interface mode the delay approaches the Airy front's
    a N^(-2/3) (fit of N^(2/3) delay = a + b N^(-1/3)); and the short rod's error is 2.6x the equal
    rods', which no extra path common to both (such as an (N + 1)/N 2L/c from the contact spring
    counted as one more segment, N x error = 1) explains, while the Airy front does (S = 1 against 1/2)."""
    ns = np.array([100.0, 200.0, 400.0])
    full = {}
    for case, label in ((EQUAL, "equal rods"), (SHORT, "short on long")):
        l1, l2, ratio = case
        errs, smooth = [], []
        for n in ns.astype(int):
            chain = _Chain(l1, l2, n, ratio * n)
            errs.append(chain.first_separation() / chain.T - 1)
            smooth.append(chain.first_separation(without_interface_mode=True) / chain.T - 1)
        b_fit, a_fit = np.polyfit(ns ** (-1 / 3), ns ** (2 / 3) * np.array(smooth), 1)
        a_airy = _airy_delay(0.5 if case == EQUAL else 1.0)
        steps = [errs[0] / errs[1], errs[1] / errs[2]]
        print(f"MEASURED exact chain, {label}, N = 100/200/400: duration {errs[0]:+.4%} {errs[1]:+.4%} "
              f"{errs[2]:+.4%} of 2L/c (ratios {steps[0]:.3f} {steps[1]:.3f}; N x error "
              + " ".join(f"{n * e:.3f}" for n, e in zip(ns, errs))
              + f"); without the interface mode {smooth[0]:+.4%} {smooth[1]:+.4%} {smooth[2]:+.4%}, fitted "
              f"a = {a_fit:.4f} (Airy {a_airy:.4f}, {a_fit / a_airy - 1:+.1%}), b = {b_fit:.3f}")
        assert all(1.75 <= s <= 2.05 for s in steps)  # measured 1.86-1.93: converging, no offset
        assert all(e > 0.0 for e in errs)
        assert abs(a_fit / a_airy - 1) <= {EQUAL: 0.12, SHORT: 0.03}[case]  # measured +4.2 %, -1.0 %
        full[case] = np.array(errs)
    rel = full[SHORT] / full[EQUAL]
    print("MEASURED short-on-long error / equal-rods error, N = 100/200/400: " + " ".join(f"{r:.2f}" for r in rel))
    assert np.all(rel >= 2.3)  # measured 2.60-2.69


@pytest.mark.parametrize("l1, l2, n1, n2", [(1.0, 1.0, 100, 100), (1.0, 1.0, 200, 200), (0.5, 1.0, 50, 100),
                                            (0.5, 1.0, 100, 200), (0.5, 1.0, 200, 400)])
def test_default_substeps_stay_within_a_ringing_period(l1, l2, n1, n2):
    """The configurations of test_rod_floors.py at the default substeps: the package's first contact ends
    within one interface-ringing period of the exact chain's (it lands on another trough)."""
    chain = _Chain(l1, l2, n1, n2)
    exact = chain.first_separation()
    imp = _package(l1, l2, n1, n2)
    first = imp["dur"][0]
    episode = imp["t0"][-1] + imp["dur"][-1] - imp["t0"][0]
    off = (first - exact) / chain.period
    print(f"MEASURED rods {l1}/{l2} m, N = {n1}/{n2}, default substeps: exact chain {exact / chain.T - 1:+.3%}, "
          f"package first contact {first / chain.T - 1:+.3%} ({off:+.2f} ringing periods of "
          f"{chain.period / chain.T:.2%}), episode {episode / chain.T - 1:+.3%} over {imp['t0'].size} contact(s)")
    assert abs(off) <= 1.0  # measured up to 0.52
