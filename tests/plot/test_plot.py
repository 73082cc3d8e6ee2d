"""Figures: study stores (synthetic, following seispound.study.schema) and one real run."""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

matplotlib = pytest.importorskip("matplotlib")
import matplotlib.image  # noqa: E402

import seispound as sp  # noqa: E402
from seispound import plot  # noqa: E402
from seispound.errors import InputError  # noqa: E402
from seispound.study import schema  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
RECORDS = ["elcentro", "kobe", "northridge"]
LAWS = ["Hd", "LVe"]
GAPS = [0.0, 0.01, 0.02, 0.04]
FAILED = (1, 0, 2)  # kobe, Hd, gap 0.02 m: status 0
NB, NF, NGAP = 2, 8, 4  # A: 4 floors, B: 8 floors, gaps at floors 1-4


# --------------------------------------------------------------------------- fixtures

def make_study(garbage_in_failed=False) -> xr.Dataset:
    """A study store in memory, following seispound.study.schema (version 1)."""
    rng = np.random.default_rng(20240611)
    shape = (len(RECORDS), len(LAWS), len(GAPS))
    run = ("record", "law", "gap_size")
    nan_floors = np.zeros((NB, NF), bool)
    nan_floors[0, 4:] = True  # building A has 4 floors

    def per_floor(lo, hi):
        a = rng.uniform(lo, hi, shape + (NB, NF))
        a[..., nan_floors] = np.nan
        return a

    amp = per_floor(0.9, 1.8)
    peak0 = per_floor(0.02, 0.2)
    force = rng.uniform(1e5, 3e6, shape + (NGAP,))
    counts = rng.integers(0, 30, shape + (NGAP,))
    status = np.full(shape, schema.STATUS_DONE, np.int8)
    status[FAILED] = schema.STATUS_FAILED
    error = np.full(shape, "", dtype=object)
    error[FAILED] = "integration failed: too many rejected steps"
    # values of runs not done are NaN (schema); a corrupt store may hold garbage there
    fill = 50.0 if garbage_in_failed else np.nan
    amp[FAILED] = fill
    peak0[FAILED] = fill
    force[FAILED] = fill * 1e6
    counts[FAILED] = -1

    with warnings.catch_warnings():  # the failed run is all NaN: its max is NaN, as in the schema
        warnings.simplefilter("ignore", RuntimeWarning)
        max_amp = np.nanmax(amp, axis=(-2, -1))
    trail_bf, trail_g = ("building", "floor"), ("gap",)
    data = {
        "status": (run, status, {"flag_values": [1, 0, -1], "flag_meanings": "done failed not_run_yet"}),
        "error": (run, error, {}),
        "amplification": (run + trail_bf, amp, {"units": "1"}),
        "peak_displacement": (run + trail_bf, amp * peak0, {"units": "m"}),
        "peak_displacement_no_pounding": (run + trail_bf, peak0, {"units": "m"}),
        "peak_drift": (run + trail_bf, peak0 / 3, {"units": "m"}),
        "peak_pounding_force": (run + trail_g, force, {"units": "N"}),
        "impact_count": (run + trail_g, counts.astype(np.int64), {"units": "1"}),
        "max_amplification": (run, max_amp, {"units": "1"}),
        "max_pounding_force": (run, force.max(axis=-1), {"units": "N"}),
        "total_impacts": (run, np.where(status == 1, counts.sum(axis=-1), -1).astype(np.int64),
                          {"units": "1"}),
    }
    coords = {
        "record": ("record", np.array(RECORDS, dtype=object)),
        "record_file": ("record", np.array([f"records/{r}.AT2" for r in RECORDS], dtype=object)),
        "law": ("law", np.array(LAWS, dtype=object)),
        "gap_size": ("gap_size", np.array(GAPS), {"units": "m"}),
        "building": ("building", np.array(["A", "B"], dtype=object)),
        "floor": ("floor", np.arange(1, NF + 1)),
        "gap": ("gap", np.arange(NGAP)),
        "gap_left": ("gap", np.array(["A"] * NGAP, dtype=object)),
        "gap_right": ("gap", np.array(["B"] * NGAP, dtype=object)),
        "gap_left_floor": ("gap", np.arange(1, NGAP + 1)),
        "gap_right_floor": ("gap", np.arange(1, NGAP + 1)),
        "gap_height": ("gap", 3.0 * np.arange(1, NGAP + 1), {"units": "m"}),
    }
    ds = xr.Dataset(data, coords)
    ds.attrs.update(schema=schema.SCHEMA, schema_version=schema.SCHEMA_VERSION, title="synthetic study",
                    run_dims=json.dumps(list(run)), runs_total=status.size,
                    runs_done=int((status == 1).sum()), runs_failed=1)
    return ds


