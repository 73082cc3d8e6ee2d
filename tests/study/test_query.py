"""The query side of a study store (seispound.study.query).

Small synthetic stores follow seispound.study.schema exactly and are written
with h5netcdf.  Expected numbers are computed from the raw numpy arrays with
plain loops (a hand-written linear quantile, sorted scans for "smallest"),
never with the xarray calls under test.
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import math

import numpy as np
import pytest
import xarray as xr

from seispound.errors import InputError
from seispound.study import query as Q
from seispound.study.schema import SCHEMA, SCHEMA_VERSION, SUMMARY_VARIABLES

RECORDS = ["RSN6_ELC180", "RSN15_TAFT", "RSN30_PKF"]
LAWS = ["Hd", "LVe"]
GAPS = [0.04, 0.01, 0.03, 0.02]  # file order, deliberately not sorted
BUILDINGS = ["A", "B"]
N_FLOORS = [3, 2]  # B's floor 3 is NaN padding
NR, NL, NG, NB, NF, NE = len(RECORDS), len(LAWS), len(GAPS), len(BUILDINGS), 3, 2
# base amplification per (law, gap value): Hd passes 1.2 at 0.02 and 0.04 but
# not at 0.03 (not monotone); LVe passes from 0.03 on.  Noise is < 0.05.
BASE = {("Hd", 0.01): 1.50, ("Hd", 0.02): 1.10, ("Hd", 0.03): 1.30, ("Hd", 0.04): 1.05,
        ("LVe", 0.01): 1.40, ("LVe", 0.02): 1.35, ("LVe", 0.03): 1.10, ("LVe", 0.04): 1.00}
FAILED = [(0, 1, 2), (1, 0, 1)]  # (record, law, gap position): LVe @ 0.03, Hd @ 0.01
PENDING = [(2, 0, 0)]  # Hd @ 0.04


def make_raw(seed=0):
    """The numbers of a study, as plain numpy arrays (NaN where not done)."""
    rng = np.random.default_rng(seed)
    run = (NR, NL, NG)
    status = np.ones(run, np.int8)
    for idx in FAILED:
        status[idx] = 0
    for idx in PENDING:
        status[idx] = -1
    amp = np.full(run + (NB, NF), np.nan)
    pd_ = np.full(run + (NB, NF), np.nan)
    force = np.full(run + (NE,), np.nan)
    count = np.full(run + (NE,), -1, np.int64)
    for r in range(NR):
        for l in range(NL):
            for g in range(NG):
                if status[r, l, g] != 1:
                    continue
                for b in range(NB):
                    for f in range(N_FLOORS[b]):
                        amp[r, l, g, b, f] = BASE[LAWS[l], GAPS[g]] + rng.uniform(0, 0.05)
                        pd_[r, l, g, b, f] = rng.uniform(0.01, 0.2)
                force[r, l, g] = rng.uniform(1e5, 2e6, NE)
                count[r, l, g] = rng.integers(0, 4, NE)
    maxamp = np.full(run, np.nan)
    maxforce = np.full(run, np.nan)
    total = np.full(run, -1, np.int64)
    for idx in np.ndindex(run):
        if status[idx] == 1:
            maxamp[idx] = max(v for v in amp[idx].ravel() if not math.isnan(v))
            maxforce[idx] = max(force[idx])
            total[idx] = sum(count[idx])
    error = np.where(status == 0, "IntegrationError: Newmark iteration did not converge", "").astype(object)
    return dict(status=status, error=error, amplification=amp, peak_displacement=pd_,
                peak_displacement_no_pounding=pd_ / amp, peak_drift=pd_ / 3,
                peak_pounding_force=force, impact_count=count, max_amplification=maxamp,
                max_pounding_force=maxforce, total_impacts=total)


def build_dataset(raw, *, schema=SCHEMA) -> xr.Dataset:
    """A Dataset laid out as seispound.study.schema says."""
    run = ("record", "law", "gap_size")
    data = {
        "status": (run, raw["status"], {"units": "1", "flag_values": np.array([1, 0, -1], np.int8),
                                        "flag_meanings": "done failed not_run"}),
        "error": (run, raw["error"].astype(str), {}),
    }
    trailing = {(): (), ("building", "floor"): ("building", "floor"), ("gap",): ("gap",)}
    for name, dims, units, long_name, _dtype in SUMMARY_VARIABLES:
        if name not in raw:  # quantities the query tests do not use: NaN of the right shape
            shape = raw["status"].shape + {(): (), ("building", "floor"): raw["amplification"].shape[-2:],
                                           ("gap",): raw["peak_pounding_force"].shape[-1:]}[dims]
            raw[name] = np.full(shape, np.nan)
        data[name] = (run + trailing[dims], raw[name], {"units": units, "long_name": long_name})
    coords = {
        "record": RECORDS, "record_file": ("record", [f"records/{r}.AT2" for r in RECORDS]),
        "law": LAWS, "gap_size": ("gap_size", GAPS, {"units": "m"}),
        "building": BUILDINGS, "floor": np.arange(1, NF + 1), "gap": np.arange(NE),
        "gap_left": ("gap", ["A", "A"]), "gap_right": ("gap", ["B", "B"]),
        "gap_left_floor": ("gap", [1, 2]), "gap_right_floor": ("gap", [1, 2]),
        "gap_height": ("gap", [3.0, 6.0], {"units": "m"}),
    }
    n_done = int((raw["status"] == 1).sum())
    n_failed = int((raw["status"] == 0).sum())
    attrs = {"schema": schema, "schema_version": SCHEMA_VERSION, "title": "synthetic gap study",
             "seispound_version": "0.1.0", "study_file": "study.toml", "study_text": "# study",
             "model_file": "two.toml", "model_text": "# model",
             "records": json.dumps([{"file": f"records/{r}.AT2", "sha256": "0" * 64} for r in RECORDS]),
             "axes": json.dumps([{"name": "law", "path": "contact.law", "values": LAWS},
                                 {"name": "gap_size", "path": "gap.0.size", "values": GAPS}]),
             "run_dims": json.dumps(list(run)), "study_hash": "abc123",
             "runs_total": raw["status"].size, "runs_done": n_done, "runs_failed": n_failed}
    return xr.Dataset(data, coords=coords, attrs=attrs)


@pytest.fixture(scope="module")
def raw():
    return make_raw()


@pytest.fixture(scope="module")
def store(tmp_path_factory, raw):
    """One store for the module: every test only reads it."""
    path = tmp_path_factory.mktemp("study") / "study.h5"
    build_dataset(raw).to_netcdf(path, engine="h5netcdf")
    return path


@pytest.fixture
def ds(store):
    with Q.open_study(store) as ds:
        yield ds


# ------------------------------------------------------------ reference helpers


def q_linear(values, q):
    """Quantile with linear interpolation between order statistics (numpy "linear")."""
    xs = sorted(values)
    h = (len(xs) - 1) * q
    lo = int(math.floor(h))
    hi = min(lo + 1, len(xs) - 1)
    return xs[lo] + (h - lo) * (xs[hi] - xs[lo])


def over_records(arr, stat, strict=False):
    """stat over the record axis (0) of a (record, law, gap) array, NaN skipped."""
    out = np.full(arr.shape[1:], np.nan)
    for l in range(arr.shape[1]):
        for g in range(arr.shape[2]):
            vals = [v for v in arr[:, l, g] if not math.isnan(v)]
            if vals and not (strict and len(vals) < arr.shape[0]):
                out[l, g] = stat(vals)
    return out


def smallest_ref(passing, gaps, monotone=False):
    """Per law: the smallest gap value passing (scan in sorted order)."""
    out = []
    for l in range(passing.shape[0]):
        order = sorted(range(len(gaps)), key=lambda g: gaps[g])
        found = math.nan
        for k, g in enumerate(order):
            if passing[l, g] and (not monotone or all(passing[l, h] for h in order[k:])):
                found = gaps[g]
                break
        out.append(found)
    return np.array(out)


def same(a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    assert a.shape == b.shape
    assert np.array_equal(np.isnan(a), np.isnan(b)), (a, b)
    np.testing.assert_allclose(a[~np.isnan(a)], b[~np.isnan(b)], rtol=1e-12)


def status_mask(raw):
    return raw["status"] == 1


# ------------------------------------------------------------------ open_study


def test_open_study_is_lazy_and_keeps_attrs_as_strings(store):
    with Q.open_study(store) as ds:
        assert ds.attrs["schema"] == SCHEMA
        assert isinstance(ds.attrs["run_dims"], str)
        # lazily indexed: nothing loaded yet
        assert not ds["amplification"].variable._in_memory
        assert ds.sizes["record"] == 3 and ds.sizes["gap_size"] == 4


def test_open_study_missing_file(tmp_path):
    with pytest.raises(InputError, match="not found") as err:
        Q.open_study(tmp_path / "nope.h5")
    assert "nope.h5" in str(err.value)


def test_open_study_not_hdf5(tmp_path):
    path = tmp_path / "text.h5"
    path.write_text("hello")
    with pytest.raises(InputError, match="not an HDF5 file") as err:
        Q.open_study(path)
    assert err.value.file == str(path)


def test_open_study_wrong_schema(tmp_path, raw):
    path = tmp_path / "result.h5"
    build_dataset(raw, schema="seispound-result").to_netcdf(path, engine="h5netcdf")
    with pytest.raises(InputError, match="seispound-result") as err:
        Q.open_study(path)
    assert err.value.key == "schema"
    assert str(err.value).startswith(f"{path}: schema: ")


def test_open_study_newer_schema_version(tmp_path, raw):
    path = tmp_path / "future.h5"
    ds = build_dataset(raw)
    ds.attrs["schema_version"] = SCHEMA_VERSION + 1
    ds.to_netcdf(path, engine="h5netcdf")
    with pytest.raises(InputError) as err:
        Q.open_study(path)
    assert err.value.key == "schema_version"


def test_run_dims(ds):
    assert Q.run_dims(ds) == ["record", "law", "gap_size"]


# -------------------------------------------------------------- done and worst


def test_done_masks_runs_not_done(ds, raw):
    out = Q.done(ds, "max_amplification")
    assert out.dims == ("record", "law", "gap_size")
    ok = status_mask(raw)
    assert int(out.notnull().sum()) == int(ok.sum()) == 21
    same(out.values[ok], raw["max_amplification"][ok])
    assert out.attrs["units"] == "1"


def test_done_turns_int_minus_one_into_nan(ds, raw):
    out = Q.done(ds, "total_impacts")
    assert out.dtype.kind == "f"
    for idx in np.ndindex(raw["status"].shape):
        if raw["status"][idx] == 1:
            assert out.values[idx] == raw["total_impacts"][idx]
        else:
            assert math.isnan(out.values[idx])
    assert (np.asarray(ds["total_impacts"].values) == -1).sum() == 3  # stored -1, not NaN


def test_done_unknown_variable(ds):
    with pytest.raises(InputError, match="no variable 'amp'.*max_amplification") as err:
        Q.done(ds, "amp")
    assert err.value.key == "--var"


def test_worst_over_building_and_floor(ds, raw):
    out = Q.worst(Q.done(ds, "amplification"))
    assert out.dims == ("record", "law", "gap_size")
    ref = np.full(raw["status"].shape, np.nan)
    for idx in np.ndindex(ref.shape):
        vals = [v for v in raw["amplification"][idx].ravel() if not math.isnan(v)]
        if vals:
            ref[idx] = max(vals)
    same(out, ref)
    same(out, raw["max_amplification"])  # the store's own summary agrees


def test_worst_over_gap_and_nothing_to_do(ds, raw):
    out = Q.worst(Q.done(ds, "peak_pounding_force"))
    same(out, raw["max_pounding_force"])
    scalar = Q.done(ds, "max_amplification")
    assert Q.worst(scalar) is scalar


# --------------------------------------------------------------------- reduce


@pytest.mark.parametrize("how, stat", [
    ("max", max), ("min", min), ("mean", lambda v: sum(v) / len(v)),
    ("median", lambda v: q_linear(v, 0.5)),
    ("std", lambda v: math.sqrt(sum((x - sum(v) / len(v)) ** 2 for x in v) / len(v))),
    ("q90", lambda v: q_linear(v, 0.9)), ("q0.9", lambda v: q_linear(v, 0.9)),
    ("p90", lambda v: q_linear(v, 0.9)), (0.9, lambda v: q_linear(v, 0.9)),
    ("p5", lambda v: q_linear(v, 0.05)), ("p1", lambda v: q_linear(v, 0.01)),
    ("q1", max), ("Q75", lambda v: q_linear(v, 0.75)),
])
def test_reduce_over_records(ds, raw, how, stat):
    out = Q.reduce(Q.done(ds, "max_amplification"), "record", how)
    assert out.dims == ("law", "gap_size")
    assert "quantile" not in out.coords
    assert out.name == "max_amplification" and out.attrs["units"] == "1"
    same(out, over_records(raw["max_amplification"], stat))


def test_reduce_count_and_strict(ds, raw):
    da = Q.done(ds, "max_amplification")
    count = Q.reduce(da, "record", "count")
    ref = np.sum(raw["status"] == 1, axis=0)
    assert count.values.tolist() == ref.tolist()
    assert ref.min() == 2  # the data has runs missing, so the next line can fail
    strict = Q.reduce(da, "record", "q90", skipna=False)
    same(strict, over_records(raw["max_amplification"], lambda v: q_linear(v, 0.9), strict=True))
    assert int(strict.isnull().sum()) == 3


def test_reduce_several_dims_in_one_go(ds, raw):
    out = Q.reduce(Q.done(ds, "amplification"), "record,building,floor", "q50")
    assert out.dims == ("law", "gap_size")
    for l in range(NL):
        for g in range(NG):
            vals = [v for v in raw["amplification"][:, l, g].ravel() if not math.isnan(v)]
            assert out.values[l, g] == pytest.approx(q_linear(vals, 0.5), rel=1e-12)


@pytest.mark.parametrize("how", ["avg", "q", "q101", "p200", "x90", "q-5"])
def test_reduce_bad_how(ds, how):
    with pytest.raises(InputError) as err:
        Q.reduce(Q.done(ds, "max_amplification"), "record", how)
    assert err.value.key == "--reduce"


def test_reduce_unknown_dim_lists_dims(ds):
    with pytest.raises(InputError, match="no dimension floor; dimensions: record, law, gap_size") as err:
        Q.reduce(Q.done(ds, "max_amplification"), "floor", "max")
    assert err.value.key == "--reduce"


def test_reduce_needs_numbers(ds):
    with pytest.raises(InputError, match="not numeric"):
        Q.reduce(ds["error"], "record", "max")


# --------------------------------------------------------------------- select


def test_select_string_and_float_scalars(ds, raw):
    out = Q.select(Q.done(ds, "max_amplification"), {"law": "LVe", "gap_size": "0.03"})
    assert out.dims == ("record",)
    same(out, np.where(raw["status"][:, 1, 2] == 1, raw["max_amplification"][:, 1, 2], np.nan))
    # within 1e-9 relative is the same value; numbers as numbers work too
    near = Q.select(ds["max_amplification"], {"gap_size": "0.0300000000001", "law": "LVe"})
    same(near, raw["max_amplification"][:, 1, 2])
    same(Q.select(ds["max_amplification"], {"gap_size": 0.03, "law": "LVe"}), near)


def test_select_rejects_a_near_miss(ds):
    with pytest.raises(InputError, match=r"no value '0.0301'; values: 0.04, 0.01, 0.03, 0.02") as err:
        Q.select(ds["max_amplification"], {"gap_size": "0.0301"})
    assert err.value.key == "--sel gap_size"


def test_select_ranges_and_lists(ds, raw):
    da = ds["max_amplification"]
    rng = Q.select(da, {"gap_size": "0.015:0.03"})  # inclusive, in file order
    assert rng["gap_size"].values.tolist() == [0.03, 0.02]
    same(rng, raw["max_amplification"][:, :, [2, 3]])
    assert Q.select(da, {"gap_size": "0.03:"})["gap_size"].values.tolist() == [0.04, 0.03]
    assert Q.select(da, {"gap_size": ":0.01"})["gap_size"].values.tolist() == [0.01]
    both = Q.select(da, {"law": "LVe,Hd", "record": "RSN30_PKF"})
    assert both.dims == ("law", "gap_size") and both["law"].values.tolist() == ["Hd", "LVe"]
    same(both, raw["max_amplification"][2])


def test_select_trailing_dims_and_coordinates_along_a_dim(ds, raw):
    amp = Q.select(ds["amplification"], {"building": "B", "floor": "2"})
    same(amp, raw["amplification"][:, :, :, 1, 1])
    by_file = Q.select(ds["max_amplification"], {"record_file": "records/RSN15_TAFT.AT2"})
    same(by_file, raw["max_amplification"][1])


def test_select_unknown_dim(ds):
    with pytest.raises(InputError, match="no dimension 'building'; dimensions: record, law, gap_size") as err:
        Q.select(ds["max_amplification"], {"building": "A"})
    assert err.value.key == "--sel building"


def test_select_unknown_value_lists_values(ds):
    with pytest.raises(InputError, match="no value 'Hertz'; values: Hd, LVe") as err:
        Q.select(ds["max_amplification"], {"law": "Hertz"})
    assert err.value.key == "--sel law"


@pytest.mark.parametrize("sel, msg", [
    ({"law": "Hd:LVe"}, "needs a numeric coordinate"),
    ({"gap_size": "wide"}, "not a number"),
    ({"gap_size": "0.5:0.6"}, "no value '0.5:0.6'"),
    ({"floor": "1.5"}, "not an integer"),
    ({"floor": "inf"}, "not an integer"),
    ({"gap_size": "nan"}, "nan is not"),
])
def test_select_malformed(ds, sel, msg):
    with pytest.raises(InputError, match=msg) as err:
        Q.select(ds["amplification"], sel)
    assert err.value.key == f"--sel {next(iter(sel))}"


# ---------------------------------------------------------------------- where


@pytest.mark.parametrize("cond, test", [
    ("<1.2", lambda v: v < 1.2), ("  >= 1.3 ", lambda v: v >= 1.3), (">1.0e0", lambda v: v > 1.0),
    ("<=1.12", lambda v: v <= 1.12),
])
def test_where_on_values(ds, raw, cond, test):
    out = Q.where(Q.done(ds, "max_amplification"), cond)
    ref = np.array([v if (not math.isnan(v) and test(v)) else np.nan
                    for v in raw["max_amplification"].ravel()]).reshape(raw["status"].shape)
    assert 0 < np.isfinite(ref).sum() < ref.size
    same(out, ref)
    assert out.attrs["units"] == "1"


def test_where_boundary_is_exact(ds, raw):
    v = float(raw["max_amplification"][0, 0, 1])  # a stored value, typed back exactly
    da = Q.done(ds, "max_amplification")
    for cond, kept in [(f"<={v!r}", True), (f"<{v!r}", False), (f">={v!r}", True), (f">{v!r}", False),
                       (f"=={v!r}", True), (f"!={v!r}", False)]:
        assert bool(Q.where(da, cond).notnull().values[0, 0, 1]) is kept, cond


def test_where_equality_on_counts(ds, raw):
    out = Q.where(Q.done(ds, "total_impacts"), "==0")
    zero = (raw["total_impacts"] == 0) & (raw["status"] == 1)
    assert np.array_equal(out.notnull().values, zero)
    nonzero = Q.where(Q.done(ds, "total_impacts"), "!=0")
    assert np.array_equal(nonzero.notnull().values, (raw["total_impacts"] > 0) & (raw["status"] == 1))


@pytest.mark.parametrize("cond", ["<<1", "1.2", "< abc", "=>1", "< 1 2", "", "< nan"])
def test_where_malformed(ds, cond):
    with pytest.raises(InputError, match="cannot read condition") as err:
        Q.where(Q.done(ds, "max_amplification"), cond)
    assert err.value.key == "--where"


# ---------------------------------------------------------- smallest_passing


@pytest.mark.parametrize("monotone", [False, True])
@pytest.mark.parametrize("skipna", [False, True])
def test_smallest_passing_against_loops(ds, raw, monotone, skipna):
    out = Q.smallest_passing(ds, "gap_size", 1.2, monotone=monotone, skipna=skipna)
    assert out.dims == ("law",) and out["law"].values.tolist() == LAWS
    assert out.name == "smallest_gap_size" and out.attrs["units"] == "m"
    q90 = over_records(raw["max_amplification"], lambda v: q_linear(v, 0.9), strict=not skipna)
    passing = np.nan_to_num(q90, nan=np.inf) < 1.2
    ref = smallest_ref(passing, GAPS, monotone)
    same(out, ref)
    # the values the data were built to give (see BASE, FAILED, PENDING)
    expected = {(False, False): [0.02, 0.04], (True, False): [np.nan, 0.04],
                (False, True): [0.02, 0.03], (True, True): [0.04, 0.03]}[monotone, skipna]
    same(out, expected)


def test_smallest_passing_sorts_by_value_not_position(ds):
    # positions 0..3 hold 0.04, 0.01, 0.03, 0.02: the first passing *position*
    # for Hd is 0.04, the smallest passing *value* is 0.02
    out = Q.smallest_passing(ds, "gap_size", 1.2, monotone=False)
    assert float(out.sel(law="Hd")) == 0.02


def test_smallest_passing_above(ds, raw):
    out = Q.smallest_passing(ds, "gap_size", 1.32, below=False, q=0.5, skipna=True, monotone=False)
    med = over_records(raw["max_amplification"], lambda v: q_linear(v, 0.5))
    ref = smallest_ref(med > 1.32, GAPS)
    same(out, ref)
    same(out, [0.01, 0.01])
    none = Q.smallest_passing(ds, "gap_size", 5.0, below=False, monotone=False)
    assert none.isnull().all()


def test_smallest_passing_per_record_and_other_var(ds, raw):
    out = Q.smallest_passing(ds, "gap_size", 1e6, var="peak_pounding_force", over=None, monotone=False)
    assert out.dims == ("record", "law")
    worst = np.full(raw["status"].shape, np.nan)
    for idx in np.ndindex(worst.shape):
        if raw["status"][idx] == 1:
            worst[idx] = max(raw["peak_pounding_force"][idx])
    for r in range(NR):
        same(out.values[r], smallest_ref(np.nan_to_num(worst[r], nan=np.inf) < 1e6, GAPS))
    assert out.notnull().any()


def test_axis_limit_largest_and_monotone():
    ok = xr.DataArray([[True, False, True, True], [True, True, False, True]], dims=("k", "x"),
                      coords={"x": [3.0, 1.0, 2.0, 4.0]})
    # sorted by x: row 0 passes at 1? no: x=1 is False, x=2,3,4 True; row 1: x=1,3,4 True, x=2 False
    same(Q.axis_limit(ok, "x", monotone=False), [2.0, 1.0])
    same(Q.axis_limit(ok, "x", monotone=True), [2.0, 3.0])
    same(Q.axis_limit(ok, "x", largest=True, monotone=False), [4.0, 4.0])
    same(Q.axis_limit(ok, "x", largest=True, monotone=True), [np.nan, 1.0])
    with pytest.raises(InputError, match="no coordinate 'y'") as err:
        Q.axis_limit(ok, "y", monotone=False)
    assert err.value.key == "--smallest"


# --------------------------------------------------- zipped axis (member coords)


def test_zipped_axis_member_coordinate(tmp_path):
    sizes = [0.03, 0.01, 0.02]  # the member values along the zipped axis
    amp = np.array([[1.1, 1.5, 1.1], [1.3, 1.6, 1.0]])  # (record, spacing)
    ds = xr.Dataset(
        {"status": (("record", "spacing"), np.ones((2, 3), np.int8)),
         "max_amplification": (("record", "spacing"), amp, {"units": "1"})},
        coords={"record": ["r1", "r2"], "spacing": np.arange(3), "gap.0.size": ("spacing", sizes)},
        attrs={"schema": SCHEMA, "schema_version": SCHEMA_VERSION, "run_dims": '["record", "spacing"]'})
    path = tmp_path / "zip.h5"
    ds.to_netcdf(path, engine="h5netcdf")
    with Q.open_study(path) as st:
        out = Q.smallest_passing(st, "gap.0.size", 1.2, q=1.0, monotone=False)
        # max over records per spacing: 1.3, 1.6, 1.1 -> passes at 0.02 only
        assert float(out) == 0.02 and out.name == "smallest_gap.0.size"
        # strictly below / above: a quantile equal to the threshold does not pass
        assert Q.smallest_passing(st, "gap.0.size", 1.1, q=1.0, monotone=False).isnull()
        assert float(Q.smallest_passing(st, "gap.0.size", 1.1 + 1e-12, q=1.0, monotone=False)) == 0.02
        assert float(Q.smallest_passing(st, "gap.0.size", 1.3, q=1.0, below=False, monotone=False)) == 0.01
        assert float(Q.smallest_passing(st, "gap.0.size", 1.3 - 1e-12, q=1.0, below=False, monotone=False)) == 0.01
        assert Q.smallest_passing(st, "gap.0.size", 1.6, q=1.0, below=False, monotone=False).isnull()
        sel = Q.select(st["max_amplification"], {"gap.0.size": "0.01"})
        assert sel.values.tolist() == [1.5, 1.6]


# ------------------------------------------------------------------ tabulating


def test_to_csv_round_trip(ds, raw):
    da = Q.select(Q.done(ds, "max_amplification"), {"law": "Hd"})
    rows = list(csv.reader(io.StringIO(Q.to_csv(da))))
    assert rows[0] == ["record", "gap_size [m]", "max_amplification [1]"]
    assert len(rows) == 1 + NR * NG
    for r in range(NR):
        for g in range(NG):
            rec, gap, val = rows[1 + r * NG + g]
            assert rec == RECORDS[r] and float(gap) == GAPS[g]
            ref = raw["max_amplification"][r, 0, g]
            if raw["status"][r, 0, g] == 1:
                assert float(val) == ref  # full precision
            else:
                assert val == ""
    dropped = list(csv.reader(io.StringIO(Q.to_csv(da, dropna=True))))
    assert len(dropped) == 1 + int((raw["status"][:, 0, :] == 1).sum()) == 1 + 10


def test_to_table_layout(ds, raw):
    da = Q.reduce(Q.done(ds, "max_amplification"), "record", "max")
    lines = Q.to_table(da).splitlines()
    assert lines[0].split() == ["law", "gap_size", "[m]", "max_amplification", "[1]"]
    assert len(lines) == 1 + NL * NG
    ref = over_records(raw["max_amplification"], max)
    for k, line in enumerate(lines[1:]):
        law, gap, val = line.split()
        assert law == LAWS[k // NG] and float(gap) == GAPS[k % NG]
        assert float(val) == pytest.approx(ref[k // NG, k % NG], rel=1e-5)
    assert len({len(line) for line in lines[1:]}) == 1  # aligned columns
    # integers print as integers, missing values as the given marker
    counts = Q.to_table(Q.reduce(Q.done(ds, "max_amplification"), "record", "count")).split()
    assert "3" in counts and "3.0" not in counts
    gone = Q.to_table(Q.smallest_passing(ds, "gap_size", 0.5, monotone=False), missing="none").splitlines()
    assert [line.split() for line in gone[1:]] == [["Hd", "none"], ["LVe", "none"]]


def test_to_json_records_and_units(ds, raw):
    da = Q.done(ds, "peak_pounding_force")
    doc = json.loads(Q.to_json(Q.select(da, {"record": "RSN6_ELC180", "law": "LVe"})))
    assert doc["variable"] == "peak_pounding_force"
    assert doc["units"] == {"gap_size": "m", "peak_pounding_force": "N"}
    assert doc["dims"] == ["gap_size", "gap"]
    assert len(doc["records"]) == NG * NE
    for k, rec in enumerate(doc["records"]):
        g, e = divmod(k, NE)
        assert rec["gap_size"] == GAPS[g] and rec["gap"] == e
        ref = raw["peak_pounding_force"][0, 1, g, e]
        assert rec["peak_pounding_force"] == (None if math.isnan(ref) else ref)
    assert sum(rec["peak_pounding_force"] is None for rec in doc["records"]) == NE  # the failed run
    empty = json.loads(Q.to_json(Q.where(Q.done(ds, "max_amplification"), "<0"), dropna=True))
    assert empty["records"] == [] and empty["dims"] == ["record", "law", "gap_size"]


def test_scalar_table(ds, raw):
    da = Q.reduce(Q.done(ds, "max_amplification"), "record,law,gap_size", "max")
    lines = Q.to_table(da).splitlines()
    assert lines[0] == "max_amplification [1]"
    assert float(lines[1]) == pytest.approx(np.nanmax(raw["max_amplification"]), rel=1e-5)


def test_overview(ds):
    text = Q.overview(ds)
    assert text.splitlines()[0] == "synthetic gap study"
    assert "runs: 24 = 21 done, 2 failed, 1 pending" in text
    assert "gap_size [m]" in text and "0.04, 0.01, 0.03, 0.02" in text
    assert "max_amplification [1]" in text and "peak_pounding_force [N]" in text


# ------------------------------------------------------------------ command line


def cli(argv, capsys):
    ap = argparse.ArgumentParser(prog="seispound")
    Q.add_query_parser(ap.add_subparsers(dest="command"))
    args = ap.parse_args(["query", *map(str, argv)])
    code = Q.cmd_query(args)
    out = capsys.readouterr()
    return code, out.out, out.err


def test_cli_overview(store, capsys):
    code, out, err = cli([store], capsys)
    assert code == 0 and err == ""
    assert "runs: 24 = 21 done, 2 failed, 1 pending" in out


def test_cli_smallest_gap_per_law(store, raw, capsys):
    code, out, err = cli([store, "--reduce", "record=q90", "--where", "<1.2", "--smallest", "gap_size",
                          "--strict", "--format", "csv", "--first-passing"], capsys)
    assert code == 0
    # Hd passes at 0.02 and fails again above it: said, with the safe answer
    assert "note: law=Hd: the condition holds at gap_size = 0.02 m but fails again above it" in err
    rows = list(csv.reader(io.StringIO(out)))
    assert rows[0] == ["law", "smallest_gap_size [m]"]
    q90 = over_records(raw["max_amplification"], lambda v: q_linear(v, 0.9), strict=True)
    ref = smallest_ref(np.nan_to_num(q90, nan=np.inf) < 1.2, GAPS)
    assert [r[0] for r in rows[1:]] == LAWS
    same([float(r[1]) for r in rows[1:]], ref)
    same([float(r[1]) for r in rows[1:]], [0.02, 0.04])


def test_cli_smallest_monotone_lenient_and_note(store, raw, capsys):
    code, out, err = cli([store, "--reduce", "record=p90", "--where", "<1.2", "--smallest", "gap_size",
                          "--monotone"], capsys)
    assert code == 0
    assert "3 of 24 selected runs are not done" in err
    lines = out.splitlines()
    assert lines[0].split() == ["law", "smallest_gap_size", "[m]"]
    assert [line.split() for line in lines[1:]] == [["Hd", "0.04"], ["LVe", "0.03"]]


def test_cli_smallest_is_the_safe_gap_by_default(store, raw, capsys):
    """Without a flag, --smallest answers the gap from which every larger gap studied passes, and says where
    the first passing gap differs (an engineer's "safe gap", not the first that happens to pass)."""
    code, out, err = cli([store, "--reduce", "record=q90", "--where", "<1.2", "--smallest", "gap_size", "--strict"],
                         capsys)
    assert code == 0
    q90 = over_records(raw["max_amplification"], lambda v: q_linear(v, 0.9), strict=True)
    passing = np.nan_to_num(q90, nan=np.inf) < 1.2
    safe, first = smallest_ref(passing, GAPS, monotone=True), smallest_ref(passing, GAPS)
    got = [float(line.split()[-1]) if line.split()[-1] != "none" else np.nan for line in out.splitlines()[1:]]
    same(got, safe)
    differs = [law for law, a, b in zip(LAWS, first, safe) if not (a == b or (np.isnan(a) and np.isnan(b)))]
    assert differs  # the fixture has a law whose first passing gap fails again above it
    for law in differs:
        assert f"note: law={law}: the condition holds at gap_size" in err and "fails again above it" in err


def test_cli_largest_and_none(store, capsys):
    _, out, _ = cli([store, "--reduce", "record=max", "--where", "<1.2", "--largest", "gap_size",
                     "--sel", "law=Hd", "--first-passing"], capsys)
    # Hd: max over records passes at 0.02 and 0.04 (pending run skipped at 0.04)
    assert out.splitlines()[1].strip() == "0.04"
    _, out, _ = cli([store, "--reduce", "record=max", "--where", "<0.5", "--smallest", "gap_size"], capsys)
    assert [line.split()[-1] for line in out.splitlines()[1:]] == ["none", "none"]


def test_cli_steps_in_order(store, raw, capsys):
    """--sel, then --reduce twice, then two --where conditions."""
    code, out, _ = cli([store, "--var", "amplification", "--sel", "gap_size=0.02:0.04", "--sel", "building=A",
                        "--reduce", "floor=max", "--reduce", "record=mean", "--where", ">1.1",
                        "--where", "<1.32", "--format", "json"], capsys)
    assert code == 0
    doc = json.loads(out)
    assert doc["dims"] == ["law", "gap_size"]
    got = {(r["law"], r["gap_size"]): r["amplification"] for r in doc["records"]}
    n_kept = 0
    for l in range(NL):
        for g in range(NG):
            if GAPS[g] < 0.02:
                assert (LAWS[l], GAPS[g]) not in got
                continue
            per_rec = []
            for r in range(NR):
                vals = [v for v in raw["amplification"][r, l, g, 0] if not math.isnan(v)]
                if raw["status"][r, l, g] == 1:
                    per_rec.append(max(vals))
            m = sum(per_rec) / len(per_rec)
            if 1.1 < m < 1.32:
                n_kept += 1
                assert got[LAWS[l], GAPS[g]] == pytest.approx(m, rel=1e-12)
            else:
                assert got[LAWS[l], GAPS[g]] is None
    assert 0 < n_kept < 6


def test_cli_failed_runs_with_errors(store, raw, capsys):
    code, out, _ = cli([store, "--var", "error", "--status", "failed", "--dropna", "--format", "csv"], capsys)
    assert code == 0
    rows = list(csv.reader(io.StringIO(out)))
    assert rows[0] == ["record", "law", "gap_size [m]", "error"]
    got = [(r[0], r[1], float(r[2])) for r in rows[1:]]
    ref = [(RECORDS[r], LAWS[l], GAPS[g]) for r, l, g in sorted(FAILED)]
    assert got == ref
    assert all("IntegrationError" in r[3] for r in rows[1:])


def test_cli_status_default_all_for_status_var(store, raw, capsys):
    _, out, _ = cli([store, "--var", "status", "--reduce", "record,law,gap_size=count"], capsys)
    assert out.splitlines()[1].strip() == "24"
    _, out, _ = cli([store, "--var", "status", "--status", "pending", "--reduce", "record,law,gap_size=count"],
                    capsys)
    assert out.splitlines()[1].strip() == "1"


def test_cli_output_file_atomic_and_format_from_suffix(store, tmp_path, raw, capsys):
    out_path = tmp_path / "out" / "q.json"
    out_path.parent.mkdir()
    code, out, _ = cli([store, "--reduce", "record=count", "-o", out_path], capsys)
    assert code == 0 and out == ""
    assert sorted(p.name for p in out_path.parent.iterdir()) == ["q.json"]
    doc = json.loads(out_path.read_text())
    counts = {(r["law"], r["gap_size"]): r["max_amplification"] for r in doc["records"]}
    for l in range(NL):
        for g in range(NG):
            assert counts[LAWS[l], GAPS[g]] == int((raw["status"][:, l, g] == 1).sum())


def test_cli_output_folder_missing(store, tmp_path, capsys):
    with pytest.raises(InputError, match="output folder does not exist") as err:
        cli([store, "--var", "max_amplification", "-o", tmp_path / "nope" / "q.csv"], capsys)
    assert err.value.key == "-o"
    assert not (tmp_path / "nope").exists()


@pytest.mark.parametrize("argv, key, msg", [
    (["--var", "amp"], "--var", "no variable 'amp'"),
    (["--sel", "bogus=1"], "--sel bogus", "no dimension 'bogus'"),
    (["--sel", "law=Hertz"], "--sel law", "values: Hd, LVe"),
    (["--sel", "gap_size=0.025"], "--sel gap_size", "values: 0.04, 0.01, 0.03, 0.02"),
    (["--sel", "law"], "--sel", "DIM=VALUE"),
    (["--sel", "law=Hd", "--sel", "law=LVe"], "--sel law", "given twice"),
    (["--reduce", "record=avg"], "--reduce", "unknown reduction"),
    (["--reduce", "floor=max"], "--reduce", "no dimension floor"),
    (["--where", "below 1.2"], "--where", "cannot read condition"),
    (["--status", "finished"], "--status", "unknown status"),
    (["--where", "<1", "--smallest", "law"], "--smallest", "no order"),
    (["--where", "<1", "--smallest", "spacing"], "--smallest", "no coordinate 'spacing'"),
    (["--smallest", "gap_size"], "--smallest", "needs --where"),
    (["--monotone", "--var", "max_amplification"], "--monotone", "needs --smallest"),
])
def test_cli_bad_input_names_file_and_key(store, capsys, argv, key, msg):
    with pytest.raises(InputError, match=msg) as err:
        cli([store, *argv], capsys)
    assert err.value.key == key
    assert str(err.value).startswith(f"{store}: {key}: ")


def test_cli_not_a_study(tmp_path, capsys):
    path = tmp_path / "model.toml"
    path.write_text('title = "x"\n')
    with pytest.raises(InputError, match="not an HDF5 file") as err:
        cli([path], capsys)
    assert str(err.value).startswith(f"{path}: ")


# ------------------------------------------- docs/study_queries.md: CLI == Python

DOC_EXAMPLES = [
    (["--var", "max_amplification", "--reduce", "record=q90", "--where", "<1.2", "--smallest", "gap_size",
      "--strict"],
     lambda ds: Q.to_table(Q.smallest_passing(ds, "gap_size", 1.2, var="max_amplification", over="record",
                                              q=0.9), missing="none")),
    (["--var", "max_pounding_force", "--sel", "law=Hd", "--reduce", "record=mean", "--format", "csv"],
     lambda ds: Q.to_csv(Q.reduce(Q.select(Q.done(ds, "max_pounding_force"), {"law": "Hd"}), "record", "mean"))),
    (["--var", "max_amplification", "--sel", "law=LVe", "--sel", "gap_size=:0.02", "--where", ">1.3",
      "--dropna"],
     lambda ds: Q.to_table(Q.where(Q.select(Q.done(ds, "max_amplification"),
                                            {"law": "LVe", "gap_size": ":0.02"}), ">1.3"), dropna=True)),
    (["--var", "error", "--status", "failed", "--dropna"],
     lambda ds: Q.to_table(Q.mask_status(ds["error"], ds["status"], "failed"), dropna=True)),
]


@pytest.mark.parametrize("argv, python", DOC_EXAMPLES)
def test_doc_examples_cli_equals_python(store, ds, capsys, argv, python):
    _, out, _ = cli([store, *argv], capsys)
    assert out == python(ds)
    assert len(out.splitlines()) >= 3  # a header and at least two rows: something to compare
