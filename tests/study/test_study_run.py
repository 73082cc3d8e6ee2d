"""`seispound study`: the store against single runs, twins shared, failures recorded, histories kept."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest
import xarray as xr

import seispound as sp
from seispound.study import load_study, run_study
from seispound.study import execute as ex
from seispound.study import worker
from seispound.study.execute import plan
from seispound.study.journal import journal_path

from .conftest import cli, model_copy, write_study


def single_run(folder, record, law, stiffness, gap):
    """The same run as one study point, built by editing the model text (not through the study code)."""
    from seispound.motion.catalogue import bundled_path

    text = (folder / "two.toml").read_text(encoding="utf-8")
    text = re.sub(r'(?m)^file = "[^"]+"', f'file = "{bundled_path(record).as_posix()}"', text)
    text = re.sub(r'(?m)^law = "Hd"', f'law = "{law}"', text)
    text = re.sub(r"(?m)^stiffness = [0-9.eE+-]+", f"stiffness = {stiffness!r}", text)
    text = re.sub(r"(?m)^size = [0-9.eE+-]+", f"size = {gap!r}", text)
    path = folder / f"single_{record}_{law}_{gap}.toml"
    path.write_text(text, encoding="utf-8")
    return sp.simulate(sp.load_model(path))


def test_cli_study_store_matches_single_runs(reference_store):
    study_file, out = reference_store
    assert not journal_path(out).exists()  # complete: the journal is gone
    ds = xr.open_dataset(out, engine="h5netcdf").load()
    assert ds.attrs["schema"] == "seispound-study"
    assert json.loads(ds.attrs["run_dims"]) == ["record", "law", "gap_size"]
    assert dict(ds.status.sizes) == {"record": 2, "law": 2, "gap_size": 3}
    assert (ds.status == 1).all() and (ds.error == "").all()
    assert ds.attrs["runs_done"] == 12 and ds.attrs["runs_failed"] == 0
    assert ds.law.values.tolist() == ["Hd", "LVe"]
    assert ds["contact.stiffness"].values.tolist() == [2.75e9, 1.6e8]
    assert ds.gap_size.values.tolist() == [0.005, 0.01, 0.02] and ds.gap_size.attrs["units"] == "m"
    assert "two.toml" in ds.attrs["model_file"] and ds.attrs["study_text"] == study_file.read_text()
    # three points, checked against simulate() on a hand-edited model file
    for rec, law, k, gap in [("elcentro_180", "Hd", 2.75e9, 0.005), ("elcentro_270", "LVe", 1.6e8, 0.01),
                             ("elcentro_180", "LVe", 1.6e8, 0.02)]:
        one = single_run(study_file.parent, rec, law, k, gap)
        pt = ds.sel(record=rec, law=law, gap_size=gap)
        for var in ("amplification", "peak_displacement", "peak_displacement_no_pounding", "peak_drift",
                    *(f"{p}{q}{s}" for q in ("acceleration", "drift_ratio", "storey_shear")
                      for p, s in (("peak_", ""), ("peak_", "_no_pounding"), ("", "_amplification")))):
            np.testing.assert_allclose(pt[var].values, one[var].values, rtol=1e-12, equal_nan=True, err_msg=var)
        np.testing.assert_allclose(pt.peak_pounding_force.values, one.peak_pounding_force.values, rtol=1e-12)
        assert pt.impact_count.values.tolist() == one.impact_count.values.tolist()
        assert int(pt.total_impacts) == int(one.impact_count.sum()) > 0
        assert float(pt.max_amplification) == pytest.approx(float(one.amplification.max()), rel=1e-12)
        assert float(pt.max_pounding_force) == pytest.approx(float(one.peak_pounding_force.max()), rel=1e-12)
        for q in ("acceleration", "drift_ratio", "storey_shear"):
            assert float(pt[f"max_{q}_amplification"]) == pytest.approx(float(one[f"{q}_amplification"].max()),
                                                                         rel=1e-12)
        assert float(pt.max_peak_acceleration) == pytest.approx(float(one.peak_acceleration.max()), rel=1e-12)
    # closing the gap changes the answer: the store is not one run repeated
    assert ds.total_impacts.sel(gap_size=0.005).sum() > ds.total_impacts.sel(gap_size=0.02).sum()


def test_twin_runs_once_per_record(tmp_path, monkeypatch):
    study = load_study(write_study(tmp_path))
    calls = []
    orig = worker.twin_task

    def counting(s, i):
        calls.append(i)
        return orig(s, i)

    monkeypatch.setattr(ex, "twin_task", counting)
    res = run_study(study, tmp_path / "s.h5", scheduler="serial", progress=False)
    assert res["done"] == 12
    assert len(calls) == 2  # one per record, reused by the 6 runs (2 laws x 3 gaps) of each
    assert sorted(study.run_position(i)[0] for i in calls) == [0, 1]


def test_plan_covers_every_run_once_and_groups_by_twin(tmp_path):
    study = load_study(write_study(tmp_path, gaps=(0.005, 0.01, 0.02, 0.03)))
    todo = [i for i in range(study.n_runs) if i % 5]  # some already stored
    groups = plan(study, todo, n_workers=2, chunk=3)
    seen = [i for _, chunks in groups for c in chunks for i in c]
    assert sorted(seen) == todo
    for first, chunks in groups:
        key = study.twin_key(first)
        assert all(study.twin_key(i) == key for c in chunks for i in c)
        assert all(1 <= len(c) <= 3 for c in chunks)


def test_failed_runs_are_recorded_and_the_study_goes_on(tmp_path):
    folder = tmp_path / "f"
    folder.mkdir()
    model_copy(folder, 5.0)
    (folder / "broken.AT2").write_text("this is not a record\n1 2 3\n")
    from seispound.motion.catalogue import bundled_path

    good = bundled_path("elcentro_180")
    (folder / "study.toml").write_text(f"""
