"""The seed's slab-impact study, reproduced: ``python -m benchmarks.seed_study [--out docs]``.

1. Synthetic "experimental" recordings of the seed's eight trials (release distances 10, 15, 37,
   56, 66, 71, 87, 94 mm on 1.5 m cables: v0 = d sqrt(g/L)) from the distributed-mass model
   models/slab_pendulum_rods.toml (rod slabs, bolted elements on joints, Hertz contact of the
   hemisphere with restitution 0.7), sampled at 10 kHz: the "measured" force is the striker's
   mass times the acceleration at its middle (as the seed computes it from an accelerometer),
   the displacements those of the far ends (the seed's lasers); sensor noise 0.5 % of the peak
   force and 1 um; the striker reaches the struck slab 10 ms into the record.
2. The seed's procedure (``seispound.calibrate.impact``) on them with the lumped pendulum model
   models/slab_pendulum.toml, for the five laws: stiffness per trial and law matching the peak
   force, e from the displacements, NE over the first positive pulse.
3. A table like the seed's Table 1, a figure like its Fig. 7, and the features the seed reports:
   pulse skewness, negative force after the pulse, the internal period.

Writes OUT/seed_study.md and OUT/seed_study.png.
"""

from __future__ import annotations

import argparse
import math
import tempfile
import warnings
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
RELEASE_MM = (10, 15, 37, 56, 66, 71, 87, 94)
G, CABLE = 9.81, 1.5
STRIKER_MASS = 110.0  # slab 95 kg + element 15 kg
SEED_TABLE = {  # the seed's Table 1: velocity, NE of LVe, MLVe, NIVe, Hd, LHC [%]
    1: (0.030, 50.18, 69.53, 61.42, 26.12, 43.38), 2: (0.040, 74.25, 87.32, 79.59, 48.14, 64.52),
    3: (0.096, 62.33, 79.14, 68.39, 38.81, 56.68), 4: (0.146, 80.22, 94.44, 83.04, 56.66, 73.60),
    5: (0.171, 91.76, 103.11, 92.08, 69.06, 84.97), 6: (0.183, 79.89, 91.55, 76.87, 57.92, 76.31),
    7: (0.226, 90.22, 101.03, 91.24, 67.36, 82.65), 8: (0.243, 81.93, 93.15, 81.04, 60.30, 76.92)}


def make_recordings(folder: Path, seed: int = 7, sensor=0.5):
    """Write trial_<k>.mseed, channels.toml (for the lumped model) and trials.toml; return the raw series.

    ``sensor``: where on the striker the accelerometer sits (a fraction of the slab's length, or
    "attachment": on the bolted element)."""
    import obspy
    import tomllib

    from seispound.calibrate.channels import Channel
    from seispound.calibrate.observe import Observer, Trial
    from seispound.calibrate.recording import Recording

    rods = REPO / "models" / "slab_pendulum_rods.toml"
    data = tomllib.loads(rods.read_text())
    chans = [Channel("XX.STR.00.HNX", "acceleration", "striker", 1, None),  # at the sensor
             Channel("XX.STR.00.LDX", "displacement", "striker", 1, 0.0),
             Channel("XX.STK.00.LDX", "displacement", "struck", 1, 1.0)]
    dt, n = 1e-4, 1001  # 10 kHz, 0.1 s
    rng = np.random.default_rng(seed)
    series, lines = {}, []
    for k, d in enumerate(RELEASE_MM, start=1):
        v0 = d * 1e-3 * math.sqrt(G / CABLE)
        dummy = Recording(dt, {c.id: np.zeros(n) for c in chans}, [])
        obs = Observer(data, rods.parent, chans, [Trial(dummy, f"trial {k}", initial_velocity={"striker": [v0]})])
        sim = obs.simulate([("gap.1.size", v0 * 0.01),  # contact 10 ms in: a window before it
                            ("building.striker.floor_model.sensor", sensor)])[0]
        force = -STRIKER_MASS * sim["XX.STR.00.HNX"]
        force = force + 0.005 * force.max() * rng.standard_normal(n)
        xa = sim["XX.STR.00.LDX"] + 1e-6 * rng.standard_normal(n)
        xb = sim["XX.STK.00.LDX"] + 1e-6 * rng.standard_normal(n)
        series[k] = (v0, force)
        st = obspy.Stream()
        for cid, x in (("XX.LAB.00.FRC", force), ("XX.STR.00.LDX", xa), ("XX.STK.00.LDX", xb)):
            net, sta, loc, cha = cid.split(".")
            st += obspy.Trace(x.astype(np.float64), header=dict(network=net, station=sta, location=loc,
                                                                channel=cha, delta=dt))
        st.write(str(folder / f"trial_{k}.mseed"), format="MSEED", encoding="FLOAT64")
        lines.append(f'[[trial]]\nname = "{k}"\nrecording = "trial_{k}.mseed"\n')
    (folder / "trials.toml").write_text("\n".join(lines))
    (folder / "channels.toml").write_text(
        '[[channel]]\nid = "XX.LAB.00.FRC"\nquantity = "force"\ngap = 1\n\n'
        '[[channel]]\nid = "XX.STR.00.LDX"\nquantity = "displacement"\nbuilding = "striker"\nfloor = 1\n\n'
        '[[channel]]\nid = "XX.STK.00.LDX"\nquantity = "displacement"\nbuilding = "struck"\nfloor = 1\n')
    return series


