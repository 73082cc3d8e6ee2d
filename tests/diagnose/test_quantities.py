"""The quantities a named physics is reported with (``diagnose/quantities.py``).

* ``flexible_base_period`` against closed forms (kind: closed form): one storey on a sway spring
  with a massless, non-rocking foundation is two springs in series, T = 2 pi sqrt(m (1/k + 1/kx));
  a rigid base gives the fixed-base period of ``Building.modes``.
* ``_first_axial`` against the continuous rod's f1 = c / (2 L), c = sqrt(EA L / m) (kind: closed
  form; the lumped chain converges from below as O(1/N^2): 4 segments 2.6 % low, 64 segments 0.01 %).
* the delta method against the linear case (a quantity equal to a parameter has its standard error),
  and a parameter at a bound is reported as not identified, with no standard error.
"""

import math

import numpy as np

from seispound.calibrate.fit import CalibrationResult
from seispound.diagnose.quantities import _delta, _first_axial, flexible_base_period
from seispound.structure.building import Building


def test_sdof_on_a_sway_spring_is_two_springs_in_series():
    m, k, kx = 1e5, 2e8, 5e8
    t = flexible_base_period([m], [k], [3.0], kx, math.inf, 1e-6 * m, 1e-6 * m)
    exact = 2 * math.pi * math.sqrt(m * (1 / k + 1 / kx))
    assert abs(t / exact - 1) < 1e-6


def test_rigid_base_is_the_fixed_base_period():
    b = Building(name="A", floor_masses=[1e5] * 5, storey_stiffness=[1.2e8] * 5, storey_heights=[3.0] * 5)
    t = flexible_base_period([1e5] * 5, [1.2e8] * 5, [3.0] * 5, math.inf, math.inf, 1.0, 1.0)
    assert abs(t / (2 * math.pi / b.modes()[0][0]) - 1) < 1e-6


def test_first_axial_frequency_converges_to_the_rod():
    m, ea, length = 1e5, 1e10, 20.0
    exact = math.sqrt(ea * length / m) / (2 * length)
    err4 = _first_axial(m, {"segments": 4, "length": length, "axial_stiffness": ea}) / exact - 1
    err64 = _first_axial(m, {"segments": 64, "length": length, "axial_stiffness": ea, "centre_of_mass": 0.5}) / exact - 1
    print(f"MEASURED first axial frequency: 4 segments {err4:+.2%}, 64 segments {err64:+.3%}")
    assert -0.04 < err4 < -0.01 and abs(err64) < 3e-4


def _fit(value, stderr, at_bound=False):
    return CalibrationResult(parameters={"a": dict(value=value, start=1.0, stderr=stderr, lo=0.0, hi=10.0,
                                                   at_bound=at_bound, factor=False)},
                             correlation=np.eye(1), ne_before={}, ne_after={}, ne_mean_before=0, ne_mean_after=0,
                             evaluations=0, seconds=0, model_text="", n=1, n_eff=1, success=True, message="")


def test_delta_method_and_not_identified():
    q = _delta(_fit(2.0, 0.1), "a squared", "-", lambda x: x["a"] ** 2, ["a"])
    assert abs(q["value"] - 4.0) < 1e-12 and abs(q["stderr"] - 0.4) < 1e-6
    q = _delta(_fit(10.0, 0.1, at_bound=True), "a", "-", lambda x: x["a"], ["a"])
    assert q["stderr"] is None and "bound" in q["reason"]
    q = _delta(_fit(2.0, 0.0), "a", "-", lambda x: x["a"], ["a"])
    assert q["stderr"] is None and "do not constrain" in q["reason"]
    q = _delta(_fit(2.0, 1.2), "a", "-", lambda x: x["a"], ["a"])  # an interval that reaches zero
    assert q["stderr"] is None and "do not determine" in q["reason"]


def test_a_value_a_hair_inside_a_bound_ended_at_it():
    """least_squares' trust region keeps its iterates inside the bounds: a yield drift pushed onto "never yields"
    (5 in 0.0005..5, log-fitted) ended at 4.999996 with an empty active set, in a held-out case."""
    import math

    from seispound.calibrate.fit import ended_at_bound

    lo, hi = math.log(0.0005), math.log(5.0)
    assert ended_at_bound(math.log(4.999996), lo, hi)
    assert ended_at_bound(math.log(0.0005000001), lo, hi)
    assert not ended_at_bound(math.log(4.99), lo, hi)  # 2.2e-4 of the range inside: a value the data set
    assert not ended_at_bound(math.log(0.02), lo, hi)
    assert ended_at_bound(math.log(0.02), lo, hi, active=1)


