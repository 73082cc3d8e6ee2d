"""How many full-row Newmark steps a run needs, and how many multi-rate stepping could save.

``python -m benchmarks.attempts`` runs rows of the scaling benchmark
(``benchmarks.scaling``: 20 s of El Centro 180, dt = 0.005 s, Hd, 2 cm gaps;
4 x 10 to 4 x 100 storeys and 4 and 16 pairs colliding at different times)
and the canonical row of three through a *counting copy* of the kernel: the
source of ``seispound/integrate/_driver.py`` (the time loop) with counters inserted at fixed
anchors (each must occur exactly once, so a changed kernel fails loudly here
instead of being counted wrongly), compiled without cache.  The counting copy
computes the same numbers as the kernel (``tests/test_attempts.py`` checks it
bit for bit).  Every step is taken physically (``free_flight=False``), so every
unit of work is an *attempt*: one Newmark step of the whole row, accepted or
redone.  The counting copy runs single-rate (``multirate=False``), so that its
attempts are full-row attempts.

For each row and number of contact substeps per impact it prints

* attempts per analysis step (what the kernel does now, in units of a
  full-row step);
* the multi-rate kernel as built (``integrate(multirate=True)``, the default):
  its DOF-steps (``stats["dof_steps"]``: waiting steps, catch-up steps and
  the stepping buildings' attempts, each weighted by its DOFs) per analysis
  step and DOF;
* the same for ideal multi-rate stepping: in every analysis step, only the
  buildings that take part in a contact or an event in that step (the DOF
  range from the first to the last building each such gap links) take the
  step's attempts; the others take one step of dt.  Rollbacks and the
  interpolation at gaps between a stepping and a waiting building are free
  here, so a real multi-rate kernel can only do worse;
* the mean number of gaps closed in the attempts with contact, the floor levels hit,
  and the error of the largest peak pounding force against 128 substeps.

A cost per DOF per analysis step within 3 times a bare Newmark loop needs
(attempts per analysis step) x (cost of an attempt / cost of a bare step) <= 3.
An attempt includes a bare step's work, so the second factor is at least 1:
the first factor bounds the ratio from below whatever the attempt costs.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib.util
import sys
import tempfile
from pathlib import Path

import numpy as np

import seispound.integrate.newmark as newmark_module
from seispound.integrate import Newmark

KERNEL = Path(newmark_module.__file__).with_name("_driver.py")

# probe entries
P_ATTEMPTS, P_DOF_ATTEMPTS, P_MULTIRATE, P_CONTACT_ATTEMPTS, P_CLOSED_SUM = 0, 1, 2, 3, 4
N_PROBE = 5

# The counts live in the kernel's stats array, extended past its N_STATS counters (``counting``): at
# X + P_* the probe, X + 5 the attempts of the current analysis step, X + 6 + i whether DOF i was in a
# closed or targeted gap's buildings in it (X = N_STATS).
# (anchor, code, where): code inserted before or after the single occurrence of anchor
_PATCHES = [
    ("        t_end = (step + 1) * dt\n        lp = _begin(",  # an analysis step on the physical path starts
     "        t_end = (step + 1) * dt\n"
     "        for i in range(work[1][0].size + 1):\n"
     "            stats[N_STATS + 5 + i] = 0\n"
     "        lp = _begin(", "replace"),
    ("                ok, converged, h, coef, lp = _trial(h, lev, (step, t), cnt, lp, model, work, outs, stats)\n"
     "                if not ok:\n                    break\n",
     "                stats[N_STATS + 5] += 1\n"  # an attempt's predictor ran
     "                stats[N_STATS + 0] += 1\n"
     "                stats[N_STATS + 1] += work[1][0].size\n"
     "                if cnt[1] > 0:\n"
     "                    stats[N_STATS + 3] += 1\n"
     "                    stats[N_STATS + 4] += cnt[1]\n"
     "                for q in range(cnt[1] + 1):\n"
     "                    gq = work[6][0][q] if q < cnt[1] else target\n"
     "                    if gq >= 0:\n"
     "                        for i in range(model[2][2][gq], model[2][3][gq]):\n"
     "                            stats[N_STATS + 6 + i] = 1\n", "after"),
    ("        step += 1\n        # ---- the analysis step's END",  # ... and ends
     "        n_busy = 0\n"
     "        for i in range(work[1][0].size):\n"
     "            n_busy += stats[N_STATS + 6 + i]\n"
     "        if n_busy > 0:\n"
     "            stats[N_STATS + 2] += stats[N_STATS + 5] * n_busy + (work[1][0].size - n_busy)\n"
     "        else:\n"
     "            stats[N_STATS + 2] += stats[N_STATS + 5] * work[1][0].size\n", "before"),
]


def counting_kernel():
    """Compile the counting copy of the kernel; return its module.

    Its ``integrate_kernel`` takes a stats array of N_STATS + 6 + n entries and counts past the first N_STATS
    (``_PATCHES``); ``counting`` routes the package's calls through it.
    """
    src = KERNEL.read_text()
    src = src.replace("from ..", "from seispound.").replace("from ._", "from seispound.integrate._")
    src = src.replace("from . import", "from seispound.integrate import")
    src = src.replace("from __future__ import annotations\n", "from __future__ import annotations\n"
                      "from seispound.integrate._outputs import N_STATS  # (the counters past the kernel's)\n", 1)
    src = src.replace("@njit(cache=True", "@njit(cache=False")
    for anchor, code, where in _PATCHES:
        if src.count(anchor) != 1:
            raise RuntimeError(f"{KERNEL}: anchor {anchor.strip()!r} found {src.count(anchor)} times, expected once "
                               f"(update benchmarks/attempts.py to the kernel)")
        if where == "replace":
            src = src.replace(anchor, code)
        elif where == "before":
            src = src.replace(anchor, code + anchor)
        else:
            src = src.replace(anchor, anchor + code)
    path = Path(tempfile.mkdtemp(prefix="seispound_counting_")) / "counting_kernel.py"
    path.write_text(src)
    spec = importlib.util.spec_from_file_location("seispound_counting_kernel", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@contextlib.contextmanager
def counting(module, probe):
    """Route :func:`seispound.integrate.integrate` through the counting kernel, filling ``probe``."""
    shim = type(sys)("seispound_counting_shim")
    shim.__dict__.update(module.__dict__)
    def integrate_kernel(*args):
        stats = args[-1]
        ext = np.zeros(module.N_STATS + 6 + args[0][0].size, np.int64)
        out = module.integrate_kernel(*args[:-1], ext)
        stats[:] = ext[:stats.size]
        probe[:] += ext[module.N_STATS:module.N_STATS + N_PROBE]
        return out

    shim.integrate_kernel = integrate_kernel
    saved = newmark_module.D
    newmark_module.D = shim
    try:
        yield
    finally:
        newmark_module.D = saved


def count(module, system, ag, dt, nsteps, substeps) -> tuple[dict, object]:
    """Run one case through the counting kernel, single-rate; return the counts per analysis step and the result.

    Also runs the kernel as built (multi-rate) and reports its DOF-steps per
    analysis step, in the same unit: ``built_per_step``.
    """
    probe = np.zeros(N_PROBE)
    nm = Newmark(contact_substeps=substeps)
    with counting(module, probe):
        raw = newmark_module.integrate(system, ag, dt, nsteps, nm, free_flight=False, multirate=False)
    built = newmark_module.integrate(system, ag, dt, nsteps, nm, free_flight=False)
    ds = nsteps * system.n_dof
    return dict(attempts=int(probe[P_ATTEMPTS]), attempts_per_step=probe[P_DOF_ATTEMPTS] / ds,
                multirate_per_step=probe[P_MULTIRATE] / ds, built_per_step=built.stats["dof_steps"] / ds,
                mean_closed=probe[P_CLOSED_SUM] / max(probe[P_CONTACT_ATTEMPTS], 1.0)), raw


def _cases():
    from seispound import load_model
    from benchmarks.canonical import CANONICAL
    from seispound.simulation import prepare_ground_motion
    from seispound.structure import assemble

    from .scaling import _ground, _row, pairs

    m = load_model(CANONICAL)
    ag3, _ = prepare_ground_motion(m)
    yield "row of three", assemble(m.buildings, m.gaps, m.contact), ag3, m.analysis.dt, m.analysis.nsteps
    ag, nsteps = _ground(20.0, 0.005)
    for nb, ns in ((2, 10), (4, 10), (4, 25), (4, 50), (4, 100)):
        yield f"{nb} x {ns}", _row(nb, ns), ag, 0.005, nsteps
    for k in (4, 16):  # pairs that collide at different times (benchmarks.scaling)
        yield f"{k} pairs", pairs(k, identical=False), ag, 0.005, nsteps


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.attempts", description=__doc__.split("\n\n")[0])
    ap.add_argument("--substeps", type=int, nargs="+", default=[32, 16, 8],
                    help="contact substeps per impact to count (default 32 16 8)")
    args = ap.parse_args(argv)
    module = counting_kernel()
    print("full-row attempts per analysis step: single-rate, ideal multi-rate, and the multi-rate kernel as built"
          " (free flight off)")
    print(f"{'row':>13} {'DOFs':>5} {'substeps':>8} {'impacts':>7} {'floors hit':>10} {'closed':>6} "
          f"{'single':>6} {'ideal':>6} {'built':>6} {'peak force err':>14}")
    for name, system, ag, dt, nsteps in _cases():
        ref = count(module, system, ag, dt, nsteps, 128)[1].peak_force.max()
        for ns in args.substeps:
            c, raw = count(module, system, ag, dt, nsteps, ns)
            gaps = raw.impacts["gap"]
            floors = np.unique(system.dof_floor[system.gap_i[gaps]]).size  # floor levels hit, any gap
            err = abs(raw.peak_force.max() / ref - 1.0) * 100 if ref > 0 else 0.0
            print(f"{name:>13} {system.n_dof:5d} {ns:8d} {gaps.size:7d} {floors:10d} {c['mean_closed']:6.2f} "
                  f"{c['attempts_per_step']:6.2f} {c['multirate_per_step']:6.2f} {c['built_per_step']:6.2f} "
                  f"{err:13.2f}%", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
