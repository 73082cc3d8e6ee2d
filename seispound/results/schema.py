"""The result Dataset of one run: schema, units, provenance.

Schema ``seispound-result`` version 3 (``ds.attrs["schema_version"]``)
---------------------------------------------------------------------------
Dimensions
    time (nt), building (nb), floor (max floors; absent floors are NaN), mode (= floor count),
    gap (one per gap element = pair of floors at a common level),
    impact (one per impact, in order of onset), energy_component (6).
Coordinates
    time [s]; building (names, left to right); floor (1-based); mode (1-based);
    floor_height(building, floor) [m]; gap (0-based);
    gap_left, gap_right (building names), gap_left_floor, gap_right_floor,
    gap_height [m], gap_size [m], gap_law (name), gap_kind ("floor-to-floor" or "floor-to-storey"),
    gap_left_weight, gap_right_weight [1] (1 for a floor; for a side struck on a storey, the point's
    height above the floor below over the storey height; gap_*_floor is then the floor above);
    energy_component names.
Data variables (units in ``attrs["units"]``)
    displacement(time, building, floor) [m], relative to the ground under that building (the free field),
        +x to the right; on a flexible foundation it includes the foundation's sway and rocking
    velocity(time, building, floor) [m/s], relative to the ground under that building
    acceleration(time, building, floor) [m/s^2], absolute (ground + relative)
    drift(time, building, floor) [m], the storey's deformation: u_floor - u_floor_below (ground for
        floor 1); on a flexible foundation minus the storey height x rocking (the foundation's sway below floor 1)
    foundation_sway(time, building) [m], foundation_rocking(time, building) [rad] (NaN: a fixed base)
    node_displacement(time, building, floor, node) [m], with coordinates node and node_position(building, node)
        [m from the left face]: only when some building has rod floors; displacement, velocity and
        acceleration of a rod floor are those at its sensor, its drift the mass-weighted mean of its nodes'
    storey_force(time, building, floor) [N], the spring force of the storey below the floor: k x drift,
        or a yielding storey's force (bilinear, Bouc-Wen); dashpot force excluded
    residual_drift(building, floor) [m], drift at the end of the record
    pounding_force(time, gap) [N], compression positive, at the analysis instants
    peak_displacement(building, floor) [m], max |u| over every (sub)step
    peak_displacement_no_pounding(building, floor) [m], same, gaps disabled
    amplification(building, floor) [-], peak_displacement / peak_displacement_no_pounding
    peak_drift(building, floor) [m], max |drift| at the analysis instants
    peak_acceleration, peak_acceleration_no_pounding (building, floor) [m/s^2]: max |absolute
        floor acceleration| at the analysis instants; acceleration_amplification [1] their ratio
    peak_drift_ratio, peak_drift_ratio_no_pounding (building, floor) [1]: max |drift| / storey
        height of the storey below the floor; drift_ratio_amplification [1]
    peak_storey_shear, peak_storey_shear_no_pounding (building, floor) [N]: max |k drift| of the
        storey below the floor (spring force; dashpot excluded); storey_shear_amplification [1]
    period(building, mode) [s], fixed-base natural periods (NaN beyond a building's floors)
    (see :mod:`seispound.results.peaks`; with ``twin=False`` the no-pounding values are NaN)
    peak_pounding_force(gap) [N], over every substep
    impact_count(gap) [-]
    impact_gap(impact), impact_onset(impact) [s], impact_approach_velocity(impact) [m/s],
    impact_separation_velocity(impact) [m/s], impact_velocity_ratio(impact) [-] (separation /
    approach: an MDoF impact's apparent restitution, not the law's e),
    impact_peak_force(impact) [N], impact_duration(impact) [s], impact_damping(impact),
    impact_law_restitution(impact) [-] (the e the law's damping was set from)
    ground_acceleration(time) [m/s^2], the row's record
    base_acceleration(time, building) [m/s^2], the ground motion under each building
    base_displacement(time, building) [m], its exact integral from rest (absolute position = displacement + this)
    energy(time, energy_component) [J]: input, kinetic, strain (linear springs plus the recoverable
        energy of hysteretic storeys), damping, contact, hysteretic (dissipated by yielding storeys)
Attributes
    schema, schema_version, title, seispound_version, created_utc, model_file,
    model_text, record (JSON provenance; "none" for free vibration), contact_law,
    dt, duration, newmark_beta, newmark_gamma, scheme (the one used: "newmark" on the general driver),
    driver ("fast" or "general": ``seispound.integrate.integrate``), newmark_substeps (the general
    driver's Newmark substeps per analysis step, ``simulation.newmark_substeps``; 1 on the fast one),
    contact_step_limit (s: the longest contact substep, ``simulation.contact_step``),
    contact_substeps (per impact duration, as run), contact_substeps_from ("tolerance": chosen by
    ``simulation.contact_substeps`` from the tolerance; "model": given), tolerance (the relative
    error accepted on the peak pounding force and peak floor response), contact_error_estimate
    (the estimated relative error of one impact at those substeps, NaN when they were given:
    ``seispound.accuracy``), peak_error_estimate (the estimated relative error of the run's peaks,
    from the run at half its substeps: ``simulation.run_row``; NaN when the substeps were given or
    nothing pounded), tolerance_runs (integrations the tolerance took),
    integrator_stats (JSON), integrator_run_as (the pounding run's integrator as numba's machine code, or
    as its Python source on a first use: ``seispound._first_use``), building_ground_motion (JSON:
    each building with a motion of its own: record, delay, filter).
"""

