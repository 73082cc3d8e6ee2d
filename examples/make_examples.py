"""Write the bundled examples for ``calibrate``, ``impact`` and ``diagnose``: ``python examples/make_examples.py``.

Each example folder holds a model, a channel map, recordings (MiniSEED) and, for the impact
tests, a trials file.  The recordings are *synthetic*: made by seispound itself from a "true"
model that differs from the example's model, with 1 % Gaussian sensor noise (fixed seeds), so
that each command has something to find.  They show how the commands are used; what the
methods are worth is shown on recordings made by independent solvers (``tests/verification``,
``benchmarks/diagnose``).

* ``calibrate/``: a 3- and a 5-storey building 2 cm apart under 6 s of El Centro 1940; the
  model's storeys are 25 % too stiff and its gap 50 % too wide.
* ``impact/``: the seed's two hung slabs struck at 0.05 and 0.15 m/s; force and both
  displacements at 10 kHz, made with Hd (3.2e9 N/m^1.5, e = 0.7).
* ``diagnose/``: the pair of ``calibrate/`` with the true parameters, whose recording was made
  with a coefficient of restitution that falls with the impact velocity
  (e = 0.85 - 1.2 v, at least 0.3), which the model (a constant e of 0.65) leaves out.
"""

from __future__ import annotations

import copy
import tomllib
from pathlib import Path

import numpy as np
import obspy

HERE = Path(__file__).resolve().parent
NOISE = 0.01

PAIR = '''# {what}
title = "{title}"

[analysis]
dt = 0.005
duration = 6.0

[ground_motion]
file = "../../ground_motions/RSN6_IMPVALL.I_I-ELC180-hor1.AT2"
units = "g"
scale = 1.5

[contact]
law = "Hd"
stiffness = 2.75e9
restitution = 0.65

[[building]]
name = "A"
floors = 3
floor_masses = 1.0e5
storey_stiffness = {kA:.6g}
storey_heights = 3.0
damping = {{ kind = "rayleigh", ratio = 0.05, modes = [1, 2] }}

[[building]]
name = "B"
floors = 5
floor_masses = 1.0e5
storey_stiffness = {kB:.6g}
storey_heights = 3.0
damping = {{ kind = "rayleigh", ratio = 0.05, modes = [1, 2] }}

[[gap]]
between = ["A", "B"]
size = {gap:.6g}
'''
TRUE = dict(kA=1.2e8, kB=1.0e8, gap=0.02)
PAIR_CHANNELS = {"XX.A.03.HNX": ("A", 3), "XX.B.03.HNX": ("B", 3), "XX.B.05.HNX": ("B", 5)}


def _channel_map(chans: dict) -> str:
    out = []
    for cid, (b, f) in chans.items():
        out.append(f'[[channel]]\nid = "{cid}"\nquantity = "acceleration"\nbuilding = "{b}"\nfloor = {f}\n')
    return "\n".join(out)


def _write(path, series: dict, dt: float, seed: int) -> None:
    rng = np.random.default_rng(seed)
    st = obspy.Stream()
    for cid, x in series.items():
        noisy = x + NOISE * np.sqrt(np.mean(x * x)) * rng.standard_normal(x.size)
        net, sta, loc, cha = cid.split(".")
        st += obspy.Trace(noisy.astype(np.float64), header=dict(network=net, station=sta, location=loc, channel=cha,
                                                                delta=dt, starttime=obspy.UTCDateTime(2021, 3, 1)))
    st.write(str(path), format="MSEED", encoding="FLOAT64")


def _pair_recording(folder: Path, data: dict, seed: int) -> None:
    from seispound.calibrate.channels import Channel
    from seispound.calibrate.observe import Observer, Trial
    from seispound.calibrate.recording import Recording

    chans = [Channel(cid, "acceleration", b, f) for cid, (b, f) in PAIR_CHANNELS.items()]
    dt = data["analysis"]["dt"]
    n = int(round(data["analysis"]["duration"] / dt)) + 1
    rec = Recording(dt, {c.id: np.zeros(n) for c in chans}, [])
    sim = Observer(data, folder, chans, [Trial(rec, "t")]).simulate([])[0]
    _write(folder / "recording.mseed", sim, dt, seed)
    (folder / "channels.toml").write_text(_channel_map(PAIR_CHANNELS), encoding="utf-8")


