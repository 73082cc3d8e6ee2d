"""The one dotted-path scheme reaches the keys of yielding storeys, foundations, rod floors and gap levels."""

import tomllib

import pytest

from seispound.model.toml_loader import parse_model
from seispound.model.paths import get_value, set_value
from tests._models import REPO

TEXT = (REPO / "models" / "yielding_pair.toml").read_text()


@pytest.mark.parametrize("path, value, check", [
    ("building.A.storey_law.yield_drift", 0.02, lambda m: m.buildings[0].storey_law.yield_drift == 0.02),
    ("building.B.storey_law.n", 5, lambda m: m.buildings[1].storey_law.n == 5),
    ("gap.1.levels", "all", lambda m: m.gaps[0].levels == "all"),
])
def test_paths_set_the_new_keys(path, value, check):
    data = tomllib.loads(TEXT)
    data["ground_motion"]["file"] = str(REPO / "ground_motions" / "RSN6_IMPVALL.I_I-ELC180-hor1.AT2")
    set_value(data, path, value)
    assert get_value(data, path) == value
    assert check(parse_model(data, REPO / "models"))


def test_paths_reach_nested_tables():
    data = tomllib.loads(TEXT)
    data["building"][0]["foundation"] = {"mass": 1e5, "rotary_inertia": 1e6,
                                         "soil": {"shear_wave_velocity": 150.0, "density": 1800.0, "poisson": 0.3},
                                         "footing": {"radius": 5.0}}
    data["building"][1]["floor_model"] = {"segments": 4, "length": 20.0, "axial_stiffness": 1e10,
                                          "attachment": {"mass": 15.0, "joint_stiffness": 1e8}}
    set_value(data, "building.A.foundation.soil.shear_wave_velocity", 300.0)
    set_value(data, "building.B.floor_model.attachment.mass", 14.0)
    model = parse_model(data, REPO / "models")
    assert model.buildings[0].foundation.soil.shear_wave_velocity == 300.0
    assert model.buildings[1].floor_model.attachment.mass == 14.0