def _restitution_fit(slope, stderr):
    from seispound.calibrate.fit import CalibrationResult

    par = lambda v, s: dict(value=v, start=v, stderr=s, lo=0.0, hi=5.0, at_bound=False, factor=False)  # noqa: E731
    return CalibrationResult(parameters={"contact.restitution.slope": par(slope, stderr),
                                         "contact.restitution.e0": par(0.8, 0.01)},
                             correlation=np.eye(2), ne_before={}, ne_after={}, ne_mean_before=0, ne_mean_after=0,
                             evaluations=0, seconds=0, model_text="", n=1, n_eff=1, success=True, message="")


def test_the_velocity_dependence_of_e_is_reported_and_can_be_unidentified():
    """The change of e between 0.1 and 0.5 m/s is what e(v) adds to a constant e (the base model's, which
    recalibration refits): for e = e0 - slope v0 it is -0.4 slope, standard error 0.4 sigma_slope (closed
    form; e0 cancels).  A slope within two of its standard errors of zero leaves it not identified, and the
    quantity is the physics's ``defining`` one, which the report then states as a caveat."""
    from seispound.diagnose.quantities import _restitution

    table = {"contact": {"restitution": {"form": "linear", "e0": 0.8, "slope": 0.5, "min": 0.05, "max": 0.99}}}
    qs = _restitution(_restitution_fit(0.5, 0.05), table)
    change = [q for q in qs if q.get("defining")]
    assert len(change) == 1 and [q["name"] for q in qs][:2] == ["e at an impact velocity of 0.1 m/s",
                                                                 "e at an impact velocity of 0.5 m/s"]
    assert abs(change[0]["value"] + 0.2) < 1e-12 and abs(change[0]["stderr"] - 0.02) < 1e-8
    flat = [q for q in _restitution(_restitution_fit(0.01, 0.05), table) if q.get("defining")][0]
    assert flat["stderr"] is None and "do not determine" in flat["reason"] and abs(flat["value"] + 0.004) < 1e-12


def test_a_named_physics_whose_defining_quantity_is_unidentified_carries_a_caveat_into_the_verdict():
    from types import SimpleNamespace

    from seispound.diagnose.api import _left_out, _verdict

    fit = _restitution_fit(0.01, 0.05)
    fit.model_text = ('[contact]\nrestitution = { form = "linear", e0 = 0.8, slope = 0.01, min = 0.05, '
                      'max = 0.99 }\n')
    prev = SimpleNamespace(name=None, fit=SimpleNamespace(ne_mean_after=0.02))
    step = SimpleNamespace(name="velocity-dependent-restitution", prev=prev, fit=SimpleNamespace(
        ne_mean_after=0.011, parameters=fit.parameters, correlation=fit.correlation, model_text=fit.model_text,
        dof=fit.dof),
        gain=0.45, bic=-10.0, probability=0.9)
    prev.bic = 20.0
    item = _left_out([step], prev.fit, 1000.0, {})[0]
    assert "do not show velocity-dependent-restitution itself" in item["caveat"]
    verdict = _verdict(0.011, 0.010, [item], False, None, [])
    assert "explains the data" in verdict and "but the data do not show" in verdict
    fit_sloped = _restitution_fit(0.5, 0.05)
    step.fit.parameters = fit_sloped.parameters
    step.fit.model_text = step.fit.model_text.replace("slope = 0.01", "slope = 0.5")
    assert "caveat" not in _left_out([step], prev.fit, 1000.0, {})[0]


def test_a_quantity_no_parameter_moves_is_not_identified():
    """A linear e(v) clipped to its maximum over 0.1-0.5 m/s is a constant e: the change of e is zero and no
    fitted parameter moves it, so it has no standard error to give (never a standard error of zero)."""
    from seispound.diagnose.quantities import _restitution

    table = {"contact": {"restitution": {"form": "linear", "e0": 0.8, "slope": 0.01, "min": 0.05, "max": 0.6}}}
    flat = [q for q in _restitution(_restitution_fit(0.01, 0.05), table) if q.get("defining")][0]
    assert flat["value"] == 0.0 and flat["stderr"] is None and "standard error is zero" in flat["reason"]