model = "two.toml"
[records]
files = ["{good.as_posix()}", "broken.AT2"]
[[axis]]
name = "gap_size"
path = "gap.1.size"
values = [0.01, 0.02]
""")
    out = folder / "s.h5"
    res = cli(["study", folder / "study.toml", "-o", out, "--scheduler", "serial"])
    assert res.returncode == 0, res.stderr
    assert "2 done, 2 failed" in res.stdout
    ds = xr.open_dataset(out, engine="h5netcdf").load()
    assert ds.status.sel(record="broken").values.tolist() == [0, 0]
    assert ds.status.sel(record=good.stem).values.tolist() == [1, 1]
    err = str(ds.error.sel(record="broken", gap_size=0.01).values)
    assert err.startswith("no-pounding twin failed:") and "broken.AT2" in err
    assert np.isnan(ds.max_amplification.sel(record="broken")).all()
    assert (ds.total_impacts.sel(record="broken") == -1).all()
    assert np.isfinite(ds.max_amplification.sel(record=good.stem)).all()


def test_histories_are_stored_decimated_and_equal_the_single_run(tmp_path):
    extra = '\n[output]\nhistories = ["pounding_force", "displacement"]\ndecimate = 4\n'
    study_file = write_study(tmp_path, duration=5.0, records=("elcentro_180",), gaps=(0.005, 0.02), extra=extra)
    out = tmp_path / "h.h5"
    res = cli(["study", study_file, "-o", out, "--scheduler", "serial", "-q"])
    assert res.returncode == 0, res.stderr
    ds = xr.open_dataset(out, engine="h5netcdf")
    one = single_run(tmp_path, "elcentro_180", "LVe", 1.6e8, 0.005)
    pt = ds.sel(record="elcentro_180", law="LVe", gap_size=0.005)
    np.testing.assert_allclose(ds.time.values, one.time.values[::4])
    np.testing.assert_allclose(pt.pounding_force.values, one.pounding_force.values[::4], rtol=1e-12)
    np.testing.assert_allclose(pt.displacement.values, one.displacement.values[::4], rtol=1e-12, equal_nan=True)
    assert float(np.abs(pt.pounding_force).max()) > 0
    # chunked one run per chunk and compressed
    import h5py

    with h5py.File(out, "r") as f:
        v = f["displacement"]
        assert v.chunks == (1, 1, 1, ds.sizes["time"], ds.sizes["building"], ds.sizes["floor"])
        assert v.compression == "gzip"


def test_rerun_of_a_complete_study_runs_nothing(reference_store, tmp_path):
    study_file, out = reference_store
    res = cli(["study", study_file, "-o", out, "--scheduler", "serial"])
    assert res.returncode == 0, res.stderr
    assert "all 12 runs were already stored" in res.stdout


def test_query_answers_equal_values_from_single_runs(reference_store):
    """`seispound query` on the study store against the same numbers from individual simulate() runs."""
    study_file, out = reference_store
    folder = study_file.parent
    laws = {"Hd": 2.75e9, "LVe": 1.6e8}
    gaps = [0.005, 0.01, 0.02]
    singles = {(rec, law, gap): single_run(folder, rec, law, k, gap)
               for rec in ("elcentro_180", "elcentro_270") for law, k in laws.items() for gap in gaps}
    # worst amplification over floors and records, per law and gap (JSON)
    res = cli(["query", out, "--reduce", "record=max", "--format", "json"])
    assert res.returncode == 0, res.stderr
    rows = {(r["law"], r["gap_size"]): r["max_amplification"] for r in json.loads(res.stdout)["records"]}
    assert len(rows) == 6
    for law in laws:
        for gap in gaps:
            want = max(float(singles[(rec, law, gap)].amplification.max()) for rec in ("elcentro_180", "elcentro_270"))
            assert rows[(law, gap)] == pytest.approx(want, rel=1e-12)
    # mean over records of the largest pounding force, Hd (CSV)
    res = cli(["query", out, "--var", "max_pounding_force", "--sel", "law=Hd", "--reduce", "record=mean",
               "--format", "csv"])
    assert res.returncode == 0, res.stderr
    lines = res.stdout.strip().splitlines()
    assert lines[0] == "gap_size [m],max_pounding_force [N]"
    got = {float(a): float(b) for a, b in (ln.split(",") for ln in lines[1:])}
    for gap in gaps:
        want = np.mean([float(singles[(rec, "Hd", gap)].peak_pounding_force.max())
                        for rec in ("elcentro_180", "elcentro_270")])
        assert got[gap] == pytest.approx(want, rel=1e-12)
    # the smallest gap per law whose largest amplification over records is below a threshold
    thr = 1.0 + 0.5 * (rows[("Hd", 0.01)] - 1.0)  # between the values, so that the answer is not trivial
    res = cli(["query", out, "--reduce", "record=max", "--where", f"<{thr!r}", "--smallest", "gap_size",
               "--format", "json"])
    assert res.returncode == 0, res.stderr
    got = {r["law"]: r["smallest_gap_size"] for r in json.loads(res.stdout)["records"]}
    for law in laws:
        passing = [g for g in gaps if max(float(singles[(rec, law, g)].amplification.max())
                                          for rec in ("elcentro_180", "elcentro_270")) < thr]
        assert got[law] == (min(passing) if passing else None)


def test_without_dask_the_default_runs_serially_and_says_so(tmp_path, monkeypatch, capsys):
    import importlib.util

    from seispound import cli as cli_mod

    study = write_study(tmp_path, duration=3.0, records=("elcentro_180",), gaps=(0.01,))
    real = importlib.util.find_spec
    monkeypatch.setattr(importlib.util, "find_spec", lambda name, *a: None if name == "dask" else real(name, *a))
    called = {}
    orig = ex.run_study

    def spy(*a, **kw):
        called["scheduler"] = kw["scheduler"]
        return orig(*a, **kw)

    monkeypatch.setattr("seispound.study.run_study", spy)
    assert cli_mod.main(["study", str(study), "-o", str(tmp_path / "s.h5")]) == 0
    err = capsys.readouterr().err
    assert called["scheduler"] == "serial"
    assert "dask is not installed" in err and "seispound[dask]" in err
    assert int(xr.open_dataset(tmp_path / "s.h5", engine="h5netcdf").status.sum()) == 2
