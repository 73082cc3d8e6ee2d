"""How long a first run takes on a fresh install: ``python -m benchmarks.startup``.

A fresh install has no numba cache: each kernel is compiled on its first call.  This runs,
in a child process with an empty ``NUMBA_CACHE_DIR`` (as a fresh install has), README
command 1 (``seispound run models/two_buildings.toml``), then in another such process the
first ``simulate`` of each physics of ``benchmarks.physics`` one after the other, and
reports the wall times and the compile notice the run printed.  A second run of
command 1, with the cache now filled, is timed for comparison.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
PHYSICS = """
import time, warnings
warnings.simplefilter("ignore")
import seispound as sp
from benchmarks.physics import cases
ms = cases(sp.load_model("models/row_of_three.toml"))
for name in ["plain", "yielding storeys", "flexible foundation", "rod floors", "floor-to-storey"]:
    t = time.perf_counter()
    sp.simulate(ms[name])
    print(f"  first simulate, {name}: {time.perf_counter() - t:.1f} s", flush=True)
"""


def _run(cmd, env, cwd):
    t0 = time.perf_counter()
    p = subprocess.run(cmd, env=env, cwd=cwd, capture_output=True, text=True)
    return time.perf_counter() - t0, p


def main(argv=None) -> int:
    argparse.ArgumentParser(description=__doc__.splitlines()[0]).parse_args(argv)
    exe = Path(sys.executable).with_name("seispound")
    with tempfile.TemporaryDirectory() as tmp:
        env = dict(os.environ, NUMBA_CACHE_DIR=str(Path(tmp) / "cache"), PYTHONPATH=str(REPO))
        out = Path(tmp) / "two_buildings.h5"
        for label in ("cold (fresh install)", "warm (cache filled)"):
            wall, p = _run([str(exe), "run", "models/two_buildings.toml", "-o", str(out)], env, REPO)
            notes = [ln for ln in p.stderr.splitlines() if "compiling" in ln]
            print(f"README command 1, {label}: {wall:.1f} s (exit {p.returncode}); notice: {notes or 'none'}")
        env["NUMBA_CACHE_DIR"] = str(Path(tmp) / "cache2")
        wall, p = _run([sys.executable, "-c", PHYSICS], env, REPO)
        print(f"each physics' first simulate, fresh cache ({wall:.1f} s in all):")
        print(p.stdout, end="")
        print("  notices:", [ln for ln in p.stderr.splitlines() if "compiling" in ln])
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
