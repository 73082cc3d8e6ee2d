"""Medians of calls timed in alternating rounds, each call on the second of two runs in a row.

The benchmarks that compare the cost of several cases in one process (``physics``, ``physics_accuracy``,
``diagnose.speed --forms`` and ``--drivers``) time them here.  Rounds that run every case in turn let the
machine's drift (20-50 % within minutes here) fall on every case alike.  Within a round each case runs
twice and the second run is timed: the run after a large case is slower (it finds the caches and the
memory as that case left them), which made the first case of every round, the ratios' denominator, slower
and the ratios to it too small (``python -m benchmarks.physics_accuracy --cold`` times the cases so).
"""

from __future__ import annotations

import statistics
import time


def warm_medians(calls: dict, repeat: int, warm: bool = True) -> dict:
    """{name: median wall time [s]} of each zero-argument call of ``calls`` over ``repeat`` rounds.

    The value a call returns is dropped outside the timed interval (a user's result outlives the call).
    ``warm`` False times each call's only run in the round (the bias described above, for comparison).
    """
    walls = {name: [] for name in calls}
    for _ in range(repeat):
        for name, call in calls.items():
            if warm:
                call()
            t0 = time.perf_counter()
            out = call()
            walls[name].append(time.perf_counter() - t0)
            del out
    return {name: statistics.median(w) for name, w in walls.items()}