def skewness_ratio(t, f):
    """Rise time / fall time of a pulse (< 1: right-skewed, the peak early; > 1: left-skewed)."""
    k = int(np.argmax(f))
    return (t[k] - t[0]) / max(t[-1] - t[k], 1e-12)


def internal_period(force, dt, i1):
    """Period [s] of the strongest line in the force after the first pulse (Welch's spectrum)."""
    from scipy.signal import welch

    tail = force[i1 + 1:i1 + 1 + 400]
    fr, p = welch(tail - tail.mean(), fs=1.0 / dt, nperseg=min(256, tail.size))
    k = int(np.argmax(p[1:])) + 1
    return 1.0 / fr[k]


def main(argv=None) -> int:
    from seispound.calibrate.impact import first_pulse, impact_study
    from seispound.model import load_model

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(REPO / "docs"))
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    out = Path(args.out)
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        series = make_recordings(folder)
        study = impact_study(load_model(REPO / "models" / "slab_pendulum.toml"), folder / "trials.toml",
                             folder / "channels.toml")
    features = []
    for t in study.trials:
        k = int(t.name)
        v0, force = series[k]
        i0, i1, _ = first_pulse(force, 1e-4)
        after = force[i1 + 1:i1 + 301]
        features.append(dict(trial=k, skew_rec=skewness_ratio(t.time, t.force),
                             skew_sim={law: skewness_ratio(lf.time, lf.force) for law, lf in t.laws.items()},
                             negative=float(-after.min() / t.peak_force), period=internal_period(force, 1e-4, i1),
                             duration=float(t.time[-1])))
    with tempfile.TemporaryDirectory() as tmp:  # the accelerometer on the striker's bolted element instead
        on_element = make_recordings(Path(tmp), sensor="attachment")
    variant = []
    for k, (v0, force) in on_element.items():
        k_pk = int(np.argmax(force))
        i1 = k_pk + int(np.argmax(force[k_pk:] <= 0)) - 1
        variant.append(dict(trial=k, peak=float(force.max()), negative=float(-force[i1 + 1:i1 + 301].min() / force.max()),
                            period=internal_period(force, 1e-4, i1)))
    study.figure(out / "seed_study.png")
    text = _report(study, features, variant)
    (out / "seed_study.md").write_text(text)
    print(text)
    return 0


