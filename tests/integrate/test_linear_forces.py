"""The general driver's K u + C v as one banded product (``_elements.linear_bands`` / ``linear_forces``), and its
M x and kinetic energy (``mass_times``, ``kinetic_energy``: the element loop, and the diagonal where every mass
is lumped, ``lumped_diagonal``), against the dense matrices of ``SystemArrays.matrices`` (assembled element by
element with np.outer).

Kind: an independent assembly of the same elements (dense outer products, not the band), on a row with
coupled masses (a foundation's rigid body), soil dashpots, rod floors and mass-proportional damping.
"""

from pathlib import Path

import numpy as np

from seispound import load_model
from seispound.floor import RodFloor
from seispound.foundation import Footing, Foundation, Soil
from seispound.integrate._elements import kinetic_energy, linear_bands, linear_forces, lumped_diagonal, mass_times

ROW = Path(__file__).resolve().parents[2] / "models" / "row_of_three.toml"


def test_banded_linear_forces_equal_the_dense_product():
    m = load_model(ROW)
    m.buildings[1].foundation = Foundation(mass=4e5, rotary_inertia=2e7, floor_rotary_inertia=3e6,
                                           soil=Soil(200.0, 1900.0, 0.3), footing=Footing(width=15.0, length=15.0))
    m.buildings[0].floor_model = RodFloor(segments=6, length=20.0, youngs_modulus=3e10, area=2.0,
                                          axial_damping=0.02)
    for b in m.buildings:
        b.validate()
    m.__dict__.pop("_assembled", None)
    system = m.assembled()
    tab = system.element_tables()
    M, C, K = system.matrices()
    p = int(tab["p"])
    KC = linear_bands(tuple(tab[k] for k in ("ms_dof", "ms_coef", "ms_val", "ms_a0", "le_dof", "le_coef", "le_k",
                                                       "le_c")), p, system.n_dof)
    rng = np.random.default_rng(3)
    worst = 0.0
    for _ in range(5):
        u, v = rng.normal(size=system.n_dof) * 1e-2, rng.normal(size=system.n_dof) * 1e-1
        f = np.empty(system.n_dof)
        linear_forces(KC, u, v, f)
        ref = K @ u + C @ v
        worst = max(worst, np.abs(f - ref).max() / np.abs(ref).max())
    print(f"MEASURED banded K u + C v against the dense product, {system.n_dof} DOFs, half bandwidth {p}: "
          f"{worst:.1e}")
    assert np.count_nonzero(C - np.diag(np.diag(C))) > 0 and p >= 2  # coupled terms are there to get wrong
    assert worst <= 1e-15  # measured 2.0e-16: round-off


def _mass_products(system, md, x):
    tab = system.element_tables()
    y = np.empty(system.n_dof)
    mass_times(tab["ms_dof"], tab["ms_coef"], tab["ms_val"], md, x, y)
    return y, kinetic_energy(tab["ms_dof"], tab["ms_coef"], tab["ms_val"], md, x)


def test_mass_products_on_the_diagonal_and_on_coupled_blocks_equal_the_dense_product():
    from tests.integrate.test_mass_blocks import _relative_system  # floors as mass blocks on (x_i, u0, theta)

    rng = np.random.default_rng(5)
    worst = {}
    for name, system in (("lumped", load_model(ROW).assembled()), ("coupled", _relative_system())):
        tab = system.element_tables()
        md = lumped_diagonal(tab["ms_dof"], tab["ms_coef"], tab["ms_val"], system.n_dof)
        M = system.matrices()[0]
        assert (md.size == system.n_dof) == (name == "lumped")  # the diagonal only where M is diagonal
        x = rng.normal(size=system.n_dof)
        y_ref, e_ref = M @ x, 0.5 * x @ M @ x
        for label, d in (("diagonal", md), ("elements", np.zeros(0)))[0 if md.size else 1:]:
            y, e = _mass_products(system, d, x)
            worst[name, label] = max(np.abs(y - y_ref).max() / np.abs(y_ref).max(), abs(e - e_ref) / e_ref)
    print("MEASURED M x and v^T M v / 2 against the dense products:",
          ", ".join(f"{n} {lab} {w:.1e}" for (n, lab), w in worst.items()))
    assert len(worst) == 3
    assert max(worst.values()) <= 1e-15  # measured 0 (lumped) and 1.6e-17 (coupled): round-off, as above
