"""Recordings of motion carry no force scale (closed form, derived): every mass, storey stiffness and the contact's
stiffness multiplied by one factor c turns the equations of motion into c times themselves, so every simulated
acceleration is unchanged.  Checked on the bundled pair (Hd), with the contact law LVe (whose dashpot follows
from e and the two masses) and with bilinear storeys given by their yield drift; a foundation's springs, not
scaled, break it, and ``calibrate.fit.force_scale`` says so."""

from __future__ import annotations

import tomllib

import numpy as np
import pytest

from seispound.calibrate.channels import Channel
from seispound.calibrate.fit import force_scale, parse_fit
from seispound.calibrate.observe import Observer, Trial
from seispound.calibrate.recording import Recording
from seispound.model.paths import get_value
from tests._models import short_copy

SCALE = ["building.A.storey_stiffness", "building.B.storey_stiffness", "building.A.floor_masses",
         "building.B.floor_masses", "contact.stiffness"]
CHANS = [Channel(f"XX.{b}.{f:02d}.HNX", "acceleration", b, f) for b, f in (("A", 2), ("A", 4), ("B", 4), ("B", 8))]
SPRINGS = ('foundation = { mass = 2e5, rotary_inertia = 2e6, floor_rotary_inertia = 5e5, sway_stiffness = 2e9, '
           'sway_damping = 4e7, rocking_stiffness = 2e11, rocking_damping = 1e9 }\n')


def _observer(tmp_path, edit=None):
    text = short_copy(tmp_path, 6.0).read_text()
    data = tomllib.loads(edit(text) if edit else text)
    n = 1201
    return data, Observer(data, tmp_path, CHANS, [Trial(Recording(0.005, {c.id: np.zeros(n) for c in CHANS}, []))])


def _scaled(data, obs, c):
    over = [(p, [v * c for v in get_value(data, p)] if isinstance(get_value(data, p), list) else get_value(data, p) * c)
            for p in SCALE]
    return obs.simulate(over)[0]


@pytest.mark.parametrize("edit", [
    None,
    lambda t: t.replace('law = "Hd"', 'law = "LVe"'),
    lambda t: t.replace("storey_heights = 3.0",
                        'storey_heights = 3.0\nstorey_law = { kind = "bilinear", yield_drift = 0.004, '
                        'post_yield_ratio = 0.05 }'),
], ids=["Hd", "LVe", "bilinear storeys"])
def test_scaling_every_force_carrier_changes_no_acceleration(tmp_path, edit):
    data, obs = _observer(tmp_path, edit)
    s0 = obs.simulate([])[0]
    s1 = _scaled(data, obs, 1.7)
    worst = max(np.max(np.abs(s1[k] - s0[k])) / np.max(np.abs(s0[k])) for k in s0)
    print(f"MEASURED largest change {worst:.2e} of a channel's peak")
    assert worst < 1e-11  # measured 6.6e-13 to 3.3e-12
    params = parse_fit(SCALE, data)
    flat = force_scale(obs, params, {p.path: get_value(data, p.path) for p in params}, obs.simulate([]))
    assert sorted(flat) == sorted(SCALE)


def test_a_foundation_holds_the_scale(tmp_path):
    # B on springs that are not scaled: the same factor now changes the response, and no direction is flat
    data, obs = _observer(tmp_path, lambda t: t.replace('name = "B"', 'name = "B"\n' + SPRINGS))
    s0 = obs.simulate([])[0]
    s1 = _scaled(data, obs, 1.7)
    assert max(np.max(np.abs(s1[k] - s0[k])) / np.max(np.abs(s0[k])) for k in s0) > 1e-3
    params = parse_fit(SCALE, data)
    assert force_scale(obs, params, {p.path: get_value(data, p.path) for p in params}, obs.simulate([])) == {}