from __future__ import annotations

import datetime as _dt
import json

import numpy as np
import xarray as xr

from .construct import dataset, variable
from .peaks import PEAKS, amplifications, dof_peaks, run_drift, storey_arrays

SCHEMA = "seispound-result"
SCHEMA_VERSION = 3

ENERGY_COMPONENTS = ["input", "kinetic", "strain", "damping", "contact", "hysteretic"]


def _per_floor(values, system, nb, nfmax):
    """Scatter DOF-indexed values (..., n) into (..., building, floor) with NaN padding."""
    values = np.asarray(values)
    out = np.full(values.shape[:-1] + (nb, nfmax), np.nan)
    out[..., system.dof_building, system.dof_floor - 1] = values
    return out


def _building_runs(system, nb):
    """[(first column, floors)] per building when each building's floors are consecutive columns from
    floor 1 up (every row the assembly writes); None otherwise."""
    b, f = system.dof_building, system.dof_floor
    runs = []
    for i in range(nb):
        cols = np.flatnonzero(b == i)
        if cols.size == 0 or np.any(np.diff(cols) != 1) or np.any(f[cols] != np.arange(1, cols.size + 1)):
            return None
        runs.append((int(cols[0]), int(cols.size)))
    return runs


def _scatter(dst, src, runs, b_of, f_of):
    """dst[:, building, floor] = src[:, column]: slice copies per building (a fancy-index scatter of
    every history cost 1 ms on the canonical row), or the general scatter."""
    if runs is None:
        dst[:, b_of, f_of] = src
        return
    for i, (c0, nf) in enumerate(runs):
        dst[:, i, :nf] = src[:, c0:c0 + nf]


