"""One entry of a list of numbers addressed by a final 1-based index: building.A.storey_stiffness.1."""

from __future__ import annotations

import numpy as np
import pytest

from seispound import InputError
from seispound.model.toml_loader import parse_model, read_toml
from seispound.model.paths import get_value, set_value
from tests._models import REPO


def _row():
    _, data = read_toml(REPO / "models" / "row_of_three.toml", "model")
    for b in data["building"]:  # a list per storey, each storey its own value
        b["storey_stiffness"] = [b["storey_stiffness"] * (1.0 - 0.05 * j) for j in range(b["floors"])]
    return data


def test_one_storey_is_read_and_set_and_the_model_sees_it():
    data = _row()
    k = list(data["building"][0]["storey_stiffness"])
    name = data["building"][0]["name"]
    assert get_value(data, f"building.{name}.storey_stiffness.1") == k[0]
    set_value(data, f"building.{name}.storey_stiffness.1", 0.5 * k[0])
    model = parse_model(data, base=REPO / "models")
    got = np.asarray(model.buildings[0].storey_stiffness, float)
    np.testing.assert_array_equal(got, [0.5 * k[0]] + k[1:])  # only the first storey changed


def test_every_building_by_star_and_a_bad_index_names_the_path():
    data = _row()
    set_value(data, "building.*.storey_stiffness.2", 1.0e7)
    assert all(b["storey_stiffness"][1] == 1.0e7 for b in data["building"])
    n = len(data["building"][0]["storey_stiffness"])
    with pytest.raises(InputError, match=rf"storey_stiffness\.{n + 1}: the list has {n} entries"):
        get_value(data, f"building.{data['building'][0]['name']}.storey_stiffness.{n + 1}")
    with pytest.raises(InputError):
        get_value(data, "gap.1")  # a final number on an array of tables is still no key
