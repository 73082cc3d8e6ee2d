"""The general driver's free flight (``integrate/transition.py``) against its off switch.

With the Newmark scheme the free-flight map of an analysis step composes the very Newmark substeps the
physical path takes, so the two runs integrate the same discrete equations: they must agree to round-off,
through every impact and every yield (a step the screen let through although a gap closed or a storey
yielded in it would be stepped as linear and show here).  With the exact scheme the steps without events
are exact; what that buys is measured in ``tests/verification`` and ``benchmarks.physics_accuracy``.
"""

from pathlib import Path

import numpy as np
import pytest

from seispound import load_model
from seispound.floor import RodFloor
from seispound.foundation import Footing, Foundation, Soil
from seispound.integrate import integrate
from seispound.integrate.settings import Newmark
from seispound.simulation import newmark_substeps, run_inputs
from seispound.storey import StoreyLaw

ROW = Path(__file__).resolve().parents[2] / "models" / "row_of_three.toml"


def _yielding(m):
    for b in m.buildings:
        b.storey_law = StoreyLaw(kind="bilinear", yield_drift=0.01, post_yield_ratio=0.05)


def _iwan(m):
    for b in m.buildings:
        b.storey_law = StoreyLaw(kind="iwan", yield_drift=0.01, post_yield_ratio=0.05, yield_spread=0.5,
                                 self_centring=0.3)


def _flag(m):
    for b in m.buildings:
        b.storey_law = StoreyLaw(kind="flag", yield_drift=0.01, post_yield_ratio=0.05, energy_dissipation=0.6)


def _foundation(m):
    m.buildings[1].foundation = Foundation(mass=4e5, rotary_inertia=2e7, floor_rotary_inertia=3e6,
                                           soil=Soil(200.0, 1900.0, 0.3), footing=Footing(width=15.0, length=15.0))


def _storey_pounding(m):
    m.buildings[2].storey_heights = np.full(m.buildings[2].n_floors, 4.0)


def _rods(m):
    m.buildings[0].floor_model = RodFloor(segments=2, length=20.0, youngs_modulus=3e10, area=2.0, axial_damping=0.02)


EDITS = {"yielding storeys": [_yielding], "foundation": [_foundation], "floor-to-storey": [_storey_pounding],
         "yielding on a foundation, floor-to-storey": [_yielding, _foundation, _storey_pounding],
         "yielding with rod floors": [_yielding, _rods], "Iwan storeys": [_iwan], "flag storeys": [_flag]}


def _case(name, seconds=12.0):
    m = load_model(ROW)
    m.analysis.duration = seconds
    for edit in EDITS[name]:
        edit(m)
    for b in m.buildings:
        b.validate()
    m.__dict__.pop("_assembled", None)
    system, motions = run_inputs(m)
    return m, system, motions.rows


def _rel(a, b):
    return float(np.abs(a - b).max() / max(np.abs(b).max(), 1e-300))


@pytest.mark.parametrize("name", list(EDITS))
def test_newmark_free_flight_equals_the_physical_path(name):
    m, system, rows = _case(name)
    an, nm = m.analysis, Newmark(contact_substeps=32)
    kw = dict(substeps=newmark_substeps(m, system), scheme="newmark")
    on = integrate(system, rows, an.dt, an.nsteps, nm, **kw)
    off = integrate(system, rows, an.dt, an.nsteps, nm, free_flight=False, **kw)
    assert on.driver == off.driver == "general"
    assert on.stats["free_flight_steps"] > an.nsteps // 4 and off.stats["free_flight_steps"] == 0
    assert on.impacts["gap"].size > 10
    errs = {k: _rel(getattr(on, k), getattr(off, k))
            for k in ("displacement", "velocity", "acceleration", "energy", "force")}
    if on.storey_force is not None and on.storey_force.size:
        errs["storey force"] = _rel(on.storey_force, off.storey_force)
    print(f"MEASURED {name}: free flight {on.stats['free_flight_steps']} of {an.nsteps} steps, "
          f"{on.impacts['gap'].size} impacts; on vs off", {k: f"{v:.1e}" for k, v in errs.items()})
    # measured at most 6e-12 (accelerations, through ~100 impacts and the yields); round-off, ~5x
    assert max(errs.values()) <= 3e-11, errs
    # peaks: free flight reads them at the analysis steps, the physical path at every Newmark substep
    peak = on.peak_displacement / off.peak_displacement - 1
    print(f"MEASURED {name}: peak displacements, free flight against every substep: {peak.min():.1e} .. {peak.max():.1e}")
    assert peak.max() <= 1e-12 and peak.min() >= -5e-4  # measured down to -2.2e-4
    np.testing.assert_array_equal(on.impacts["gap"], off.impacts["gap"])
    np.testing.assert_allclose(on.impacts["t0"], off.impacts["t0"], rtol=0, atol=1e-9)


