"""How long a calibration takes: ``python -m benchmarks.calibration [--repeat 3]``.

Two buildings (4 and 8 storeys, models/two_buildings.toml) under 30 s of El Centro; a
recording at 200 Hz of three floor accelerations, made by the package at the true parameters
with 1 % noise (a speed benchmark: the recovery itself is verified against an independent
solver in tests/verification/test_calibration_synthetic.py); six parameters fitted from 30 %
off (both storey stiffnesses, both damping ratios, the contact stiffness, the gap size).
Reported: the whole ``calibrate`` call (reading, fitting, uncertainties), medians of
``repeat``, the simulations it took and the time per simulation.
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
FIT = ["building.A.storey_stiffness", "building.B.storey_stiffness", "building.A.damping.ratio",
       "building.B.damping.ratio", "contact.stiffness", "gap.1.size"]


def setup(folder: Path):
    import obspy

    from seispound import load_model, simulate

    text = (REPO / "models" / "two_buildings.toml").read_text()
    text = text.replace('file = "../ground_motions/', f'file = "{(REPO / "ground_motions").as_posix()}/')
    (folder / "true.toml").write_text(text)
    ds = simulate(load_model(folder / "true.toml"), twin=False)
    rng = np.random.default_rng(0)
    st = obspy.Stream()
    chans = [("A", 4), ("B", 4), ("B", 8)]
    lines = []
    for b, f in chans:
        x = ds.acceleration.sel(building=b, floor=f).values
        x = x + 0.01 * np.sqrt(np.mean(x * x)) * rng.standard_normal(x.size)
        cid = f"XX.{b}.00.H{f:02d}"
        st += obspy.Trace(x, header=dict(network="XX", station=b, location="00", channel=f"H{f:02d}",
                                         delta=float(ds.attrs["dt"])))
        lines.append(f'[[channel]]\nid = "{cid}"\nquantity = "acceleration"\nbuilding = "{b}"\nfloor = {f}\n')
    st.write(str(folder / "rec.mseed"), format="MSEED", encoding="FLOAT64")
    (folder / "ch.toml").write_text("\n".join(lines))
    off = text
    for old, new in (("storey_stiffness = 1.3092e8", "storey_stiffness = 1.70196e8"),
                     ("storey_stiffness = 1.1593e8", "storey_stiffness = 0.81151e8"),
                     ("stiffness = 2.75e9", "stiffness = 3.575e9"), ("size = 0.02", "size = 0.026")):
        assert old in off, old
        off = off.replace(old, new)
    off = off.replace("ratio = 0.05, modes = [1, 2] }\ninitial", "ratio = 0.065, modes = [1, 2] }\ninitial", 1)
    off = off.replace("ratio = 0.05, modes = [1, 2] }\n\n[[gap]]", "ratio = 0.035, modes = [1, 2] }\n\n[[gap]]", 1)
    assert off.count("0.05, modes") == 0
    (folder / "model.toml").write_text(off)


def timed(folder: Path):
    """(seconds, CalibrationResult) of the whole ``calibrate`` call on the case ``setup`` wrote in ``folder``."""
    from seispound.calibrate import calibrate

    t0 = time.perf_counter()
    res = calibrate(folder / "model.toml", [folder / "rec.mseed"], channels=folder / "ch.toml", fit=FIT,
                    progress=False)
    return time.perf_counter() - t0, res


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        setup(folder)
        runs = [timed(folder) for _ in range(args.repeat)]
    t = statistics.median(r[0] for r in runs)
    res = runs[-1][1]
    print(f"calibration of {len(FIT)} parameters, 2 buildings, 30 s at 200 Hz, 3 channels: median of "
          f"{args.repeat}: {t:.2f} s, {res.evaluations} simulations ({1e3 * t / res.evaluations:.1f} ms each); "
          f"NE {res.ne_mean_before:.3f} -> {res.ne_mean_after:.4f}")
    for path, p in res.parameters.items():
        print(f"  {path:32s} {p['start']:12.5g} -> {p['value']:12.5g} +- {p['stderr']:.2g}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
