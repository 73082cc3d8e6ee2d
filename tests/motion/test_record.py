"""Record reading (units, calibration, trace selection), processing and errors."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import obspy
import pytest

from seispound.errors import InputError
from seispound.motion import G_STANDARD, Record, ground_acceleration, read_record

REPO = Path(__file__).resolve().parents[2]
ELCENTRO_180 = REPO / "ground_motions" / "RSN6_IMPVALL.I_I-ELC180-hor1.AT2"


def _assert_input_error(err: InputError, file, key: str):
    text = str(err)
    assert "\n" not in text
    assert err.key == key
    assert f": {key}: " in text
    assert Path(file).name in text


def _write_mseed(path: Path, channels=("HNE",), data=None, delta=0.01, station="STA"):
    traces = []
    for i, cha in enumerate(channels):
        d = np.arange(50, dtype=np.float64) * (i + 1) if data is None else data
        traces.append(obspy.Trace(np.asarray(d), header={
            "network": "XX", "station": station, "location": "", "channel": cha,
            "delta": delta}))
    obspy.Stream(traces).write(str(path), format="MSEED")
    return path


def _sine_record(dt, duration=10.0, f=1.0):
    t = np.arange(int(round(duration / dt)) + 1) * dt
    return Record(np.sin(2 * np.pi * f * t), dt, {"file": "synthetic"})


# ----------------------------------------------------------------- AT2 and units
def test_at2_auto_units_is_g():
    rec = read_record(ELCENTRO_180)
    tr = obspy.read(str(ELCENTRO_180))[0]
    np.testing.assert_allclose(rec.acceleration, tr.data * 9.80665, rtol=1e-15)
    assert rec.dt == pytest.approx(0.01)
    assert rec.npts == 5372
    assert rec.pga == pytest.approx(0.2807955 * 9.80665, rel=1e-12)
    assert G_STANDARD == 9.80665
    p = rec.provenance
    assert p["format"] == "PEER_AT2"
    assert p["units"] == "g"
    assert p["station"] == "El Centro Array #9"
    assert p["component"] == "180"
    assert p["event"] == "Imperial Valley-02"
    assert p["npts"] == 5372 and p["dt_original"] == pytest.approx(0.01)
    assert p["scale"] == 1.0
    assert len(p["sha256"]) == 64
    assert p["file"] == str(ELCENTRO_180)
    assert any("converted from g" in s for s in p["processing"])


def test_at2_explicit_g_and_scale():
    base = read_record(ELCENTRO_180)
    rec = read_record(ELCENTRO_180, units="g", scale=2.5)
    np.testing.assert_allclose(rec.acceleration, 2.5 * base.acceleration, rtol=1e-15)
    assert rec.provenance["scale"] == 2.5


def test_at2_contradicting_units_rejected():
    with pytest.raises(InputError) as exc:
        read_record(ELCENTRO_180, units="cm/s2")
    _assert_input_error(exc.value, ELCENTRO_180, "units")


def test_at2_trace_by_component():
    rec = read_record(ELCENTRO_180, trace="180")
    assert rec.provenance["component"] == "180"


@pytest.mark.parametrize("units, factor", [
    ("g", 9.80665), ("G", 9.80665),
    ("m/s2", 1.0), ("m/s^2", 1.0), ("m/s**2", 1.0), ("mps2", 1.0), ("M/S2", 1.0),
    ("cm/s2", 0.01), ("gal", 0.01), ("cm/s^2", 0.01), ("Gal", 0.01),
    ("mm/s2", 0.001), ("mm/s^2", 0.001),
])
def test_unit_conversions(tmp_path, units, factor):
    data = np.linspace(-3.0, 4.0, 101)
    path = _write_mseed(tmp_path / "acc.mseed", data=data)
    rec = read_record(path, units=units)
    np.testing.assert_allclose(rec.acceleration, data * factor, rtol=1e-15, atol=0)


def test_counts_with_calibration(tmp_path):
    counts = (np.arange(200) - 100).astype(np.int32) * 37
    path = _write_mseed(tmp_path / "counts.mseed", data=counts)
    cal = 2.5e-6  # m/s2 per count
    rec = read_record(path, units="counts", calibration=cal)
    np.testing.assert_allclose(rec.acceleration, counts * cal, rtol=1e-15)
    assert rec.provenance["units"] == "counts"
    assert rec.provenance["calibration"] == cal
    assert rec.provenance["format"] == "MSEED"


def test_counts_without_calibration(tmp_path):
    path = _write_mseed(tmp_path / "counts.mseed")
    with pytest.raises(InputError) as exc:
        read_record(path, units="counts")
    _assert_input_error(exc.value, path, "calibration")


@pytest.mark.parametrize("cal", [0.0, -1.0, math.nan, math.inf, "abc"])
def test_counts_bad_calibration(tmp_path, cal):
    path = _write_mseed(tmp_path / "counts.mseed")
    with pytest.raises(InputError) as exc:
        read_record(path, units="counts", calibration=cal)
    _assert_input_error(exc.value, path, "calibration")


def test_calibration_without_counts_rejected(tmp_path):
    path = _write_mseed(tmp_path / "acc.mseed")
    with pytest.raises(InputError) as exc:
        read_record(path, units="m/s2", calibration=1e-6)
    _assert_input_error(exc.value, path, "calibration")


def test_auto_units_rejected_for_non_at2(tmp_path):
    path = _write_mseed(tmp_path / "acc.mseed")
    with pytest.raises(InputError) as exc:
        read_record(path)
    _assert_input_error(exc.value, path, "units")


@pytest.mark.parametrize("units", ["furlongs", "m/s", "", None, 9.81])
def test_unparseable_units(tmp_path, units):
    path = _write_mseed(tmp_path / "acc.mseed")
    with pytest.raises(InputError) as exc:
        read_record(path, units=units)
    _assert_input_error(exc.value, path, "units")


@pytest.mark.parametrize("scale", [0.0, -2.0, math.nan, math.inf])
def test_bad_scale(scale):
    with pytest.raises(InputError) as exc:
        read_record(ELCENTRO_180, scale=scale)
    _assert_input_error(exc.value, ELCENTRO_180, "scale")


# ---------------------------------------------------------------- trace choice
def test_trace_selection_by_index_and_name(tmp_path):
    path = _write_mseed(tmp_path / "3c.mseed", channels=("HNE", "HNN", "HNZ"))
    base = np.arange(50, dtype=np.float64)
    assert read_record(path, units="m/s2").provenance["trace"] == "XX.STA..HNE"
    np.testing.assert_array_equal(read_record(path, trace=1, units="m/s2").acceleration,
                                  2 * base)
    rec = read_record(path, trace="HNZ", units="m/s2")
    assert rec.provenance["trace"] == "XX.STA..HNZ"
    np.testing.assert_array_equal(rec.acceleration, 3 * base)
    assert read_record(path, trace="XX.STA..HNN", units="m/s2").provenance["trace"] \
        == "XX.STA..HNN"
    assert read_record(path, trace="hne", units="m/s2").provenance["component"] == "HNE"
    assert read_record(path, trace="N", units="m/s2").provenance["trace"] == "XX.STA..HNN"


@pytest.mark.parametrize("trace", ["HNX", 3, -1, 1.5, True])
def test_unknown_trace(tmp_path, trace):
    path = _write_mseed(tmp_path / "3c.mseed", channels=("HNE", "HNN", "HNZ"))
    with pytest.raises(InputError) as exc:
        read_record(path, trace=trace, units="m/s2")
    _assert_input_error(exc.value, path, "trace")
    assert "XX.STA..HNE" in str(exc.value)  # lists what is available


def test_ambiguous_trace(tmp_path):
    a = _write_mseed(tmp_path / "a.mseed", station="AAA")
    st = obspy.read(str(a)) + obspy.read(str(_write_mseed(tmp_path / "b.mseed", station="BBB")))
    path = tmp_path / "both.mseed"
    st.write(str(path), format="MSEED")
    with pytest.raises(InputError) as exc:
        read_record(path, trace="HNE", units="m/s2")
    _assert_input_error(exc.value, path, "trace")
    assert read_record(path, trace="XX.BBB..HNE", units="m/s2").provenance["station"] == "BBB"


# ------------------------------------------------------------------ bad files
def test_missing_file(tmp_path):
    path = tmp_path / "nope.AT2"
    with pytest.raises(InputError) as exc:
        read_record(path)
    _assert_input_error(exc.value, path, "file")


def test_directory_is_not_a_file(tmp_path):
    with pytest.raises(InputError) as exc:
        read_record(tmp_path)
    _assert_input_error(exc.value, tmp_path, "file")


@pytest.mark.filterwarnings("ignore::UserWarning")  # ObsPy's WIN probe warns on junk
@pytest.mark.parametrize("content", [b"", b"just some text\nnot a waveform\n",
                                     bytes(range(256)) * 10])
def test_unreadable_file(tmp_path, content):
    path = tmp_path / "junk.dat"
    path.write_bytes(content)
    with pytest.raises(InputError) as exc:
        read_record(path, units="g")
    _assert_input_error(exc.value, path, "format")


def test_at2_errors_carry_file_and_key(tmp_path):
    lines = ELCENTRO_180.read_text().splitlines()
    path = tmp_path / "short.AT2"
    path.write_text("\n".join(lines[:-1]) + "\n")
    with pytest.raises(InputError) as exc:
        read_record(path)
    _assert_input_error(exc.value, path, "NPTS")


def test_glob_characters_in_file_name(tmp_path):
    path = tmp_path / "rec[1].AT2"
    path.write_bytes(ELCENTRO_180.read_bytes())
    assert read_record(path).npts == 5372


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_data(tmp_path, bad):
    data = np.linspace(0, 1, 20)
    data[7] = bad
    path = _write_mseed(tmp_path / "nan.mseed", data=data)
    with pytest.raises(InputError) as exc:
        read_record(path, units="m/s2")
    _assert_input_error(exc.value, path, "data")
    assert "sample 7" in str(exc.value)


# -------------------------------------------------------------------- Record
def test_record_properties_and_immutability():
    rec = Record([0.0, 1.0, -3.0, 2.0], 0.5, {"file": "x"})
    assert rec.npts == 4
    assert rec.duration == 1.5
    np.testing.assert_array_equal(rec.time, [0.0, 0.5, 1.0, 1.5])
    assert rec.pga == 3.0
    assert rec.acceleration.dtype == np.float64
    with pytest.raises(ValueError):
        rec.acceleration[0] = 5.0
    with pytest.raises(dataclasses.FrozenInstanceError):
        rec.dt = 1.0


@pytest.mark.parametrize("acc, dt, key", [
    ([1.0, np.nan, 2.0], 0.01, "data"), ([1.0], 0.01, "data"), ([[1.0, 2.0]], 0.01, "data"),
    ([1.0, 2.0], 0.0, "dt"), ([1.0, 2.0], -0.01, "dt"), ([1.0, 2.0], np.nan, "dt"),
])
def test_record_validation(acc, dt, key):
    with pytest.raises(InputError) as exc:
        Record(acc, dt, {"file": "model.toml"})
    _assert_input_error(exc.value, "model.toml", key)


def test_resample_finer_matches_sine():
    rec = _sine_record(0.01)
    fine = rec.resampled(0.005)
    assert fine.dt == 0.005
    assert fine.npts == 2001
    exact = np.sin(2 * np.pi * fine.time)
    assert np.max(np.abs(fine.acceleration - exact)) < 1e-3
    assert "linear interpolation" in fine.provenance["processing"][-1]


def test_resample_coarser_matches_sine():
    rec = _sine_record(0.01)
    coarse = rec.resampled(0.02)
    assert coarse.dt == 0.02
    assert coarse.npts == 501
    exact = np.sin(2 * np.pi * coarse.time)
    inner = slice(50, -50)  # 1 s away from the ends (filter edge effects)
    assert np.max(np.abs(coarse.acceleration[inner] - exact[inner])) < 1e-3
    assert "resample_poly" in coarse.provenance["processing"][-1]


def test_resample_non_integer_ratio():
    rec = _sine_record(0.01)
    coarse = rec.resampled(0.015)
    exact = np.sin(2 * np.pi * coarse.time)
    assert np.max(np.abs(coarse.acceleration[70:-70] - exact[70:-70])) < 1e-3


def test_resample_coarser_is_anti_aliased():
    # 40 Hz is above the 25 Hz Nyquist of dt=0.02: it must be removed, not
    # folded to 10 Hz as plain sample-picking would do.
    rec = _sine_record(0.005, f=40.0)
    coarse = rec.resampled(0.02)
    assert np.max(np.abs(coarse.acceleration[50:-50])) < 1e-2


def test_resample_same_dt_and_errors():
    rec = _sine_record(0.01)
    assert rec.resampled(0.01) is rec
    with pytest.raises(InputError) as exc:
        rec.resampled(0.01 * math.sqrt(2))
    _assert_input_error(exc.value, "synthetic", "dt")
    with pytest.raises(InputError) as exc:
        rec.resampled(0.0)
    _assert_input_error(exc.value, "synthetic", "dt")


@pytest.mark.parametrize("order", [0, 1, 2, 3])
def test_baseline_removes_polynomial(order):
    dt = 0.01
    t = np.arange(3001) * dt
    signal = np.sin(2 * np.pi * 1.3 * t) * np.exp(-0.1 * t)
    trend = np.polynomial.polynomial.polyval(t, [0.3, -0.02, 1e-3, -2e-5][:order + 1])
    clean = Record(signal, dt).baseline_corrected(order)
    drifted = Record(signal + trend, dt).baseline_corrected(order)
    np.testing.assert_allclose(drifted.acceleration, clean.acceleration, rtol=0, atol=1e-12)
    pure = Record(trend, dt).baseline_corrected(order)
    np.testing.assert_allclose(pure.acceleration, 0.0, atol=1e-12)
    assert f"order {order}" in drifted.provenance["processing"][-1]


def test_baseline_linear_on_at2_is_small():
    rec = read_record(ELCENTRO_180)
    corrected = rec.baseline_corrected(1)
    assert np.max(np.abs(corrected.acceleration - rec.acceleration)) < 0.01 * rec.pga


@pytest.mark.parametrize("order", [-1, 4, 1.0, "1", True])
def test_baseline_bad_order(order):
    with pytest.raises(InputError) as exc:
        _sine_record(0.01).baseline_corrected(order)
    _assert_input_error(exc.value, "synthetic", "order")


def test_truncate_and_pad_lengths():
    rec = _sine_record(0.01)  # 1001 samples, 10 s
    cut = rec.truncated(4.0)
    assert cut.npts == 401 and cut.duration == pytest.approx(4.0)
    np.testing.assert_array_equal(cut.acceleration, rec.acceleration[:401])
    assert rec.truncated(12.0) is rec
    padded = rec.padded(15.0)
    assert padded.npts == 1501 and padded.duration == pytest.approx(15.0)
    np.testing.assert_array_equal(padded.acceleration[:1001], rec.acceleration)
    assert np.all(padded.acceleration[1001:] == 0.0)
    assert rec.padded(15.005).npts == 1502  # "at least" the duration
    assert rec.padded(5.0) is rec
    assert [s.split()[0] for s in cut.provenance["processing"]][-1] == "truncated"
    assert padded.provenance["processing"][-1].startswith("zero-padded")
    for bad in (0.0, -1.0, math.nan):
        with pytest.raises(InputError) as exc:
            rec.truncated(bad)
        _assert_input_error(exc.value, "synthetic", "duration")


def test_scaled():
    rec = _sine_record(0.01)
    twice = rec.scaled(2.0).scaled(1.5)
    np.testing.assert_allclose(twice.acceleration, 3.0 * rec.acceleration)
    assert twice.provenance["scale"] == 3.0
    assert rec.provenance.get("processing") == []  # the original is untouched
    with pytest.raises(InputError) as exc:
        rec.scaled(-1.0)
    _assert_input_error(exc.value, "synthetic", "scale")


def test_ground_acceleration_grid():
    rec = read_record(ELCENTRO_180)  # 53.71 s at 0.01 s
    acc = ground_acceleration(rec, 0.005, 60.0)
    assert acc.shape == (round(60.0 / 0.005) + 1,)
    assert acc.flags.writeable
    np.testing.assert_allclose(acc[::2][:rec.npts], rec.acceleration, rtol=1e-12, atol=1e-15)
    assert np.all(acc[2 * rec.npts:] == 0.0)
    short = ground_acceleration(rec, 0.01, 10.0)
    np.testing.assert_array_equal(short, rec.acceleration[:1001])
    with pytest.raises(InputError) as exc:
        ground_acceleration(rec, 0.01, -1.0)
    _assert_input_error(exc.value, ELCENTRO_180, "duration")
