"""A named physics in physical terms: the quantities its fit determines, with standard errors.

Each quantity is a function of the fitted parameters; its standard error comes from the fit's
covariance (the calibration's sandwich, ``calibrate.fit``) by the delta method, with central
differences of the function (sigma_q^2 = g^T C g, g = dq/dx), and its 68 % interval from Student's t
with the effective degrees of freedom of that variance in the direction g (``CalibrationResult.dof``).
A quantity whose parameters sit at a bound of the fit, or whose standard error is zero, not finite or
over half its value (a 95 % interval that would reach zero), is reported as not identified, with the reason, never
with a standard error of zero.  A quantity marked ``defining`` is what the physics adds to the base
model (its departure from the null point, where the base model cannot reach): the change of e with
the impact velocity, a foundation's lengthening of the first-mode period, a floor's axial frequency
or its body's on the joint, a yield drift, a delay or low-pass corner.  When a named physics has
such quantities and none of them is identified, the report says that the data do not show the
physics itself (``api._left_out``).

Quantities (units in each entry):

* soil-structure-interaction: each building's soil shear-wave velocity (and footing width where
  fitted), first-mode period on its foundation (beside the fixed-base one) and the lengthening
  between them, the share of the half-space's radiation damping;
* distributed-mass: each building's first free-free axial frequency of a floor (the lumped chain
  of the rod floor as modelled), the axial damping ratio; or, for a body on a compliant joint,
  the body's mass and its natural frequency on the joint;
* inelastic-storey: each building's yield drift, the post-yield stiffness ratio (and Bouc-Wen's
  exponent, a peak-oriented law's unloading exponent and pinching, an Iwan law's spread of yield drifts
  and self-centring share, or a flag's height); a yield drift larger than every storey deformation of the fitted run is not identified
  (a Bouc-Wen or degrading storey departs from linearity below it, and the fit reads that, not the yield);
* velocity-dependent-restitution: e at impact velocities of 0.1 and 0.5 m/s, and the change of e
  between them (the velocity dependence itself, marked ``defining``);
* spatially-varying-input: each building's delay (and low-pass corner), or the share of the motion recorded
  at its base that drives it.
"""

from __future__ import annotations

import math
import tomllib

import numpy as np

from ..calibrate.fit import interval68

__all__ = ["quantities", "flexible_base_period", "storey_reach"]

UNDETERMINED = 0.5  # a standard error above this fraction of the value: the quantity is reported as undetermined


def flexible_base_period(masses, stiffness, heights, sway, rocking, m0, i0) -> float:
    """First-mode period [s] of a shear building on a rigid foundation that sways and rocks on springs.

    Derived here (not read): floor i's total displacement is x_i + u0 + z_i theta, with x the storey
    deformations' sum relative to the foundation, u0 its sway and theta its rocking; the mass matrix
    is T^T diag(m, m0, i0) T in (x, u0, theta) with the floors' rotary inertia neglected, the
    stiffness matrix blockdiag(K_shear, sway, rocking) [N/m, N m/rad]; masses [kg], heights [m].
    An infinite ``sway`` or ``rocking`` removes that degree of freedom (a rigid base in it).
    """
    from scipy.linalg import eigh

    from ..structure.building import shear_stiffness_matrix

    m = np.asarray(masses, float)
    n = m.size
    z = np.cumsum(np.asarray(heights, float))
    T = np.zeros((n + 2, n + 2))
    T[:n, :n] = np.eye(n)
    T[:n, n], T[:n, n + 1] = 1.0, z
    T[n, n], T[n + 1, n + 1] = 1.0, 1.0
    M = T.T @ np.diag(np.concatenate([m, [m0, i0]])) @ T
    K = np.zeros((n + 2, n + 2))
    K[:n, :n] = shear_stiffness_matrix(np.asarray(stiffness, float))
    K[n, n], K[n + 1, n + 1] = sway, rocking
    keep = list(range(n)) + [n + j for j, k in enumerate((sway, rocking)) if math.isfinite(k)]  # inf: rigid
    w2 = eigh(K[np.ix_(keep, keep)], M[np.ix_(keep, keep)], eigvals_only=True)
    return 2.0 * math.pi / math.sqrt(w2[0])


