"""Ground motions in the forms users hold them, and the provenance of every step applied.

* ``[ground_motion] format``: any obspy format name, or "text";
* one- and two-column text records with stated dt and units;
* an ``obspy.Trace`` or a numpy array with its dt from Python;
* the stored provenance names resampling, decimation, truncation and zero padding.
"""

from __future__ import annotations

import json

import numpy as np
import obspy
import pytest

import seispound as sp
from seispound import InputError, cli
from seispound.model import GroundMotionSpec
from seispound.motion import read_record
from seispound.plausibility import PlausibilityWarning
from tests.cli.test_bad_input import BASE, RECORD, sub, write_model

G = 9.80665


@pytest.fixture(scope="module")
def elcentro():
    return read_record(RECORD)



def _processing(ds):
    return json.loads(ds.attrs["record"])["processing"]


def test_provenance_names_decimation_truncation_and_padding(tmp_path):
    """dt 0.02 s on a 0.01 s record lasting 53.71 s, analysed for 60 s."""
    text = sub("dt = 0.005", "dt = 0.02")(sub("duration = 0.2", "duration = 60.0")(BASE))
    with pytest.warns(PlausibilityWarning):
        ds = sp.simulate(sp.load_model(write_model(tmp_path, text)), twin=False)
    steps = _processing(ds)
    assert steps[0].startswith("read trace .ELCEN..180 from rec.AT2 (PEER_AT2) with 5372 samples at dt=0.01 s")
    assert steps[1] == "converted from g to m/s2 (x 9.80665)"
    assert steps[2].startswith("decimated (resampled to a coarser step) from dt=0.01 s to dt=0.02 s")
    assert "anti-alias low-pass at 25 Hz: content up to 20 Hz is kept" in steps[2]
    assert steps[3] == "zero-padded from 53.7 s to 60 s (3001 samples)"
    prov = json.loads(ds.attrs["record"])
    assert prov["decimated"] is True and prov["highest_resolved_frequency"] == pytest.approx(20.0)
    assert prov["zero_padded_from"] == pytest.approx(53.71) and prov["truncated_to"] is None
    assert prov["pga"] == pytest.approx(0.2808 * G, rel=2e-4)  # PEER header PGA
    assert ds.sizes["time"] == 3001 and float(np.abs(ds.ground_acceleration[2686:]).max()) == 0.0


def test_provenance_names_upsampling_and_truncation(tmp_path):
    ds = sp.simulate(sp.load_model(write_model(tmp_path, BASE)), twin=False)
    steps = _processing(ds)
    assert steps[2] == "resampled from dt=0.01 s to dt=0.005 s by linear interpolation (upsampling)"
    assert steps[3] == "truncated to 0.2 s (41 samples)"
    prov = json.loads(ds.attrs["record"])
    assert prov["decimated"] is False and prov["highest_resolved_frequency"] == pytest.approx(50.0)
    assert prov["truncated_to"] == pytest.approx(0.2) and prov["zero_padded_from"] is None


def test_format_key_reads_the_same_record(tmp_path):
    plain = sp.simulate(sp.load_model(write_model(tmp_path, BASE)), twin=False)
    named = sp.simulate(sp.load_model(write_model(tmp_path, sub('units = "g"', 'units = "g"\nformat = "peer_at2"')(BASE))),
                        twin=False)
    assert np.array_equal(plain.displacement.values, named.displacement.values, equal_nan=True)


@pytest.mark.parametrize("edit, key, words", [
    (sub('units = "g"', 'units = "g"\nformat = "XYZ"'), "ground_motion.format", "unknown record format 'XYZ'; one of: AH"),
    (sub('units = "g"', 'units = "g"\ndt = 0.01'), "ground_motion.dt", 'stated only for text records'),
    (sub('units = "g"', 'units = "g"\nformat = "text"\ndt = -1.0'), "ground_motion.dt", "must be a time step > 0"),
])
def test_bad_format_settings(tmp_path, capsys, edit, key, words):
    model = write_model(tmp_path, edit(BASE))
    assert cli.main(["run", str(model), "-o", str(tmp_path / "r.h5")]) == 2
    line = capsys.readouterr().err.strip()
    assert "\n" not in line and f"model.toml: {key}: " in line and words in line, line
    assert not (tmp_path / "r.h5").exists()


def test_unreadable_record_hint_can_be_followed(tmp_path):
    (tmp_path / "rec.dat").write_text("this is not a waveform\n")
    text = sub('file = "rec.AT2"', 'file = "rec.dat"')(BASE)
    (tmp_path / "model.toml").write_text(text)
    with pytest.raises(InputError) as info:
        sp.simulate(sp.load_model(tmp_path / "model.toml"))
    assert '[ground_motion] format = "MSEED"' in str(info.value) and '"text"' in str(info.value)


