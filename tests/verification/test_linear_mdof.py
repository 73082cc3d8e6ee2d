"""Linear multi-storey response to El Centro: kernel vs modal superposition vs the reference twin.

References
----------
* Chopra, A.K., Dynamics of Structures, 4th ed. (2012), Ch. 12-13: classical
  modal analysis of a shear building with Rayleigh damping (modal damping
  ratios xi_n = a0 / (2 w_n) + a1 w_n / 2, Eq. 11.4.5); Sec. 5.2: the
  piecewise-exact integration of an SDOF under piecewise-linear excitation
  (Nigam & Jennings 1969), which is what ``scipy.signal.lsim(interp=True)``
  evaluates with the matrix exponential.
* The excitation is the first 20 s of El Centro 1940 (PEER RSN6, 180 deg),
  interpolated linearly between its samples (dt = 0.01 s), which is also how the
  kernel reads a ground motion between its own samples.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sl
from scipy import signal

from seispound.contact import make_law
from seispound.integrate import integrate
from seispound.structure import Gap, assemble
from tests.reference_twin import shear_matrices, simulate_reference

from ._helpers import el_centro, read_at2, shear_building

T_END = 20.0


def modal_superposition(building, ag, dt):
    """Relative floor displacements [m], shape (nt, N), by exact modal superposition.

    Each mode q_n'' + 2 xi_n w_n q_n' + w_n^2 q_n = -Gamma_n a_g (Gamma_n = phi_n^T M 1
    with mass-normalised phi_n) is integrated exactly for the piecewise-linear a_g
    by ``scipy.signal.lsim`` (first-order hold); u = sum_n phi_n q_n.
    """
    w, phi = building.modes()
    a0, a1 = building.rayleigh_coefficients()
    t = np.arange(ag.size) * dt
    u = np.zeros((ag.size, building.n_floors))
    for n in range(w.size):
        xi = a0 / (2.0 * w[n]) + a1 * w[n] / 2.0
        gamma_n = phi[:, n] @ building.floor_masses
        mode = signal.StateSpace([[0.0, 1.0], [-w[n] ** 2, -2.0 * xi * w[n]]], [[0.0], [-gamma_n]],
                                 [[1.0, 0.0]], [[0.0]])
        _, q, _ = signal.lsim(mode, ag, t, interp=True)
        u += np.outer(q, phi[:, n])
    return u


def row():
    """Three buildings: 5 storeys (T1 = 0.5 s), 8 storeys (0.8 s), 3 storeys (0.3 s); floor mass 1e5 kg, 5 %."""
    return [shear_building("A", 5, 0.5), shear_building("B", 8, 0.8), shear_building("C", 3, 0.3)]


@pytest.fixture(scope="module")
def exact_peaks():
    """Modal-superposition peaks of each building, on the 0.0025 s grid (which contains the 0.01 s grid)."""
    ag, _ = el_centro(T_END, 0.0025)
    out = {}
    for b in row():
        u = modal_superposition(b, ag, 0.0025)
        out[b.name] = (np.abs(u).max(axis=0), u)
    return out


@pytest.fixture(scope="module")
def twin_peaks_A():
    """Reference twin (LSODA, rtol 1e-9, restarted at every record sample) for building A alone."""
    b = shear_building("A", 5, 0.5)
    m, K, C = shear_matrices(b.floor_masses, b.storey_stiffness, *b.rayleigh_coefficients())
    rdt, acc = read_at2()
    tr = np.arange(acc.size) * rdt
    res = simulate_reference(m, K, C, [], lambda t: np.interp(t, tr, acc), T_END, np.zeros(5),
                             rtol=1e-9, breakpoints=tr[tr < T_END])
    return res.peak_displacement


def test_modal_reference_agrees_with_twin(exact_peaks, twin_peaks_A):
    """The two independent references agree (lsim vs event-free solve_ivp): a check of the checks."""
    rel = np.abs(exact_peaks["A"][0] / twin_peaks_A - 1.0)
    print(f"MEASURED linear: modal (0.0025 grid) vs twin (dense) peak diff max {rel.max():.2e}")
    assert rel.max() <= 1.5e-4  # measured 6.4e-5 = grid sampling of the modal peaks; the twin's peaks are dense


# limits on the peak error against modal superposition and against the twin: at dt = 0.01 the output
# sampling of the peaks (measured 2.0e-3 for both); at 0.0025, the modal grid itself, the scheme is exact
# for the piecewise-linear record: round-off against modal (measured 8.9e-16, limit ~10x), the twin's own
# peak-sampling difference (6.4e-5)
@pytest.mark.parametrize("dt, tol_modal, tol_twin", [(0.01, 5e-3, 5e-3), (0.0025, 1e-14, 1.5e-4)])
def test_five_storey_peaks(dt, tol_modal, tol_twin, exact_peaks, twin_peaks_A):
    """Peak floor displacements within 0.5 % (dt = 0.01) of modal superposition and twin; at dt = 0.0025
    equal to modal superposition to round-off and to the twin within 0.015 %."""
    b = shear_building("A", 5, 0.5)
    ag, nsteps = el_centro(T_END, dt)
    r = integrate(assemble([b], []), ag, dt, nsteps)
    assert r.stats["steps"] == nsteps  # a linear run takes exactly one step per analysis step
    err_modal = np.abs(r.peak_displacement / exact_peaks["A"][0] - 1.0)
    err_twin = np.abs(r.peak_displacement / twin_peaks_A - 1.0)
    print(f"MEASURED linear 5-storey dt={dt}: peak error vs modal {err_modal.max():.2e}, "
          f"vs twin {err_twin.max():.2e}")
    assert err_modal.max() <= tol_modal
    assert err_twin.max() <= tol_twin
    if dt == 0.0025:
        # whole history on the common grid, relative to the peak
        u_ex = exact_peaks["A"][1]
        hist = np.max(np.abs(r.displacement - u_ex)) / exact_peaks["A"][0].max()
        print(f"MEASURED linear 5-storey dt={dt}: max history error / peak {hist:.2e}")
        assert hist <= 2e-14  # measured 1.7e-15: round-off, ~10x


# measured 2.0e-3 (output sampling of the peaks at dt = 0.01) and 4.5e-14 (round-off at 0.0025: ~10x)
@pytest.mark.parametrize("dt, tol", [(0.01, 5e-3), (0.0025, 5e-13)])
def test_row_of_three_without_contact(dt, tol, exact_peaks):
    """Three buildings with 10 m gaps (never closing): every floor's peak vs each building's modal solution."""
    ag, nsteps = el_centro(T_END, dt)
    bs = row()
    law = make_law("Hd", stiffness=5e9, restitution=0.65)
    sysrow = assemble(bs, [Gap(("A", "B"), 10.0), Gap(("B", "C"), 10.0)], law)
    assert sysrow.n_gap == 3 + 5  # A-B at 5 common levels, B-C at 3
    r = integrate(sysrow, ag, dt, nsteps)
    assert r.impacts["gap"].size == 0
    assert np.all(r.force == 0.0)
    assert r.stats["steps"] == nsteps
    start = 0
    worst = 0.0
    for b in bs:
        peaks = r.peak_displacement[start:start + b.n_floors]
        start += b.n_floors
        worst = max(worst, np.max(np.abs(peaks / exact_peaks[b.name][0] - 1.0)))
    print(f"MEASURED linear row of 3 dt={dt}: worst peak error vs modal {worst:.2e}")
    assert worst <= tol


def test_open_gaps_reproduce_uncoupled_buildings_exactly():
    """Row with gaps of 10 m = each building run alone, bit for bit (or to round-off)."""
    dt = 0.01
    ag, nsteps = el_centro(T_END, dt)
    bs = row()
    law = make_law("LVe", stiffness=1e9, restitution=0.65)
    r = integrate(assemble(bs, [Gap(("A", "B"), 10.0), Gap(("B", "C"), 10.0)], law), ag, dt, nsteps)
    start = 0
    worst = 0.0
    for b in bs:
        alone = integrate(assemble([b], []), ag, dt, nsteps)
        sl_ = slice(start, start + b.n_floors)
        start += b.n_floors
        for name in ("displacement", "velocity", "acceleration"):
            a_row = getattr(r, name)[:, sl_]
            a_one = getattr(alone, name)
            diff = np.max(np.abs(a_row - a_one)) / np.max(np.abs(a_one))
            worst = max(worst, diff)
        print(f"MEASURED linear: row peaks {b.name} equal bit for bit: "
              f"{np.array_equal(r.peak_displacement[sl_], alone.peak_displacement)}")
        assert np.array_equal(r.peak_displacement[sl_], alone.peak_displacement) or \
            np.max(np.abs(r.peak_displacement[sl_] / alone.peak_displacement - 1)) <= 2.5e-15  # measured: equal
    print(f"MEASURED linear: row (gap 10 m) vs buildings alone, max relative difference {worst:.1e}")
    assert worst <= 2.5e-15  # measured 2.3e-16 (one ulp): round-off, ~10x


def test_block_diagonal_assembly_matches_independent_matrices():
    """The assembled row's K and C are the block-diagonal of the buildings' own matrices (twin's builder)."""
    bs = row()
    sysrow = assemble(bs, [Gap(("A", "B"), 10.0), Gap(("B", "C"), 10.0)], make_law("Hd", stiffness=1e9))
    blocks = [shear_matrices(b.floor_masses, b.storey_stiffness, *b.rayleigh_coefficients()) for b in bs]
    K = sl.block_diag(*[blk[1] for blk in blocks])
    C = sl.block_diag(*[blk[2] for blk in blocks])
    dK = np.abs(sysrow.stiffness_matrix() - K).max() / np.abs(K).max()
    dC = np.abs(sysrow.damping_matrix() - C).max() / np.abs(C).max()
    nz = K != 0
    rK = np.abs(sysrow.stiffness_matrix()[nz] / K[nz] - 1).max()
    print(f"MEASURED linear: assembled K, C against the block diagonal, max difference / max entry {dK:.1e}, {dC:.1e}; "
          f"K entrywise {rK:.1e}")
    assert np.allclose(sysrow.stiffness_matrix(), K, rtol=1e-14, atol=0)  # measured: equal
    # measured: equal, bit for bit; a few ulps allowed for another BLAS / CPU
    assert np.allclose(sysrow.damping_matrix(), C, rtol=1e-14, atol=1e-14 * np.abs(C).max())
    # gap elements join floor f of A with floor f of B (same elevation), bottom up
    assert list(zip(sysrow.gap_i[:5], sysrow.gap_j[:5])) == [(f, 5 + f) for f in range(5)]
