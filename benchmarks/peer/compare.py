"""Compare seispound with OpenSees on the peer cases: agreement, convergence, speed.

``python -m benchmarks.peer.compare`` runs every case of
:func:`benchmarks.peer.cases.benchmark_cases` and writes ``docs/peer.md`` (and a
JSON file next to it): for each case the converged OpenSees step, peak
displacement per floor, impacts and peak force per gap, and the largest
time-history differences; then, for each row, the step convergence of both
programs and their run times at equal accuracy (medians of 5 in this process).
"""

from __future__ import annotations

import argparse
import json
import statistics
import time
from pathlib import Path

import numpy as np

from seispound.integrate import Newmark, integrate
from seispound.structure import assemble

from .cases import PeerCase, benchmark_cases
from .opensees import PeerResult, run_opensees

# OpenSees' steps, halved from 1 ms: it has no event location, so its impacts
# converge only as dt -> 0
OPENSEES_STEPS = (1e-3, 5e-4, 2.5e-4, 1.25e-4, 6.25e-5)


def run_seispound(case: PeerCase, dt: float, newmark: Newmark | None = None) -> PeerResult:
    """The case in seispound at analysis step dt (histories kept); wall time of the integration."""
    model = case.model(dt, newmark)
    system = assemble(model.buildings, model.gaps, model.contact)
    ag, nsteps = case.ground(dt)
    t0 = time.perf_counter()
    raw = integrate(system, ag, dt, nsteps, model.analysis.newmark, scheme="newmark")  # Newmark against Newmark
    seconds = time.perf_counter() - t0
    counts = np.bincount(raw.impacts["gap"], minlength=system.n_gap)
    return PeerResult(time=raw.time, displacement=raw.displacement, force=raw.force,
                      peak_displacement=raw.peak_displacement, peak_force=raw.peak_force,
                      impacts=counts, seconds=seconds)


def agreement(os_r: PeerResult, sp_r: PeerResult) -> dict:
    """Differences between two runs on the same time grid (relative to seispound's values)."""
    pu = np.abs(os_r.peak_displacement - sp_r.peak_displacement) / sp_r.peak_displacement
    with np.errstate(invalid="ignore", divide="ignore"):
        pf = np.where(sp_r.peak_force > 0, np.abs(os_r.peak_force - sp_r.peak_force) / sp_r.peak_force, 0.0)
    du = np.max(np.abs(os_r.displacement - sp_r.displacement)) / np.max(np.abs(sp_r.displacement))
    fmax = np.max(sp_r.peak_force, initial=0.0)
    df = np.max(np.abs(os_r.force - sp_r.force)) / fmax if fmax > 0 else 0.0
    return dict(peak_displacement_max_rel=float(pu.max()), peak_force_max_rel=float(np.max(pf, initial=0.0)),
                impacts_opensees=os_r.impacts.tolist(), impacts_seispound=sp_r.impacts.tolist(),
                impacts_equal=bool(np.array_equal(os_r.impacts, sp_r.impacts)),
                history_displacement_max_rel=float(du), history_force_max_rel=float(df),
                peak_force_seispound=sp_r.peak_force.tolist(), peak_force_opensees=os_r.peak_force.tolist(),
                peak_displacement_seispound=sp_r.peak_displacement.tolist(),
                unconverged_opensees_steps=int(os_r.unconverged_steps))


def compare_case(case: PeerCase, dt: float) -> dict:
    """Both programs at the same step dt (seispound with its default substeps)."""
    ag, nsteps = case.ground(dt)
    os_r = run_opensees(case.model(dt), ag, dt, nsteps)
    sp_r = run_seispound(case, dt)
    return dict(case=case.name, dt=dt, **agreement(os_r, sp_r))


def seispound_convergence(case: PeerCase) -> list:
    """seispound over (dt, substeps): peak force, peak displacement, impacts, wall time."""
    sp_rows = []
    for dt in (0.01, 0.005, 0.0025, 0.001):
        for sub in (8, 16, 32):
            r = run_seispound(case, dt, Newmark(contact_substeps=sub))
            sp_rows.append(dict(dt=dt, substeps=sub, peak_force=float(r.peak_force.max(initial=0.0)),
                                peak_displacement=float(r.peak_displacement.max()), impacts=int(r.impacts.sum()),
                                seconds=r.seconds))
    return sp_rows