def _text_model(tmp_path, name, extra):
    text = sub('file = "rec.AT2"', f'file = "{name}"')(BASE)
    return write_model(tmp_path, sub('units = "g"', f'units = "g"\n{extra}')(text))


def test_text_records_one_and_two_columns_equal_the_file(tmp_path, elcentro):
    a = elcentro.acceleration / G
    np.savetxt(tmp_path / "one.txt", a, fmt="%.8e", header="El Centro 180 [g], dt = 0.01 s")
    t = np.arange(a.size) * 0.01
    (tmp_path / "two.csv").write_text("# time [s], acceleration [g]\n" +
                                      "".join(f"{ti:.2f}, {ai:.8e}\n" for ti, ai in zip(t, a)))
    ref = sp.simulate(sp.load_model(write_model(tmp_path, BASE)), twin=False)
    one = sp.simulate(sp.load_model(_text_model(tmp_path, "one.txt", 'format = "text"\ndt = 0.01')), twin=False)
    two = sp.simulate(sp.load_model(_text_model(tmp_path, "two.csv", 'format = "text"')), twin=False)
    for ds in (one, two):
        assert np.nanmax(np.abs(ds.displacement.values - ref.displacement.values)) <= 1e-12 * np.nanmax(
            np.abs(ref.displacement.values))
    assert _processing(one)[0] == "read 5372 samples from one.txt (text, 1 column, dt stated) at dt=0.01 s"
    assert _processing(two)[0].startswith("read 5372 samples from two.csv (text, 2 columns: time, acceleration)")
    assert json.loads(two.attrs["record"])["sha256"] != json.loads(ref.attrs["record"])["sha256"]


@pytest.mark.parametrize("content, extra, key, words", [
    ("0.1\n0.2\n0.3\n", 'format = "text"', "ground_motion.dt", "needs its time step"),
    ("0 0.1\n0.01 0.2\n0.025 0.3\n0.03 0.1\n", 'format = "text"', "ground_motion.dt",
     "not uniform: row 3 is at 0.025 s, expected 0.02 s"),
    ("0 0.1\n0.01 0.2\n0.02 0.3\n", 'format = "text"\ndt = 0.005', "ground_motion.dt", "disagrees"),
    ("0 0.1\n0.01 0.2\n0.02 abc\n", 'format = "text"', "line 3", "not a number in '0.02 abc'"),
    ("0 0.1 5\n0.01 0.2 5\n", 'format = "text"', "line 1", "3 columns"),
    ("0 0.1\n0.01\n", 'format = "text"', "line 2", "1 values where the lines above have 2"),
])
def test_bad_text_records(tmp_path, capsys, content, extra, key, words):
    (tmp_path / "r.txt").write_text(content)
    model = _text_model(tmp_path, "r.txt", extra)
    assert cli.main(["run", str(model), "-o", str(tmp_path / "out.h5")]) == 2
    line = capsys.readouterr().err.strip()
    assert "\n" not in line and f": {key}: " in line and words in line, line
    assert not (tmp_path / "out.h5").exists()


def test_trace_and_array_from_python_equal_the_file(tmp_path, elcentro):
    ref = sp.simulate(sp.load_model(write_model(tmp_path, BASE)))
    model = sp.load_model(write_model(tmp_path, BASE))
    tr = obspy.read(str(RECORD))[0]
    model.ground_motion = GroundMotionSpec.from_trace(tr, units="g")
    from_trace = sp.simulate(model)
    model.ground_motion = GroundMotionSpec.from_array(elcentro.acceleration, 0.01, units="m/s2")
    from_array = sp.simulate(model)
    for ds in (from_trace, from_array):
        assert np.nanmax(np.abs(ds.displacement.values - ref.displacement.values)) <= 1e-12 * np.nanmax(
            np.abs(ref.displacement.values))
        assert np.nanmax(np.abs(ds.amplification.values - ref.amplification.values)) <= 1e-12
    prov = json.loads(from_trace.attrs["record"])
    assert prov["file"] == "obspy.Trace .ELCEN..180" and len(prov["sha256"]) == 64
    assert json.loads(from_array.attrs["record"])["processing"][0] == \
        "taken from numpy array with 5372 samples at dt=0.01 s"


@pytest.mark.parametrize("args, key", [
    (dict(acceleration=np.zeros((3, 2)), dt=0.01, units="g"), "data"),
    (dict(acceleration=np.array([0.0, np.nan, 1.0]), dt=0.01, units="g"), "data"),
    (dict(acceleration=np.zeros(10), dt=0.0, units="g"), "dt"),
    (dict(acceleration=np.zeros(10), dt=0.01, units="auto"), "units"),
    (dict(acceleration=np.zeros(10), dt=0.01, units="furlongs"), "units"),
])
def test_bad_arrays_named(args, key):
    with pytest.raises(InputError) as info:
        GroundMotionSpec.from_array(**args)
    assert info.value.key == key and "\n" not in str(info.value)
