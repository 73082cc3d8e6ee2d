"""Monte Carlo check of calibration's 68 % intervals with coloured model error on white noise.

Kind: statistical verification (a Monte Carlo against the known truth, not the package against
itself).  A three-storey building (T1 = 0.45 s, f1 = 2.24 Hz, f2 = 6.28 Hz) is simulated at known
storey stiffness and damping ratio; each repetition adds to its three floor accelerations a model
error (white noise through a resonant filter of quality factor 8, ``scipy.signal.iirpeak``, shared
by the floors with a floor-dependent gain, plus an independent part per floor) and 1 % white
sensor noise, then fits both parameters with ``calibrate_observer``.  The reported 68 % interval
(value +- half68: Student's t with the sandwich variance's Satterthwaite degrees of freedom, 3-6
here) must cover the truth in 60-76 % of the 200 repetitions, with the model error centred between
the first two modes, just below the first, and on the first (the hardest: the fitted stiffness
absorbs part of the error).  Measured on these seeds: 68.0 / 76.0 %, 71.0 / 72.5 % and 67.5 / 61.0 %
(stiffness / damping ratio); +- one standard error gave 65.5 / 71.5, 63.5 / 67.0 and 60.0 / 54.5 %,
and the AR(1) effective sample size before it 99-100, 55-60 and 28-31 %.  On 400 further seeds
(200-599, run once after the method was fixed): 76.5 / 77.0, 72.0 / 76.3 and 68.5 / 63.8 %
(docs/diagnose.md).
"""

import numpy as np
import pytest
from scipy import signal

from seispound.calibrate import fit as F
from seispound.calibrate.channels import Channel
from seispound.calibrate.observe import Observer, Trial
from seispound.calibrate.recording import Recording
from tests._models import REPO

DT, N, REPS = 0.01, 1001, 200
TRUTH = {"building.A.storey_stiffness": 1.0e8, "building.A.damping.ratio": 0.05}


def _model():
    import tomllib

    return tomllib.loads(f'''
[analysis]
dt = {DT}
duration = 10.0
[ground_motion]
file = "{REPO / 'ground_motions' / 'RSN6_IMPVALL.I_I-ELC180-hor1.AT2'}"
units = "g"
[contact]
law = "Hd"
stiffness = 2.75e9
restitution = 0.65
[[building]]
name = "A"
floors = 3
floor_masses = 1.0e5
storey_stiffness = 1.0e8
storey_heights = 3.0
damping = {{ kind = "rayleigh", ratio = 0.05, modes = [1, 2] }}
''')


def _narrowband(rng, f0):
    b, a = signal.iirpeak(f0, 8.0, fs=1.0 / DT)
    x = signal.lfilter(b, a, rng.standard_normal(N + 500))[500:]
    return x / x.std()


def _coverage(f0, amplitude):
    data = _model()
    chans = [Channel(f"XX.A.{f:02d}.HNX", "acceleration", "A", f) for f in (1, 2, 3)]
    clean = Observer(data, REPO, chans, [Trial(Recording(DT, {c.id: np.zeros(N) for c in chans}, []))]).simulate([])[0]
    params = F.parse_fit(["building.A.storey_stiffness=5e7:2e8", "building.A.damping.ratio=0.01:0.2"], data)
    z, sd = [], []
    for seed in range(REPS):
        rng = np.random.default_rng(seed)
        shared = _narrowband(rng, f0)
        rec = {}
        for k, c in enumerate(chans):
            s = clean[c.id].std()
            error = amplitude * s * (0.6 + 0.2 * k) * (shared + 0.3 * _narrowband(rng, f0))
            rec[c.id] = clean[c.id] + error + 0.01 * s * rng.standard_normal(N)
        obs = Observer(data, REPO, chans, [Trial(Recording(DT, rec, []))])
        res = F.calibrate_observer(obs, params, progress=False, tolerance=1e-10)
        z.append([(res.parameters[p]["value"] - TRUTH[p]) / res.parameters[p]["half68"] for p in TRUTH])
        sd.append([res.parameters[p]["value"] for p in TRUTH])
    cover = np.mean(np.abs(np.array(z)) <= 1.0, axis=0)
    print(f"MEASURED f0 {f0} Hz: coverage of the 68 % interval {cover}, spread / median reported error "
          f"{np.std(sd, axis=0) / np.median(np.abs(np.array(sd) - list(TRUTH.values())) / np.abs(z), axis=0)}")
    return cover


@pytest.mark.parametrize("f0, amplitude", [(3.5, 0.3), (2.0, 0.2), (2.24, 0.1)])
def test_interval_covers_the_truth_at_its_nominal_rate(f0, amplitude):
    cover = _coverage(f0, amplitude)
    assert np.all((cover >= 0.60) & (cover <= 0.76)), cover
