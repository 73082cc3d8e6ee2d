"""``[analysis] tolerance``: the contact substeps chosen from the accuracy a user states.

How good the choice is (the estimate against closed forms and the reference twin) is in
``tests/verification/test_accuracy_estimate.py``; on whole rows, ``benchmarks.tolerance``.
Here: the settings flow (model file, ``simulate``, a study axis), what the result records, an
explicit ``contact_substeps`` winning, and bad input.
"""

import math
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import seispound as sp
from seispound import accuracy
from seispound.errors import InputError
from tests._models import short_copy

SEISPOUND = Path(sys.executable).parent / "seispound"


@pytest.fixture(scope="module")
def model_file(tmp_path_factory):
    return short_copy(tmp_path_factory.mktemp("tol"), 6.0)


def _with(path, line, folder, name):
    text = path.read_text(encoding="utf-8").replace("[analysis]\n", f"[analysis]\n{line}\n", 1)
    out = folder / name
    out.write_text(text, encoding="utf-8")
    return out


def test_default_tolerance_chooses_the_substeps_and_records_them(model_file):
    model = sp.load_model(model_file)
    ds = sp.simulate(model, twin=False)
    n, est = accuracy.choose_contact_substeps([model.contact], 0.01)
    assert ds.attrs["tolerance"] == 0.01
    assert ds.attrs["contact_substeps_from"] == "tolerance"
    assert int(ds.sizes["impact"]) > 0
    # started from the isolated impact's choice, refined by powers of two while the peaks' estimate was above
    runs = ds.attrs["tolerance_runs"]
    assert runs >= 2 and ds.attrs["contact_substeps"] == n * 2 ** (runs - 2)
    assert est <= accuracy.SAFETY * 0.01
    assert ds.attrs["contact_error_estimate"] <= est
    assert 0 < ds.attrs["peak_error_estimate"] <= 0.01


