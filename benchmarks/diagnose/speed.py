"""How long one diagnosis takes: ``python -m benchmarks.diagnose.speed [--families none,inelastic-storey]``.

The issue's case: a two-building recording of 30 s at 200 Hz (every floor's acceleration and
both roofs' displacements, 1 % noise), made by the independent generator (``generate.py``),
one case per family.  Timed: the whole ``diagnose`` call as a user makes it (reading the
model, recording and channel map, numerics check, recalibration, every hypothesis, the
report, the augmented model and the figure).  Target: under 60 s each on this machine.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

from .generate import write_case


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--families", default="none,inelastic-storey,spatially-varying-input")
    ap.add_argument("--seed", type=int, default=31)
    args = ap.parse_args(argv)
    from seispound.diagnose import diagnose

    with tempfile.TemporaryDirectory() as tmp:
        for fam in args.families.split(","):
            f = Path(tmp) / fam
            key = write_case(f, fam, args.seed, duration=30.0, buildings=2)
            t0 = time.perf_counter()
            d = diagnose(f / "model.toml", [f / "recording.mseed"], channels=f / "channels.toml",
                         report=f / "report.json", figure=f / "fig.png", progress=False)
            wall = time.perf_counter() - t0
            print(f"{fam}: 2 buildings ({key['impacts']} impacts), 30 s at 200 Hz: diagnose {wall:.1f} s "
                  f"({'under' if wall < 60 else 'OVER'} 60 s); named {[x['physics'] for x in d.left_out] or 'nothing'}"
                  f", NE {d.ne_before:.4f} -> {d.ne_after:.4f}", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