def test_exact_free_flight_keeps_the_energy_balance():
    """Exact free flight with yielding storeys on a foundation: the balance closes to round-off (the storeys'
    work is exact while they are elastic, the dampers' follows from the balance, the physical path's from
    the trapezoidal rule)."""
    m, system, rows = _case("yielding on a foundation, floor-to-storey")
    an = m.analysis
    raw = integrate(system, rows, an.dt, an.nsteps, Newmark(contact_substeps=32),
                    substeps=newmark_substeps(m, system), scheme="exact")
    assert raw.scheme == "exact" and raw.stats["free_flight_steps"] > an.nsteps // 4
    e = raw.energy
    balance = np.abs(e[:, 0] - e[:, 1:].sum(axis=1)).max() / np.abs(e[:, 0]).max()
    print(f"MEASURED exact free flight, yielding on a foundation: energy balance {balance:.1e}, "
          f"hysteretic {e[-1, 5]:.4g} J")
    assert balance <= 1e-12  # measured 2.5e-14 on the 40 s row: round-off
    assert e[-1, 5] > 0.0


@pytest.mark.parametrize("law", [dict(kind="bouc-wen", n=2.0),
                                 dict(kind="peak-oriented", unloading_exponent=0.4, pinching=0.3),
                                 dict(kind="flag", energy_dissipation=0.6),
                                 dict(kind="iwan", yield_spread=0.5, self_centring=0.3)],
                         ids=["bouc-wen", "peak-oriented", "flag", "iwan"])
def test_hysteretic_storeys_fly_free_with_their_offsets_iterated(law):
    """A smooth hysteresis has no elastic range, and a peak-oriented one leaves it at its first yield: their
    storeys fly free with their offset forces iterated within each step (``_general_flight._hysteretic_flight``;
    a peak-oriented storey whose slope changes inside the step sends it to the physical path), and so does a flag
    storey on a branch of its flag, and an Iwan storey once a spring has left its elastic range; the scheme says
    exact, and the off switch puts those steps back on the physical path (their accuracy against the twins:
    ``tests/verification/test_yielding_storeys``, ``test_peak_oriented_storeys``, ``test_flag_storeys``,
    ``test_iwan_storeys``)."""
    m, system, rows = _case("yielding storeys", seconds=6.0 if law["kind"] in ("flag", "iwan") else 2.0)
    for b in m.buildings:
        b.storey_law = StoreyLaw(yield_drift=0.01, post_yield_ratio=0.05, **law)
        b.validate()
    m.__dict__.pop("_assembled", None)
    system, motions = run_inputs(m)
    args = (system, motions.rows, m.analysis.dt, m.analysis.nsteps, Newmark(contact_substeps=32))
    on, off = integrate(*args), integrate(*args, hysteretic_flight=False)
    print(f"MEASURED {law['kind']}: free-flight steps {on.stats['free_flight_steps']} and "
          f"{off.stats['free_flight_steps']} (off) of {m.analysis.nsteps}")
    assert on.stats["free_flight_steps"] >= 0.5 * m.analysis.nsteps and on.scheme == "exact"
    newmark = integrate(*args, scheme="newmark").stats["free_flight_steps"]  # the Newmark scheme: no iterated terms
    if law["kind"] in ("flag", "iwan"):  # off, such a storey still flies free inside its window, and only there
        assert newmark == off.stats["free_flight_steps"] < on.stats["free_flight_steps"] - 0.05 * m.analysis.nsteps
    else:
        assert newmark == off.stats["free_flight_steps"] == 0 and off.scheme == "newmark"


