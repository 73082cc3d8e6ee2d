"""Multi-rate stepping: only the buildings of a contact group take contact substeps.

While a gap is closed, the buildings it links (its contact group) take the
contact substeps; every other building waits, takes the analysis step in one
Newmark step of dt, and is screened against its stepping neighbours along that
step's own trajectory.  When a gap of a waiting building may close inside a
substep, the building catches up to the substep's start and steps from there
(a *join*).  Checked here against the reference twin (a join inside a long
impact), against each pair run alone (pairs that share no gap must not slow
each other down nor change each other's answer) and against single-rate
stepping (``multirate=False``, every building takes every substep).
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sl

from seispound.contact import make_law
from seispound.integrate import integrate
from seispound.structure import Gap, assemble
from tests.reference_twin import RefGap, RefLaw, shear_matrices, simulate_reference
from tests.verification._helpers import el_centro, shear_building

E_HD = 0.65


def _energy_residual(r):
    """Largest |input - (kinetic + strain + damping + contact)| over the run, relative to the largest input."""
    e = r.energy
    return np.max(np.abs(e[:, 0] - e[:, 1:].sum(axis=1))) / np.max(np.abs(e[:, 0]))


@pytest.fixture(scope="module")
def join_case():
    """A | B | C in free vibration: A (2 storeys) hits B at 0.5 m/s and stays in contact ~0.11 s
    (a soft Hd law, k = 1e8 N/m^1.5); C (2 storeys) swings at B and hits it while A still presses,
    so C waits at the start of that analysis step and must join inside it."""
    bs = [shear_building("A", 2, 0.3, v0=0.5), shear_building("B", 3, 0.4), shear_building("C", 2, 0.25, v0=-0.4)]
    law = make_law("Hd", stiffness=1e8, restitution=E_HD)
    system = assemble(bs, [Gap(("A", "B"), 0.005), Gap(("B", "C"), 0.008)], law)
    dt, t_end = 0.002, 1.0
    nsteps = int(round(t_end / dt))
    ag = np.zeros(nsteps + 1)
    # C holds 2 of the 7 DOFs: below the default share that waits (WAIT_SHARE), so let it wait
    # (Newmark throughout: the waiting buildings' steps are Newmark steps in either scheme)
    runs = {mr: integrate(system, ag, dt, nsteps, multirate=mr, wait_share=0.0, scheme="newmark")
            for mr in (True, False)}
    mats = [shear_matrices(x.floor_masses, x.storey_stiffness, *x.rayleigh_coefficients()) for x in bs]
    m = np.concatenate([x[0] for x in mats])
    K = sl.block_diag(*[x[1] for x in mats])
    C = sl.block_diag(*[x[2] for x in mats])
    gaps = [RefGap(int(i), int(j), float(s), RefLaw("Hd", 1e8, E_HD))
            for i, j, s in zip(system.gap_i, system.gap_j, system.gap_size)]
    twin = simulate_reference(m, K, C, gaps, lambda t: 0.0, t_end, system.v0, rtol=1e-10)
    return system, runs, twin


def test_a_waiting_building_joins_inside_a_step_and_matches_the_twin(join_case):
    system, runs, twin = join_case
    r = runs[True]
    imp = r.impacts
    on_bc = np.isin(imp["gap"], (2, 3))
    # C's first impact on B starts while A still presses on B, in a later analysis step
    ab = ~on_bc
    first_bc = imp["t0"][on_bc].min()
    inside = (imp["t0"][ab] < first_bc) & (first_bc < imp["t0"][ab] + imp["dur"][ab])
    assert inside.any() and int(first_bc / 0.002) > int(imp["t0"][ab][inside].min() / 0.002)
    assert r.stats["joins"] >= 1 and r.stats["waiting_steps"] > 50
    active = twin.peak_force > 0
    du = np.max(np.abs(r.peak_displacement / twin.peak_displacement - 1.0))
    df = np.max(np.abs(r.peak_force[active] / twin.peak_force[active] - 1.0))
    dt0 = np.max(np.abs(np.sort(imp["t0"]) - np.sort(twin.impacts["t0"])))
    print(f"MEASURED join case: joins {r.stats['joins']}, waiting steps {r.stats['waiting_steps']}, impacts "
          f"{imp['gap'].size} / twin {twin.impacts['gap'].size}, peak displacement error {du:.2e}, "
          f"peak force error {df:.2e}, onset times within {dt0:.2e} s, energy residual {_energy_residual(r):.2e}")
    assert imp["gap"].size == twin.impacts["gap"].size >= 8
    assert np.array_equal(np.sort(imp["gap"]), np.sort(twin.impacts["gap"]))
    assert du <= 1e-3
    assert df <= 5e-3
    assert dt0 <= 2e-3  # within one analysis step (dt = 2 ms)
    assert _energy_residual(r) <= 1e-6


def test_multirate_differs_from_single_rate_by_the_waiting_steps_discretisation_only(join_case):
    """Both integrate the same equations; they differ by C's dt steps against substeps: O(dt^2) of free flight."""
    _, runs, _ = join_case
    a, b = runs[True], runs[False]
    assert b.stats["joins"] == 0 and b.stats["waiting_steps"] == 0
    du = np.max(np.abs(a.displacement - b.displacement)) / np.max(np.abs(b.displacement))
    df = np.max(np.abs(a.peak_force - b.peak_force)) / b.peak_force.max()
    print(f"MEASURED multi-rate vs single-rate: displacement {du:.2e}, peak force {df:.2e}, "
          f"DOF-steps {a.stats['dof_steps']} vs {b.stats['dof_steps']}")
    assert a.impacts["gap"].size == b.impacts["gap"].size
    assert du <= 1e-4
    assert df <= 1e-4
    assert a.stats["dof_steps"] < b.stats["dof_steps"]