def _first_axial(mass, rod) -> float:
    """First nonzero free-free axial frequency [Hz] of a floor of mass [kg] as the rod table ``rod`` describes."""
    from ..floor.rod import RodFloor

    keys = ("segments", "length", "axial_stiffness", "centre_of_mass")
    return RodFloor(**{k: rod[k] for k in keys if k in rod}).first_axial_omega(mass) / (2.0 * math.pi)


def _covariance(fit, paths):
    sd = np.array([fit.parameters[p]["stderr"] for p in paths], float)
    names = list(fit.parameters)
    idx = [names.index(p) for p in paths]
    corr = np.nan_to_num(np.asarray(fit.correlation, float)[np.ix_(idx, idx)], nan=0.0)
    np.fill_diagonal(corr, 1.0)
    return np.outer(sd, sd) * corr


def _delta(fit, name, units, fn, paths, rel=1e-4, defining=False) -> dict:
    """{name, value, stderr, units} of fn(values) by the delta method; stderr None (with the reason) when the
    fit does not identify one of ``paths``.  ``defining``: the entry says that the quantity is what the
    physics adds to the base model (module docstring)."""
    q = _delta_method(fit, name, units, fn, paths, rel)
    if defining:
        q["defining"] = True
    return q


def _delta_method(fit, name, units, fn, paths, rel) -> dict:
    x = {p: float(fit.parameters[p]["value"]) for p in fit.parameters}
    value = float(fn(x))
    for p in paths:
        q = fit.parameters[p]
        if q["at_bound"]:
            return {"name": name, "value": value, "stderr": None, "units": units,
                    "reason": f"{p} ended at a bound of its fit ({q['lo']:g}..{q['hi']:g})"}
        if not (math.isfinite(q["stderr"]) and q["stderr"] > 0):
            return {"name": name, "value": value, "stderr": None, "units": units,
                    "reason": f"the data do not constrain {p}"}
    g = []
    for p in paths:
        h = rel * max(abs(x[p]), 1e-12)
        up, dn = dict(x), dict(x)
        up[p] += h
        dn[p] -= h
        g.append((fn(up) - fn(dn)) / (2.0 * h))
    g = np.array(g)
    sd = float(math.sqrt(max(g @ _covariance(fit, paths) @ g, 0.0)))
    if not sd > 0.0:  # no parameter moves it at the fitted point (an e(v) clipped to a constant, say)
        return {"name": name, "value": value, "stderr": None, "units": units,
                "reason": "no fitted parameter moves it at the fitted values: its standard error is zero"}
    if sd > UNDETERMINED * abs(value):
        return {"name": name, "value": value, "stderr": None, "units": units,
                "reason": f"the data do not determine it (standard error {sd:.2g} {units}, over half its value)"}
    full = np.zeros(len(fit.parameters))
    names = list(fit.parameters)
    for p, gp in zip(paths, g):
        full[names.index(p)] = gp
    dof = fit.dof(full)
    return {"name": name, "value": value, "stderr": sd, "units": units, "dof": dof, "half68": interval68(sd, dof)}


def _buildings(data):
    return {b["name"]: b for b in data.get("building", [])}


def _list(v, n):
    return [float(x) for x in v] if isinstance(v, list) else [float(v)] * n


def _floors(b):
    m = b["floor_masses"]
    return len(m) if isinstance(m, list) else int(b.get("floors", 1))


