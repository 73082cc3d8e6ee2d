"""Freed memory kept for the next run (``seispound._memory``): a run's arrays from pages the process holds."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]

CHILD = """
import json, resource, warnings
import seispound as sp
from seispound._memory import keep_freed_memory
from benchmarks.physics import cases
warnings.simplefilter("ignore")
m = cases(sp.load_model("models/row_of_three.toml"))["flexible foundation"]
sp.simulate(m)
f0 = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
for _ in range(3):
    sp.simulate(m)
print(json.dumps({"set": keep_freed_memory(),
                  "faults": (resource.getrusage(resource.RUSAGE_SELF).ru_minflt - f0) / 3}))
"""


def _child(keep: str) -> dict:
    env = dict(os.environ, SEISPOUND_KEEP_MEMORY=keep, PYTHONPATH=str(REPO))
    out = subprocess.run([sys.executable, "-c", CHILD], cwd=REPO, env=env, capture_output=True, text=True,
                         check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_a_run_reuses_the_memory_the_last_one_freed():
    """On glibc, importing the package sets the allocator to keep freed memory: a ``simulate`` of the canonical
    row with a foundation (the run, its twin, the floors' read-out, the Dataset) then takes almost no page
    fault (0-1 measured), where glibc's defaults take one per fresh 4 kB page of its arrays (5 488-5 976
    measured), and ``SEISPOUND_KEEP_MEMORY=0`` leaves those defaults."""
    kept, defaults = _child("1"), _child("0")
    assert kept["set"] is True and defaults["set"] is False
    assert kept["faults"] < 50
    assert defaults["faults"] > 2000
