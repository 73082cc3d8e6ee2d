"""A building driven by the acceleration recorded at its base (``spatially-varying-input``'s third form).

Partly incoherent input has a random part that no delay or filter of the free field reproduces; a sensor
at the building's base records it.  ``diagnose`` hands the form each building's base channel that is not
the model's own input (``api._context``), and the form fits the share w of it in the building's motion from
w = 0, the base model.  Regression guard on data the package made (the truth w = 1 and the noise's NE are known, so a
fit that does not converge, or a form that drives the wrong building, fails)."""

from __future__ import annotations

import copy
import tomllib
from pathlib import Path

import numpy as np

from seispound.calibrate.channels import Channel
from seispound.calibrate.fit import calibrate_observer, parse_fit
from seispound.calibrate.observe import Observer, Trial
from seispound.calibrate.recording import Recording
from seispound.diagnose import api
from seispound.diagnose.hypotheses import HYPOTHESES
from seispound.model.paths import set_value

REPO = Path(__file__).resolve().parents[2]
MODELS = REPO / "models"
DT, T = 0.005, 4.0


def _incoherent(ag, rng):
    """The row's record plus an independent signal with its amplitude spectrum (random phases), half as strong."""
    spec = np.abs(np.fft.rfft(ag)) * np.exp(2j * np.pi * rng.uniform(size=ag.size // 2 + 1))
    return ag + 0.5 * np.fft.irfft(spec, ag.size)


def _case(tmp_path):
    import obspy

    from seispound.simulation import prepare_ground_motion
    import seispound as sp

    data = tomllib.loads((MODELS / "two_buildings.toml").read_text())
    data["analysis"]["duration"] = T
    n = int(round(T / DT)) + 1
    ag, _ = prepare_ground_motion(sp.load_model(MODELS / "two_buildings.toml"))
    rng = np.random.default_rng(11)
    base_b = _incoherent(np.asarray(ag[:n], float), rng)
    tr = obspy.Trace(base_b, header={"network": "XX", "station": "B", "location": "00", "channel": "HNX",
                                     "delta": DT})
    file = tmp_path / "recording.mseed"
    obspy.Stream([tr]).write(str(file), format="MSEED", encoding="FLOAT64")
    floors = [Channel(f"XX.{b}.{f:02d}.HNX", "acceleration", b, f) for b in ("A", "B") for f in (2, 4)]
    truth_data = copy.deepcopy(data)
    truth_data["building"][1]["ground_motion"] = {"file": str(file), "trace": "XX.B.00.HNX", "units": "m/s2"}
    blank = [Trial(Recording(DT, {c.id: np.zeros(n) for c in floors}, []))]
    truth = Observer(truth_data, MODELS, floors, blank).simulate([])[0]
    rec = {c.id: truth[c.id] + 0.01 * truth[c.id].std() * rng.standard_normal(n) for c in floors}
    base_chans = [Channel("XX.FF.00.HNX", "acceleration", "A", 0), Channel("XX.B.00.HNX", "acceleration", "B", 0)]
    rec["XX.B.00.HNX"], rec["XX.FF.00.HNX"] = base_b, np.asarray(ag[:n], float)
    files = {"XX.B.00.HNX": str(file), "XX.FF.00.HNX": str(tmp_path / "ground_motion.mseed")}
    return data, floors, base_chans, Trial(Recording(DT, rec, [str(file)], files))


def test_the_context_holds_each_buildings_base_channel_and_none_for_several_trials(tmp_path):
    data, floors, base_chans, trial = _case(tmp_path)
    # the free field, the model's input, is mapped at A's floor 0 too: it is no base channel of A
    ctx = api._context(base_chans + floors, [trial], {"XX.FF.00.HNX"})
    assert ctx.base_records == {"B": {"file": str(tmp_path / "recording.mseed"), "trace": "XX.B.00.HNX", "scale": 1.0}}
    assert set(api._context(base_chans + floors, [trial]).base_records) == {"A", "B"}  # (without the input's id)
    assert api._context(base_chans + floors, [trial, trial], {"XX.FF.00.HNX"}).base_records == {}


def test_the_share_of_the_recorded_base_motion_is_fitted_from_the_base_model_to_one(tmp_path):
    data, floors, base_chans, trial = _case(tmp_path)
    hyp = HYPOTHESES["spatially-varying-input"]
    k = next(k for k, f in enumerate(hyp.forms) if getattr(f, "reads_recording", False))
    aug, specs, null = hyp.augment(data, k, api._context(base_chans + floors, [trial], {"XX.FF.00.HNX"}))
    table = copy.deepcopy(aug)
    for path, value in null.items():
        set_value(table, path, value)
    before = Observer(table, MODELS, floors, [trial]).simulate([])[0]
    ne_before = np.mean([np.linalg.norm(before[c.id] - trial.recording.data[c.id])
                         / np.linalg.norm(trial.recording.data[c.id]) for c in floors])
    # as diagnose does: the scan's best start (pounding makes the misfit between w = 0 and 1 rugged), then a fit
    start = api._best_candidates(aug, specs, MODELS, floors, [trial])[0][0]
    for path, value in start.items():
        set_value(aug, path, value)
    obs = Observer(aug, MODELS, floors, [trial])
    fit = calibrate_observer(obs, parse_fit(specs, aug), progress=False, max_evaluations=40, tolerance=1e-6)
    w = fit.parameters["building.B.ground_motion.weight"]["value"]
    noise = np.mean([0.01 * trial.recording.data[c.id].std() / np.linalg.norm(trial.recording.data[c.id])
                     * np.sqrt(trial.recording.npts) for c in floors])
    print(f"w {w:.6f}, NE at w = 0 {ne_before:.4f}, start {start}, after {fit.ne_mean_after:.5f}, noise {noise:.5f}")
    assert ne_before > 20 * noise  # the base model, driven by the free field, misses B
    assert abs(w - 1.0) <= 3e-4  # measured 1.1e-4
    assert fit.ne_mean_after <= 1.03 * noise  # measured 1.01
