"""``storey_stiffness_taper``: a smooth taper of the storey stiffnesses over the height, one or two numbers to vary."""

from __future__ import annotations

import numpy as np
import pytest

from seispound import InputError
from seispound.model.paths import set_value
from seispound.model.toml_loader import parse_model, read_toml
from tests._models import REPO


def _row():
    _, data = read_toml(REPO / "models" / "row_of_three.toml", "model")
    return data


def test_the_taper_multiplies_storey_i_by_taper_to_the_power_of_its_height_share():
    # closed form: k_i = k taper^((i - 1) / (N - 1)), storey 1 unchanged, the top one times taper
    data = _row()
    b = data["building"][0]
    n, k = b["floors"], b["storey_stiffness"]
    set_value(data, f"building.{b['name']}.storey_stiffness_taper", 0.5)
    got = np.asarray(parse_model(data, base=REPO / "models").buildings[0].storey_stiffness, float)
    want = k * 0.5 ** (np.arange(n) / (n - 1))
    np.testing.assert_allclose(got, want, rtol=1e-15)
    assert got[0] == k and got[-1] == pytest.approx(0.5 * k, rel=1e-15)


def test_the_table_form_passes_through_its_middle_and_top_values():
    # closed form: ln f(x) = (4 ln m - ln r) x + (2 ln r - 4 ln m) x^2 through f(0) = 1, f(1/2) = m, f(1) = r
    data = _row()
    b = data["building"][0]
    b["floors"] = 5
    b["storey_stiffness"] = [1e8] * 5
    for fld in ("floor_masses", "storey_heights"):
        b[fld] = b[fld] if not isinstance(b[fld], list) else [b[fld][0]] * 5
    set_value(data, f"building.{b['name']}.storey_stiffness_taper", {"top": 0.5, "middle": 0.75})
    got = np.asarray(parse_model(data, base=REPO / "models").buildings[0].storey_stiffness, float)
    x = np.arange(5) / 4.0
    lr, lm = np.log(0.5), np.log(0.75)
    np.testing.assert_allclose(got, 1e8 * np.exp((4 * lm - lr) * x + (2 * lr - 4 * lm) * x ** 2), rtol=1e-14)
    np.testing.assert_allclose(got[[0, 2, 4]], [1e8, 0.75e8, 0.5e8], rtol=1e-14)
    # a linear taper to 0.5 is within 1 % of the log-quadratic through its middle and top
    np.testing.assert_allclose(got, 1e8 * (1 - 0.5 * x), rtol=0.01)
    # the middle defaults to the geometric taper's sqrt(top)
    set_value(data, f"building.{b['name']}.storey_stiffness_taper", {"top": 0.5})
    geo = np.asarray(parse_model(data, base=REPO / "models").buildings[0].storey_stiffness, float)
    np.testing.assert_allclose(geo, 1e8 * 0.5 ** x, rtol=1e-14)


def test_a_taper_of_one_is_the_model_as_written_and_the_factor_commutes():
    data = _row()
    plain = parse_model(data, base=REPO / "models")
    data["building"][1]["storey_stiffness_taper"] = 1.0
    same = parse_model(data, base=REPO / "models")
    np.testing.assert_array_equal(plain.buildings[1].storey_stiffness, same.buildings[1].storey_stiffness)


@pytest.mark.parametrize("value, match", [(0.0, "must be a number > 0"), (-1.0, "must be a number > 0"),
                                          ("0.5", "must be a number > 0"), (float("nan"), "must be a number > 0")])
def test_a_bad_taper_is_one_line_naming_the_key(value, match):
    data = _row()
    name = data["building"][0]["name"]
    data["building"][0]["storey_stiffness_taper"] = value
    with pytest.raises(InputError, match=rf"building\.{name}\.storey_stiffness_taper: {match}"):
        parse_model(data, base=REPO / "models")


@pytest.mark.parametrize("value, key, match", [({"middle": 0.7}, "storey_stiffness_taper.top", "is required"),
                                               ({"top": 0.5, "middle": 0}, "storey_stiffness_taper.middle", "> 0"),
                                               ({"top": 0.5, "mid": 0.7}, "storey_stiffness_taper", "mid")])
def test_a_bad_taper_table_is_one_line_naming_the_key(value, key, match):
    data = _row()
    name = data["building"][0]["name"]
    data["building"][0]["storey_stiffness_taper"] = value
    with pytest.raises(InputError, match=rf"building\.{name}\.{key}.*{match}"):
        parse_model(data, base=REPO / "models")


def test_a_single_storey_cannot_taper():
    data = _row()
    b = data["building"][0]
    b["floors"], b["floor_masses"], b["storey_stiffness"], b["storey_heights"] = 1, 1e5, 1e8, 3.0
    b["storey_stiffness_taper"] = 0.5
    with pytest.raises(InputError, match="two or more storeys"):
        parse_model(data, base=REPO / "models")
