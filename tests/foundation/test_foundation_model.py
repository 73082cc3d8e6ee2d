"""Foundations in the model: parsing (springs or soil and footing), what a run stores, and the schema's frame."""

import numpy as np
import pytest

from seispound import simulate
from seispound.foundation import Footing, Soil, cone_impedances
from seispound.model import load_model
from seispound.structure import assemble
from tests._models import short_copy

SOIL_FOUNDATION = ('foundation = { mass = 2.0e5, rotary_inertia = 1.0e6, floor_rotary_inertia = 5.0e5, '
                   'soil = { shear_wave_velocity = 150.0, density = 1800.0, poisson = 0.35 }, '
                   'footing = { width = 12.0, length = 15.0 } }\n')


def _model(tmp_path, foundation=SOIL_FOUNDATION, duration=4.0):
    path = short_copy(tmp_path, duration)
    text = path.read_text().replace('name = "A"\n', 'name = "A"\n' + foundation, 1)
    path.write_text(text)
    return load_model(path)


def test_soil_and_footing_give_the_cone_impedances(tmp_path):
    model = _model(tmp_path)
    f = model.buildings[0].foundation
    assert isinstance(f.soil, Soil) and isinstance(f.footing, Footing)
    imp = f.impedances()
    assert imp == cone_impedances(Soil(150.0, 1800.0, 0.35), Footing(width=12.0, length=15.0))
    # poisson 0.35 > 1/3: a trapped rotary inertia joins the rocking DOF
    assert f.rocking_inertia(4) == pytest.approx(1e6 + 4 * 5e5 + imp["trapped_rotary_inertia"])
    system = assemble(model.buildings, model.gaps, model.contact)
    assert system.needs_general_driver
    assert system.n_dof == 4 + 3 + 8  # sway, rocking and the rocking cone's internal DOF
    np.testing.assert_array_equal(system.outputs.foundation, [[0, 1], [-1, -1]])
    # the cone's DOF (2): its inertia rho I0 z0, the rocking dashpot from theta to it, no spring, no output
    assert system.dof_kind[2] == 5 and system.mass[2] == pytest.approx(imp["rocking_cone_inertia"], rel=1e-15)
    assert not system.outputs.sensor[:, 2].any() and not system.outputs.deformation[:, 2].any()
    M, C, K = system.matrices()
    assert not K[2].any() and C[2, 2] == pytest.approx(imp["rocking_damping"], rel=1e-15)
    assert C[0, 2] == pytest.approx(-imp["rocking_damping"], rel=1e-15)


def test_radiation_scales_the_cone_dashpots_and_the_rocking_cone_inertia_only():
    full = cone_impedances(Soil(150.0, 1800.0, 0.3), Footing(width=12.0, length=15.0))
    layer = cone_impedances(Soil(150.0, 1800.0, 0.3, radiation=0.25), Footing(width=12.0, length=15.0))
    for k in ("sway_damping", "rocking_damping", "rocking_cone_inertia"):
        assert layer[k] == pytest.approx(0.25 * full[k], rel=1e-15)
    for k in ("sway_stiffness", "rocking_stiffness", "trapped_rotary_inertia", "rocking_apex_height"):
        assert layer[k] == full[k]


@pytest.mark.parametrize("foundation, n_extra, rocking_c", [
    (SOIL_FOUNDATION.replace("poisson = 0.35 }", "poisson = 0.3, radiation = 0.0 }"), 2, 0.0),
    ('foundation = { mass = 2.0e5, rotary_inertia = 1.0e6, sway_stiffness = 1.0e9, sway_damping = 1.0e6, '
     'rocking_stiffness = 1.0e11, rocking_damping = 3.0e8 }\n', 2, 3.0e8),
])
def test_without_a_cone_the_rocking_dashpot_acts_to_the_ground(tmp_path, foundation, n_extra, rocking_c):
    """A site that radiates nothing (radiation 0), or springs and dashpots given: no internal DOF, as before."""
    model = _model(tmp_path, foundation)
    system = assemble(model.buildings, model.gaps, model.contact)
    assert system.n_dof == 4 + n_extra + 8 and not np.any(system.dof_kind == 5)
    el_c = np.zeros(system.el_i.size) if system.el_c is None else system.el_c
    rock = (system.el_i == 0) & (system.el_j == -1)  # the rocking element: theta to the ground
    assert el_c[rock].tolist() == [rocking_c] and system.el_k[rock][0] > 0