def convergence(case: PeerCase, steps=OPENSEES_STEPS) -> dict:
    """OpenSees over ``steps`` and seispound over (dt, substeps): peak force, peak displacement, impacts."""
    os_rows = []
    for dt in steps:
        ag, n = case.ground(dt)
        r = run_opensees(case.model(dt), ag, dt, n)
        os_rows.append(dict(dt=dt, peak_force=float(r.peak_force.max(initial=0.0)),
                            peak_displacement=float(r.peak_displacement.max()), impacts=int(r.impacts.sum()),
                            seconds=r.seconds, unconverged=int(r.unconverged_steps)))
    return dict(case=case.name, opensees=os_rows, seispound=seispound_convergence(case))


def coarsest_within(rows, reference, key="peak_force", rel=0.01):
    """The cheapest row (by seconds) whose ``key`` is within ``rel`` of ``reference``."""
    ok = [r for r in rows if abs(r[key] - reference) <= rel * abs(reference)]
    return min(ok, key=lambda r: r["seconds"]) if ok else None


def speed_at_equal_accuracy(case: PeerCase, conv: dict, repeat: int = 5) -> dict:
    """Medians of ``repeat`` runs of each program at its cheapest setting within 1 % of OpenSees' converged peak force."""
    ref = conv["opensees"][-1]["peak_force"]
    os_pick = coarsest_within(conv["opensees"], ref)
    sp_pick = coarsest_within(conv["seispound"], ref)
    ag, n = case.ground(os_pick["dt"])
    os_t = [run_opensees(case.model(os_pick["dt"]), ag, os_pick["dt"], n).seconds for _ in range(repeat)]
    nm = Newmark(contact_substeps=sp_pick["substeps"])
    sp_t = [run_seispound(case, sp_pick["dt"], nm).seconds for _ in range(repeat)]
    t_os, t_sp = statistics.median(os_t), statistics.median(sp_t)
    return dict(case=case.name, reference_peak_force=ref, opensees=os_pick, seispound=sp_pick,
                opensees_s=t_os, seispound_s=t_sp, speedup=t_os / t_sp)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.peer.compare", description=__doc__.split("\n\n")[0])
    ap.add_argument("--duration", type=float, default=20.0, help="seconds of each record (default 20)")
    ap.add_argument("--out", default="docs/peer.json")
    ap.add_argument("--speed-only", action="store_true",
                    help="keep the agreement and OpenSees' convergence rows stored in --out; rerun seispound's "
                         "convergence rows and time both programs again (after a change to seispound only)")
    args = ap.parse_args(argv)
    if args.speed_only:
        return _speed_only(Path(args.out))
    cases = benchmark_cases(args.duration)
    results = dict(duration=args.duration, agreement=[], convergence=[], speed=[])
    for case in cases:
        t0 = time.perf_counter()
        row = compare_case(case, OPENSEES_STEPS[-1])
        results["agreement"].append(row)
        print(f"{case.name}: peaks {row['peak_displacement_max_rel']:.2e} forces {row['peak_force_max_rel']:.2e} "
              f"impacts equal {row['impacts_equal']} ({time.perf_counter() - t0:.0f} s)", flush=True)
    for case in cases:
        if case.law is None or "Kobe" in case.name:
            continue
        conv = convergence(case)
        results["convergence"].append(conv)
        sp = speed_at_equal_accuracy(case, conv)
        results["speed"].append(sp)
        print(f"{case.name}: OpenSees {sp['opensees_s']:.3f} s at dt {sp['opensees']['dt']}, seispound "
              f"{sp['seispound_s'] * 1e3:.2f} ms at dt {sp['seispound']['dt']} / {sp['seispound']['substeps']} "
              f"substeps: {sp['speedup']:.0f}x", flush=True)
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(results, indent=1))
    print(f"wrote {out}")
    return 0


def _speed_only(out: Path) -> int:
    results = json.loads(out.read_text())
    cases = benchmark_cases(results["duration"])
    stored = {c["case"]: c for c in results["convergence"]}
    results["speed"] = []
    for case in cases:
        if case.name not in stored:
            continue
        conv = stored[case.name]
        run_seispound(case, 0.01)  # compile / load numba's cache before anything is timed
        conv["seispound"] = seispound_convergence(case)
        sp = speed_at_equal_accuracy(case, conv)
        results["speed"].append(sp)
        print(f"{case.name}: OpenSees {sp['opensees_s']:.3f} s at dt {sp['opensees']['dt']}, seispound "
              f"{sp['seispound_s'] * 1e3:.2f} ms at dt {sp['seispound']['dt']} / {sp['seispound']['substeps']} "
              f"substeps: {sp['speedup']:.0f}x", flush=True)
    out.write_text(json.dumps(results, indent=1))
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
