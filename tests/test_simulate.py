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


def test_assembly_is_kept_for_a_model_and_redone_after_an_edit():
    """Model.assembled keeps the system for the model's content; an edit from Python assembles afresh."""
    m = sp.load_model(MODEL)
    m.analysis.duration = 2.0
    first = m.assembled()
    assert m.assembled() is first  # kept
    with pytest.raises(ValueError):  # read-only: shared by every run of the model
        first.gap_size[0] = 1.0
    before = sp.simulate(m, twin=False)
    m.gaps[0].size *= 2.0  # an edit inside a part
    second = m.assembled()
    assert second is not first and second.gap_size[0] == pytest.approx(2.0 * first.gap_size[0])
    after = sp.simulate(m, twin=False)
    assert float(after.gap_size[0]) == pytest.approx(2.0 * float(before.gap_size[0]))
    m.buildings[0].storey_stiffness = m.buildings[0].storey_stiffness * 1.1  # a field replaced
    assert m.assembled() is not second
    m.buildings[0].storey_stiffness = "not numbers"  # validation still runs on every change
    with pytest.raises(sp.InputError):
        m.assembled()


def test_in_memory_record_prepared_once_and_not_corruptible():
    """Samples given in memory are prepared once per content; the caller's copy cannot reach the cache."""
    from seispound.model.spec import GroundMotionSpec

    m = sp.load_model(MODEL)
    m.analysis.duration = 2.0
    acc = np.sin(np.linspace(0.0, 20.0, 401))
    m.ground_motion = GroundMotionSpec.from_array(acc, 0.01, units="m/s2")
    a = sp.simulate(m, twin=False)
    a.ground_acceleration.values[:] = 99.0  # the result's copy
    b = sp.simulate(m, twin=False)
    assert float(abs(b.ground_acceleration).max()) <= 1.0
    m.ground_motion = GroundMotionSpec.from_array(2.0 * acc, 0.01, units="m/s2")
    c = sp.simulate(m, twin=False)
    np.testing.assert_allclose(c.ground_acceleration.values, 2.0 * b.ground_acceleration.values)


def test_result_layout_and_model_findings_follow_edits():
    """What simulate keeps with the model's content (the result layout, the model-only findings) is rebuilt
    after an edit: the periods and gap sizes of the result, and the coarse-step warning, follow the model."""
    import pickle
    import warnings

    m = sp.load_model(MODEL)
    m.analysis.duration = 2.0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        first = sp.simulate(m, twin=False)
        again = sp.simulate(m, twin=False)
    assert m.kept()["layout"] is not None and "model_findings" in m.kept()
    assert np.array_equal(first.period.values, again.period.values, equal_nan=True)
    again.period.values[:] = 0.0  # a result's coordinates and variables are its own
    again.gap_size.values[:] = 0.0
    third = sp.simulate(m, twin=False)
    np.testing.assert_array_equal(third.period.values, first.period.values)
    np.testing.assert_array_equal(third.gap_size.values, first.gap_size.values)
    m.buildings[0].storey_stiffness = m.buildings[0].storey_stiffness * 4.0  # periods halve
    m.gaps[0].size *= 2.0
    m.analysis.dt = 0.05  # coarse: a finding that depends on the model alone
    from seispound.plausibility import PlausibilityWarning

    with pytest.warns(PlausibilityWarning, match="steps per period"):
        edited = sp.simulate(m, twin=False)
    np.testing.assert_allclose(edited.period.values[0], first.period.values[0] / 2.0, rtol=1e-12)
    np.testing.assert_allclose(edited.period.values[1], first.period.values[1], rtol=1e-12, equal_nan=True)
    assert float(edited.gap_size[0]) == pytest.approx(2.0 * float(first.gap_size[0]))
    assert "coarse_step" in edited.attrs["plausibility"] and "coarse_step" not in first.attrs["plausibility"]
    # a building pickles without its kept modes, and finds them again
    b = m.buildings[0]
    w = b.modes()[0]
    assert "_modes" in b.__dict__ and "_modes" not in pickle.loads(pickle.dumps(b)).__dict__
    np.testing.assert_array_equal(pickle.loads(pickle.dumps(b)).modes()[0], w)


def test_provenance_of_samples_is_a_copy():
    """The provenance handed out for samples in memory is a copy: a caller's addition stays its own."""
    from seispound.model.spec import GroundMotionSpec
    from seispound.simulation import prepare_ground_motion

    m = sp.load_model(MODEL)
    m.analysis.duration = 2.0
    m.ground_motion = GroundMotionSpec.from_array(np.sin(np.linspace(0.0, 20.0, 401)), 0.01, units="m/s2")
    _, prov = prepare_ground_motion(m)
    prov["mine"] = 1
    for v in prov.values():
        if isinstance(v, list):
            v.append("mine")
    _, again = prepare_ground_motion(m)
    assert "mine" not in again and all("mine" not in v for v in again.values() if isinstance(v, list))
