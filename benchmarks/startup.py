"""How long a first run takes on a fresh install: ``python -m benchmarks.startup``.

A fresh install has no numba cache.  A first ``simulate`` runs the integrator's Python source
while a process in the background compiles it (``seispound._first_use``).  This runs, in a child
process with an empty ``NUMBA_CACHE_DIR`` (as a fresh install has), README command 1
(``seispound run models/two_buildings.toml``), times until the background compile has finished,
runs command 1 again with the cache filled, then in another such process the first ``simulate``
of each physics of ``benchmarks.physics`` one after the other, and reports the wall times and
the notices printed.  ``--compile-first`` also times command 1 cold with the interpretation
switched off (``SEISPOUND_INTERPRET_SECONDS=0``: it waits for the compile, as before).

``--passes``: instead, where a driver's cold compile goes.  In a child process with an empty
cache, the first ``simulate`` of ``models/two_buildings.toml`` (the fast driver) and of
``models/yielding_pair.toml`` (the general driver), with numba's per-pass timings of each
linear part's loop (``_driver.drive_two_node``, ``drive_coupled``, with its phases inlined; ``pipeline_times`` in the compile's metadata: type inference, SSA
reconstruction, lowering, ...; a pass's time includes the compiles of the functions it reaches
first) and LLVM's own total (``NUMBA_LLVM_PASS_TIMINGS``), and the compile events of the
functions it compiled (``numba.core.event``), by exclusive time.

``--inlines``: what numba's inlining of the ``inline="always"`` helpers costs.  numba copies an
inlined function's IR at each call site (``InlineWorker.inline_ir``), everything already inlined
into it included; this wraps that method to time each copy, and prints, for the first ``simulate``
of each model in a child process with an empty cache, the wall time, the copies' total and the
largest copies with the function's blocks and variables (its scope, which each block's copy takes
along).
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
import os
import seispound as sp
from benchmarks.physics import cases
os.environ.pop("SEISPOUND_INTERPRET_SECONDS", None)  # as a user's first runs: set by benchmarks/__init__.py
ms = cases(sp.load_model("models/row_of_three.toml"))
for name in ["plain", "yielding storeys", "flexible foundation", "rod floors", "floor-to-storey"]:
    t = time.perf_counter()
    run_as = sp.simulate(ms[name]).attrs["integrator_run_as"].split(":")[0]
    print(f"  first simulate, {name}: {time.perf_counter() - t:.1f} s ({run_as})", flush=True)
"""


PASSES = """
import re, time, warnings
warnings.simplefilter("ignore")
from numba.core import event
import seispound as sp
from seispound.integrate import _driver
for model, kernel in (("models/two_buildings.toml", _driver.drive_two_node),
                      ("models/yielding_pair.toml", _driver.drive_coupled)):  # the loop, with its phases inlined
    with event.install_recorder("numba:compile") as rec:
        t0 = time.perf_counter()
        sp.simulate(sp.load_model(model))
        wall = time.perf_counter() - t0
    md = next(iter(kernel.overloads.values())).metadata
    passes = sorted(((t.init + t.run + t.finalize, name.split("_", 1)[1])
                     for name, t in md["pipeline_times"]["nopython"].items()), reverse=True)
    llvm = re.search(r"Total time: ([0-9.]+)", md["llvm_pass_timings"].summary())
    print(f"{model}: first simulate {wall:.1f} s; {kernel.py_func.__name__}'s passes: "
          + ", ".join(f"{name} {sec:.1f} s" for sec, name in passes[:6])
          + f"; LLVM's passes {float(llvm.group(1)):.1f} s")
    stack, excl = [], {}
    for ts, ev in rec.buffer:
        name = ev.data["dispatcher"].py_func.__qualname__
        if ev.is_start:
            stack.append([name, ts, 0.0])
            continue
        name, t, inner = stack.pop()
        excl[name] = excl.get(name, 0.0) + ts - t - inner
        if stack:
            stack[-1][2] += ts - t
    print(f"  {len(excl)} functions compiled; exclusive seconds: "
          + ", ".join(f"{k} {v:.1f}" for k, v in sorted(excl.items(), key=lambda x: -x[1])[:6]), flush=True)
"""