class Layout:
    """What a model's result Datasets share from run to run: names, sizes, the (building, floor) layout of the
    DOFs, storey arrays, periods and the coordinates that do not depend on the run.

    ``simulate`` keeps it with the model's content (``Model.kept``), so a script, study or fit that reruns a
    model builds it once; the arrays are the layout's own and are copied into each Dataset.
    """

    def __init__(self, model, system_dofs):
        from .floors import floor_view

        system = floor_view(None, system_dofs)[1]
        self.system = system
        self.names = [b.name for b in model.buildings]
        nb = self.nb = len(self.names)
        nfmax = self.nfmax = max(b.n_floors for b in model.buildings)
        self.heights = np.full((nb, nfmax), np.nan)
        self.periods = np.full((nb, nfmax), np.nan)
        for i, b in enumerate(model.buildings):
            self.heights[i, : b.n_floors] = b.floor_heights
            self.periods[i, : b.n_floors] = b.periods
        self.runs = _building_runs(system, nb)
        self.below, self.storey_h, self.storey_k = storey_arrays(system, model.buildings)
        self.storey_k_floor = _per_floor(self.storey_k, system, nb, nfmax)
        links = system.links
        self.law_names = json.dumps(sorted({lk.law.name for lk in links}))
        self.coords = _static_coords(self.names, nfmax, self.heights, links, system.gap_size)

    def per_floor(self, values):
        """DOF-indexed values (..., n) on the (..., building, floor) layout, NaN-padded."""
        return _per_floor(values, self.system, self.nb, self.nfmax)


def _static_coords(b_names, nfmax, heights, links, gap_size) -> dict:
    """The coordinates that depend on the model alone: {name: (dims, values, attrs)}."""
    return dict(
        building=("building", np.array(b_names, dtype=object), {"long_name": "building, left to right"}),
        floor=("floor", np.arange(1, nfmax + 1), {"long_name": "floor number (1 = first above ground)"}),
        mode=("mode", np.arange(1, nfmax + 1), {"long_name": "mode number (1 = fundamental)"}),
        floor_height=(("building", "floor"), heights, {"units": "m", "long_name": "floor elevation"}),
        gap=("gap", np.arange(len(links)), {"long_name": "gap element"}),
        gap_left=("gap", np.array([b_names[lk.left] for lk in links], dtype=object),
                  {"long_name": "left building"}),
        gap_right=("gap", np.array([b_names[lk.right] for lk in links], dtype=object),
                   {"long_name": "right building"}),
        gap_left_floor=("gap", np.array([lk.left_floor for lk in links], np.int64), {"units": "1"}),
        gap_right_floor=("gap", np.array([lk.right_floor for lk in links], np.int64), {"units": "1"}),
        gap_height=("gap", np.array([lk.height for lk in links], float), {"units": "m"}),
        gap_kind=("gap", np.array([lk.kind for lk in links], dtype=object),
                  {"long_name": "floor-to-floor, or floor-to-storey (a floor against the columns between two "
                                "floors of the neighbour)"}),
        gap_left_weight=("gap", np.array([lk.left_weight for lk in links], float),
                         {"units": "1", "long_name": "1 for a floor; for a storey, the point's height above "
                                                     "the floor below / storey height"}),
        gap_right_weight=("gap", np.array([lk.right_weight for lk in links], float), {"units": "1"}),
        gap_size=("gap", np.array(gap_size, float), {"units": "m", "long_name": "at-rest gap"}),
        gap_law=("gap", np.array([lk.law.name for lk in links], dtype=object), {"long_name": "contact law"}),
    )


