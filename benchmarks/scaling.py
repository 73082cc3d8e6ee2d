"""How the cost of a run grows with the number of DOFs and with the record length.

``python -m benchmarks.scaling`` times the pounding kernel (histories kept) and a
bare linear Newmark loop of the same size, medians of 5 in this process, for

* rows of 1-4 buildings of 10-100 storeys (10 to 400 DOFs), 20 s of El Centro
  180 at dt = 0.005 s, law Hd, gaps 2 cm;
* rows of k = 1-16 pairs of buildings (10 storeys, T1 = 1.0 and 0.8 s, a
  2 cm gap inside each pair, none between pairs; 20 to 320 DOFs), once with
  identical pairs (every pair collides at the same instants: the collisions
  grow with the row) and once with each pair's periods scaled by 1 + 0.05 p
  (the pairs collide at different times);
* the canonical row of three (26 DOFs) under 10, 20, 40 and 80 s of motion
  (El Centro 180 repeated end to end).

It prints the cost per DOF per analysis step of both, their ratio (``x bare``), the steps
taken by the stepping buildings (contact substeps included), the attempts (steps
taken plus steps redone to land on an event or after a Newton failure), the
work (``stats["dof_steps"]``: every step of every building, accepted or redone,
waiting and free-flight steps included, weighted by its DOFs, per DOF per
analysis step: 1 for a bare loop) and the cost per unit of that work, also
as a ratio to the bare loop's cost per DOF-step (``work x bare``; ``taken x
bare`` per step taken for the record lengths).  Linear growth shows as a flat
cost per DOF-step; a cost per unit of work that stays flat while the cost per
DOF-step grows says the growth is in the number of steps (impacts, substeps,
located events), not in the cost of each.
"""

from __future__ import annotations

import argparse
import numpy as np

from seispound import load_model
from benchmarks._bare import bare_newmark
from seispound.contact import make_law
from seispound.integrate import integrate
from seispound.motion import read_record
from benchmarks.canonical import _median_time
from seispound.motion.catalogue import bundled_path
from seispound.structure import Building, Gap, RayleighDamping, assemble

from .peer.cases import uniform_storey_stiffness

PERIOD_PER_STOREY = 0.1  # s: T1 ~ 0.1 N, a common rule of thumb for frames


def _row(n_buildings: int, storeys: int):
    """n_buildings of ``storeys`` storeys, T1 = 0.1 N x (1, 0.8, 1.2, 0.9)[i], floor mass 1e5 kg."""
    factors = (1.0, 0.8, 1.2, 0.9)
    bs = []
    for i in range(n_buildings):
        T = PERIOD_PER_STOREY * storeys * factors[i % 4]
        k = uniform_storey_stiffness(1e5, storeys, T)
        bs.append(Building(f"B{i + 1}", [1e5] * storeys, [k] * storeys, [3.0] * storeys,
                           RayleighDamping(0.05, (1, 2))))
    gaps = [Gap((a.name, b.name), 0.02) for a, b in zip(bs, bs[1:])]
    return assemble(bs, gaps, make_law("Hd", stiffness=2.75e9, restitution=0.65))


def pairs(k: int, identical: bool):
    """k pairs A_p | B_p of 10 storeys (T1 = 1.0 and 0.8 s, times 1 + 0.05 p unless identical), gaps 2 cm."""
    bs, gaps = [], []
    for p in range(k):
        f = 1.0 if identical else 1.0 + 0.05 * p
        a, b = (Building(f"{x}{p}", [1e5] * 10, [uniform_storey_stiffness(1e5, 10, T * f)] * 10, [3.0] * 10,
                         RayleighDamping(0.05, (1, 2))) for x, T in (("A", 1.0), ("B", 0.8)))
        bs += [a, b]
        gaps.append(Gap((a.name, b.name), 0.02))
    return assemble(bs, gaps, make_law("Hd", stiffness=2.75e9, restitution=0.65))


def _ground(duration: float, dt: float) -> tuple[np.ndarray, int]:
    rec = read_record(bundled_path("elcentro_180"))
    acc = np.asarray(rec.acceleration)
    nsteps = int(round(duration / dt))
    t = np.arange(nsteps + 1) * dt
    reps = int(np.ceil(duration / (acc.size * rec.dt))) + 1
    tiled = np.tile(acc, reps)
    return np.interp(t, np.arange(tiled.size) * rec.dt, tiled), nsteps


def _time(fn, repeat):
    fn()  # compile / warm up
    return _median_time(fn, repeat)


