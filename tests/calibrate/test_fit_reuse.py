"""A fit's result comes from the simulations it ran: no simulation of its own at the end.

``calibrate_observer`` keeps the simulations of its lowest-misfit evaluations and ends at one of them (least
squares returns a point it evaluated), so the NE it reports at the fitted values must equal that of a fresh
simulation there, and the Observer must have run exactly one simulation per evaluation in the fit's history.
A regression guard of the reuse, not a verification.
"""

import tomllib

import pytest

from seispound.calibrate.api import load_inputs
from seispound.calibrate.fit import calibrate_observer, normalised_errors, parse_fit
from seispound.calibrate.observe import Observer
from tests.verification.test_calibration_synthetic import _model, _recordings

FIT = ["building.A.storey_stiffness", "gap.1.size", "building.B.damping.ratio"]


def test_the_reported_fit_is_a_fresh_simulation_at_the_fitted_values(tmp_path):
    _recordings(tmp_path)
    model, chans, trials = load_inputs(_model(tmp_path, off=1.1), [tmp_path / "recording.mseed"],
                                       tmp_path / "channels.toml", None)
    data = tomllib.loads(model.text)
    obs = Observer(data, tmp_path, chans, trials)
    res = calibrate_observer(obs, parse_fit(FIT, data), progress=False, max_evaluations=60)
    assert obs.evaluations == len(res.history)  # one simulation per evaluation, none at the end
    fitted = Observer(tomllib.loads(res.model_text), tmp_path, chans, trials).simulate([])
    recs = [{c.id: t.recording.data[c.id] for c in chans} for t in trials]
    for t, sim, rec in zip(trials, fitted, recs):
        fresh = normalised_errors(sim, rec)
        for cid, ne in res.ne_after[t.name].items():
            print(f"MEASURED {cid}: reported NE {ne!r}, fresh {fresh[cid]!r}")
            assert ne == pytest.approx(fresh[cid], rel=1e-12)  # measured equal to the last digit
