"""The general driver's Newmark substeps (``simulation.newmark_substeps``): decided by the model, said by the
run, and what they buy.

The accuracy check compares a run at the analysis step with one at a tenth of it (the same code
converged in time): a self-convergence check, a regression guard of the rule's effect, not a
verification of the physics (``tests/verification`` holds those).
"""

import warnings

import numpy as np

import seispound as sp
from seispound.cli import summary
from benchmarks.physics_accuracy import CASES, _text
from seispound.simulation import MAX_NEWMARK_SUBSTEPS, NEWMARK_THETA, _run_inputs, newmark_substeps


def _model(tmp_path, dt, case="bilinear storeys", name="pair.toml"):
    """The 5 + 8 storey pair of ``benchmarks.physics_accuracy``, 6 s of it."""
    f = tmp_path / name
    f.write_text(_text(CASES[case], dt).replace("duration = 20.0", "duration = 6.0"))
    return sp.load_model(f)


def test_the_rule_follows_the_highest_storey_frequency(tmp_path):
    m = _model(tmp_path, 0.005)
    _, system, _ = _run_inputs(m)
    w_hi = max(b.modes()[0].max() for b in m.buildings)
    n = newmark_substeps(m, system)
    assert n == 2 and w_hi * 0.005 / n <= NEWMARK_THETA < w_hi * 0.005  # 0.33 rad at 5 ms: two substeps
    m.analysis.dt = 0.05
    assert newmark_substeps(m, system) == MAX_NEWMARK_SUBSTEPS  # capped
    elastic = _model(tmp_path, 0.005, case="elastic row", name="elastic.toml")
    assert newmark_substeps(elastic, _run_inputs(elastic)[1]) == 1  # the fast driver is exact between impacts


def test_the_run_says_it_steps_by_newmark_with_substeps(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = sp.simulate(_model(tmp_path, 0.005), twin=False)
    assert ds.attrs["driver"] == "general" and ds.attrs["scheme"] == "exact" and ds.attrs["newmark_substeps"] == 2
    text = summary(ds)
    assert "analysis steps in free flight (exact steps" in text and "2 substeps per analysis step" in text
    m = _model(tmp_path, 0.005, case="Bouc-Wen storeys", name="bw.toml")  # offsets iterated in free flight
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = sp.simulate(m, twin=False)
    assert ds.attrs["scheme"] == "exact" and "analysis steps in free flight" in summary(ds)
    m.analysis.scheme = "newmark"  # the Newmark scheme: no free flight, and the summary says so
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = sp.simulate(m, twin=False)
    assert ds.attrs["scheme"] == "newmark" and "Newmark steps throughout" in summary(ds)


def test_substeps_bring_floor_accelerations_near_the_converged_run(tmp_path, monkeypatch):
    """The substeps' effect on the physical path: the yielding storeys on it whenever they yield (the off switch
    of their free flight, ``hysteretic_flight=False``); with their free flight on, the default, the run is at
    least as accurate."""
    import functools

    from seispound import simulation

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = sp.simulate(_model(tmp_path, 0.0005, name="ref.toml"), twin=False)
        m = _model(tmp_path, 0.005)
        default = sp.simulate(m, twin=False)
        monkeypatch.setattr(simulation, "integrate", functools.partial(simulation.integrate, hysteretic_flight=False))
        ds = sp.simulate(m, twin=False)
        monkeypatch.setattr(simulation, "MAX_NEWMARK_SUBSTEPS", 1)  # the step alone, as before the rule
        plain = sp.simulate(m, twin=False)
    a_ref = np.nan_to_num(ref.acceleration.values[::10])

    def ne(x):
        a = np.nan_to_num(x.acceleration.values)
        return float(np.linalg.norm(a - a_ref) / np.linalg.norm(a_ref))

    print(f"MEASURED floor-acceleration NE at 5 ms against 0.5 ms, yielding on the physical path: {100 * ne(ds):.2f} "
          f"% with {ds.attrs['newmark_substeps']} substeps, {100 * ne(plain):.2f} % without; in free flight "
          f"{100 * ne(default):.2f} %")
    assert ne(ds) <= 0.005 and ne(plain) >= 2.5 * ne(ds)
    assert ne(default) <= ne(ds)


def test_rod_floors_take_contact_substeps_short_enough_for_their_axial_modes(tmp_path):
    """Rod floors' axial modes (220 Hz) limit the contact substep (``simulation.contact_step``)."""
    from seispound import simulation

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ref = sp.simulate(_model(tmp_path, 0.0005, case="rod floors", name="ref.toml"), twin=False)
        m = _model(tmp_path, 0.005, case="rod floors")
        ds = sp.simulate(m, twin=False)
        theta = simulation.CONTACT_THETA
        try:
            simulation.CONTACT_THETA = np.inf  # no limit: 1/32 of the impact duration alone
            plain = sp.simulate(m, twin=False)
        finally:
            simulation.CONTACT_THETA = theta
    a_ref = np.nan_to_num(ref.acceleration.values[::10])

    def ne(x):
        return float(np.linalg.norm(np.nan_to_num(x.acceleration.values) - a_ref) / np.linalg.norm(a_ref))

    limit = ds.attrs["contact_step_limit"]
    print(f"MEASURED rod floors, floor-acceleration NE at 5 ms against 0.5 ms: {100 * ne(ds):.2f} % with contact "
          f"substeps of at most {1e3 * limit:.3f} ms, {100 * ne(plain):.2f} % without")
    assert 1e-4 < limit < 1e-3 and not np.isfinite(plain.attrs["contact_step_limit"])
    assert ne(ds) <= 0.005 and ne(plain) >= 2.5 * ne(ds)
