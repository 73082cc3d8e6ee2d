"""Gaps addressed by the names of the buildings they join: model.gap("A", "B") and gap.A|B in study paths."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import seispound as sp
from seispound import InputError
from seispound.model.toml_loader import read_toml
from seispound.model.paths import resolve
from tests._models import REPO
from tests.study.conftest import write_study


def test_path_by_names_resolves_to_the_indexed_table():
    _, data = read_toml(REPO / "models" / "row_of_three.toml", "model")
    for path, index in (("gap.West|Middle.size", 0), ("gap.Middle|West.size", 0), ("gap.East|Middle.size", 1)):
        ((table, key),) = resolve(data, path)
        assert table is data["gap"][index] and key == "size"
    with pytest.raises(InputError, match=r"no gap between East and West \(gaps: West\|Middle, Middle\|East\)"):
        resolve(data, "gap.West|East.size")


def test_model_gap_by_names(tmp_path):
    model = sp.load_model(REPO / "models" / "row_of_three.toml")
    assert model.gap("Middle", "West") is model.gaps[0] and model.gap("Middle", "East") is model.gaps[1]
    model.gap("West", "Middle").size = 0.05
    assert model.assembled().gap_size[:8].tolist() == [0.05] * 8
    with pytest.raises(InputError) as info:
        model.gap("West", "East")
    assert info.value.key == "gap" and "gaps: West|Middle, Middle|East" in str(info.value)


def test_study_axis_by_names_equals_axis_by_index(tmp_path):
    stores = {}
    for name, path in (("by_index", "gap.1.size"), ("by_names", "gap.B|A.size")):
        study_file = write_study(tmp_path / name, duration=1.0, records=("elcentro_180",), gaps=(0.005, 0.01))
        text = study_file.read_text().replace('path = "gap.*.size"', f'path = "{path}"')
        study_file.write_text(text)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sp.run_study(sp.load_study(study_file), tmp_path / name / "s.h5", scheduler="serial", progress=False)
        stores[name] = sp.open_study(tmp_path / name / "s.h5")
    a, b = stores["by_index"], stores["by_names"]
    assert int((a.status == 1).sum()) == 4
    np.testing.assert_array_equal(a.peak_pounding_force.values, b.peak_pounding_force.values)
    np.testing.assert_array_equal(a.amplification.values, b.amplification.values)


def test_paths_reach_the_new_model_keys(tmp_path):
    """A study or a fit addresses e(v0) parameters, a building's delay and the scheme by the same dotted paths."""
    import tomllib

    from seispound.model import parse_model
    from seispound.model.paths import get_value, set_value
    from tests.cli.test_bad_input import BASE, write_model

    text = BASE.replace("restitution = 0.65", 'restitution = { form = "exponential", e0 = 0.9, e_inf = 0.5, v_c = 0.3 }')
    text = text.replace('name = "B"\nfloors = 8\n', 'name = "B"\nfloors = 8\nground_motion = { delay = 0.02 }\n')
    data = tomllib.loads(text)
    assert get_value(data, "contact.restitution.v_c") == 0.3
    set_value(data, "contact.restitution.v_c", 0.9)
    set_value(data, "building.B.ground_motion.delay", 0.07)
    set_value(data, "analysis.scheme", "newmark")
    write_model(tmp_path)  # the record next to the model
    model = parse_model(data, base=tmp_path)
    assert model.contact.restitution.v_c == 0.9
    assert model.buildings[1].ground_motion.delay == 0.07
    assert model.analysis.scheme == "newmark"
