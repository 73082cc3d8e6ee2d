"""Benchmark of the canonical case: ``python -m benchmarks.canonical``.

Canonical case (issue 2, item 11): a row of three buildings (8, 12 and 6
storeys, floor mass 1e5 kg, T1 = 0.8, 1.2 and 0.6 s), 40 s of the bundled El
Centro 1940 record at dt = 0.005 s, law Hd, gaps 2 cm, with the automatic
no-pounding twin: ``models/row_of_three.toml``.

Reported: medians of 5 runs after compilation, of (a) one run = pounding
kernel + no-pounding twin kernel, (b) each kernel alone, (c) the full
``simulate`` (record reading and Dataset assembly included), next to (d) a bare
linear Newmark loop of the same size (same banded factor and solve, nothing
else) in the same process, and the ratios to (d).
"""

from __future__ import annotations

import argparse
import json
import statistics
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parent.parent
CANONICAL = REPO / "models" / "row_of_three.toml"


def _median_time(fn, repeat):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def run_benchmark(model_path=CANONICAL, repeat: int = 5) -> dict:
    """Time the canonical case; return the figures in seconds and ratios."""
    from seispound import load_model, simulate
    from benchmarks._bare import bare_newmark
    from seispound.integrate import integrate
    from seispound.simulation import prepare_ground_motion
    from seispound.structure import assemble

    model = load_model(model_path)
    an = model.analysis
    system = assemble(model.buildings, model.gaps, model.contact)
    twin = system.without_contact()
    ag, _ = prepare_ground_motion(model)
    out = np.empty((an.nsteps + 1, system.n_dof))
    nmk = an.newmark

    def pound():
        return integrate(system, ag, an.dt, an.nsteps, nmk)

    def no_pound():  # as simulate() runs it: with histories (its peak accelerations, drifts, shears)
        return integrate(twin, ag, an.dt, an.nsteps, nmk)

    def bare():
        bare_newmark(system.mass, system.dof_a0, system.el_i, system.el_j, system.el_k, system.el_a1,
                     system.bandwidth, ag, an.dt, an.nsteps, nmk.beta, nmk.gamma, out)

    cases = {"pound": pound, "twin": no_pound, "run": lambda: (pound(), no_pound()), "bare": bare,
             "simulate": lambda: simulate(model)}
    # compile (or load numba's cache) and warm up before timing
    raw = pound()
    for fn in cases.values():
        fn()
    # interleaved rounds: a slow spell of the machine hits every case alike
    times = {name: [] for name in cases}
    for _ in range(repeat):
        for name, fn in cases.items():
            times[name].append(_median_time(fn, 1))
    t_pound, t_twin, t_run, t_bare, t_sim = (statistics.median(times[k])
                                             for k in ("pound", "twin", "run", "bare", "simulate"))
    return dict(
        model=str(model_path), n_dof=system.n_dof, n_gap=system.n_gap, nsteps=an.nsteps, dt=an.dt,
        repeat=repeat, impacts=int(raw.impacts["gap"].size), steps_taken=raw.stats["steps"],
        free_flight_steps=raw.stats["free_flight_steps"], rejected_steps=raw.stats["rejected"],
        run_s=t_run, pounding_kernel_s=t_pound, twin_kernel_s=t_twin, simulate_s=t_sim, bare_loop_s=t_bare,
        run_over_bare=t_run / t_bare, pounding_over_bare=t_pound / t_bare, twin_over_bare=t_twin / t_bare,
        ns_per_dof_step_bare=t_bare / (an.nsteps * system.n_dof) * 1e9,
        ns_per_dof_step_twin=t_twin / (an.nsteps * system.n_dof) * 1e9,
        # per step actually taken (contact substeps and located steps included)
        ns_per_dof_step_taken_pounding=t_pound / (raw.stats["steps"] * system.n_dof) * 1e9,
    )


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.canonical", description=__doc__.split("\n\n")[0])
    ap.add_argument("--model", default=str(CANONICAL), help="model file (default: the canonical row of three)")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--json", action="store_true", help="print the figures as JSON")
    args = ap.parse_args(argv)
    r = run_benchmark(args.model, args.repeat)
    if args.json:
        print(json.dumps(r, indent=2))
        return 0
    ms = 1e3
    print(f"canonical case: {r['n_dof']} DOFs, {r['n_gap']} gap elements, {r['nsteps']} steps of "
          f"{r['dt']} s; {r['impacts']} impacts, {r['steps_taken']} steps taken with contact substeps "
          f"({r['free_flight_steps']} of them in free flight, {r['rejected_steps']} redone to locate events)")
    print(f"medians of {r['repeat']} runs after compilation:")
    print(f"  run (pounding + no-pounding twin) {r['run_s'] * ms:8.2f} ms   {r['run_over_bare']:5.2f} x bare loop")
    print(f"  pounding kernel alone             {r['pounding_kernel_s'] * ms:8.2f} ms   "
          f"{r['pounding_over_bare']:5.2f} x bare loop")
    print(f"  no-pounding twin kernel alone     {r['twin_kernel_s'] * ms:8.2f} ms   "
          f"{r['twin_over_bare']:5.2f} x bare loop")
    print(f"  simulate() incl. record + Dataset {r['simulate_s'] * ms:8.2f} ms")
    print(f"  bare linear Newmark loop          {r['bare_loop_s'] * ms:8.2f} ms   "
          f"({r['ns_per_dof_step_bare']:.1f} ns per DOF per step; twin {r['ns_per_dof_step_twin']:.1f}; "
          f"pounding kernel {r['ns_per_dof_step_taken_pounding']:.1f} per DOF per step taken, "
          f"{r['ns_per_dof_step_taken_pounding'] / r['ns_per_dof_step_bare']:.2f} x bare)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
