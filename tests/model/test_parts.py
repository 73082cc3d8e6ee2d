"""Variants of a model read with ``Parts`` (model/parts.py) are the models read afresh.

Regression guards, not verification: a variant reuses the buildings and layouts an earlier
variant read, and must give the same assembled arrays, the same run and the same errors as
reading its table from scratch.
"""

import copy
import dataclasses
import tomllib
from pathlib import Path

import numpy as np
import pytest

from seispound import simulate
from seispound.errors import InputError
from seispound.model.parts import Parts, frozen
from seispound.model.paths import set_value
from seispound.model.toml_loader import parse_model

MODELS = Path(__file__).resolve().parents[2] / "models"
BASE = tomllib.loads((MODELS / "two_buildings.toml").read_text())
VARIANTS = [
    [],
    [("building.A.storey_stiffness", 1.5e8)],
    [("building.B.damping.ratio", 0.03)],
    [("contact.stiffness", 3.0e9), ("gap.1.size", 0.03)],
    [("building.A.storey_stiffness", 1.5e8)],  # again: both buildings as read before
    [],
]


def _table(overrides):
    data = copy.deepcopy(BASE)
    data["analysis"]["duration"] = 8.0
    for path, value in overrides:
        set_value(data, path, value)
    return data


def _same_system(a, b):
    for f in dataclasses.fields(a):
        x, y = getattr(a, f.name), getattr(b, f.name)
        if isinstance(x, np.ndarray) or isinstance(y, np.ndarray):
            assert np.array_equal(x, y), f.name
        elif f.name not in ("links", "outputs"):
            assert x == y, f.name


def test_variants_assemble_as_the_models_read_afresh():
    parts = Parts()
    for overrides in VARIANTS:
        variant = parse_model(_table(overrides), base=MODELS, parts=parts)
        fresh = parse_model(_table(overrides), base=MODELS)
        _same_system(variant.assembled(), fresh.assembled())
    # 6 variants x 2 buildings: A read 3 times (base, stiffer A, then both reused), B twice (base, B's damping)
    assert (parts.misses, parts.hits) == (4, 8)


def test_a_variant_runs_as_the_model_read_afresh():
    parts = Parts()
    parse_model(_table([]), base=MODELS, parts=parts)  # the base read first, so the variant reuses B
    over = [("building.A.storey_stiffness", 1.5e8), ("contact.stiffness", 3.0e9)]
    variant = simulate(parse_model(_table(over), base=MODELS, parts=parts), twin=False)
    fresh = simulate(parse_model(_table(over), base=MODELS), twin=False)
    assert parts.hits == 1
    for name in ("displacement", "acceleration", "pounding_force"):
        assert np.array_equal(variant[name].values, fresh[name].values, equal_nan=True), name


def test_a_changed_building_is_validated_again():
    parts = Parts()
    parse_model(_table([]), base=MODELS, parts=parts)
    with pytest.raises(InputError, match="building.A.storey_stiffness"):
        parse_model(_table([("building.A.storey_stiffness", -1.0)]), base=MODELS, parts=parts)
    # a type that validation tells apart is another key
    assert frozen({"floors": 3}) != frozen({"floors": 3.0})
    with pytest.raises(InputError, match="building.A.floors"):
        parse_model(_table([("building.A.floors", 4.0)]), base=MODELS, parts=parts)


def test_a_building_let_go_is_laid_out_afresh():
    parts = Parts(size=2)
    first = parse_model(_table([("building.A.storey_stiffness", 1.4e8)]), base=MODELS, parts=parts)
    a = first.buildings[0]
    assert parts.owns(a)
    for k in (1.5e8, 1.6e8):  # two more buildings A: the first one goes
        parse_model(_table([("building.A.storey_stiffness", k)]), base=MODELS, parts=parts)
    assert not parts.owns(a)
    again = parse_model(_table([("building.A.storey_stiffness", 1.4e8)]), base=MODELS, parts=parts)
    assert again.buildings[0] is not a
    _same_system(again.assembled(), parse_model(_table([("building.A.storey_stiffness", 1.4e8)]),
                                                base=MODELS).assembled())


def test_fit_evaluations_with_and_without_reuse_agree(tmp_path, monkeypatch):
    """Observer.simulate (a fit's evaluation) reads its variants with Parts; the off switch reads them afresh."""
    import obspy

    from seispound.calibrate.api import load_inputs
    from seispound.calibrate.observe import Observer
    from seispound.model import parts as parts_module

    text = (MODELS / "two_buildings.toml").read_text().replace("duration = 30.0", "duration = 8.0")
    text = text.replace('file = "../ground_motions/', f'file = "{(MODELS.parent / "ground_motions").as_posix()}/')
    assert "duration = 8.0" in text
    (tmp_path / "model.toml").write_text(text)
    ds = simulate(parse_model(tomllib.loads(text), base=tmp_path), twin=False)
    x = np.ascontiguousarray(ds.acceleration.sel(building="B", floor=4).values)
    tr = obspy.Trace(x, header=dict(network="XX", station="B", location="00", channel="H04",
                                    delta=float(ds.attrs["dt"])))
    obspy.Stream([tr]).write(str(tmp_path / "rec.mseed"), format="MSEED", encoding="FLOAT64")
    (tmp_path / "ch.toml").write_text('[[channel]]\nid = "XX.B.00.H04"\nquantity = "acceleration"\n'
                                      'building = "B"\nfloor = 4\n')
    model, chans, trials = load_inputs(tmp_path / "model.toml", [tmp_path / "rec.mseed"], tmp_path / "ch.toml", None)
    points = [[("building.A.storey_stiffness", 1.4e8)], [("building.B.storey_stiffness", 1.2e8)],
              [("building.A.storey_stiffness", 1.4e8), ("contact.stiffness", 3.0e9)]]
    runs = {}
    for reuse in (True, False):
        monkeypatch.setattr(parts_module, "REUSE", reuse)
        obs = Observer(tomllib.loads(text), tmp_path, chans, trials)
        runs[reuse] = [obs.simulate(p)[0]["XX.B.00.H04"] for p in points]
        assert (obs._parts.hits > 0) == reuse
    for a, b in zip(runs[True], runs[False]):
        assert np.array_equal(a, b)