def raw(ds, var, law=None):
    """(record, gap) values of one law as a plain array, failed run masked with NaN by hand."""
    a = np.array(ds[var].transpose("law", "gap_size", "record").values, dtype=float)
    a[FAILED[1], FAILED[2], FAILED[0]] = np.nan
    return a if law is None else a[LAWS.index(law)]


@pytest.fixture
def study():
    return make_study()


@pytest.fixture
def study_file(tmp_path):
    path = tmp_path / "study.h5"
    make_study().to_netcdf(path, engine="h5netcdf")
    return path


@pytest.fixture(scope="module")
def run_file(tmp_path_factory):
    ds = sp.simulate(sp.load_model(REPO / "models" / "two_buildings.toml"))
    path = tmp_path_factory.mktemp("run") / "run.h5"
    sp.write_result(ds, path)
    return path


@pytest.fixture(scope="module")
def run_ds(run_file):
    return sp.open_result(run_file)


def line(ax, label):
    found = [ln for ln in ax.lines if ln.get_label() == label]
    assert len(found) == 1, [ln.get_label() for ln in ax.lines]
    return found[0]


def svg_text(path):
    return Path(path).read_text(encoding="utf-8")


def save_with_text(func, *args, **kwargs):
    """Call a saving function with SVG text kept as text (searchable)."""
    with matplotlib.rc_context({"svg.fonttype": "none"}):
        return func(*args, **kwargs)


# --------------------------------------------------------------------------- study: files

def test_study_amplification_writes_png_and_svg(study, tmp_path):
    png, svg = save_with_text(plot.study_amplification, study, "gap_size", by="law", out=tmp_path / "amp")
    assert (png, svg) == (tmp_path / "amp.png", tmp_path / "amp.svg")
    img = matplotlib.image.imread(png)
    w, h = plot.STUDY_FIGSIZE
    assert img.shape[:2] == (round(h * plot.DPI), round(w * plot.DPI))
    assert img.std() > 0.01  # not a blank image
    text = svg_text(svg)
    assert text.lstrip().startswith("<?xml") and "</svg>" in text
    assert "gap size [m]" in text
    assert "max amplification [-]" in text
    assert "no amplification" in text and "Hd" in text and "LVe" in text
    # atomic: only the two figures, no temporary left behind
    assert sorted(p.name for p in tmp_path.iterdir()) == ["amp.png", "amp.svg"]


def test_output_suffix_is_dropped_and_files_replaced(study, tmp_path):
    (tmp_path / "f.png").write_bytes(b"old")
    png, svg = plot.study_force(study, "gap_size", out=tmp_path / "f.svg")
    assert (png.name, svg.name) == ("f.png", "f.svg")
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["f.png", "f.svg"]


def test_study_force_svg_labels_with_units(study, tmp_path):
    _, svg = save_with_text(plot.study_force, study, "gap_size", by="law", out=tmp_path / "force")
    text = svg_text(svg)
    assert "gap size [m]" in text
    assert "peak pounding force [MN]" in text  # forces up to 3e6 N


# --------------------------------------------------------------------------- study: plotted data