INLINES = """
import collections, time, warnings
warnings.simplefilter("ignore")
from numba.core import inline_closurecall as icc
copies = collections.defaultdict(lambda: [0, 0.0, 0, 0])
inline_ir = icc.InlineWorker.inline_ir
def timed(self, caller_ir, block, i, callee_ir, *args, **kwargs):
    t0 = time.perf_counter()
    out = inline_ir(self, caller_ir, block, i, callee_ir, *args, **kwargs)
    c = copies[(callee_ir.func_id.func_qualname, caller_ir.func_id.func_qualname)]
    c[0] += 1
    c[1] += time.perf_counter() - t0
    c[2] = len(callee_ir.blocks)
    c[3] = len(next(iter(callee_ir.blocks.values())).scope.localvars._con)
    return out
icc.InlineWorker.inline_ir = timed
import seispound as sp
for model in ("models/two_buildings.toml", "models/yielding_pair.toml"):
    copies.clear()
    t0 = time.perf_counter()
    sp.simulate(sp.load_model(model))
    wall = time.perf_counter() - t0
    print(f"{model}: first simulate {wall:.1f} s, of which inlined copies {sum(c[1] for c in copies.values()):.1f} s",
          flush=True)
    for (name, caller), (k, sec, nb, nv) in sorted(copies.items(), key=lambda kv: -kv[1][1])[:5]:
        print(f"  {sec:6.2f} s  {name} into {caller} (x{k}; {nb} blocks, {nv} variables)", flush=True)
"""


def _run(cmd, env, cwd):
    t0 = time.perf_counter()
    p = subprocess.run(cmd, env=env, cwd=cwd, capture_output=True, text=True)
    return time.perf_counter() - t0, p


def _compiling(cache: str) -> bool:
    """True while a background compile (``seispound._compile_ahead``) into ``cache`` runs."""
    for proc in Path("/proc").iterdir():
        try:
            if (b"seispound._compile_ahead" in (proc / "cmdline").read_bytes()
                    and f"NUMBA_CACHE_DIR={cache}".encode() in (proc / "environ").read_bytes().split(b"\0")):
                return True
        except OSError:
            continue
    return False


def _notices(p):
    return [ln for ln in p.stderr.splitlines() if ln.startswith("seispound:")]


def _readme_command(exe, env, tmp, compile_first):
    """README command 1 cold, then after the background compile, warm; and cold with the Python run off."""
    cmd = [str(exe), "run", "models/two_buildings.toml", "-o", str(tmp / "two_buildings.h5")]
    t0 = time.perf_counter()
    wall, p = _run(cmd, env, REPO)
    print(f"README command 1, cold (fresh install): {wall:.1f} s (exit {p.returncode}); notices: {_notices(p)}")
    while _compiling(env["NUMBA_CACHE_DIR"]):
        time.sleep(0.5)
    print(f"  the background compile finished {time.perf_counter() - t0:.1f} s after the command started")
    wall, p = _run(cmd, env, REPO)
    print(f"README command 1, warm (cache filled): {wall:.1f} s (exit {p.returncode}); notices: {_notices(p)}")
    if compile_first:
        env0 = dict(env, NUMBA_CACHE_DIR=str(tmp / "cache0"), SEISPOUND_INTERPRET_SECONDS="0")
        wall, p = _run(cmd, env0, REPO)
        print(f"README command 1, cold, compiled first: {wall:.1f} s (exit {p.returncode}); notices: {_notices(p)}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--passes", action="store_true", help="where each driver's cold compile goes")
    ap.add_argument("--inlines", action="store_true", help="what numba's copies of inlined functions cost")
    ap.add_argument("--compile-first", action="store_true",
                    help="also time command 1 cold with the interpretation switched off")
    ap.add_argument("--physics-only", action="store_true", help="only the first simulate of each physics")
    args = ap.parse_args(argv)
    exe = Path(sys.executable).with_name("seispound")
    with tempfile.TemporaryDirectory() as tmp:
        env = dict(os.environ, NUMBA_CACHE_DIR=str(Path(tmp) / "cache"), PYTHONPATH=str(REPO))
        env.pop("SEISPOUND_INTERPRET_SECONDS", None)  # set by benchmarks/__init__.py; a user's first run has it unset
        if args.passes or args.inlines:
            env["SEISPOUND_INTERPRET_SECONDS"] = "0"  # these time the compile
            if args.passes:
                env["NUMBA_LLVM_PASS_TIMINGS"] = "1"
            wall, p = _run([sys.executable, "-c", PASSES if args.passes else INLINES], env, REPO)
            print(p.stdout, end="")
            if p.returncode:
                print(p.stderr[-2000:])
            return p.returncode
        if not args.physics_only:
            _readme_command(exe, env, Path(tmp), args.compile_first)
        env["NUMBA_CACHE_DIR"] = str(Path(tmp) / "cache2")
        wall, p = _run([sys.executable, "-c", PHYSICS], env, REPO)
        print(f"each physics' first simulate, fresh cache ({wall:.1f} s in all):")
        print(p.stdout, end="")
        print("  notices:", _notices(p))
        while _compiling(env["NUMBA_CACHE_DIR"]):  # leave nothing running
            time.sleep(0.5)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