def test_the_peaks_estimate_is_the_change_from_the_run_at_half_its_substeps(model_file):
    from dataclasses import replace

    from seispound.integrate import integrate
    from seispound.simulation import _peak_change, _run_inputs, contact_step, run_row

    model = sp.load_model(model_file)
    kept, system, motions = _run_inputs(model)
    raw = run_row(model, system, motions.rows)
    n = raw.stats["contact_substeps"]
    an = model.analysis
    coarse = integrate(system, motions.rows, an.dt, an.nsteps, replace(an.newmark, contact_substeps=n // 2),
                       contact_step=2 * contact_step(system))
    assert raw.stats["peak_error_estimate"] == pytest.approx(_peak_change(raw, coarse), rel=1e-12)


def test_looser_tolerance_fewer_substeps_and_results_within_it(model_file):
    model = sp.load_model(model_file)
    runs = {tol: sp.simulate(model, twin=False, tolerance=tol) for tol in (0.001, 0.01, 0.05)}
    subs = [runs[t].attrs["contact_substeps"] for t in (0.001, 0.01, 0.05)]
    assert subs[0] > subs[1] >= subs[2]
    # against the same model at 512 substeps: each run within its own tolerance on the peak force
    ref = sp.simulate(_given(model, 512), twin=False)
    f_ref = float(ref.peak_pounding_force.max())
    a_ref = ref.peak_acceleration.values
    for tol, ds in runs.items():
        err = abs(float(ds.peak_pounding_force.max()) / f_ref - 1.0)
        print(f"MEASURED tolerance {tol}: {ds.attrs['contact_substeps']} substeps, peak force error {err:.2e}")
        assert err <= tol
        err_a = float(np.nanmax(np.abs(ds.peak_acceleration.values / a_ref - 1.0)))
        print(f"MEASURED tolerance {tol}: peak floor acceleration error {err_a:.2e}")
        assert err_a <= tol


def _given(model, n):
    from dataclasses import replace

    return replace(model, analysis=replace(model.analysis, newmark=replace(model.analysis.newmark,
                                                                           contact_substeps=n)))


def test_explicit_contact_substeps_win(model_file, tmp_path):
    path = _with(model_file, "contact_substeps = 12", tmp_path, "given.toml")
    ds = sp.simulate(sp.load_model(path), twin=False, tolerance=0.001)
    assert ds.attrs["contact_substeps"] == 12
    assert ds.attrs["contact_substeps_from"] == "model"
    assert math.isnan(ds.attrs["contact_error_estimate"])


def test_tolerance_from_the_model_file(model_file, tmp_path):
    path = _with(model_file, "tolerance = 0.05", tmp_path, "loose.toml")
    ds = sp.simulate(sp.load_model(path), twin=False)
    assert ds.attrs["tolerance"] == 0.05
    start = accuracy.choose_contact_substeps([sp.load_model(path).contact], 0.05)[0]
    assert ds.attrs["contact_substeps"] == start * 2 ** (ds.attrs["tolerance_runs"] - 2)
    assert ds.attrs["peak_error_estimate"] <= 0.05


@pytest.mark.parametrize("bad", [0.0, -0.01, 0.7, float("nan")])
def test_tolerance_outside_the_range_is_refused(model_file, bad):
    with pytest.raises(InputError) as err:
        sp.simulate(sp.load_model(model_file), twin=False, tolerance=bad)
    assert err.value.key == "analysis.tolerance"
    assert "(0, 0.5]" in str(err.value)


def test_cli_bad_tolerance_is_one_line_exit_2_nothing_written(model_file, tmp_path):
    path = _with(model_file, "tolerance = 0.6", tmp_path, "bad.toml")
    out = tmp_path / "bad.h5"
    res = subprocess.run([str(SEISPOUND), "run", str(path), "-o", str(out)], capture_output=True, text=True,
                         timeout=300)
    assert res.returncode == 2
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and "bad.toml" in lines[0] and "analysis.tolerance" in lines[0], res.stderr
    assert not out.exists()


def test_cli_summary_says_how_the_substeps_were_chosen(model_file, tmp_path):
    res = subprocess.run([str(SEISPOUND), "run", str(model_file), "-o", str(tmp_path / "r.h5")],
                         capture_output=True, text=True, timeout=300)
    assert res.returncode == 0, res.stderr
    m = re.search(r"(\d+) contact substeps per impact, chosen for a tolerance of 0.01: estimated error of the "
                  r"peaks ([0-9.e-]+) \(of an impact ([0-9.e-]+)\), from (\d+) runs", res.stdout)
    assert m, res.stdout
    assert float(m.group(2)) <= 0.01 and float(m.group(3)) <= 0.005 and int(m.group(4)) >= 2


def test_tolerance_is_a_study_axis(model_file, tmp_path):
    from seispound.study import load_study, open_study, run_study

    (tmp_path / "two.toml").write_text(model_file.read_text(encoding="utf-8"), encoding="utf-8")
    study = tmp_path / "study.toml"
    study.write_text('title = "tolerance axis"\nmodel = "two.toml"\n[records]\nbundled = ["elcentro_180"]\n'
                     '[[axis]]\nname = "tolerance"\npath = "analysis.tolerance"\nvalues = [0.001, 0.05]\n',
                     encoding="utf-8")
    out = tmp_path / "study.h5"
    run_study(load_study(study), out, scheduler="serial", progress=False)
    ds = open_study(out)
    subs = ds.contact_substeps.squeeze().values
    assert subs[0] > subs[1]
    est = ds.peak_error_estimate.squeeze().values
    assert 0 < est[0] <= 0.001 and 0 < est[1] <= 0.05


def test_a_tolerance_not_reached_is_said(model_file, monkeypatch):
    from seispound import simulation
    from seispound.plausibility import PlausibilityWarning

    # the start and the refinement both stop at 8 substeps, far from what 1e-4 needs
    monkeypatch.setattr(accuracy, "MAX_SUBSTEPS", 8)
    monkeypatch.setattr(simulation, "MAX_CONTACT_SUBSTEPS", 8)
    with pytest.warns(PlausibilityWarning, match=r"the tolerance 0.0001 was not reached"):
        ds = sp.simulate(sp.load_model(model_file), twin=False, tolerance=1e-4)
    assert ds.attrs["peak_error_estimate"] > 1e-4
