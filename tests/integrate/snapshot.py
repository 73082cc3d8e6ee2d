"""Every output of both drivers on many rows, saved and compared bit for bit, for refactoring the loop.

``python -m tests.integrate.snapshot save FILE`` before a change of the drivers' code that must not change
a result, ``python -m tests.integrate.snapshot check FILE`` after it: it prints each array that differs
(with its largest difference relative to its largest entry) and exits 1 if any does.  The rows: every case
of ``kernel_reference.py`` under both schemes, on the fast driver as chosen and on the general driver
forced; the bundled models (`models/*.toml`: both drivers, multi-rate stepping, yielding storeys, rods);
each physics of ``benchmarks.physics`` on the canonical row (12 s); a delayed and low-passed input; initial
velocities with a gap closed at t = 0.  A regression guard of one environment (numpy, numba, the CPU),
stricter than ``test_kernel_reference.py``'s 1e-12: a refactoring keeps every bit.
"""

from __future__ import annotations

import pickle
import sys
import warnings

import numpy as np

import seispound as sp
from seispound.contact import make_law
from seispound.integrate import integrate
from seispound.model import Analysis, BuildingMotion, GroundMotionSpec, Model
from seispound.structure import Gap
from tests.integrate.kernel_reference import FIELDS, cases
from tests.verification._helpers import el_centro, shear_building

DATASET = ("displacement", "acceleration", "pounding_force", "energy")


def _raw(raw):
    out = {f: np.asarray(getattr(raw, f)) for f in FIELDS}
    out.update({f"impacts.{k}": np.asarray(v) for k, v in raw.impacts.items()})
    out["stats"] = np.array(list(raw.stats.values()))
    return out


def _dataset(ds):
    return {k: ds[k].values for k in DATASET}


def runs() -> dict:
    """case -> {output name: array}."""
    from benchmarks.physics import cases as physics

    out = {}
    for name, (system, ag, dt, nsteps, kw) in cases().items():
        for scheme in ("newmark", "exact"):
            out[f"{name}/{scheme}"] = _raw(integrate(system, ag, dt, nsteps, **{"scheme": scheme, **kw}))
            if "linear-acceleration" not in name:
                out[f"{name}/{scheme}/general"] = _raw(integrate(system, ag, dt, nsteps,
                                                                 **{"scheme": scheme, **kw, "driver": "general"}))
    for model in ("two_buildings", "row_of_three", "yielding_pair", "slab_pendulum", "slab_pendulum_rods"):
        out[model] = _dataset(sp.simulate(sp.load_model(f"models/{model}.toml")))
    for name, m in physics(sp.load_model("models/row_of_three.toml")).items():
        m.analysis.duration = min(m.analysis.duration, 12.0)
        out[f"physics/{name}"] = _dataset(sp.simulate(m))
    ag, _ = el_centro(8.0, 0.005)
    law = make_law("Hd", stiffness=5e9, restitution=0.65)
    m = Model("delayed", [shear_building("A", 4, 0.5), shear_building("B", 8, 1.0)], [Gap(("A", "B"), 0.01)], law,
              Analysis(dt=0.005, duration=8.0), ground_motion=GroundMotionSpec.from_array(ag, 0.005, units="m/s2",
                                                                                           name="El Centro"))
    m.buildings[1].ground_motion = BuildingMotion(delay=0.04, lowpass=8.0)
    out["delayed input"] = _dataset(sp.simulate(m))
    bs = [shear_building("A", 2, 0.3, v0=0.5), shear_building("B", 3, 0.4), shear_building("C", 2, 0.25, v0=-0.4)]
    m = Model("initial velocities", bs, [Gap(("A", "B"), 0.0), Gap(("B", "C"), 0.002)], law,
              Analysis(dt=0.005, duration=3.0),
              ground_motion=GroundMotionSpec.from_array(np.zeros(601), 0.005, units="m/s2", name="none"))
    out["initial velocities"] = _dataset(sp.simulate(m))
    return out


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 2 or argv[0] not in ("save", "check"):
        print(__doc__.splitlines()[2], file=sys.stderr)
        return 2
    warnings.simplefilter("ignore")
    what, path = argv
    now = runs()
    if what == "save":
        with open(path, "wb") as f:
            pickle.dump(now, f)
        print(f"saved {len(now)} cases to {path}")
        return 0
    with open(path, "rb") as f:
        ref = pickle.load(f)
    differ = 0
    for case, arrays in ref.items():
        for key, value in arrays.items():
            got = now[case][key]
            if got.shape != value.shape or not np.array_equal(got, value, equal_nan=True):
                rel = (np.nanmax(np.abs(got - value)) / max(np.nanmax(np.abs(value)), 1e-300)
                       if got.shape == value.shape else "shape")
                print(f"differs: {case} {key} {rel}")
                differ += 1
    print(f"{len(ref)} cases, {differ} arrays differ")
    return 1 if differ else 0


if __name__ == "__main__":
    raise SystemExit(main())
