"""Plausibility guards: warned about (warnings, result attributes, run summary) or refused unless forced."""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest
import xarray as xr
from scipy.linalg import eigh

import seispound as sp
from seispound import InputError, cli
from seispound.plausibility import PlausibilityWarning, check_after_run, check_before_run
from tests.cli.test_bad_input import BASE, sub, write_model

PGA_ELCENTRO_G = 0.2808  # El Centro 1940 180, PEER header (tests/motion/test_at2.py)



def _codes(ds):
    return [f["code"] for f in json.loads(ds.attrs["plausibility"])]


def test_clean_model_has_no_findings(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("error", PlausibilityWarning)
        ds = sp.simulate(sp.load_model(write_model(tmp_path, BASE)), twin=False)
    assert json.loads(ds.attrs["plausibility"]) == []


def test_pga_above_3g_refused_unless_forced(tmp_path, capsys):
    """A record in cm/s2 declared as g: El Centro 0.2808 g times 981 = 275 g."""
    model = write_model(tmp_path, sub('units = "g"', 'units = "g"\nscale = 981.0')(BASE))
    assert cli.main(["run", str(model), "-o", str(tmp_path / "r.h5")]) == 2
    line = capsys.readouterr().err.strip()
    assert "\n" not in line and "model.toml: ground_motion.units: the record's PGA is 275.5 g" in line
    assert not (tmp_path / "r.h5").exists()
    with pytest.warns(PlausibilityWarning, match="PGA is 275.5 g"):
        ds = sp.simulate(sp.load_model(model), twin=False, force=True)
    found = json.loads(ds.attrs["plausibility"])
    assert found[0]["code"] == "pga" and found[0]["refuse"] is True
    assert float(found[0]["message"].split("(")[1].split(" m/s2")[0]) == pytest.approx(
        PGA_ELCENTRO_G * 981 * 9.80665, rel=2e-3)
    assert cli.main(["run", str(model), "-o", str(tmp_path / "r.h5"), "--force"]) == 0
    assert "warning: the record's PGA is 275.5 g" in capsys.readouterr().out
    assert "pga" in _codes(sp.open_result(tmp_path / "r.h5"))


def test_just_below_3g_runs_silently(tmp_path):
    scale = 2.99 / PGA_ELCENTRO_G
    model = sp.load_model(write_model(tmp_path, sub('units = "g"', f'units = "g"\nscale = {scale}')(BASE)))
    found = check_before_run(model, {"pga": 2.99 * 9.80665})
    assert [f.code for f in found] == []


def test_coarser_step_than_the_record_says_it_decimated(tmp_path):
    text = sub("dt = 0.005", "dt = 0.02")(BASE)
    with pytest.warns(PlausibilityWarning, match="decimated"):
        ds = sp.simulate(sp.load_model(write_model(tmp_path, text)), twin=False)
    msg = next(f["message"] for f in json.loads(ds.attrs["plausibility"]) if f["code"] == "decimated")
    assert "the analysis step 0.02 s is coarser than the record's step 0.01 s" in msg
    f_hi = float(msg.split("frequencies up to ")[1].split(" Hz")[0])
    assert 0.75 * 25.0 <= f_hi < 25.0  # below the new Nyquist frequency 1 / (2 x 0.02 s)


def test_duration_beyond_the_record_says_zero_padded(tmp_path):
    text = sub("duration = 0.2", "duration = 60.0")(BASE)  # El Centro 180 lasts 53.71 s
    model = sp.load_model(write_model(tmp_path, text))
    with pytest.warns(PlausibilityWarning, match="zero-padded"):
        ds = sp.simulate(model, twin=False)
    msg = next(f["message"] for f in json.loads(ds.attrs["plausibility"]) if f["code"] == "zero_padded")
    end = float(msg.split("the record ends at ")[1].split(" s")[0])
    assert end == pytest.approx(53.71, abs=1e-9)
    assert "the last 6.29 s are free vibration" in msg


def _share_mode(m, k):
    """Mode number needed for 90 % of the effective modal mass, from dense M, K (Chopra Eq. 13.2.14)."""
    K = np.diag(np.r_[k[:-1] + k[1:], k[-1]]) - np.diag(k[1:], 1) - np.diag(k[1:], -1)
    w2, phi = eigh(K, np.diag(m))
    ln = phi.T @ m
    share = np.cumsum(ln ** 2 / (np.einsum("ij,i,ij->j", phi, m, phi))) / m.sum()
    j = int(np.argmax(share >= 0.9))
    return j + 1, 2 * np.pi / np.sqrt(w2[j])


def test_step_too_coarse_for_the_modes_that_matter(tmp_path):
    model = sp.load_model(write_model(tmp_path, BASE))
    (mode, period), name = min((_share_mode(b.floor_masses, b.storey_stiffness), b.name)
                               for b in model.buildings)
    assert mode == 2 and name == "A"  # uniform shear buildings: mode 1 holds 84-88 %, modes 1-2 above 90 %
    model.analysis.dt = 0.11 * period
    model.analysis.scheme = "newmark"
    found = [f for f in check_before_run(model, None) if f.code == "coarse_step"]
    assert len(found) == 1 and f"building A's mode {mode} (T = {period:.3g} s)" in found[0].message
    err = (2 * np.pi * 0.11) ** 2 / 12 * 100  # average acceleration: period error (omega dt)^2 / 12
    assert f"about {err:.2g} % long" in found[0].message
    model.analysis.scheme = "exact"  # no period error; the sampling of peaks remains
    found = [f for f in check_before_run(model, None) if f.code == "coarse_step"]
    under = (1 - np.cos(np.pi * 0.11)) * 100
    assert len(found) == 1 and f"under-read by up to {under:.2g} %" in found[0].message
    model.analysis.dt = 0.099 * period
    assert [f for f in check_before_run(model, None) if f.code == "coarse_step"] == []


def test_floors_that_mostly_face_a_storey(tmp_path):
    """A: floors at 3, 6, ..., 18 m; B: at 3, 7.5, 12, 16.5 m: below B's roof only 3 m and 12 m are shared."""
    text = BASE.replace("storey_heights = [3.0, 3.0, 3.0, 3.0]", "storey_heights = [3.0, 3.0, 3.0, 3.0, 3.0, 3.0]")
    text = text.replace("floor_masses = [1.0e5, 1.0e5, 1.0e5, 1.0e5]", "floor_masses = 1.0e5\nfloors = 6")
    text = text.replace("storey_stiffness = [1.3092e8, 1.3092e8, 1.3092e8, 1.3092e8]", "storey_stiffness = 1.3e8")
    text = text.replace("floors = 8\n", "floors = 4\n").replace("storey_heights = 3.0\n", "storey_heights = [3.0, 4.5, 4.5, 4.5]\n")
    text = text.replace('size = 0.02', 'size = 0.02\nlevels = "floors"', 1)
    model = sp.load_model(write_model(tmp_path, text))
    found = [f for f in check_before_run(model, None) if f.code == "floor_levels"]
    assert len(found) == 1
    msg = found[0].message
    assert "only 2 of the floor levels below the lower roof are shared (5 floors" in msg
    assert "gap elements at 3, 12 m only" in msg
    assert "A's floors 2 (6 m), 3 (9 m), 5 (15 m) face a storey of B; B's floors 2 (7.5 m), 4 (16.5 m) face a " \
           "storey of A" in msg
    assert found[0].key == "gap.1.levels"
    # by default B's floors (the lower roof) strike A's storeys; A's floors facing B's storeys are named
    model.gaps[0].levels = "lower"
    (f,) = [f for f in check_before_run(model, None) if f.code == "floor_levels"]
    assert "A's floors 2 (6 m), 3 (9 m), 5 (15 m) face a storey of B and have no gap element" in f.message
    model.gaps[0].levels = "all"
    assert [f for f in check_before_run(model, None) if f.code == "floor_levels"] == []


def test_velocity_ratio_outside_unit_interval_is_named_not_an_error():
    ds = xr.Dataset({"impact_velocity_ratio": ("impact", [0.6, 1.25, -0.05, 0.7, np.nan])})
    (f,) = check_after_run(ds)
    assert f.code == "velocity_ratio" and not f.refuse and f.advisory
    import warnings

    from seispound.plausibility import issue

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        issue([f], force=False)  # expected and no error: stored and noted, never warned
    assert f.message.startswith("2 of 5 impacts have a separation/approach velocity ratio outside [0, 1]")
    assert "range -0.05 to 1.25" in f.message and "not an error" in f.message
    ds = xr.Dataset({"impact_velocity_ratio": ("impact", [0.6, 1.0, 0.0])})
    assert check_after_run(ds) == []


def test_findings_refuse_only_what_is_marked(tmp_path):
    """Every non-refusing finding lets the run go on (exit 0) and is printed by the run summary."""
    text = sub("duration = 0.2", "duration = 55.0")(BASE)
    text = sub("dt = 0.005", "dt = 0.02")(text)
    model = write_model(tmp_path, text)
    assert cli.main(["run", str(model), "-o", str(tmp_path / "r.h5"), "--no-twin"]) == 0
    ds = sp.open_result(tmp_path / "r.h5")
    assert {"decimated", "zero_padded"} <= set(_codes(ds))


def test_refusal_is_an_input_error_naming_file_and_key(tmp_path):
    model = sp.load_model(write_model(tmp_path, sub('units = "g"', 'units = "g"\nscale = 20.0')(BASE)))
    with pytest.raises(InputError) as info:
        sp.simulate(model)
    assert info.value.key == "ground_motion.units" and info.value.file.endswith("model.toml")


def test_study_refuses_an_implausible_record_before_any_run(tmp_path, capsys):
    from tests.study.conftest import write_study

    study = write_study(tmp_path, duration=0.3, records=("elcentro_180",), gaps=(0.01,))
    model = tmp_path / "two.toml"
    model.write_text(model.read_text().replace("scale = 1.0", "scale = 981.0"))
    out = tmp_path / "s.h5"
    assert cli.main(["study", str(study), "-o", str(out), "--scheduler", "serial", "-q"]) == 2
    line = capsys.readouterr().err.strip()
    assert "\n" not in line and "study.toml: records: record elcentro_180" in line and "PGA is 275.5 g" in line
    assert not out.exists() and not list(tmp_path.glob("*.journal"))
    assert cli.main(["study", str(study), "-o", str(out), "--scheduler", "serial", "--force"]) == 0
    assert "warning: record elcentro_180: the record's PGA is 275.5 g" in capsys.readouterr().err
    assert out.exists()


def test_a_warning_names_the_line_that_called_simulate():
    from dataclasses import replace

    from tests._models import REPO

    model = sp.load_model(REPO / "models" / "two_buildings.toml")
    model = replace(model, analysis=replace(model.analysis, dt=0.02))  # 8.7 steps per period of a mode needed
    with pytest.warns(PlausibilityWarning) as caught:
        sp.simulate(model, twin=False)
    assert {w.filename for w in caught} == {__file__}