def test_median_lines_equal_numpy_median_over_records(study):
    ax = plot.study_amplification_figure(study, "gap_size", by="law").axes[0]
    for law in LAWS:
        ln = line(ax, law)
        np.testing.assert_allclose(ln.get_xdata(), GAPS)
        expected = np.nanmedian(raw(study, "max_amplification", law), axis=1)
        np.testing.assert_allclose(ln.get_ydata(), expected, rtol=1e-12)
    # the failed cell is the median of the two remaining records, not of three
    hd = line(ax, "Hd").get_ydata()[FAILED[2]]
    ok = [float(study.max_amplification[r, 0, FAILED[2]]) for r in (0, 2)]
    assert hd == pytest.approx(np.mean(ok))


def test_each_record_drawn_and_band_spans_min_to_max(study):
    ax = plot.study_amplification_figure(study, "gap_size", by="law").axes[0]
    vals = raw(study, "max_amplification")
    for i, law in enumerate(LAWS):
        # record labels repeat per law: tell the laws apart by colour
        recs = [ln for ln in ax.lines if ln.get_label().startswith("_record=")
                and ln.get_color() == line(ax, law).get_color()]
        assert [ln.get_label() for ln in recs] == [f"_record={r}" for r in RECORDS]
        for r, ln in enumerate(recs):
            np.testing.assert_array_equal(ln.get_ydata(), vals[i, :, r])
    bands = ax.collections
    assert len(bands) == len(LAWS)
    for i, band in enumerate(bands):
        ys = band.get_paths()[0].vertices[:, 1]
        lo, hi = np.nanmin(vals[i], axis=1), np.nanmax(vals[i], axis=1)
        assert np.allclose(ys.min(), lo.min()) and np.allclose(ys.max(), hi.max())
        for v in np.concatenate([lo, hi]):
            assert np.isclose(ys, v).any()


def test_failed_run_left_out_even_with_a_value(tmp_path):
    bad = make_study(garbage_in_failed=True)  # status 0 but a finite value of 50
    fig = plot.study_amplification_figure(bad, "gap_size", by="law")
    ax = fig.axes[0]
    hd = line(ax, "Hd").get_ydata()
    assert np.all(hd < 2.0)
    kobe_hd = [ln for ln in ax.lines if ln.get_label() == "_record=kobe"
               and ln.get_color() == line(ax, "Hd").get_color()][0]
    assert np.isnan(kobe_hd.get_ydata()[FAILED[2]])
    assert ax.get_ylim()[1] < 5.0
    assert "1 of 24 runs not done, left out" in ax.get_title()


def test_reference_line_at_one_only_for_amplification(study):
    ax = plot.study_amplification_figure(study, "gap_size", by="law").axes[0]
    ref = [ln for ln in ax.lines if ln.get_linestyle() == "--"]
    assert len(ref) == 1 and np.all(np.asarray(ref[0].get_ydata()) == 1.0)
    ax = plot.study_force_figure(study, "gap_size", by="law").axes[0]
    assert not [ln for ln in ax.lines if ln.get_linestyle() == "--"]


def test_remaining_dims_reduced_with_max_and_said_in_title(study):
    ax = plot.study_amplification_figure(study, "gap_size").axes[0]
    ln = line(ax, "max amplification")
    expected = np.nanmedian(np.nanmax(raw(study, "max_amplification"), axis=0), axis=1)
    np.testing.assert_allclose(ln.get_ydata(), expected)
    assert "max over law" in ax.get_title()


def test_sel_fixes_a_dimension(study):
    ax = plot.study_amplification_figure(study, "gap_size", sel={"law": "LVe"}).axes[0]
    ln = line(ax, "max amplification")
    np.testing.assert_allclose(ln.get_ydata(), np.nanmedian(raw(study, "max_amplification", "LVe"), axis=1))
    assert "law=LVe" in ax.get_title() and "max over law" not in ax.get_title()


