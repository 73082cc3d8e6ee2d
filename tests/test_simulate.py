"""simulate(): record cache, repeatability, free vibration."""

import os
import shutil
from pathlib import Path

import numpy as np
import pytest

import seispound as sp
from seispound.simulation import prepare_ground_motion

REPO = Path(__file__).resolve().parents[1]
MODEL = REPO / "models" / "two_buildings.toml"
RECORD = REPO / "ground_motions" / "RSN6_IMPVALL.I_I-ELC180-hor1.AT2"


def _short_model(tmp_path, record):
    text = MODEL.read_text().replace("duration = 30.0", "duration = 2.0")
    text = text.replace('file = "../ground_motions/RSN6_IMPVALL.I_I-ELC180-hor1.AT2"', f'file = "{record.name}"')
    path = tmp_path / "m.toml"
    path.write_text(text)
    return path


def test_repeated_runs_are_identical():
    m = sp.load_model(MODEL)
    m.analysis.duration = 3.0
    a, b = sp.simulate(m), sp.simulate(m)
    assert np.array_equal(a.displacement.values, b.displacement.values, equal_nan=True)
    assert np.array_equal(a.impact_peak_force.values, b.impact_peak_force.values)


def test_record_cache_follows_edits_of_the_record(tmp_path):
    rec = tmp_path / "rec.AT2"
    shutil.copy(RECORD, rec)
    model = sp.load_model(_short_model(tmp_path, rec))
    ag1, prov1 = prepare_ground_motion(model)
    # scale every sample by 2 (rewrite the data lines), keep the header
    lines = rec.read_text().splitlines()
    body = " ".join(lines[4:]).split()
    doubled = [f"{2 * float(x):.7E}" for x in body]
    rec.write_text("\n".join(lines[:4] + [" ".join(doubled[i:i + 5]) for i in range(0, len(doubled), 5)]) + "\n")
    st = rec.stat()
    os.utime(rec, ns=(st.st_atime_ns, st.st_mtime_ns + 10**9))  # a later mtime even on coarse clocks
    ag2, prov2 = prepare_ground_motion(model)
    assert prov1["sha256"] != prov2["sha256"]
    assert np.allclose(ag2, 2 * ag1, rtol=1e-6, atol=1e-12)


def test_cached_record_cannot_be_corrupted_by_the_caller():
    model = sp.load_model(MODEL)
    ag, _ = prepare_ground_motion(model)
    ag[:] = 0.0
    ag_again, _ = prepare_ground_motion(model)
    assert np.abs(ag_again).max() > 1.0  # El Centro 180: PGA 2.75 m/s^2


def test_free_vibration_impact_test_has_no_record_and_one_impact():
    ds = sp.simulate(sp.load_model(REPO / "models" / "slab_pendulum.toml"))
    assert ds.attrs["record"] == "none"
    assert np.all(ds.ground_acceleration.values == 0.0)
    assert ds.sizes["impact"] == 1
    assert float(ds.impact_velocity_ratio[0]) == pytest.approx(0.7, rel=5e-3)
    # the striker hands most of its momentum to the struck slab: m1 v0 = m1 v1 + m2 v2
    assert float(ds.impact_approach_velocity[0]) == pytest.approx(0.096, rel=1e-6)