def test_a_physics_with_several_defining_quantities_is_shown_by_any_one_of_them():
    """Spatially varying input is shown by a delay the data identify; a caveat only when none is."""
    from types import SimpleNamespace

    from seispound.calibrate.fit import CalibrationResult
    from seispound.diagnose.api import _left_out

    def fit(se_b):
        par = lambda v, s: dict(value=v, start=v, stderr=s, lo=0.0, hi=0.5, at_bound=False, factor=False)  # noqa: E731
        return CalibrationResult(parameters={"building.B.ground_motion.delay": par(0.06, se_b),
                                             "building.C.ground_motion.delay": par(0.001, 0.01)},
                                 correlation=np.eye(2), ne_before={}, ne_after={}, ne_mean_before=0,
                                 ne_mean_after=0.011, evaluations=0, seconds=0, model_text="", n=1, n_eff=1,
                                 success=True, message="")

    prev = SimpleNamespace(name=None, bic=20.0, fit=SimpleNamespace(ne_mean_after=0.5))
    step = SimpleNamespace(name="spatially-varying-input", prev=prev, fit=fit(1e-4), gain=0.9, bic=-10.0,
                           probability=0.99)
    item = _left_out([step], prev.fit, 1000.0, {})[0]
    assert [q["stderr"] is None for q in item["quantities"]] == [False, True] and "caveat" not in item
    step.fit = fit(0.05)  # B's delay within its interval of zero too
    item = _left_out([step], prev.fit, 1000.0, {})[0]
    assert item["caveat"].startswith("the data do not show spatially-varying-input itself: none of B: delay")


def _yield_fit(values, stderr=1e-3):
    from seispound.calibrate.fit import CalibrationResult

    par = lambda v: dict(value=v, start=v, stderr=stderr, lo=1e-4, hi=1.0, at_bound=False, factor=False)  # noqa: E731
    return CalibrationResult(parameters={f"building.{b}.storey_law.yield_drift": par(v) for b, v in values.items()},
                             correlation=np.eye(len(values)), ne_before={}, ne_after={}, ne_mean_before=0,
                             ne_mean_after=0, evaluations=0, seconds=0, model_text="", n=1, n_eff=1, success=True,
                             message="")


def test_a_yield_drift_beyond_the_storeys_reach_is_not_identified():
    """A yield drift larger than every storey deformation of the fitted run is read off the storeys' departure
    from linearity below it (Bouc-Wen, degrading forms), not off yielding: it keeps its value, loses its
    standard error and says why.  One the storeys pass keeps its standard error; one drift for the whole row
    (``*``) is compared with the largest deformation of any building."""
    from seispound.diagnose.quantities import _yielding

    qs = {q["name"]: q for q in _yielding(_yield_fit({"A": 0.02, "B": 0.01}), {}, {"A": 0.015, "B": 0.012})}
    a, b = qs["A: yield drift"], qs["B: yield drift"]
    assert a["stderr"] is None and a["beyond_reach"] and "0.015 m (75 % of it)" in a["reason"] and a["value"] == 0.02
    assert abs(b["stderr"] - 1e-3) < 1e-12 and "beyond_reach" not in b and b["defining"]
    row = _yielding(_yield_fit({"*": 0.013}), {}, {"A": 0.010, "B": 0.014})[0]
    assert abs(row["stderr"] - 1e-3) < 1e-12
    row = _yielding(_yield_fit({"*": 0.015}), {}, {"A": 0.010, "B": 0.014})[0]
    assert row["stderr"] is None and "the row reach at most 0.014 m" in row["reason"]
    assert abs(_yielding(_yield_fit({"A": 0.02}), {}, None)[0]["stderr"] - 1e-3) < 1e-12  # no run to compare with


def test_a_yielding_physics_shown_below_its_yield_drift_carries_no_caveat():
    """The caveat "the data do not show the physics itself" is for a fit whose defining quantities the data
    do not constrain; a yield drift beyond the storeys' reach still comes with a hysteresis the fit reads."""
    from types import SimpleNamespace

    from seispound.diagnose.api import _left_out

    fit = _yield_fit({"A": 0.02})
    prev = SimpleNamespace(name=None, fit=SimpleNamespace(ne_mean_after=0.05), bic=20.0)
    step = SimpleNamespace(name="inelastic-storey", prev=prev, fit=fit, gain=0.6, bic=-10.0, probability=0.9)
    item = _left_out([step], prev.fit, 1000.0, {}, lambda f: {"A": 0.01})[0]
    assert item["quantities"][0]["beyond_reach"] and "caveat" not in item
    assert item["quantities"][0]["stderr"] is None
    assert _left_out([step], prev.fit, 1000.0, {}, lambda f: {"A": 0.03})[0]["quantities"][0]["stderr"] > 0


