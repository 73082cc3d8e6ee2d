"""Rod floors in the model: parsing, the DOF layout (nodes, attachments, storey springs by nodal mass), what a
run stores, and one-line errors."""

import numpy as np
import pytest

from seispound import simulate
from seispound.errors import InputError
from seispound.floor import RodFloor
from seispound.model import load_model
from seispound.structure import assemble
from tests._models import short_copy

ROD = ('floor_model = { kind = "rod", segments = 4, length = 20.0, youngs_modulus = 3.0e10, area = 2.0, '
       'axial_damping = 0.02, sensor = 0.25, attachment = { mass = 500.0, joint_stiffness = 1.0e9, '
       'joint_damping = 1.0e5 } }\n')


def _model(tmp_path, floor_model=ROD, duration=3.0):
    path = short_copy(tmp_path, duration)
    path.write_text(path.read_text().replace('name = "A"\n', 'name = "A"\n' + floor_model, 1))
    return load_model(path)


def test_layout_of_rod_floors(tmp_path):
    model = _model(tmp_path)
    rod = model.buildings[0].floor_model
    assert isinstance(rod, RodFloor) and rod.ea == 6e10 and rod.attachment.mass == 500.0
    system = assemble(model.buildings, model.gaps, model.contact)
    # A: 4 floors x (5 nodes + 1 attachment on the right face, toward B); B: 8 lumped floors
    assert system.n_dof == 4 * 6 + 8
    a = system.dof_building == 0
    np.testing.assert_allclose(system.mass[a].sum(), 4 * (1e5 + 500.0))
    # a storey's springs share its stiffness by nodal mass: a rigid floor feels the lumped storey
    M, _, K = system.matrices()
    rigid = np.zeros(system.n_dof)
    rigid[np.flatnonzero(a)[:6]] = 1.0  # floor 1 (its nodes and attachment) moves by 1 m
    assert (K @ rigid)[np.flatnonzero(a)[:6]].sum() == pytest.approx(2 * 1.3092e8, rel=1e-12)
    # the gaps act on A's attachments, the law sees the whole floor's mass
    assert all(system.dof_kind[i] == 4 for i in system.gap_i)
    # the sensor at a quarter of the length is node 1
    out = system.outputs
    assert out.sensor[0, np.flatnonzero(a)[1]] == 1.0


def test_a_run_stores_nodes_and_the_sensor(tmp_path):
    ds = simulate(_model(tmp_path), twin=False)
    # the joint's dashpot makes the row's damping non-classical: no modal basis, so the exact scheme
    # flies it free on the general driver (newmark.general_driver_needed), not by the fast driver's Newmark
    assert ds.attrs["driver"] == "general" and ds.attrs["scheme"] == "exact"
    assert ds.node_displacement.sizes["node"] == 5
    np.testing.assert_allclose(ds.node_position.sel(building="A"), [0, 5, 10, 15, 20])
    np.testing.assert_array_equal(ds.displacement.sel(building="A"), ds.node_displacement.sel(building="A", node=1))
    assert bool(ds.node_displacement.sel(building="B").isnull().all())
    # the floor's drift is the mass-weighted mean of its nodes' storey deformations
    w = np.array([0.125, 0.25, 0.25, 0.25, 0.125])
    nodes = ds.node_displacement.sel(building="A")
    mean = (nodes * w).sum("node")
    np.testing.assert_allclose(ds.drift.sel(building="A", floor=2), mean.sel(floor=2) - mean.sel(floor=1), atol=1e-15)
    e = ds.energy
    balance = e.sel(energy_component="input") - e.drop_sel(energy_component="input").sum("energy_component")
    assert float(abs(balance).max()) <= 1e-9 * float(e.sel(energy_component="input").max())


def test_fast_and_general_drivers_agree_on_rod_floors(tmp_path):
    from seispound.integrate import integrate
    from seispound.simulation import run_inputs

    model = _model(tmp_path)
    system, motions = run_inputs(model)
    an = model.analysis
    fast = integrate(system, motions.rows, an.dt, an.nsteps, an.newmark, scheme="newmark")
    general = integrate(system, motions.rows, an.dt, an.nsteps, an.newmark, driver="general", scheme="newmark")
    err = float(np.abs(fast.displacement - general.displacement).max() / np.abs(general.displacement).max())
    errf = float(np.abs(fast.force - general.force).max() / np.abs(general.force).max())
    print(f"MEASURED rod floors, fast against general driver: displacement {err:.1e}, force {errf:.1e}")
    assert fast.driver == "fast" and err <= 1e-9 and errf <= 1e-8


@pytest.mark.parametrize("table, key", [
    ('{ kind = "plate", segments = 4, length = 20.0 }', "building.A.floor_model.kind"),
    ('{ segments = 0, length = 20.0, axial_stiffness = 1.0e9 }', "building.A.floor_model.segments"),
    ('{ segments = 4, axial_stiffness = 1.0e9 }', "building.A.floor_model.length"),
    ('{ segments = 4, length = 20.0, youngs_modulus = 3.0e10 }', "building.A.floor_model.area"),
    ('{ segments = 4, length = 20.0, axial_stiffness = 1.0e9, area = 2.0 }',
     "building.A.floor_model.axial_stiffness"),
    ('{ segments = 4, length = 20.0, axial_stiffness = 1.0e9, sensor = 1.5 }', "building.A.floor_model.sensor"),
    ('{ segments = 4, length = 20.0, axial_stiffness = 1.0e9, sensor = "attachment" }',
     "building.A.floor_model.sensor"),
    ('{ segments = 4, length = 20.0, axial_stiffness = 1.0e9, attachment = { mass = 15.0 } }',
     "building.A.floor_model.attachment.joint_stiffness"),
    ('{ segments = 4, length = 20.0, axial_stiffness = 1.0e9, axial_damping = 1.5 }',
     "building.A.floor_model.axial_damping"),
    ('{ segments = 4, length = 20.0, axial_stifness = 1.0e9 }', "building.A.floor_model.axial_stifness"),
])
def test_bad_rod_floors_name_their_key(tmp_path, table, key):
    with pytest.raises(InputError) as err:
        _model(tmp_path, f"floor_model = {table}\n")
    assert err.value.key == key