def test_a_run_stores_foundation_motion_and_drift_as_storey_deformation(tmp_path):
    model = _model(tmp_path)
    ds = simulate(model)
    assert ds.attrs["driver"] == "general"
    sway = ds.foundation_sway.sel(building="A")
    rock = ds.foundation_rocking.sel(building="A")
    assert float(abs(sway).max()) > 0 and float(abs(rock).max()) > 0
    assert bool(np.isnan(ds.foundation_sway.sel(building="B")).all())
    # the rocking cone's internal DOF is no floor: A's 4 floors, then NaN up to B's 8; the summary's floors likewise
    assert ds.sizes["floor"] == 8 and list(ds.floor.values) == list(range(1, 9))
    peak = ds.peak_displacement.sel(building="A").values
    assert np.isfinite(peak[:4]).all() and np.isnan(peak[4:]).all()
    from seispound.cli import summary

    assert "floor 0" not in summary(ds)
    u = ds.displacement.sel(building="A")
    # drift of storey 1 = w1 - u0 - h1 theta; storey 2 = w2 - w1 - h theta
    np.testing.assert_allclose(ds.drift.sel(building="A", floor=1), u.sel(floor=1) - sway - 3.0 * rock, atol=1e-15)
    np.testing.assert_allclose(ds.drift.sel(building="A", floor=2), u.sel(floor=2) - u.sel(floor=1) - 3.0 * rock,
                               atol=1e-15)
    # elastic storeys: the storey force is k times that deformation
    np.testing.assert_allclose(ds.storey_force.sel(building="A"), 1.3092e8 * ds.drift.sel(building="A"))
    e = ds.energy
    balance = e.sel(energy_component="input") - e.drop_sel(energy_component="input").sum("energy_component")
    assert float(abs(balance).max()) <= 1e-9 * float(e.sel(energy_component="input").max())


def test_a_stiff_foundation_approaches_the_fixed_base(tmp_path):
    """Springs 1e6 times the storeys' and a light foundation: the floors move as on a fixed base."""
    stiff = ('foundation = { mass = 1.0e3, rotary_inertia = 1.0e3, sway_stiffness = 1.0e14, sway_damping = 0.0, '
             'rocking_stiffness = 1.0e16, rocking_damping = 0.0 }\n')
    flex_model = _model(tmp_path, stiff)
    flex_model.analysis.newmark.contact_substeps = 32  # both runs alike: the drivers are compared, not a tolerance
    flex_model.analysis.scheme = "newmark"  # its free flight composes the same Newmark substeps
    flex = simulate(flex_model, twin=False)
    n = flex.attrs["newmark_substeps"]  # the general driver's Newmark substeps: the fixed base steps alike
    model = load_model(short_copy(tmp_path, 4.0))
    model.analysis.newmark.contact_substeps = 32
    model.analysis.scheme = "newmark"  # as the general driver steps
    model.analysis.dt /= n
    fixed = simulate(model, twin=False)
    u0 = fixed.displacement.sel(building="A").isel(time=slice(0, None, n))
    u1 = flex.displacement.sel(building="A")
    err = float(abs(u1 - u0).max() / abs(u0).max())
    print(f"MEASURED stiff foundation against the fixed base: {err:.1e} of the peak displacement")
    # measured 3.3e-4: the 1e14 N/m springs set the row's omega_max, so the flexible row's contact substeps are
    # 4 times shorter (simulation.contact_step); with equal substeps 2.4e-6
    assert err <= 1e-3


@pytest.mark.parametrize("table, key", [
    ("{ rotary_inertia = 1.0 }", "building.A.foundation.mass"),
    ("{ mass = 1.0e5, rotary_inertia = 1.0e6, sway_stiffness = 1.0e9 }", "building.A.foundation.sway_damping"),
    ("{ mass = 1.0e5, rotary_inertia = 1.0e6, soil = { shear_wave_velocity = 150.0, density = 1800.0, "
     "poisson = 0.3 } }", "building.A.foundation.footing"),
    ("{ mass = 1.0e5, rotary_inertia = 1.0e6, soil = { shear_wave_velocity = 150.0, density = 1800.0, "
     "poisson = 0.5 }, footing = { radius = 5.0 } }", "building.A.foundation.soil.poisson"),
    ("{ mass = 1.0e5, sway_stiffness = 1.0e9, sway_damping = 0.0, rocking_stiffness = 1.0e11, "
     "rocking_damping = 0.0 }", "building.A.foundation.rotary_inertia"),
    ("{ mass = 1.0e5, rotary_inertia = 1.0e6, soil = { shear_wave_velocity = 150.0, density = 1800.0 }, "
     "footing = { radius = 5.0 } }", "building.A.foundation.soil.poisson"),
    ("{ mass = 1.0e5, rotary_inertia = 1.0e6, footing = { radius = 5.0, width = 3.0 }, soil = { "
     "shear_wave_velocity = 150.0, density = 1800.0, poisson = 0.3 } }", "building.A.foundation.footing.radius"),
    ("{ mass = 1.0e5, rotary_inertia = 1.0e6, sway_stiffnes = 1.0e9 }", "building.A.foundation.sway_stiffnes"),
    ("{ mass = 1.0e5, rotary_inertia = 1.0e6, soil = { shear_wave_velocity = 150.0, density = 1800.0, "
     "poisson = 0.3, radiation = 1.5 }, footing = { radius = 5.0 } }", "building.A.foundation.soil.radiation"),
])
def test_bad_foundations_name_their_key(tmp_path, table, key):
    from seispound.errors import InputError

    with pytest.raises(InputError) as err:
        _model(tmp_path, f"foundation = {table}\n")
    assert err.value.key == key