def test_per_floor_variable_with_sel_from_strings(study):
    ax = plot.study_amplification_figure(study, "gap_size", by="law", var="amplification",
                                         sel={"building": "B", "floor": "8"}).axes[0]
    a = study.amplification.sel(building="B", floor=8).transpose("law", "gap_size", "record").values.copy()
    a[FAILED[1], FAILED[2], FAILED[0]] = np.nan
    np.testing.assert_allclose(line(ax, "LVe").get_ydata(), np.nanmedian(a[1], axis=1))
    assert "building=B" in ax.get_title() and "floor=8" in ax.get_title()


def test_force_in_meganewton_or_kilonewton(study):
    ax = plot.study_force_figure(study, "gap_size", by="law").axes[0]
    assert ax.get_ylabel() == "peak pounding force [MN]"
    expected = np.nanmedian(raw(study, "max_pounding_force", "Hd"), axis=1) / 1e6
    np.testing.assert_allclose(line(ax, "Hd").get_ydata(), expected)
    small = study.copy()
    small["max_pounding_force"] = study.max_pounding_force / 100  # up to 30 kN
    ax = plot.study_force_figure(small, "gap_size", by="law").axes[0]
    assert ax.get_ylabel() == "peak pounding force [kN]"
    np.testing.assert_allclose(line(ax, "Hd").get_ydata(), expected * 1e6 / 100 / 1e3)


def test_axis_values_drawn_in_increasing_order(study):
    shuffled = study.isel(gap_size=[3, 0, 2, 1])
    ax = plot.study_amplification_figure(shuffled, "gap_size", by="law").axes[0]
    np.testing.assert_allclose(line(ax, "Hd").get_xdata(), GAPS)
    np.testing.assert_allclose(line(ax, "Hd").get_ydata(),
                               np.nanmedian(raw(study, "max_amplification", "Hd"), axis=1))


def test_zipped_axis_shows_its_members(study):
    # a zipped axis: index 0..n-1 along the dimension, members as coordinates on it
    zipped = study.rename(gap_size="gaps").assign_coords(
        gaps=np.arange(len(GAPS)),
        **{"gap.0.size": ("gaps", np.array(GAPS), {"units": "m"}),
           "gap.1.size": ("gaps", 2 * np.array(GAPS), {"units": "m"})})
    assert plot.default_axis(zipped) == "gaps"
    ax = plot.study_amplification_figure(zipped, "gaps", by="law").axes[0]
    np.testing.assert_array_equal(line(ax, "Hd").get_xdata(), np.arange(len(GAPS)))
    assert [t.get_text() for t in ax.get_xticklabels()][2] == "gap.0.size=0.02 m\ngap.1.size=0.04 m"


def test_categorical_axis_gets_tick_labels(study):
    ax = plot.study_amplification_figure(study, "law", by="gap_size").axes[0]
    assert [t.get_text() for t in ax.get_xticklabels()] == LAWS
    assert ax.get_xlabel() == "law"
    np.testing.assert_allclose(line(ax, "0.02").get_ydata(),
                               np.nanmedian(raw(study, "max_amplification")[:, 2, :], axis=1))


@pytest.mark.parametrize("kwargs, key", [
    (dict(axis="gap"), "--axis"),            # a dimension, but not a run dimension
    (dict(axis="nope"), "--axis"),
    (dict(axis="gap_size", by="gap_size"), "--by"),
    (dict(axis="gap_size", by="colour"), "--by"),
    (dict(axis="gap_size", over="gap_size"), "--over"),
    (dict(axis="gap_size", over="floor"), "--over"),
    (dict(axis="gap_size", sel={"nope": "1"}), "--sel"),
    (dict(axis="gap_size", sel={"law": "Hertz"}), "--sel"),
    (dict(axis="gap_size", by="law", sel={"law": "Hd"}), "--sel"),
    (dict(axis="gap_size", sel={"gap_size": "0.02"}), "--sel"),
    (dict(axis="gap_size", sel={"record": "kobe", "law": "Hd", "gap_size": "0.02"}), "--sel"),
    (dict(axis="gap_size", var="nope"), "var"),
])
def test_bad_study_choices_name_the_option(study, tmp_path, kwargs, key):
    axis = kwargs.pop("axis")
    with pytest.raises(InputError) as info:
        plot.study_amplification(study, axis, **kwargs, out=tmp_path / "x")
    assert info.value.key == key
    assert not list(tmp_path.iterdir())


