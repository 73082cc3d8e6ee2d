"""How accurate each physics is at a 5 ms step: ``python -m benchmarks.physics_accuracy [--physics a,b]``.

A 5 + 8 storey pair (1e5 kg floors, 3 m storeys, 5 % Rayleigh, Hd contact, 2 cm gap) under
1.5 x El Centro 1940 for 20 s, with one physics switched on at a time, then all together.
Each case runs ``simulate(twin=False)`` at the analysis step 5 ms and at 0.5 ms (the converged
reference); reported are the floor-acceleration NE, ||a - a_ref|| / ||a_ref|| over every floor
and the 5 ms samples, the number of impacts of each, the scheme the run used (its ``scheme`` and
``driver`` attributes) and the wall time of the 5 ms run with its ratio to the elastic row's: the
median of ``--repeat`` rounds that run every case in turn, alternating in one process, each case timed on the
second of two runs in a row (``timing.warm_medians``), so that neither the machine's drift between cases
(20-50 % within minutes here) nor the case run before enters the ratios.  Issue 29's targets: NE at most 0.5 % for each
physics alone and for all together; each physics at most 2 times the elastic row's time, all
together at most 5.  Both runs take 32 contact substeps per impact (given,
not chosen from a tolerance), so that what differs between them is the step of each physics; the
tolerance (``[analysis] tolerance``, docs/tolerance.md) speaks of peaks, not of a whole history.
"""

from __future__ import annotations

import argparse
import tempfile
import warnings
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
ROW = """
title = "accuracy of each physics"
[analysis]
dt = {dt}
duration = 20.0
contact_substeps = 32
[ground_motion]
file = "{record}"
units = "g"
scale = 1.5
[contact]
law = "Hd"
stiffness = 2.75e9
restitution = {restitution}
[[building]]
name = "A"
floors = 5
floor_masses = 1.0e5
storey_stiffness = 1.2e8
storey_heights = 3.0
damping = {{ kind = "rayleigh", ratio = 0.05, modes = [1, 2] }}
{a_extra}
[[building]]
name = "B"
floors = 8
floor_masses = 1.0e5
storey_stiffness = 1.1e8
storey_heights = {b_heights}
damping = {{ kind = "rayleigh", ratio = 0.05, modes = [1, 2] }}
{b_extra}
[[gap]]
between = ["A", "B"]
size = 0.02
"""
BILINEAR = 'storey_law = { kind = "bilinear", yield_drift = 0.008, post_yield_ratio = 0.05 }'
BOUC_WEN = 'storey_law = { kind = "bouc-wen", yield_drift = 0.008, post_yield_ratio = 0.05, n = 2 }'
PEAK = ('storey_law = { kind = "peak-oriented", yield_drift = 0.008, post_yield_ratio = 0.05, unloading_exponent = 0.4, '
        'pinching = 0.3 }')
IWAN = ('storey_law = { kind = "iwan", yield_drift = 0.008, post_yield_ratio = 0.05, yield_spread = 0.5, '
        'self_centring = 0.3 }')
FLAG = 'storey_law = { kind = "flag", yield_drift = 0.008, post_yield_ratio = 0.05, energy_dissipation = 0.6 }'
SPRINGS = ('foundation = { mass = 2e5, rotary_inertia = 2e6, floor_rotary_inertia = 5e5, sway_stiffness = 2e9, '
           'sway_damping = 4e7, rocking_stiffness = 2e11, rocking_damping = 1e9 }')
SOIL = ('foundation = { mass = 2e5, rotary_inertia = 2e6, floor_rotary_inertia = 5e5, '
        'soil = { shear_wave_velocity = 200.0, density = 1900.0, poisson = 0.3 }, '
        'footing = { width = 15.0, length = 15.0 } }')