def test_storey_reach_is_the_peak_drift_of_the_fitted_run(tmp_path):
    """The largest storey deformation that ``storey_reach`` reads from a fit's run equals the largest
    ``peak_drift`` of ``simulate``'s result for the same model and motion, per building (kind: regression
    guard; two code paths of the package, the fit's lean run and the Dataset's peaks, on the yielding pair
    with bilinear and Bouc-Wen storeys)."""
    import tomllib

    import seispound as sp
    from seispound.calibrate.observe import Trial
    from seispound.calibrate.recording import Recording
    from seispound.diagnose.quantities import storey_reach
    from tests._models import short_copy

    path = short_copy(tmp_path, 4.0, "yielding_pair.toml")
    data = tomllib.loads(path.read_text(encoding="utf-8"))
    dt = data["analysis"].get("dt", 0.005)
    n = int(round(4.0 / dt)) + 1
    reach = storey_reach(data, tmp_path, [], [Trial(Recording(dt, {"x": np.zeros(n)}, []))])
    model = sp.load_model(path)
    ds = sp.simulate(model, twin=False)
    for b in ds.building.values:
        peak = float(ds.peak_drift.sel(building=b).max())
        print(f"MEASURED {b}: storey_reach {reach[str(b)]:.6g} m, peak_drift {peak:.6g} m")
        assert peak > 1e-3 and abs(reach[str(b)] / peak - 1) < 1e-9  # measured: equal to the printed digits


def _iwan_fit(dy, spread, centring):
    from seispound.calibrate.fit import CalibrationResult

    def par(v, lo, hi):
        return dict(value=v, start=v, stderr=1e-3 * max(v, 1.0), lo=lo, hi=hi, at_bound=False, factor=False)

    params = {"building.A.storey_law.yield_drift": par(dy, 1e-4, 1.0),
              "building.*.storey_law.yield_spread": par(spread, 0.0, 1.0),
              "building.*.storey_law.self_centring": par(centring, 0.0, 0.9)}
    return CalibrationResult(parameters=params, correlation=np.eye(3), ne_before={}, ne_after={}, ne_mean_before=0,
                             ne_mean_after=0, evaluations=0, seconds=0, model_text="", n=1, n_eff=1, success=True,
                             message="")


def test_an_iwan_yield_drift_is_its_springs_strength_over_their_stiffness():
    """An Iwan storey's reported yield drift is what the other yielding forms call it: the hysteretic springs'
    strength over their initial stiffness, (F(d) - alpha k d) / ((1 - alpha) k) once every spring has yielded.
    Checked against the law itself (kind: the derivation in ``_yield_drift`` against the springs of
    ``integrate._iwan`` driven monotonically past the largest slider's yield drift); zero spread and no
    self-centring give the law's yield_drift (the bilinear law)."""
    from seispound.contact.codes import N_PAR
    from seispound.diagnose.quantities import _yielding
    from seispound.integrate._material import N_STATE, material_trial
    from seispound.storey import StoreyLaw
    from seispound.storey import codes as C

    k, alpha = 2e7, 0.05
    for dy, spread, centring in ((0.01, 0.0, 0.0), (0.012, 0.45, 0.0), (0.008, 0.8, 0.3)):
        law = StoreyLaw(kind="iwan", yield_drift=dy, post_yield_ratio=alpha, yield_spread=spread,
                        self_centring=centring)
        law.validate(1)
        far = 20 * dy * 10 ** spread
        force, _, _ = material_trial(C.IWAN, law.kernel_rows([k], N_PAR)[1], np.zeros((1, N_STATE)),
                                     np.zeros((1, N_STATE)), 0, far, 0.0)
        expected = (force - alpha * k * far) / ((1 - alpha) * k)
        data = {"building": [{"name": "A", "storey_law": {"kind": "iwan"}}]}
        q = _yielding(_iwan_fit(dy, spread, centring), data)[0]
        assert q["name"] == "A: yield drift" and abs(q["value"] / expected - 1) < 1e-12, (q["value"], expected)
        assert q["stderr"] > 0 and q["defining"]
        if spread == 0 and centring == 0:
            assert abs(q["value"] - dy) < 1e-15
        else:
            assert q["value"] > dy * 1.01  # above the sliders' geometric mean, where the spread lifts it
