"""The result Dataset: schema, provenance, derived quantities, HDF5 round trip."""

from __future__ import annotations

import json
import sys
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

import h5py
import numpy as np
import pytest
import xarray as xr

import seispound
from tests._models import short_copy as _short_copy
from seispound import InputError, load_model, open_result, simulate, write_result

REPO = Path(__file__).resolve().parents[2]
DURATION = 3.0
DT = 0.005
RECORD_FILE = "RSN6_IMPVALL.I_I-ELC180-hor1.AT2"


def short_copy(folder: Path, duration=DURATION) -> Path:
    return _short_copy(folder, duration)


@pytest.fixture(scope="module")
def model_path(tmp_path_factory):
    return short_copy(tmp_path_factory.mktemp("results"))


@pytest.fixture(scope="module")
def ds(model_path):
    return simulate(load_model(model_path))


@pytest.fixture(scope="module")
def written(ds, tmp_path_factory):
    path = tmp_path_factory.mktemp("written") / "two.h5"
    write_result(ds, path)
    return path


# -- schema ---------------------------------------------------------------------------------
def test_dimensions(ds):
    assert set(ds.dims) == {"time", "building", "floor", "mode", "gap", "impact", "energy_component"}
    assert ds.sizes["time"] == round(DURATION / DT) + 1
    assert ds.sizes["building"] == 2
    assert ds.sizes["floor"] == 8
    assert ds.sizes["gap"] == 4  # A and B share levels 3, 6, 9, 12 m
    assert ds.sizes["energy_component"] == 6
    assert list(ds.energy_component.values) == ["input", "kinetic", "strain", "damping", "contact", "hysteretic"]
    np.testing.assert_allclose(ds.time.values, np.arange(ds.sizes["time"]) * DT, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(ds.gap_height.values, [3.0, 6.0, 9.0, 12.0])
    assert ds.displacement.dims == ("time", "building", "floor")
    assert ds.pounding_force.dims == ("time", "gap")
    assert ds.impact_onset.dims == ("impact",)
    assert ds.energy.dims == ("time", "energy_component")


def test_every_data_variable_has_units_and_long_name(ds):
    assert len(ds.data_vars) >= 20
    for name, var in ds.data_vars.items():
        assert isinstance(var.attrs.get("units"), str) and var.attrs["units"], name
        assert isinstance(var.attrs.get("long_name"), str) and var.attrs["long_name"], name
    units = {n: v.attrs["units"] for n, v in ds.data_vars.items()}
    assert units["displacement"] == "m"
    assert units["velocity"] == "m/s"
    assert units["acceleration"] == "m/s^2"
    assert units["pounding_force"] == "N"
    assert units["impact_onset"] == "s"
    assert units["energy"] == "J"
    assert units["amplification"] == "1"


def test_attributes(ds, model_path):
    assert ds.attrs["schema"] == "seispound-result"
    assert ds.attrs["schema_version"] == 3
    assert ds.attrs["seispound_version"] == seispound.__version__
    assert ds.attrs["model_text"] == model_path.read_text(encoding="utf-8")
    assert ds.attrs["title"] == "Two buildings of different height, El Centro 1940, Hd contact"
    assert ds.attrs["dt"] == DT
    assert ds.attrs["duration"] == DURATION
    assert (ds.attrs["newmark_beta"], ds.attrs["newmark_gamma"]) == (0.25, 0.5)
    assert json.loads(ds.attrs["contact_law"]) == ["Hd"]


def test_record_provenance_has_the_catalogue_sha256(ds):
    cat = tomllib.loads((REPO / "ground_motions" / "catalogue.toml").read_text(encoding="utf-8"))
    entry = next(r for r in cat["record"] if r["file"] == RECORD_FILE)
    rec = json.loads(ds.attrs["record"])
    assert rec["sha256"] == entry["sha256"]
    assert Path(rec["file"]).name == RECORD_FILE
    assert rec["npts"] == entry["npts"]
    assert rec["dt_original"] == entry["dt"]
    assert rec["units"] == "g"


# -- derived quantities ------------------------------------------------------------------------
def test_amplification_is_the_peak_ratio(ds):
    peak = ds.peak_displacement.values
    peak0 = ds.peak_displacement_no_pounding.values
    with np.errstate(invalid="ignore"):
        expected = peak / peak0
    np.testing.assert_array_equal(ds.amplification.values, expected)
    # where the floors exist the ratio is a finite positive number
    exists = ~np.isnan(peak0)
    assert exists.sum() == 12
    assert np.all(np.isfinite(ds.amplification.values[exists]))
    assert np.all(ds.amplification.values[exists] > 0)


def test_pounding_changes_the_response(ds):
    # 3 s of El Centro at 2 cm: impacts happen and the peaks differ from the twin's
    assert ds.sizes["impact"] > 0
    amp = ds.amplification.values
    assert np.nanmax(np.abs(amp - 1.0)) > 1e-3


def test_peak_displacement_bounds_the_grid_values(ds):
    grid = np.abs(ds.displacement.values).max(axis=0)  # NaN for absent floors
    peak = ds.peak_displacement.values
    exists = ~np.isnan(grid)
    assert np.all(peak[exists] >= grid[exists])
    # substep peaks exceed the sampled ones by no more than the motion within one step
    vmax = np.abs(ds.velocity.values).max(axis=0)
    assert np.all(peak[exists] <= grid[exists] + vmax[exists] * DT)


def test_drift_is_floor_minus_floor_below(ds):
    u = ds.displacement.values
    below = np.concatenate([np.zeros(u.shape[:2] + (1,)), u[..., :-1]], axis=-1)
    np.testing.assert_array_equal(ds.drift.values, u - below)
    # floor 1 against the ground
    np.testing.assert_array_equal(ds.drift.sel(floor=1).values, ds.displacement.sel(floor=1).values)
    peak_drift = np.abs(ds.drift.values).max(axis=0)
    np.testing.assert_array_equal(ds.peak_drift.values, peak_drift)


def test_impact_count_is_the_bincount_of_impact_gap(ds):
    gap = ds.impact_gap.values
    np.testing.assert_array_equal(ds.impact_count.values, np.bincount(gap, minlength=ds.sizes["gap"]))
    assert ds.impact_count.sum() == ds.sizes["impact"]
    onset = ds.impact_onset.values
    assert np.all(np.diff(onset) >= 0)  # in order of onset
    assert np.all((onset >= 0) & (onset <= DURATION))
    assert np.all(ds.impact_approach_velocity.values > 0)


def test_pounding_force_is_compressive_for_hd(ds):
    f = ds.pounding_force.values
    assert np.all(np.isfinite(f))
    assert f.min() >= 0.0
    assert f.max() > 0.0
    assert np.all(ds.peak_pounding_force.values >= f.max(axis=0))
    assert np.all(ds.impact_peak_force.values > 0)
    # a gap with no impact never carries a force
    quiet = ds.impact_count.values == 0
    assert np.all(f[:, quiet] == 0.0)
    assert np.all(ds.peak_pounding_force.values[quiet] == 0.0)


def test_absent_floors_are_nan(ds):
    a = ds.sel(building="A")
    b = ds.sel(building="B")
    upper = a.sel(floor=[5, 6, 7, 8])
    for name in ("displacement", "velocity", "acceleration", "drift", "peak_displacement",
                 "peak_displacement_no_pounding", "amplification", "peak_drift", "floor_height"):
        assert bool(upper[name].isnull().all()), name
        assert bool(a[name].sel(floor=[1, 2, 3, 4]).notnull().all()), name
        assert bool(b[name].notnull().all()), name
    np.testing.assert_array_equal(b.floor_height.values, 3.0 * np.arange(1, 9))


# -- storage ---------------------------------------------------------------------------------------
def test_round_trip_is_lossless(ds, written):
    with xr.open_dataset(written, engine="h5netcdf") as back:
        back = back.load()
    xr.testing.assert_identical(back, ds)
    # and through the package's reader
    xr.testing.assert_identical(open_result(written), ds)
    assert sorted(p.name for p in written.parent.iterdir()) == ["two.h5"]


def test_plain_h5py_reads_the_file(ds, written):
    with h5py.File(written, "r") as f:
        disp = f["displacement"][...]
        assert disp.shape == ds.displacement.shape
        np.testing.assert_array_equal(disp, ds.displacement.values)
        np.testing.assert_array_equal(f["impact_count"][...], ds.impact_count.values)
        units = f["displacement"].attrs["units"]
        assert (units.decode() if isinstance(units, bytes) else units) == "m"
        schema = f.attrs["schema"]
        assert (schema.decode() if isinstance(schema, bytes) else schema) == "seispound-result"


def test_write_into_a_missing_folder(ds, tmp_path):
    target = tmp_path / "missing" / "x.h5"
    with pytest.raises(InputError) as info:
        write_result(ds, target)
    assert info.value.key == "output"
    assert "x.h5" in str(info.value) and len(str(info.value).splitlines()) == 1
    assert list(tmp_path.iterdir()) == []


def test_open_missing_result(tmp_path):
    with pytest.raises(InputError) as info:
        open_result(tmp_path / "none.h5")
    assert "none.h5" in str(info.value)


def test_no_twin_gives_nan_amplification(model_path, ds):
    model = load_model(model_path)
    single = simulate(model, twin=False)
    assert bool(single.amplification.isnull().all())
    assert bool(single.peak_displacement_no_pounding.isnull().all())
    # the pounding run itself is the same
    np.testing.assert_array_equal(single.displacement.values, ds.displacement.values)
    np.testing.assert_array_equal(single.peak_displacement.values, ds.peak_displacement.values)
    np.testing.assert_array_equal(single.impact_count.values, ds.impact_count.values)