def build_dataset(model, system, raw, raw_twin, ground_acc, record_provenance, version, motions=None,
                  layout: Layout | None = None) -> xr.Dataset:
    """Assemble the result Dataset of one run (see the module docstring for the schema).

    ``layout``: the model's :class:`Layout`, if the caller keeps it (built here otherwise).
    """
    from .floors import floor_view, foundation_motion

    lay = Layout(model, system) if layout is None else layout
    system_dofs, raw_dofs = system, raw
    raw = floor_view(raw, system_dofs)[0]
    raw_twin = floor_view(raw_twin, system_dofs)[0]
    system = lay.system
    b_names, nb, nfmax = lay.names, lay.nb, lay.nfmax

    # the five (time, building, floor) histories share one buffer: one large
    # allocation is backed by huge pages (a few page faults instead of thousands)
    nt = raw.displacement.shape[0]
    hist = np.full((5, nt, nb, nfmax), np.nan)
    b_of, f_of = system.dof_building, system.dof_floor - 1
    u, vel, acc, drift, shear = hist
    runs = lay.runs
    _scatter(u, raw.displacement, runs, b_of, f_of)
    _scatter(vel, raw.velocity, runs, b_of, f_of)
    _scatter(acc, raw.acceleration, runs, b_of, f_of)
    # drift per DOF: floor minus the floor below (the ground below the first)
    below, storey_h, storey_k = lay.below, lay.storey_h, lay.storey_k
    drift_dof = run_drift(raw, below)
    _scatter(drift, drift_dof, runs, b_of, f_of)
    # storey force k x drift, elementwise on the (building, floor) layout (no second scatter);
    # a yielding storey's own force where there is one
    np.multiply(drift, lay.storey_k_floor, out=shear)
    if raw.storey_force is not None and raw.storey_dofs.size:
        shear[:, b_of[raw.storey_dofs], f_of[raw.storey_dofs]] = raw.storey_force
    peaks = dof_peaks(raw, below, storey_h, storey_k, drift_dof)
    peaks0 = None if raw_twin is None else dof_peaks(raw_twin, below, storey_h, storey_k)
    amps = amplifications(peaks, peaks0)
    # every per-DOF quantity onto the (building, floor) layout in one scatter
    nan = np.full(system.n_dof, np.nan)
    names = [q for q, _, _ in PEAKS]
    rows = ([peaks[q] for q in names] + [nan if peaks0 is None else peaks0[q] for q in names]
            + [amps[q] for q in names] + [peaks["residual_drift"]])
    floors = lay.per_floor(np.stack(rows))
    with_, without, amp_of = (dict(zip(names, floors[i * len(names):(i + 1) * len(names)])) for i in range(3))
    residual = floors[-1]
    peak, peak0, amp = with_["displacement"], without["displacement"], amp_of["displacement"]
    peak_drift = with_["drift"]
    engineering = {}
    for name, units, what in (("acceleration", "m/s^2", "peak |absolute floor acceleration| (analysis instants)"),
                              ("drift_ratio", "1", "peak |inter-storey drift| / storey height (storey below)"),
                              ("storey_shear", "N", "peak |storey shear| = storey spring force k x drift "
                                                    "(storey below; dashpot force excluded)")):
        engineering[f"peak_{name}"] = (with_[name], units, f"{what}, with pounding")
        engineering[f"peak_{name}_no_pounding"] = (without[name], units, f"{what}, without pounding (gaps disabled)")
        engineering[f"{name}_amplification"] = (amp_of[name], "1", f"{name.replace('_', ' ')} amplification: "
                                                "peak with pounding / peak without")
    periods = lay.periods.copy()

    base_acc, base_disp = _base_motion(motions, ground_acc, model.analysis.dt, nb)
    sway, rocking = foundation_motion(raw_dofs, system_dofs, nb)
    rods = _rod_nodes(model, system_dofs, raw_dofs, nb, nfmax)
    links = system.links
    ng = len(links)
    imp = raw.impacts
    ni = imp["gap"].size
    with np.errstate(divide="ignore", invalid="ignore"):
        velocity_ratio = np.where(imp["v0"] > 0, imp["vout"] / imp["v0"], np.nan)
    counts = np.bincount(imp["gap"], minlength=ng) if ng else np.zeros(0, int)

    def var(dims, data, units, long_name, **extra):
        return variable(dims, data, {"units": units, "long_name": long_name, **extra})

    tbf = ("time", "building", "floor")
    data_vars = dict(
        displacement=var(tbf, u, "m", "floor displacement relative to the ground (+ to the right)"),
        velocity=var(tbf, vel, "m/s",
                     "floor velocity relative to the ground"),
        acceleration=var(tbf, acc, "m/s^2",
                         "absolute floor acceleration"),
        drift=var(tbf, drift, "m", "inter-storey drift (floor minus floor below)"),
        storey_force=var(tbf, shear, "N", "storey spring force of the storey below the floor: k x drift, or a "
                                          "yielding storey's force (dashpot force excluded)"),
        residual_drift=var(("building", "floor"), residual, "m",
                           "inter-storey drift at the end of the record (permanent drift of a yielding storey)"),
        pounding_force=var(("time", "gap"), raw.force, "N", "pounding force (compression positive)"),
        peak_displacement=var(("building", "floor"), peak, "m", "peak |displacement| with pounding"),
        peak_displacement_no_pounding=var(("building", "floor"), peak0, "m",
                                          "peak |displacement| without pounding (gaps disabled)"),
        amplification=var(("building", "floor"), amp, "1",
                          "displacement amplification: peak with pounding / peak without"),
        peak_drift=var(("building", "floor"), peak_drift, "m",
                       "peak |inter-storey drift| (analysis instants)"),
        **{name: var(("building", "floor"), data, units, what) for name, (data, units, what) in engineering.items()},
        period=var(("building", "mode"), periods, "s", "fixed-base natural period"),
        peak_pounding_force=var(("gap",), raw.peak_force, "N", "peak pounding force"),
        impact_count=var(("gap",), counts.astype(np.int64), "1", "number of impacts"),
        impact_gap=var(("impact",), imp["gap"].astype(np.int64), "1", "gap element of the impact"),
        impact_onset=var(("impact",), imp["t0"], "s", "time of first contact"),
        impact_approach_velocity=var(("impact",), imp["v0"], "m/s",
                                     "relative approach velocity at first contact"),
        impact_separation_velocity=var(("impact",), imp["vout"], "m/s",
                                       "relative separation velocity when the gap reopens"),
        impact_velocity_ratio=var(("impact",), velocity_ratio, "1",
                                  "separation / approach velocity of the two floors (an MDoF impact's "
                                  "apparent restitution: storey forces act during contact, so it may lie "
                                  "outside [0, 1]; not the law's e)"),
        impact_peak_force=var(("impact",), imp["fmax"], "N", "peak force of the impact"),
        impact_duration=var(("impact",), imp["dur"], "s", "contact duration (NaN if still in contact)"),
        impact_law_restitution=var(("impact",), imp["e"], "1",
                                   "the law's coefficient of restitution e for this impact (a velocity-"
                                   "dependent restitution evaluated at the approach velocity); its damping "
                                   "was set from it"),
        impact_damping=var(("impact",), imp["zeta"], "law-dependent",
                           "damping used: zeta [N s/m^(n+1)] for Hd, LHC, Hertzdamp; "
                           "c [N s/m] for LVe, MLVe; xi-bar [-] for NIVe"),
        ground_acceleration=var(("time",), ground_acc, "m/s^2", "ground acceleration of the row's record"),
        base_acceleration=var(("time", "building"), base_acc, "m/s^2",
                              "ground acceleration under each building (the row's record unless the building "
                              "has a motion of its own)"),
        base_displacement=var(("time", "building"), base_disp, "m",
                              "ground displacement under each building (exact integral of the piecewise-linear "
                              "acceleration from rest); absolute floor position = displacement + this"),
        foundation_sway=var(("time", "building"), sway, "m",
                            "foundation sway relative to the free field (NaN: a fixed base)"),
        foundation_rocking=var(("time", "building"), rocking, "rad",
                               "foundation rocking, positive when the top moves +x (NaN: a fixed base)"),
        energy=var(("time", "energy_component"), raw.energy, "J",
                   "energy balance (relative frame): input = kinetic + strain + damping + contact + "
                   "hysteretic"),
    )
    coords = dict(time=("time", raw.time, {"units": "s", "long_name": "time"}),
                  **{k: (d, v.copy(), dict(a)) for k, (d, v, a) in lay.coords.items()},
                  impact=("impact", np.arange(ni), {"long_name": "impact number"}),
                  energy_component=("energy_component", np.array(ENERGY_COMPONENTS, dtype=object), {}))
    if rods is not None:
        disp, pos = rods
        data_vars["node_displacement"] = var(("time", "building", "floor", "node"), disp, "m",
                                             "displacement of each node of a rod floor (relative to the ground)")
        coords["node"] = ("node", np.arange(pos.shape[1]), {"long_name": "rod node, left face = 0"})
        coords["node_position"] = (("building", "node"), pos,
                                   {"units": "m", "long_name": "node position from the floor's left face"})
    nm = model.analysis.newmark
    attrs = dict(
        schema=SCHEMA,
        schema_version=SCHEMA_VERSION,
        title=model.title,
        seispound_version=version,
        created_utc=_dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
        model_file=str(model.source or ""),
        model_text=model.text or "",
        record=json.dumps(record_provenance) if record_provenance else "none",
        building_ground_motion=json.dumps({} if motions is None else {
            name: own for name, own in zip(b_names, motions.per_building) if own is not None}),
        contact_law=lay.law_names,
        dt=float(model.analysis.dt),
        duration=float(model.analysis.nsteps * model.analysis.dt),
        newmark_beta=float(nm.beta),
        newmark_gamma=float(nm.gamma),
        scheme=raw.scheme,  # what ran between impacts: "newmark" where the exact scheme had no basis
        driver=raw.driver,
        newmark_substeps=int(raw.stats.get("newmark_substeps", 1)),
        contact_step_limit=float(raw.stats.get("contact_step", np.inf)),
        contact_substeps=int(raw.stats.get("contact_substeps", _given(nm.contact_substeps))),
        contact_substeps_from="tolerance" if nm.contact_substeps is None else "model",
        tolerance=float(model.analysis.tolerance),
        contact_error_estimate=float(raw.stats.get("contact_error_estimate", np.nan)),
        peak_error_estimate=float(raw.stats.get("peak_error_estimate", np.nan)),
        tolerance_runs=int(raw.stats.get("tolerance_runs", 1)),
        integrator_stats=json.dumps(raw.stats),
        integrator_run_as=("Python: the integrator's source, run while numba compiled it (its first use)"
                           if raw.stats.get("interpreted") else "numba machine code"),
        sign_convention="x positive from left building to right; penetration = u_left - u_right - gap",
    )
    return dataset(data_vars, coords, attrs)