def measure(system, ag, dt, nsteps, repeat=5) -> dict:
    out = np.empty((nsteps + 1, system.n_dof))
    ds = nsteps * system.n_dof
    raw = integrate(system, ag, dt, nsteps)
    t_run = _time(lambda: integrate(system, ag, dt, nsteps), repeat)
    t_bare = _time(lambda: bare_newmark(system.mass, system.dof_a0, system.el_i, system.el_j, system.el_k,
                                        system.el_a1, system.bandwidth, ag, dt, nsteps, 0.25, 0.5, out), repeat)
    return dict(n_dof=system.n_dof, nsteps=nsteps, impacts=int(raw.impacts["gap"].size),
                steps_taken=raw.stats["steps"], free_flight=raw.stats["free_flight_steps"],
                attempts=raw.stats["steps"] + raw.stats["rejected"],
                ns_per_dof_attempt=t_run / ((raw.stats["steps"] + raw.stats["rejected"]) * system.n_dof) * 1e9,
                work=raw.stats["dof_steps"] / ds, ns_per_work=t_run / raw.stats["dof_steps"] * 1e9,
                run_s=t_run, bare_s=t_bare, ns_per_dof_step=t_run / ds * 1e9,
                ns_per_dof_step_taken=t_run / (raw.stats["steps"] * system.n_dof) * 1e9,
                bare_ns_per_dof_step=t_bare / ds * 1e9, ratio=t_run / t_bare)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.scaling", description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args(argv)
    dt = 0.005
    print("cost against the number of DOFs (20 s of El Centro 180, dt 0.005 s, Hd, gaps 2 cm)")
    print(f"{'row':>14} {'DOFs':>5} {'impacts':>7} {'steps':>7} {'free':>6} {'attempts':>8} {'run ms':>8} "
          f"{'ns/DOF-step':>11} {'work':>5} {'per work':>8} {'bare ns':>8} {'x bare':>6} "
          f"{'work x bare':>11}")
    ag, nsteps = _ground(20.0, dt)
    for nb, ns in ((1, 10), (2, 10), (4, 10), (4, 25), (4, 50), (4, 100)):
        r = measure(_row(nb, ns), ag, dt, nsteps, args.repeat)
        print(f"{f'{nb} x {ns}':>14} {r['n_dof']:5d} {r['impacts']:7d} {r['steps_taken']:7d} {r['free_flight']:6d} "
              f"{r['attempts']:8d} {r['run_s'] * 1e3:8.2f} {r['ns_per_dof_step']:11.1f} "
              f"{r['work']:5.2f} {r['ns_per_work']:8.1f} "
              f"{r['bare_ns_per_dof_step']:8.1f} {r['ratio']:6.2f} "
              f"{r['ns_per_work'] / r['bare_ns_per_dof_step']:11.2f}", flush=True)
    for identical in (True, False):
        print(f"\ncost against the number of buildings: rows of k pairs, {'identical' if identical else 'different'}"
              f" (20 s of El Centro 180, dt 0.005 s, Hd, gaps 2 cm)")
        print(f"{'pairs':>14} {'DOFs':>5} {'impacts':>7} {'steps':>7} {'free':>6} {'attempts':>8} {'run ms':>8} "
              f"{'ns/DOF-step':>11} {'work':>5} {'per work':>8} {'bare ns':>8} {'x bare':>6} "
          f"{'work x bare':>11}")
        for k in (1, 2, 4, 8, 16):
            r = measure(pairs(k, identical), ag, dt, nsteps, args.repeat)
            print(f"{k:>14} {r['n_dof']:5d} {r['impacts']:7d} {r['steps_taken']:7d} {r['free_flight']:6d} "
                  f"{r['attempts']:8d} {r['run_s'] * 1e3:8.2f} {r['ns_per_dof_step']:11.1f} "
                  f"{r['work']:5.2f} {r['ns_per_work']:8.1f} "
                  f"{r['bare_ns_per_dof_step']:8.1f} {r['ratio']:6.2f} "
              f"{r['ns_per_work'] / r['bare_ns_per_dof_step']:11.2f}", flush=True)
    print("\ncost against the record length (canonical row of three, 26 DOFs)")
    print(f"{'seconds':>8} {'steps':>6} {'impacts':>7} {'run ms':>8} {'ns/DOF-step':>11} {'per taken':>9} "
          f"{'x bare':>6} {'taken x bare':>12}")
    from benchmarks.canonical import CANONICAL

    m = load_model(CANONICAL)
    system = assemble(m.buildings, m.gaps, m.contact)
    for seconds in (10.0, 20.0, 40.0, 80.0):
        ag, nsteps = _ground(seconds, dt)
        r = measure(system, ag, dt, nsteps, args.repeat)
        print(f"{seconds:8.0f} {nsteps:6d} {r['impacts']:7d} {r['run_s'] * 1e3:8.2f} {r['ns_per_dof_step']:11.1f} "
              f"{r['ns_per_dof_step_taken']:9.1f} {r['ratio']:6.2f} "
              f"{r['ns_per_dof_step_taken'] / r['bare_ns_per_dof_step']:12.2f}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