def test_all_failed_selection_is_an_input_error(study, tmp_path):
    only_failed = study.isel(record=[1], law=[0], gap_size=[2])
    with pytest.raises(InputError, match="no finished run") as info:
        plot.study_force(only_failed, "gap_size", out=tmp_path / "x")
    assert info.value.key == "--sel"


def test_missing_output_folder(study, tmp_path):
    with pytest.raises(InputError) as info:
        plot.study_amplification(study, "gap_size", out=tmp_path / "no" / "amp")
    assert info.value.key == "--output"


def test_missing_matplotlib_is_an_input_error(study, tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # import now fails
    with pytest.raises(InputError, match=r"pip install 'seispound\[plot\]'") as info:
        plot.study_amplification(study, "gap_size", out=tmp_path / "x")
    assert info.value.key == "plot"


def test_import_stays_light():
    # what importing seispound.plot adds to `import seispound`: no heavy module
    code = ("import sys, seispound; before = set(sys.modules); import seispound.plot; "
            "print(sorted(m for m in set(sys.modules) - before "
            "if m.split('.')[0] in ('matplotlib', 'xarray', 'numpy')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"
    assert "seispound.plot" not in subprocess.run(
        [sys.executable, "-c", "import sys, seispound; print(list(sys.modules))"],
        capture_output=True, text=True, check=True).stdout
    assert plot.STATUS_DONE == schema.STATUS_DONE


# --------------------------------------------------------------------------- single run

def test_run_histories_files_and_labels(run_ds, tmp_path):
    png, svg = save_with_text(plot.run_histories, run_ds, [("A", 4), ("B", 4)], out=tmp_path / "hist.png")
    img = matplotlib.image.imread(png)
    w, h = plot.RUN_FIGSIZE
    assert img.shape[:2] == (round(h * plot.DPI), round(w * plot.DPI))
    text = svg_text(svg)
    for label in ("displacement [cm]", "pounding force [kN]", "time [s]", "A floor 4", "B floor 4",
                  "gap 3: A 4 | B 4"):
        assert label in text, label


def test_run_histories_data(run_ds):
    fig = plot.run_histories_figure(run_ds, ["A:3", ("B", 4)])
    ax_u, ax_d, ax_f = fig.axes[:3]
    assert ax_u.get_shared_x_axes().joined(ax_u, ax_f) and ax_u.get_shared_x_axes().joined(ax_u, ax_d)
    t = run_ds.time.values
    for name, floor in (("A", 3), ("B", 4)):
        ln = line(ax_u, f"{name} floor {floor}")
        np.testing.assert_array_equal(ln.get_xdata(), t)
        np.testing.assert_allclose(ln.get_ydata(), run_ds.displacement.sel(building=name, floor=floor) * 100)
    # gaps 2 (A3|B3, via A:3) and 3 (A4|B4, via B:4)
    labels = [ln.get_label() for ln in ax_f.lines if not ln.get_label().startswith("_")]
    assert labels == ["gap 2: A 3 | B 3", "gap 3: A 4 | B 4"]
    for g in (2, 3):
        force = line(ax_f, f"gap {g}: A {g + 1} | B {g + 1}")
        np.testing.assert_allclose(force.get_ydata(), run_ds.pounding_force.isel(gap=g) / 1e3)
        marks = line(ax_f, f"_impacts gap {g}")
        hit = run_ds.impact_gap.values == g
        assert hit.sum() == int(run_ds.impact_count[g]) > 0
        np.testing.assert_array_equal(marks.get_xdata(), run_ds.impact_onset.values[hit])
        np.testing.assert_allclose(marks.get_ydata(), run_ds.impact_peak_force.values[hit] / 1e3)


def test_relative_displacement_against_gap_size(run_ds):
    """The middle panel: u_left - u_right of each gap element and its size, so the closing gap shows."""
    fig = plot.run_histories_figure(run_ds, [("A", 4), ("B", 4)])
    ax_d = fig.axes[1]
    rel = line(ax_d, "u_A4 - u_B4 (gap 3)")
    want = (run_ds.displacement.sel(building="A", floor=4) - run_ds.displacement.sel(building="B", floor=4)) * 100
    np.testing.assert_allclose(rel.get_ydata(), want.values)
    size = line(ax_d, "_size gap 3")
    assert size.get_ydata()[0] == pytest.approx(float(run_ds.gap_size[3]) * 100)
    # every impact of gap 3 starts where the relative displacement reaches the gap size
    assert float(want.max()) >= float(run_ds.gap_size[3]) * 100 * 0.999
    assert "Histories of A floor 4, B floor 4" in fig.get_suptitle()
    assert fig.axes[2].get_xlabel() == "time [s]"


def test_short_impact_tests_use_milliseconds(tmp_path):
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = sp.simulate(sp.load_model(REPO / "models" / "slab_pendulum.toml"))
    assert float(ds.time[-1]) < plot.MS_BELOW
    fig = plot.run_histories_figure(ds)
    assert fig.axes[2].get_xlabel() == "time [ms]"
    marks = [ln for ln in fig.axes[2].lines if ln.get_label().startswith("_impacts")]
    np.testing.assert_allclose(marks[0].get_xdata(), ds.impact_onset.values[ds.impact_gap.values == 0] * 1e3)
    legend = [t.get_text() for t in fig.axes[2].get_legend().get_texts()]
    assert any(f"onsets {float(ds.impact_onset[0]) * 1e3:.1f}" in x for x in legend)


def test_default_floors_are_the_gap_with_most_impacts(run_ds):
    g = int(np.argmax(run_ds.impact_count.values))
    expected = [("A", int(run_ds.gap_left_floor[g])), ("B", int(run_ds.gap_right_floor[g]))]
    assert plot.default_floors(run_ds) == expected
    ax_u = plot.run_histories_figure(run_ds).axes[0]
    assert [ln.get_label() for ln in ax_u.lines if not ln.get_label().startswith("_")] == \
        [f"{b} floor {f}" for b, f in expected]


def test_floor_without_gap_says_so(run_ds):
    ax_f = plot.run_histories_figure(run_ds, [("B", 8)]).axes[2]
    assert not ax_f.lines
    assert [t.get_text() for t in ax_f.texts] == ["no gap element at these floors"]


@pytest.mark.parametrize("floors", [[("C", 1)], [("A", 5)], [("B", 0)], ["A4"], ["A:x"], []])
def test_bad_floors(run_ds, tmp_path, floors):
    with pytest.raises(InputError) as info:
        plot.run_histories(run_ds, floors, out=tmp_path / "h")
    assert info.value.key == "--floors"
    assert not list(tmp_path.iterdir())


# --------------------------------------------------------------------------- command line glue

def cli(argv):
    ap = argparse.ArgumentParser(prog="seispound")
    plot.add_plot_parser(ap.add_subparsers(dest="command"))
    args = ap.parse_args(["plot", *argv])
    return plot.cmd_plot(args)


def test_cli_study_defaults(study_file, tmp_path, capsys):
    assert cli([str(study_file), "-o", str(tmp_path / "a"), "--by", "law"]) == 0
    assert (tmp_path / "a.png").is_file() and (tmp_path / "a.svg").is_file()
    assert "a.png" in capsys.readouterr().out
    assert cli([str(study_file), "-o", str(tmp_path / "f"), "--kind", "force", "--axis", "record",
                "--over", "gap_size", "--sel", "law=Hd"]) == 0
    assert (tmp_path / "f.svg").is_file()


def test_cli_result_defaults(run_file, tmp_path):
    assert cli([str(run_file), "-o", str(tmp_path / "h"), "--floors", "A:4", "B:4"]) == 0
    assert (tmp_path / "h.png").is_file() and (tmp_path / "h.svg").is_file()


def test_default_axis(study):
    assert plot.default_axis(study) == "gap_size"
    other = study.rename(gap_size="pga")
    assert plot.default_axis(other) == "pga"


@pytest.mark.parametrize("argv, key", [
    (["--kind", "histories"], "--kind"),
    (["--kind", "spectrum"], "--kind"),
    (["--axis", "nope"], "--axis"),
    (["--by", "nope"], "--by"),
    (["--sel", "law"], "--sel"),
    (["--sel", "record=kobe"], "--sel"),    # record is the --over dimension
    (["--over", "gap_size"], "--over"),     # also the default --axis
    (["--floors", "A:4"], "--floors"),
])
def test_cli_bad_study_options(study_file, tmp_path, argv, key):
    with pytest.raises(InputError) as info:
        cli([str(study_file), "-o", str(tmp_path / "x"), *argv])
    assert info.value.key == key
    assert info.value.file == str(study_file)


@pytest.mark.parametrize("argv, key", [
    (["--kind", "amplification"], "--kind"),
    (["--axis", "gap_size"], "--axis"),
    (["--sel", "law=Hd"], "--sel"),
    (["--floors", "Z:1"], "--floors"),
])
def test_cli_bad_result_options(run_file, tmp_path, argv, key):
    with pytest.raises(InputError) as info:
        cli([str(run_file), "-o", str(tmp_path / "x"), *argv])
    assert info.value.key == key
    assert not list(tmp_path.glob("x.*"))


def test_cli_bad_files(tmp_path):
    with pytest.raises(InputError, match="file not found"):
        cli([str(tmp_path / "none.h5"), "-o", str(tmp_path / "x")])
    text = tmp_path / "text.h5"
    text.write_text("not hdf5")
    with pytest.raises(InputError, match="HDF5"):
        cli([str(text), "-o", str(tmp_path / "x")])
    other = tmp_path / "other.h5"
    xr.Dataset({"a": ("x", [1.0])}, attrs={"schema": "something"}).to_netcdf(other, engine="h5netcdf")
    with pytest.raises(InputError) as info:
        cli([str(other), "-o", str(tmp_path / "x")])
    assert info.value.key == "schema"


def test_cli_study_var_plots_another_quantity(study_file, tmp_path, capsys):
    """--var picks a run variable (e.g. max_acceleration_amplification); the figure is titled by it."""
    ds = xr.open_dataset(study_file, engine="h5netcdf").load()
    ds["max_acceleration_amplification"] = 3.0 * ds.max_amplification
    ds.max_acceleration_amplification.attrs["units"] = "1"
    path = tmp_path / "with_acc.h5"
    ds.to_netcdf(path, engine="h5netcdf")
    assert cli([str(path), "-o", str(tmp_path / "acc"), "--by", "law", "--var",
                "max_acceleration_amplification"]) == 0
    fig = plot.study_amplification_figure(ds, "gap_size", by="law", var="max_acceleration_amplification")
    assert fig.axes[0].get_title().startswith("max acceleration amplification: median over record")
    hd = line(fig.axes[0], "Hd")
    want = np.nanmedian(3.0 * ds.max_amplification.sel(law="Hd").transpose("gap_size", "record").values, axis=1)
    np.testing.assert_allclose(hd.get_ydata(), want[np.argsort(ds.gap_size.values)])
    with pytest.raises(InputError) as info:
        cli([str(path), "-o", str(tmp_path / "bad"), "--var", "amplification"])
    assert info.value.key == "--var" and "'amplification' is not a run variable" in str(info.value)
