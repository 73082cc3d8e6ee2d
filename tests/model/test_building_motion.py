"""``[[building]] ground_motion`` and ``[ground_motion] apparent_velocity`` in model files."""

import json

import numpy as np
import pytest

import seispound as sp
from seispound.motion.spatial import variant
from tests.cli.test_bad_input import BASE, write_model


def _with(text, b_line="", gm_line="", a_line=""):
    text = text.replace('name = "B"\nfloors = 8\n', f'name = "B"\nfloors = 8\n{b_line}')
    text = text.replace('units = "g"\n', f'units = "g"\n{gm_line}')
    return text.replace('name = "A"\n', f'name = "A"\n{a_line}')


def test_apparent_velocity_gives_each_building_position_over_velocity(tmp_path):
    path = write_model(tmp_path, _with(BASE, "position = 30.0\n", "apparent_velocity = 600.0\n", "position = 0.0\n"))
    model = sp.load_model(path)
    motions = model.building_motions()
    assert motions[0] is None  # at the origin: the record as it is
    assert motions[1].delay == 30.0 / 600.0
    ds = sp.simulate(model, twin=False)
    own = json.loads(ds.attrs["building_ground_motion"])
    assert list(own) == ["B"] and own["B"]["delay_s"] == 0.05
    ag = ds.ground_acceleration.values
    rise = json.loads(ds.attrs["record"])["dt_original"]  # the record rises from zero over its own step
    expected, _ = variant(ag, 0.005, 0.05, rise=rise)
    assert np.array_equal(ds.base_acceleration.sel(building="B").values, expected)
    assert np.array_equal(ds.base_acceleration.sel(building="A").values, ag)


def test_a_delayed_record_arrives_the_same_at_any_analysis_step(tmp_path):
    """El Centro starts at 0.015 m/s^2: its delayed copy rises over the record's step, not the analysis step."""
    rows, row0 = {}, {}
    for dt in (0.005, 0.0005):
        path = write_model(tmp_path, _with(BASE, "ground_motion = { delay = 0.05 }\n").replace(
            "dt = 0.005", f"dt = {dt}"))
        motions = sp.simulation.prepare_ground_motions(sp.load_model(path))
        rows[dt], row0[dt] = motions.rows[-1], motions.rows[0]
    t5, t0 = np.arange(rows[0.005].size) * 0.005, np.arange(rows[0.0005].size) * 0.0005
    err = np.abs(np.interp(t0, t5, rows[0.005]) - rows[0.0005]).max()
    assert rows[0.005][9] != 0.0 and err <= 1e-12  # one piecewise-linear function at both steps
    # control: read with the ramp of one analysis step, the two inputs differ by about half the first sample
    plain = {dt: variant(row0[dt], dt, 0.05)[0] for dt in rows}
    gap = np.abs(np.interp(t0, t5, plain[0.005]) - plain[0.0005]).max()
    assert gap >= 0.4 * abs(row0[0.005][0]) > 0


def test_a_record_of_its_own_delayed_and_filtered(tmp_path):
    text = _with(BASE, 'ground_motion = { file = "rec.AT2", units = "g", scale = 0.5, delay = 0.02, lowpass = 10.0 }\n')
    model = sp.load_model(write_model(tmp_path, text))
    m = model.building_motions()[1]
    assert (m.delay, m.lowpass, m.lowpass_order, m.record.scale) == (0.02, 10.0, 2, 0.5)
    ds = sp.simulate(model, twin=False)
    own = json.loads(ds.attrs["building_ground_motion"])["B"]
    expected, steps = variant(0.5 * ds.ground_acceleration.values, 0.005, 0.02, 10.0, 2,
                              rise=own["record"]["dt_original"])
    assert np.allclose(ds.base_acceleration.sel(building="B").values, expected, rtol=1e-12, atol=1e-15)
    assert own["steps"] == steps and isinstance(own["record"], dict)


def test_a_negative_delay_advances_the_record_and_warns_when_it_cuts_strong_motion():
    import warnings

    from seispound.plausibility import PlausibilityWarning

    dt = 0.01
    ag = np.zeros(200)
    ag[50] = 1.0  # a pulse at 0.5 s, quiet before it
    out, steps = variant(ag, dt, -0.2)
    assert out[30] == 1.0 and out[50] == 0.0 and out[-20:].tolist() == [0.0] * 20  # at 0.3 s; zero at the end
    assert "advanced by 0.2 s" in steps[0]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        variant(ag, dt, -0.2)  # the cut 0.2 s are quiet: no warning
    with pytest.warns(PlausibilityWarning, match=r"delay: -0.6 s advances the record.*100% of its peak"):
        variant(ag, dt, -0.6)  # the pulse falls before the analysis starts


def test_a_share_of_its_own_record_mixes_it_with_the_rows(tmp_path):
    """w a_own + (1 - w) a_row (closed form): the own record here is the row's at half scale, so the building's
    motion is (1 - w / 2) times the row's; w = 0 is the row's record itself, to the bit, and shares its row."""
    for w, factor in ((0.25, 0.875), (1.0, 0.5), (1.5, 0.25)):
        text = _with(BASE, f'ground_motion = {{ file = "rec.AT2", units = "g", scale = 0.5, weight = {w} }}\n')
        model = sp.load_model(write_model(tmp_path, text))
        assert model.building_motions()[1].weight == w
        ds = sp.simulate(model, twin=False)
        ag = ds.ground_acceleration.values
        assert np.allclose(ds.base_acceleration.sel(building="B").values, factor * ag, rtol=1e-14, atol=1e-15)
        assert json.loads(ds.attrs["building_ground_motion"])["B"]["weight"] == w
    text = _with(BASE, 'ground_motion = { file = "rec.AT2", units = "g", weight = 0.0 }\n')
    motions = sp.simulation.prepare_ground_motions(sp.load_model(write_model(tmp_path, text)))
    assert motions.row_of.tolist() == [0, 0]


@pytest.mark.parametrize("line,key,what", [
    ("ground_motion = { weight = 0.5 }\n", "building.B.ground_motion.file", "weight describe a record"),
    ('ground_motion = { file = "rec.AT2", weight = 2.5 }\n', "building.B.ground_motion.weight", "share 0..2"),
    ('ground_motion = { file = "rec.AT2", weight = "all" }\n', "building.B.ground_motion.weight", "share 0..2"),
])
def test_a_share_without_a_record_or_outside_0_2_is_refused(tmp_path, line, key, what):
    from seispound.errors import InputError

    with pytest.raises(InputError, match=what) as err:
        sp.load_model(write_model(tmp_path, _with(BASE, line)))
    assert err.value.key == key