@pytest.mark.parametrize("law, limits, rtols", [(None, (2e-6, 2.5e-9), (1e-10, 1e-14)),
                                                (dict(kind="peak-oriented", unloading_exponent=0.4, pinching=0.3),
                                                 (1.5e-8, 3e-12), (1e-10, 1e-14)),
                                                (dict(kind="iwan", yield_spread=0.5, self_centring=0.3), (2.5e-8, 8e-13),
                                                 (1e-10, 1e-14)),
                                                (dict(kind="flag", energy_dissipation=0.6), (1.2e-4, 3e-8),
                                                 (1e-8, 1e-12))],
                         ids=["bilinear", "peak-oriented", "iwan", "flag"])
def test_the_elastic_predictor_agrees_to_the_newton_tolerance(law, limits, rtols):
    """Bilinear, peak-oriented or Iwan storeys tried at their elastic stiffness inside the linear part (Newton on the
    closed gaps alone) against the storeys always in the Newton iteration: the same equations solved by two
    Newton paths, so they agree to the tolerance ``rtol`` (amplified by pounding's sensitivity to where an
    impact lands), and the difference falls as ``rtol`` does."""
    m, system, rows = _case("yielding storeys")
    if law is not None:
        for b in m.buildings:
            b.storey_law = StoreyLaw(yield_drift=b.storey_law.yield_drift,
                                     post_yield_ratio=b.storey_law.post_yield_ratio, **law)
            b.validate()
        m.__dict__.pop("_assembled", None)
        system, motions = run_inputs(m)
        rows = motions.rows
    an = m.analysis
    kw = dict(substeps=newmark_substeps(m, system), scheme="newmark")
    diffs = []
    for rtol in rtols:
        nm = Newmark(contact_substeps=32, rtol=rtol)
        on = integrate(system, rows, an.dt, an.nsteps, nm, **kw)
        off = integrate(system, rows, an.dt, an.nsteps, nm, elastic_predictor=False, **kw)
        np.testing.assert_array_equal(on.impacts["gap"], off.impacts["gap"])
        diffs.append(max(_rel(on.displacement, off.displacement), _rel(on.acceleration, off.acceleration)))
        print(f"MEASURED elastic predictor on vs off, rtol {rtol:g}: {diffs[-1]:.1e} "
              f"(Newton iterations {on.stats['iterations']} vs {off.stats['iterations']})")
    # measured on 12 s of the yielding row: bilinear 9.5e-7 and 8.8e-10, peak-oriented 6.1e-9 and 1.2e-12, Iwan
    # 9.0e-9 and 2.8e-13 (3.8e-5 at both tolerances while the test read an Iwan storey's tangent alone: a
    # committed point beyond +-dy, the self-centring spring saturated, came back inside at another force); flag
    # (beta 0.6) 4.6e-5 and 1.1e-8 at 1e-8 and 1e-12 (5.3e-8 and 1.2e-9 at 1e-10 and 1e-14: the floor near 1e-9
    # that the bilinear row also reaches at 1e-14, round-off amplified through 103 impacts, comes sooner)
    assert diffs[0] <= limits[0] and diffs[1] <= limits[1] and diffs[1] < diffs[0] / 100


def test_a_stiffly_damped_row_flies_free_exactly():
    """A dashpot that damps a mode by e^-12500 per step (a sway dashpot of 1e12 N s/m): the exact maps need
    only decaying exponentials (``transition._exact_maps``), so the row flies free exactly and its energy
    balance closes to round-off."""
    m = load_model(ROW)
    m.analysis.duration = 2.0
    m.buildings[1].foundation = Foundation(mass=4e5, rotary_inertia=2e7, sway_stiffness=1e9, sway_damping=1e12,
                                           rocking_stiffness=1e11, rocking_damping=0.0)
    m.buildings[1].validate()
    m.__dict__.pop("_assembled", None)
    system, motions = run_inputs(m)
    raw = integrate(system, motions.rows, m.analysis.dt, m.analysis.nsteps, Newmark(contact_substeps=32))
    e = raw.energy
    balance = np.abs(e[:, 0] - e[:, 1:].sum(axis=1)).max() / np.abs(e[:, 0]).max()
    print(f"MEASURED e^-12500 per step: {raw.stats['free_flight_steps']} of {m.analysis.nsteps} steps in free "
          f"flight, energy balance {balance:.1e}")
    assert raw.scheme == "exact" and raw.stats["free_flight_steps"] > m.analysis.nsteps // 2
    assert np.all(np.isfinite(raw.displacement)) and balance <= 1e-12