RODS = 'floor_model = { kind = "rod", segments = 4, length = 20.0, axial_stiffness = 6e10, axial_damping = 0.02 }'
DELAY = 'ground_motion = { delay = 0.05 }'
CASES = {
    "elastic row": {},
    "e(v)": {"restitution": '{ form = "linear", e0 = 0.85, slope = 1.2, min = 0.3, max = 0.85 }'},
    "bilinear storeys": {"a": [BILINEAR], "b": [BILINEAR]},
    "Bouc-Wen storeys": {"a": [BOUC_WEN], "b": [BOUC_WEN]},
    "peak-oriented storeys": {"a": [PEAK], "b": [PEAK]},
    "Iwan storeys": {"a": [IWAN], "b": [IWAN]},
    "flag storeys": {"a": [FLAG], "b": [FLAG]},
    "foundation springs": {"b": [SPRINGS]},
    "soil and footing": {"b": [SOIL]},
    "rod floors": {"a": [RODS]},
    "floor-to-storey": {"b_heights": "3.3"},
    "delayed input": {"b": [DELAY]},
    "all together": {"a": [BILINEAR, RODS], "b": [BOUC_WEN, SOIL, DELAY], "b_heights": "3.3",
                     "restitution": '{ form = "linear", e0 = 0.85, slope = 1.2, min = 0.3, max = 0.85 }'},
}


def _text(case, dt):
    rec = REPO / "ground_motions" / "RSN6_IMPVALL.I_I-ELC180-hor1.AT2"
    return ROW.format(dt=dt, record=rec.as_posix(), restitution=case.get("restitution", "0.65"),
                      a_extra="\n".join(case.get("a", [])), b_extra="\n".join(case.get("b", [])),
                      b_heights=case.get("b_heights", "3.0"))


def run_case(name, folder, dt=0.005, ref_dt=0.0005):
    """The accuracy of case ``name`` at ``dt`` against ``ref_dt``, and its 5 ms model (warm) for the timing."""
    import seispound as sp

    out = {}
    for step in (dt, ref_dt):
        f = Path(folder) / f"{abs(hash((name, step)))}.toml"
        f.write_text(_text(CASES[name], step))
        m = sp.load_model(f)
        out[step] = (sp.simulate(m, twin=False), m)
    ds, model = out[dt]
    ref = out[ref_dt][0]
    k = int(round(dt / ref_dt))
    a = np.nan_to_num(ds["acceleration"].values)
    a_ref = np.nan_to_num(ref["acceleration"].values[::k][: a.shape[0]])
    ne = float(np.linalg.norm(a - a_ref) / np.linalg.norm(a_ref))
    return dict(case=name, ne=ne, impacts=int(ds.sizes["impact"]), impacts_ref=int(ref.sizes["impact"]),
                scheme=ds.attrs.get("scheme"), driver=ds.attrs.get("driver"), model=model)


def time_cases(models, repeat, twin=False, warm=True):
    """{case: median wall [s] of ``simulate(model, twin=twin)``} (``timing.warm_medians``: alternating rounds,
    each case timed on the second of two runs in a row; ``warm`` False: on its only run)."""
    import seispound as sp

    from .timing import warm_medians

    return warm_medians({name: (lambda m=m: sp.simulate(m, twin=twin)) for name, m in models.items()}, repeat, warm)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--physics", default=",".join(CASES), help="comma-separated case names")
    ap.add_argument("--repeat", type=int, default=7, help="rounds of timed 5 ms runs over every case (medians)")
    ap.add_argument("--cold", action="store_true",
                    help="time each case on its only run in a round, after the case before it (for comparison)")
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    print(f"{'case':20s} {'NE at 5 ms':>10s} {'impacts':>9s} {'ref':>5s}  scheme   driver   time [ms]  ratio")
    with tempfile.TemporaryDirectory() as tmp:
        names = args.physics.split(",")
        if "elastic row" not in names:  # the ratio's reference
            names = ["elastic row"] + names
        rows = []
        for name in names:
            rows.append(run_case(name, tmp))
            print(f"  {name}: accuracy run", flush=True)
        walls = time_cases({r["case"]: r["model"] for r in rows}, args.repeat, warm=not args.cold)
        base = walls["elastic row"]
        for r in rows:
            wall = walls[r["case"]]
            print(f"{r['case']:20s} {100 * r['ne']:9.2f}% {r['impacts']:9d} {r['impacts_ref']:5d}  {r['scheme']:8s} "
                  f"{r['driver']:8s} {1e3 * wall:8.1f}  {wall / base:5.2f}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
