"""What each physics costs on the canonical row: ``python -m benchmarks.physics [--repeat 5]``.

The canonical row of three (models/row_of_three.toml, 40 s of El Centro) is run
through the whole ``simulate(model)`` (its no-pounding twin included) as it is,
then with one physics switched on at a time, then with all of them:

* yielding storeys: every storey bilinear (yield drift 1 cm, 5 % hardening);
* Bouc-Wen storeys: every storey Bouc-Wen (the same yield drift and hardening, n = 2);
* a flexible foundation under Middle (cone impedances of a 15 m x 15 m footing
  on soil of 200 m/s);
* rod floors in West (6 segments, concrete slab 20 m x 2 m^2, 2 % axial damping);
* floor-to-storey pounding: East's storeys 4 m high, so its floors strike Middle's columns.

Every case takes 32 contact substeps (given, so that each integrates once at equal settings;
at the default tolerance a run also checks itself, docs/tolerance.md).
Reported: medians of ``repeat`` interleaved rounds (each case timed on the second of two runs in a row,
``timing.warm_medians``), each case's time and its
ratio to the plain row in the same process, the driver that ran it, and the
steps it took.
"""

from __future__ import annotations

import argparse
import copy
import warnings
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]


def cases(model):
    """name -> a copy of ``model`` with that physics on."""
    from seispound.floor import RodFloor
    from seispound.foundation import Footing, Foundation, Soil
    from seispound.storey import StoreyLaw

    def yielding(m):
        for b in m.buildings:
            b.storey_law = StoreyLaw(kind="bilinear", yield_drift=0.01, post_yield_ratio=0.05)

    def bouc_wen(m):
        for b in m.buildings:
            b.storey_law = StoreyLaw(kind="bouc-wen", yield_drift=0.01, post_yield_ratio=0.05, n=2.0)

    def foundation(m):
        m.buildings[1].foundation = Foundation(mass=4e5, rotary_inertia=2e7, floor_rotary_inertia=3e6,
                                               soil=Soil(200.0, 1900.0, 0.3), footing=Footing(width=15.0, length=15.0))

    def rods(m):
        m.buildings[0].floor_model = RodFloor(segments=6, length=20.0, youngs_modulus=3e10, area=2.0,
                                              axial_damping=0.02)

    def storey_pounding(m):
        m.buildings[2].storey_heights = np.full(m.buildings[2].n_floors, 4.0)

    edits = {"plain": [], "yielding storeys": [yielding], "Bouc-Wen storeys": [bouc_wen],
             "flexible foundation": [foundation],
             "rod floors": [rods], "floor-to-storey": [storey_pounding],
             "all together": [yielding, foundation, rods, storey_pounding]}
    out = {}
    for name, fns in edits.items():
        m = copy.deepcopy(model)
        if m.analysis.newmark.contact_substeps is None:  # equal settings: each case integrates once
            m.analysis.newmark.contact_substeps = 32
        for fn in fns:
            fn(m)
        for b in m.buildings:
            b.validate()
        m.__dict__.pop("_assembled", None)
        out[name] = m
    return out


def main(argv=None) -> int:
    from seispound import load_model, simulate

    from .physics_accuracy import time_cases

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--model", default=str(REPO / "models" / "row_of_three.toml"))
    args = ap.parse_args(argv)
    models = cases(load_model(args.model))
    warnings.simplefilter("ignore")
    info = {}
    for name, m in models.items():  # compile and warm up
        ds = simulate(m)
        import json

        st = json.loads(ds.attrs["integrator_stats"])
        info[name] = (ds.attrs["driver"], st["steps"], int(ds.sizes["impact"]))
    times = time_cases(models, args.repeat, twin=True)
    base = times["plain"]
    print(f"{args.model}: whole simulate(model) with its twin, medians of {args.repeat}, one process")
    print(f"  {'case':22s} {'time [ms]':>10s} {'ratio':>7s}  driver   steps  impacts")
    for name in models:
        t = times[name]
        drv, steps, imp = info[name]
        print(f"  {name:22s} {1e3 * t:10.1f} {t / base:7.2f}  {drv:7s} {steps:6d} {imp:8d}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