def _given(n):
    from ..integrate.settings import DEFAULT_CONTACT_SUBSTEPS

    return DEFAULT_CONTACT_SUBSTEPS if n is None else int(n)


def _rod_nodes(model, system, raw, nb, nfmax):
    """(displacement (nt, nb, nfmax, nodes), position (nb, nodes)) of the rod floors' nodes, or None if none."""
    out = system.outputs
    if out is None or not any(out.nodes):
        return None
    nn = max(len(x) for x in out.nodes)
    disp = np.full((raw.displacement.shape[0], nb, nfmax, nn), np.nan)
    pos = np.full((nb, nn), np.nan)
    for r, dofs in enumerate(out.nodes):
        if dofs:
            b, f = out.building[r], out.floor[r] - 1
            disp[:, b, f, :len(dofs)] = raw.displacement[:, dofs]
            rod = model.buildings[b].floor_model
            pos[b, :len(dofs)] = np.linspace(0.0, rod.length, len(dofs))
    return disp, pos


def _base_motion(motions, ground_acc, dt, nb):
    """Ground acceleration and displacement under each building, two (nt, nb) arrays."""
    from ..motion.spatial import ground_motion_integrals

    rows = np.atleast_2d(ground_acc) if motions is None else motions.rows
    row_of = np.zeros(nb, np.int64) if motions is None else motions.row_of
    _, ug = ground_motion_integrals(rows, dt)
    return np.ascontiguousarray(rows[row_of].T), np.ascontiguousarray(ug[row_of].T)