def calibrate_example() -> None:
    folder = HERE / "calibrate"
    folder.mkdir(exist_ok=True)
    what = ("The calibrate example: storeys 25 % too stiff and a gap 50 % too wide against the recording\n"
            "# (synthetic, made by examples/make_examples.py from kA = 1.2e8, kB = 1.0e8 N/m and a 2 cm gap).")
    text = PAIR.format(what=what, title="calibrate example: a 3- and a 5-storey building",
                       kA=1.25 * TRUE["kA"], kB=1.25 * TRUE["kB"], gap=1.5 * TRUE["gap"])
    (folder / "model.toml").write_text(text, encoding="utf-8")
    _pair_recording(folder, tomllib.loads(PAIR.format(what="", title="truth", **TRUE)), seed=11)


def diagnose_example() -> None:
    folder = HERE / "diagnose"
    folder.mkdir(exist_ok=True)
    what = ("The diagnose example: the recording was made with e = 0.85 - 1.2 v (at least 0.3), which this\n"
            "# model, a constant e of 0.65, leaves out (synthetic, made by examples/make_examples.py).")
    text = PAIR.format(what=what, title="diagnose example: a 3- and a 5-storey building", **TRUE)
    (folder / "model.toml").write_text(text, encoding="utf-8")
    truth = tomllib.loads(text)
    truth["contact"]["restitution"] = {"form": "linear", "e0": 0.85, "slope": 1.2, "min": 0.3, "max": 0.99}
    _pair_recording(folder, truth, seed=12)


def impact_example() -> None:
    from seispound.calibrate.channels import Channel
    from seispound.calibrate.observe import Observer, Trial
    from seispound.calibrate.recording import Recording

    folder = HERE / "impact"
    folder.mkdir(exist_ok=True)
    text = (HERE.parent / "models" / "slab_pendulum.toml").read_text(encoding="utf-8")
    text = text.replace("# The seed's slab-impact test", "# The impact example (recordings in this folder: synthetic, "
                        "made by examples/make_examples.py with Hd,\n# 3.2e9 N/m^1.5, e = 0.7, 1 % noise).\n"
                        "# The seed's slab-impact test", 1)
    (folder / "model.toml").write_text(text, encoding="utf-8")
    data = copy.deepcopy(tomllib.loads(text))
    chans = [Channel("XX.LAB.00.FRC", "force", gap=0), Channel("XX.A.00.LDX", "displacement", "striker", 1),
             Channel("XX.B.00.LDX", "displacement", "struck", 1)]
    lines = []
    for k, v0 in enumerate((0.05, 0.15)):
        rec = Recording(1e-4, {c.id: np.zeros(801) for c in chans}, [])
        obs = Observer(data, folder, chans, [Trial(rec, "t", initial_velocity={"striker": [v0]})])
        sim = obs.simulate([("gap.1.size", v0 * 0.01), ("analysis.dt", 1e-4)])[0]
        _write(folder / f"trial{k + 1}.mseed", sim, 1e-4, seed=20 + k)
        lines.append(f'[[trial]]\nname = "{v0} m/s"\nrecording = "trial{k + 1}.mseed"\n'
                     f'initial_velocity = {{ striker = [{v0}] }}\n')
    (folder / "trials.toml").write_text("\n".join(lines), encoding="utf-8")
    (folder / "channels.toml").write_text(
        '[[channel]]\nid = "XX.LAB.00.FRC"\nquantity = "force"\ngap = 1\n\n'
        '[[channel]]\nid = "XX.A.00.LDX"\nquantity = "displacement"\nbuilding = "striker"\nfloor = 1\n\n'
        '[[channel]]\nid = "XX.B.00.LDX"\nquantity = "displacement"\nbuilding = "struck"\nfloor = 1\n',
        encoding="utf-8")


if __name__ == "__main__":
    calibrate_example()
    impact_example()
    diagnose_example()
    print(f"examples written under {HERE}")