def _soil(fit, data):
    from ..foundation import Footing, Soil
    from ..foundation.model import cone_impedances

    out = []
    for name, b in _buildings(data).items():
        path = f"building.{name}.foundation.soil.shear_wave_velocity"
        if path not in fit.parameters:
            continue
        n = _floors(b)
        masses, stiff = _list(b["floor_masses"], n), _list(b["storey_stiffness"], n)
        heights = _list(b.get("storey_heights", 3.0), n)
        fd = b["foundation"]

        width = f"building.{name}.foundation.footing.width"
        paths = [path] + ([width] if width in fit.parameters else [])

        def period(x, fd=fd, masses=masses, stiff=stiff, heights=heights, path=path, width=width):
            soil = Soil(x[path], fd["soil"]["density"], fd["soil"]["poisson"])
            w = x.get(width, fd["footing"]["width"])
            size = (w, w) if width in x else (fd["footing"]["width"], fd["footing"]["length"])
            imp = cone_impedances(soil, Footing(width=size[0], length=size[1]))
            return flexible_base_period(masses, stiff, heights, imp["sway_stiffness"], imp["rocking_stiffness"],
                                        fd["mass"], fd["rotary_inertia"])

        out.append(_delta(fit, f"{name}: soil shear-wave velocity", "m/s", lambda x, p=path: x[p], [path]))
        if width in fit.parameters:
            out.append(_delta(fit, f"{name}: footing width", "m", lambda x, p=width: x[p], [width]))
        fixed = flexible_base_period(masses, stiff, heights, math.inf, math.inf, 1.0, 1.0)
        out.append(_delta(fit, f"{name}: first-mode period on the foundation (fixed base {fixed:.3f} s)", "s",
                          period, paths))
        # what a stiffer or softer building on a fixed base cannot give: the foundation's lengthening
        out.append(_delta(fit, f"{name}: lengthening of the first-mode period by the foundation", "s",
                          lambda x, f=period, t0=fixed: f(x) - t0, paths, defining=True))
    share = "building.*.foundation.soil.radiation"
    if share in fit.parameters:
        out.append(_delta(fit, "share of the half-space's radiation damping", "-", lambda x: x[share], [share]))
    return out


def _rods(fit, data):
    out = []
    for name, b in _buildings(data).items():
        path = f"building.{name}.floor_model.axial_stiffness"
        if path not in fit.parameters:
            continue
        rod = b["floor_model"]
        m = _list(b["floor_masses"], _floors(b))[0]
        centre = f"building.{name}.floor_model.centre_of_mass"
        paths = [path] + ([centre] if centre in fit.parameters else [])

        def first(x, path=path, centre=centre, rod=rod, m=m):
            return _first_axial(m, {**rod, "axial_stiffness": x[path], **({"centre_of_mass": x[centre]}
                                                                          if centre in x else {})})

        out.append(_delta(fit, f"{name}: first axial frequency of a floor", "Hz", first, paths, defining=True))
        if centre in fit.parameters:
            what = f"{name}: floors' centre of mass, a fraction of the length from the left face"
            out.append(_delta(fit, what, "-", lambda x, c=centre: x[c], [centre]))
    mass = "building.*.floor_model.attachment.mass"
    for name in _buildings(data):
        joint = f"building.{name}.floor_model.attachment.joint_stiffness"
        if joint in fit.parameters and mass in fit.parameters:
            out.append(_delta(fit, f"{name}: natural frequency of the body on its joint", "Hz",
                              lambda x, j=joint: math.sqrt(x[j] / x[mass]) / (2.0 * math.pi), [joint, mass],
                              defining=True))
    if mass in fit.parameters:
        out.append(_delta(fit, "mass of the body on the joint", "kg", lambda x: x[mass], [mass]))
    damp = "building.*.floor_model.axial_damping"
    if damp in fit.parameters:
        out.append(_delta(fit, "axial damping ratio of the floors' first mode", "-", lambda x: x[damp], [damp]))
    return out