def _pair(p, k_contact=2.75e9):
    a = shear_building(f"A{p}", 4, 0.4 * (1 + 0.07 * p))
    b = shear_building(f"B{p}", 6, 0.6 * (1 + 0.07 * p))
    return [a, b], [Gap((a.name, b.name), 0.01)]


def _pairs_row(k, law):
    """k pairs side by side in one row, no gap between the pairs."""
    bs, gaps = [], []
    for p in range(k):
        b2, g2 = _pair(p)
        bs += b2
        gaps += g2
    return assemble(bs, gaps, law)


@pytest.fixture(scope="module")
def pairs_case():
    k = 4
    law = make_law("Hd", stiffness=2.75e9, restitution=E_HD)
    row = _pairs_row(k, law)
    ag, nsteps = el_centro(10.0, 0.005)
    # every pair may wait whatever its share of the row (the default WAIT_SHARE lets the
    # waiting buildings wait only when they hold half the DOFs: a cost rule, not physics)
    rows = {mr: integrate(row, ag, 0.005, nsteps, multirate=mr, wait_share=0.0, scheme="newmark")
            for mr in (True, False)}
    alone = [integrate(assemble(*_pair(p), law), ag, 0.005, nsteps, scheme="newmark") for p in range(k)]
    return row, rows, alone


def test_pairs_that_share_no_gap_move_like_each_pair_alone(pairs_case):
    """With multi-rate stepping a pair waits (one dt step) while another pounds, as it does alone.

    What remains is the substep grid two pairs share while both are in contact
    at once: within the contact's own discretisation error.  Single-rate
    stepping takes every pair through every other pair's substeps, a different
    time discretisation of its free flight: its displacements are more than 10
    times further from the pair alone (measured 16 times).
    """
    row, rows, alone = pairs_case
    n1, g1 = alone[0].displacement.shape[1], alone[0].force.shape[1]
    worst = {}
    for mr, r in rows.items():
        du = df = 0.0
        for p, a in enumerate(alone):
            u = r.displacement[:, p * n1:(p + 1) * n1]
            du = max(du, np.max(np.abs(u - a.displacement)) / np.max(np.abs(a.displacement)))
            df = max(df, np.max(np.abs(r.peak_force[p * g1:(p + 1) * g1] - a.peak_force)) / a.peak_force.max())
            assert np.sum(r.impacts["gap"] // g1 == p) == a.impacts["gap"].size >= 10
        worst[mr] = (du, df)
    print(f"MEASURED pairs vs alone: multi-rate displacement {worst[True][0]:.2e}, peak force {worst[True][1]:.2e}; "
          f"single-rate {worst[False][0]:.2e}, {worst[False][1]:.2e}; DOF-steps {rows[True].stats['dof_steps']} "
          f"vs {rows[False].stats['dof_steps']} (alone, summed: {sum(a.stats['dof_steps'] for a in alone)})")
    assert worst[True][0] <= 1e-4
    assert worst[True][1] <= 2e-3
    assert worst[True][0] * 10 <= worst[False][0]
    # the work: close to the pairs run one by one (measured 1.13 times), below every pair
    # taking every substep (1.34 times the multi-rate work for these 4 pairs, 3.1 for the
    # 16 pairs of benchmarks/scaling.py)
    assert rows[True].stats["dof_steps"] <= 1.2 * sum(a.stats["dof_steps"] for a in alone)
    assert rows[True].stats["dof_steps"] < rows[False].stats["dof_steps"]


def test_under_the_exact_scheme_waiting_is_exact_too():
    """Under the exact scheme a waiting pair's one step per analysis step is exact (``_exact_waiting``), as is
    its free flight alone; single-rate stepping takes it through another pair's contact substeps instead."""
    k = 4
    law = make_law("Hd", stiffness=2.75e9, restitution=E_HD)
    row = _pairs_row(k, law)
    ag, nsteps = el_centro(10.0, 0.005)
    rows = {mr: integrate(row, ag, 0.005, nsteps, multirate=mr, wait_share=0.0) for mr in (True, False)}
    alone = [integrate(assemble(*_pair(p), law), ag, 0.005, nsteps) for p in range(k)]
    assert rows[True].stats["waiting_steps"] > 0
    n1 = alone[0].displacement.shape[1]
    worst = {}
    for mr, r in rows.items():
        du = 0.0
        for p, a in enumerate(alone):
            scale = np.abs(a.displacement).max()
            du = max(du, np.abs(r.displacement[:, p * n1:(p + 1) * n1] - a.displacement).max() / scale)
        worst[mr] = du
    print(f"MEASURED exact scheme, 4 pairs against each alone: multi-rate {worst[True]:.1e}, "
          f"single-rate {worst[False]:.1e}")
    assert worst[True] <= 1e-3
