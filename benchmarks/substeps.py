"""What the contact substeps buy and cost on the canonical case.

``python -m benchmarks.substeps`` runs the canonical row of three (the case of
``python -m benchmarks.canonical``) with ``contact_substeps`` = 8 ... 128 and, for
each, prints

* the steps taken and the impacts found;
* the time of a run (pounding run + no-pounding twin) and of the bare linear
  Newmark loop, medians of 5 interleaved rounds in this process, and their ratio;
* the error of the peak pounding force of every gap and of the peak
  displacement of every floor against a reference run with 512 substeps.

* the cost of an impact: the pounding run's time beyond the same row's no-pounding
  run, per impact, and the steps taken per impact beyond the analysis steps.

It shows where the time of a run goes: the substeps inside impacts are only
part of it, so cutting them (and accuracy with them) buys little speed.
"""

from __future__ import annotations

import argparse
import dataclasses
import statistics

import numpy as np

from seispound import load_model
from benchmarks._bare import bare_newmark
from benchmarks.canonical import CANONICAL, _median_time
from seispound.integrate import integrate
from seispound.simulation import prepare_ground_motion
from seispound.structure import assemble

REFERENCE_SUBSTEPS = 512


def run(substeps=(8, 12, 16, 24, 32, 64, 128), repeat: int = 5) -> list[dict]:
    model = load_model(CANONICAL)
    an = model.analysis
    system = assemble(model.buildings, model.gaps, model.contact)
    twin = system.without_contact()
    ag, _ = prepare_ground_motion(model)
    out = np.empty((an.nsteps + 1, system.n_dof))

    def bare():
        bare_newmark(system.mass, system.dof_a0, system.el_i, system.el_j, system.el_k, system.el_a1,
                     system.bandwidth, ag, an.dt, an.nsteps, an.newmark.beta, an.newmark.gamma, out)

    def pound(nmk):
        return integrate(system, ag, an.dt, an.nsteps, nmk)

    def no_pound():
        return integrate(twin, ag, an.dt, an.nsteps, an.newmark, store_history=False)

    ref = pound(dataclasses.replace(an.newmark, contact_substeps=REFERENCE_SUBSTEPS))
    hit = ref.peak_force > 0
    rows = []
    for ns in substeps:
        nmk = dataclasses.replace(an.newmark, contact_substeps=ns)
        r = pound(nmk)
        bare()
        no_pound()
        t_run, t_bare, t_pound, t_free = [], [], [], []
        for _ in range(repeat):
            t_bare.append(_median_time(bare, 1))
            t_run.append(_median_time(lambda: (pound(nmk), no_pound()), 1))
            t_pound.append(_median_time(lambda: pound(nmk), 1))
            t_free.append(_median_time(no_pound, 1))
        n_imp = max(int(r.impacts["gap"].size), 1)
        rows.append(dict(
            # what an impact costs: the pounding run beyond the same row never touching, per impact
            per_impact_s=(statistics.median(t_pound) - statistics.median(t_free)) / n_imp,
            steps_per_impact=(r.stats["steps"] - an.nsteps) / n_imp,
            substeps=ns, steps=r.stats["steps"], impacts=int(r.impacts["gap"].size),
            impacts_ref=int(ref.impacts["gap"].size),
            run_s=statistics.median(t_run), bare_s=statistics.median(t_bare),
            ratio=statistics.median(t_run) / statistics.median(t_bare),
            peak_force_err=float(np.max(np.abs(r.peak_force[hit] / ref.peak_force[hit] - 1.0))),
            peak_disp_err=float(np.max(np.abs(r.peak_displacement / ref.peak_displacement - 1.0))),
        ))
    return rows


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.substeps", description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args(argv)
    print(f"canonical case ({CANONICAL.name}); errors against {REFERENCE_SUBSTEPS} contact substeps")
    print(f"{'substeps':>8} {'steps':>6} {'impacts':>8} {'run ms':>7} {'bare ms':>8} {'ratio':>6} "
          f"{'peak force err':>15} {'peak disp err':>14} {'steps/impact':>13} {'us/impact':>10}")
    for r in run(repeat=args.repeat):
        print(f"{r['substeps']:8d} {r['steps']:6d} {r['impacts']:4d}/{r['impacts_ref']:<3d} {r['run_s'] * 1e3:7.2f} "
              f"{r['bare_s'] * 1e3:8.2f} {r['ratio']:6.2f} {r['peak_force_err'] * 100:14.3f}% "
              f"{r['peak_disp_err'] * 100:13.3f}% {r['steps_per_impact']:13.1f} {r['per_impact_s'] * 1e6:10.1f}",
              flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