def _yielding(fit, data, reach=None):
    out = []
    for path in fit.parameters:
        if path.endswith("storey_law.yield_drift"):
            name = path.split(".")[1]
            fn, paths = _yield_drift(fit, data, name, path)
            q = _delta(fit, f"{name}: yield drift", "m", fn, paths, defining=True)
            out.append(_beyond_reach(q, name, reach))
    laws = {(b.get("storey_law") or {}).get("kind") for b in data.get("building", [])}
    pinch = ("pinching severity s (Roufaiel & Meyer): reloading aims first at 1 - s of its target force"
             if "peak-oriented" in laws else "pinching severity zeta_s (Baber & Noori)")
    for key, what in (("post_yield_ratio", "post-yield stiffness ratio"), ("n", "Bouc-Wen exponent"),
                      ("unloading_exponent", "unloading stiffness exponent beta_u, k (dy / d_max)^beta_u (Otani)"),
                      ("strength_degradation", "strength degradation rate delta_nu (Baber & Wen)"),
                      ("stiffness_degradation", "stiffness degradation rate delta_eta (Baber & Wen)"),
                      ("pinching", pinch),
                      ("pinching_rate", "pinching growth rate p with the hysteretic energy (Foliente)"),
                      ("pinching_width", "pinching width over the yield drift psi (Foliente)"),
                      ("yield_spread", "spread s of the sliders' yield drifts about dy, decades (Iwan)"),
                      ("self_centring", "self-centring share of the hysteretic stiffness (Iwan)"),
                      ("energy_dissipation", "flag's force drop on unloading over the yield force beta (Christopoulos)")):
        path = f"building.*.storey_law.{key}"
        if path in fit.parameters:
            out.append(_delta(fit, what, "-", lambda x, p=path: x[p], [path]))
    return out


def _yield_drift(fit, data, name, path):
    """(fn, paths): a storey's yield drift [m] as every yielding form defines it alike, its hysteretic springs'
    strength over their initial stiffness (the drift at which the initial tangent meets the post-yield asymptote).

    It is the law's ``yield_drift`` for the bilinear, Bouc-Wen and peak-oriented laws.  An Iwan storey's sliders
    yield at drifts spread geometrically about ``yield_drift`` (their geometric mean), so its strength is
    c dy + (1 - c) mean(d_i) times (1 - alpha) k, with d_i the sliders' yield drifts and c the self-centring share
    (derived here from ``integrate._iwan``'s springs): the quantity is dy (c + (1 - c) mean(d_i / dy)).  The
    spread and share enter as fitted where the fit moved them, else at their values.
    """
    laws = [b.get("storey_law") or {} for b in data.get("building", []) if name in ("*", b.get("name"))]
    if not laws or any(law.get("kind") != "iwan" for law in laws):
        return (lambda x, p=path: x[p]), [path]
    from ..storey.codes import IWAN_SLIDERS

    held, paths = {}, [path]
    for key in ("yield_spread", "self_centring"):
        free = next((p for p in (f"building.{name}.storey_law.{key}", f"building.*.storey_law.{key}")
                     if p in fit.parameters), None)
        if free is not None and not fit.parameters[free]["at_bound"]:
            paths.append(free)
            held[key] = free
        else:
            held[key] = float(fit.parameters[free]["value"]) if free else float(laws[0].get(key, 0.0))
    exponents = np.array([(2.0 * (i + 0.5) / IWAN_SLIDERS - 1.0) for i in range(IWAN_SLIDERS)])

    def strength_drift(x):
        s, c = (x[held[k]] if isinstance(held[k], str) else held[k] for k in ("yield_spread", "self_centring"))
        return x[path] * (c + (1.0 - c) * float(np.mean(10.0 ** (s * exponents))))

    return strength_drift, paths


def _beyond_reach(q, name, reach):
    """A yield drift that the fitted model's storeys never reach is not identified: the record shows how far
    the storeys depart from linearity below it, not where they yield.

    reach: building name -> the largest storey deformation [m] of the fitted model over the recorded motion
    (``storey_reach``); ``*`` (one yield drift for every building) takes the largest of all.  The quantity
    keeps its value, loses its standard error and says why; ``beyond_reach`` marks it, so that the physics
    itself is not called unshown for it (``api._left_out``).
    """
    if not reach or q.get("stderr") is None:
        return q
    top = max(reach.values()) if name == "*" else reach.get(name)
    if top is None or top >= q["value"]:
        return q
    return {**{k: v for k, v in q.items() if k not in ("stderr", "dof", "half68")}, "stderr": None,
            "beyond_reach": True,
            "reason": f"the fitted storeys of {'the row' if name == '*' else name} reach at most {top:.3g} m "
                      f"({100 * top / q['value']:.0f} % of it): the record shows their departure from linearity, "
                      "not where they yield"}


