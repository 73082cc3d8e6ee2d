"""Bouc-Wen storeys in free flight against their physical path: ``python -m benchmarks.bouc_wen_flight``.

Two rows, each integrated with ``hysteretic_flight`` on (the offsets iterated within the exact
step, ``_general_flight._hysteretic_flight``) and off (Newmark substeps throughout), medians of
``--repeat`` ``integrate`` calls after a warm one, in one process:

1. the Bouc-Wen case of ``benchmarks.physics_accuracy`` (a 5 + 8 storey pair, 20 s of 1.5 x El
   Centro, 5 ms, 32 contact substeps): time, steps, iterations (Newton iterations and sweeps),
   free-flight steps, and the floor-acceleration NE between the two;
2. ``diagnose``'s Bouc-Wen form on the speed benchmark's case (two buildings of 10 and 4 storeys,
   30 s at 200 Hz, made by ``benchmarks.diagnose.generate``) at its null point and at yield drifts
   and exponents a fit visits (a non-integer exponent costs a ``pow`` per Newton iterate).
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np


def _timed(f, repeat):
    out = f()
    ts = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = f()
        ts.append(time.perf_counter() - t0)
    return out, statistics.median(ts)


def _both(model, repeat):
    from seispound.integrate import integrate
    from seispound.integrate.settings import Newmark
    from seispound.simulation import newmark_substeps, run_inputs

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        system, motions = run_inputs(model)
    an = model.analysis
    args = (system, motions.rows, an.dt, an.nsteps, Newmark(contact_substeps=32))
    kw = dict(substeps=newmark_substeps(model, system))
    return {on: _timed(lambda: integrate(*args, hysteretic_flight=on, **kw), repeat) for on in (True, False)}


def _pair(repeat):
    import seispound as sp

    from .physics_accuracy import CASES, _text

    with tempfile.TemporaryDirectory() as tmp:
        f = Path(tmp) / "bw.toml"
        f.write_text(_text(CASES["Bouc-Wen storeys"], 0.005))
        runs = _both(sp.load_model(f), repeat)
    (on, t_on), (off, t_off) = runs[True], runs[False]
    ne = np.linalg.norm(on.acceleration - off.acceleration) / np.linalg.norm(off.acceleration)
    print(f"5 + 8 storey Bouc-Wen pair, 20 s at 5 ms, median of {repeat}:")
    for name, r, t in (("free flight", on, t_on), ("physical path", off, t_off)):
        s = r.stats
        print(f"  {name:14s} {1e3 * t:6.1f} ms  steps {s['steps']:5d}  iterations {s['iterations']:6d}  "
              f"free-flight steps {s['free_flight_steps']:5d}  scheme {r.scheme}")
    print(f"  ratio {t_off / t_on:.2f}; floor accelerations {100 * ne:.2f} % apart (NE)")


def _form(repeat):
    import tomllib

    from seispound.calibrate.api import load_inputs
    from seispound.calibrate.observe import Observer
    from seispound.diagnose.hypotheses import HYPOTHESES

    from .diagnose.generate import write_case

    with tempfile.TemporaryDirectory() as tmp:
        f = Path(tmp) / "case"
        write_case(f, "inelastic-storey", 31, duration=30.0, buildings=2)
        model, chans, trials = load_inputs(f / "model.toml", [f / "recording.mseed"], f / "channels.toml", None)
        table, _, _ = HYPOTHESES["inelastic-storey"].augment(tomllib.loads(model.text), 0)
        obs = Observer(table, f, chans, trials)
        print(f"diagnose's Bouc-Wen form, two buildings, 30 s at 200 Hz, median of {repeat}:")
        for dy, n in ((5.0, 2.0), (0.005, 2.0), (0.005, 2.7), (0.005, 8.0)):
            ov = [("building.*.storey_law.post_yield_ratio", 0.05), ("building.*.storey_law.n", n)]
            ov += [(f"building.{b['name']}.storey_law.yield_drift", dy) for b in table["building"]]
            runs = _both(obs.model_for(trials[0], ov), repeat)
            t_on, t_off = runs[True][1], runs[False][1]
            print(f"  yield drift {dy:g} m, n = {n:g}: free flight {1e3 * t_on:.1f} ms, physical path "
                  f"{1e3 * t_off:.1f} ms (ratio {t_off / t_on:.2f})")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args(argv)
    _pair(args.repeat)
    _form(args.repeat)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