def _report(study, features, variant) -> str:
    mean = study.mean_ne()
    best = [min(t.laws, key=lambda law: t.laws[law].ne) for t in study.trials]
    worst = [max(t.laws, key=lambda law: t.laws[law].ne) for t in study.trials]
    lines = ["# The seed's slab-impact study, reproduced", "", "[Back to the README](../README.md)", "",
             "Generated by `python -m benchmarks.seed_study` (see its docstring): synthetic recordings of the",
             "eight trials from the distributed-mass model `models/slab_pendulum_rods.toml`, fitted by the seed's",
             "procedure (`seispound.calibrate.impact`) with the lumped `models/slab_pendulum.toml`.", "",
             "## Normalised error per trial and law (like the seed's Table 1)", "", study.table(), "",
             "Mean NE: " + ", ".join(f"{law} {v:.1%}" for law, v in mean.items()), "",
             f"Lowest NE in {sum(b == 'Hd' for b in best)} of {len(best)} trials for Hd "
             f"(best per trial: {', '.join(best)}); highest in {sum(w == 'MLVe' for w in worst)} of {len(worst)} "
             f"for MLVe (worst per trial: {', '.join(worst)}).", "",
             "The seed's Table 1 for comparison (NE %, LVe, MLVe, NIVe, Hd, LHC):", "",
             "| trial | velocity | LVe | MLVe | NIVe | Hd | LHC |", "|---|---|---|---|---|---|---|"]
    for k, row in SEED_TABLE.items():
        lines.append(f"| {k} | {row[0]:.3f} | " + " | ".join(f"{x:.2f}" for x in row[1:]) + " |")
    lines += ["", "## The features the seed reports", "",
              "| trial | pulse [ms] | rise/fall measured | rise/fall Hd | rise/fall LVe | largest negative force "
              "after the pulse / peak | strongest period after the pulse [ms] |",
              "|---|---|---|---|---|---|---|"]
    for f in features:
        lines.append(f"| {f['trial']} | {1e3 * f['duration']:.2f} | {f['skew_rec']:.2f} | {f['skew_sim']['Hd']:.2f} "
                     f"| {f['skew_sim']['LVe']:.2f} | {f['negative']:.2f} | {1e3 * f['period']:.2f} |")
    lines += ["", "With the accelerometer on the striker's bolted element instead of the slab's middle (the seed does not",
              "say where it was):", "", "| trial | largest negative force after the first pulse / peak | strongest "
              "period after it [ms] |", "|---|---|---|"]
    for f in variant:
        lines.append(f"| {f['trial']} | {f['negative']:.2f} | {1e3 * f['period']:.2f} |")
    lines += ["", "![measured and simulated force](seed_study.png)", "", DISCUSSION]
    return "\n".join(lines)


DISCUSSION = """## Point by point against the seed

* **Ranking of the laws: reproduced.** Hd has the lowest NE in every trial and MLVe the highest, as in
  the seed's Table 1, with LVe and NIVe between and LHC closer to Hd. The ranking follows from the
  contact: the synthetic test's contact *is* Hertzian with Hunt-Crossley damping (a hemisphere on a
  flat), which Hd is, so its fitted stiffness comes out at 4.4e9-4.9e9 N/m^1.5 against the
  contact's 4.66e9 in every trial and only the bodies' distributed mass separates it from the
  recording; the linear laws
  cannot make the pulse's shape, and MLVe's approach-only damping skews it most.
* **Size of the errors: not reproduced.** NE here is 2-9 times smaller than the seed's for every
  law. The synthetic slabs ring little: the first positive pulse lasts 2.8-4.5 ms, ten times the slabs'
  first axial period (0.33 ms) and five times the joints' (0.6 ms), so the pulse loads them almost
  quasi-statically (the seed says the same of its own slabs), and the recorded force is the lumped
  force plus a small ripple. The seed's larger NE means its measured pulses differ from any lumped
  pulse far more than a linear-elastic slab on a stiff joint explains.
* **Skewness: not reproduced.** The synthetic pulses rise faster than they fall (rise/fall below 1),
  like every simulated pulse and like the seed's simulations, whereas the seed's measured pulses
  rise slowly and fall fast. That shape needs a contact or a joint that stiffens as it closes more
  than Hertz does, or a slower load path into the accelerometer; local crushing or seating of the
  bolted element (the joint closing gaps and stiffening) would do it and is not in the model.
* **Oscillating, partly negative measured force: reproduced in kind, not in size.** With the
  accelerometer on the slab's middle the force after the pulse dips to a few per cent of the peak
  below zero; on the bolted element 3-12 %, at the joint's mode. The seed's
  large negative lobes point at the bolted elements ringing on their joints (their mode carries
  the element's 14-15 kg against the slab), more than at the slabs' axial modes.
* **Internal period near 0.4 ms: between the model's two modes.** The slabs' first free-free axial
  period is 2L/c = 0.33 ms (0.30 ms with the bolted element) and the element-on-joint modes 0.55 and
  0.56 ms at the joint stiffness assumed (2e9 N/m; eigenvalues of the assembled slabs); the seed's 0.4 ms sits between, as a stiffer joint (about 5e9 N/m) or the coupled
  slab-element mode would give.
"""


if __name__ == "__main__":
    raise SystemExit(main())