def storey_reach(model_data, base, channels, trials) -> dict:
    """Building name -> the largest storey deformation [m] of the model ``model_data`` over the trials' motion.

    Each trial is run as a fit's evaluation runs it (``calibrate.observe.Observer``); a storey's deformation is
    its two floors' relative displacement (on a foundation, the deformation of the storey's springs).
    """
    from ..calibrate.observe import Observer
    from ..results.floors import floor_view
    from ..simulation import run_inputs, run_row

    obs, reach = Observer(model_data, base, channels, trials), {}
    for trial in trials:
        model = obs.model_for(trial, [])
        system, motions = run_inputs(model)
        view, floors = floor_view(run_row(model, system, motions.rows, limit_contact_step=False), system)
        for b, building in enumerate(model.buildings):
            cols = np.flatnonzero(np.asarray(floors.dof_building) == b)
            if view.drift is not None:
                d = view.drift[:, cols]
            else:  # one DOF per floor, in floor order: the storey below floor f is u_f - u_(f-1), u_0 = 0
                u = view.displacement[:, cols[np.argsort(np.asarray(floors.dof_floor)[cols])]]
                d = np.diff(u, axis=1, prepend=0.0)
            top = float(np.abs(d).max()) if d.size else 0.0
            reach[building.name] = max(reach.get(building.name, 0.0), top)
    return reach


def _restitution(fit, data):
    from ..contact.restitution import restitution_from

    form = dict(data["contact"]["restitution"])
    paths = [p for p in fit.parameters if p.startswith("contact.restitution.")]

    def e_at(v):
        def f(x):
            table = dict(form)
            for p in paths:
                table[p.split(".")[-1]] = x[p]
            return float(restitution_from(table, key="contact.restitution")(v))
        return f

    out = [_delta(fit, f"e at an impact velocity of {v} m/s", "-", e_at(v), paths) for v in (0.1, 0.5)]
    # the velocity dependence itself: a constant e (the base model's, recalibrated) cannot make it
    return out + [_delta(fit, "change of e from 0.1 to 0.5 m/s", "-", lambda x: e_at(0.5)(x) - e_at(0.1)(x), paths,
                         defining=True)]


_INPUT_KEYS = (("delay", "delay of its ground motion", "s"), ("lowpass", "low-pass corner of its ground motion", "Hz"),
               ("weight", "share of the motion recorded at its base", "-"))


def _delays(fit, data):
    return [_delta(fit, f"{p.split('.')[1]}: {what}", units, lambda x, p=p: x[p], [p], defining=True)
            for key, what, units in _INPUT_KEYS for p in fit.parameters if p.endswith(f"ground_motion.{key}")]


_QUANTITIES = {"soil-structure-interaction": _soil, "distributed-mass": _rods, "inelastic-storey": _yielding,
               "velocity-dependent-restitution": _restitution, "spatially-varying-input": _delays}


def quantities(name: str, fit, reach=None) -> list[dict]:
    """The physics ``name``'s quantities from its fit (a CalibrationResult): [{name, value, stderr, units}].

    reach: for yielding storeys, building name -> the fitted model's largest storey deformation [m]
    (``storey_reach``); a yield drift beyond it is reported as not identified (``_beyond_reach``)."""
    fn = _QUANTITIES.get(name)
    if fn is None:
        return []
    try:
        data = tomllib.loads(fit.model_text)
        return fn(fit, data, reach) if fn is _yielding else fn(fit, data)
    except Exception as exc:  # noqa: BLE001 (a quantity that cannot be derived is reported, not fatal)
        return [{"name": "quantities", "value": float("nan"), "stderr": None, "units": "",
                 "reason": f"could not be derived ({type(exc).__name__}: {exc})"}]
