"""The model is validated the same way from a TOML file and from Python, and unstable settings are refused.

Regression tests of bugs found in a fresh install:
* ``floor_masses = "1e5"`` was blamed on ``storey_stiffness``;
* ``model.gaps[0].size = "0.02"`` was accepted from Python though the file reader refuses it;
* Newmark with beta = 1/6 and dt = 0.1 s diverged to 1e119 m and exited 0.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import seispound as sp
from seispound import InputError, cli
from seispound.integrate import IntegrationError, Newmark, integrate
from seispound.structure import assemble
from tests.cli.test_bad_input import BASE, sub, write_model



@pytest.mark.parametrize("old, new, key", [
    ("floor_masses = 1.0e5", 'floor_masses = "1e5"', "building.B.floor_masses"),
    ("storey_stiffness = 1.1593e8", 'storey_stiffness = "1.1593e8"', "building.B.storey_stiffness"),
    ("floor_masses = [1.0e5, 1.0e5, 1.0e5, 1.0e5]", 'floor_masses = [1.0e5, "1e5", 1.0e5, 1.0e5]',
     "building.A.floor_masses"),
    ("size = 0.02", 'size = "0.02"', "gap.1.size"),
    ("size = 0.02", "size = [0.02, true, 0.02, 0.02]", "gap.1.size"),
])
def test_wrong_type_reported_at_its_own_key(tmp_path, capsys, old, new, key):
    model = write_model(tmp_path, sub(old, new)(BASE))
    assert cli.main(["run", str(model), "-o", str(tmp_path / "r.h5")]) == 2
    line = capsys.readouterr().err.strip()
    assert "\n" not in line
    assert f"model.toml: {key}: must be a number or a list of numbers" in line, line
    assert not (tmp_path / "r.h5").exists()


@pytest.mark.parametrize("edit, key", [
    (lambda m: setattr(m.gaps[0], "size", "0.02"), "gap.1.size"),
    (lambda m: setattr(m.gaps[0], "size", -0.01), "gap.1.size"),
    (lambda m: setattr(m.buildings[1], "floor_masses", "1e5"), "building.B.floor_masses"),
    (lambda m: setattr(m.buildings[0], "storey_stiffness", [1e8, 1e8]), "building.A.storey_stiffness"),
    (lambda m: m.contact.set_params(restitution=1.5), "contact.restitution"),
    (lambda m: setattr(m.analysis, "dt", "0.005"), "analysis.dt"),
])
def test_python_api_validates_like_the_file_reader(tmp_path, edit, key):
    """A value set from Python after loading is refused by simulate() at the key the file reader names."""
    model = sp.load_model(write_model(tmp_path, BASE))
    edit(model)
    with pytest.raises(InputError) as info:
        sp.simulate(model, twin=False)
    assert info.value.key == key
    assert info.value.file == str(tmp_path / "model.toml")


def test_newmark_beyond_its_stability_limit_is_refused(tmp_path, capsys):
    """beta = 1/6 (linear acceleration), dt = 0.1 s: the limit dt <= 0.551 T_n (Chopra Eq. 5.5.1)."""
    text = sub("dt = 0.005", "dt = 0.1\nnewmark = { beta = 0.16666666666666666, gamma = 0.5 }")(BASE)
    text = sub("duration = 0.2", "duration = 2.0")(text)
    model = write_model(tmp_path, text)
    assert cli.main(["run", str(model), "-o", str(tmp_path / "r.h5")]) == 2
    line = capsys.readouterr().err.strip()
    assert "model.toml: analysis.dt: Newmark beta = 0.166667, gamma = 0.5 is stable only for dt <=" in line
    assert not (tmp_path / "r.h5").exists()
    # the limit itself: T_min of the row against 1 / (pi sqrt(2) sqrt(gamma - 2 beta)) = sqrt(3) / pi
    m = sp.load_model(write_model(tmp_path, BASE))
    t_min = min(b.periods[-1] for b in m.buildings)
    limit = Newmark(beta=1 / 6, gamma=0.5).stability_limit()
    assert limit == pytest.approx(math.sqrt(3) / math.pi, rel=1e-12)
    m.analysis.newmark = Newmark(beta=1 / 6, gamma=0.5)
    m.analysis.dt = 0.999 * limit * t_min  # just inside: accepted
    m.validate()
    m.analysis.dt = 1.001 * limit * t_min  # just outside: refused
    with pytest.raises(InputError, match="would diverge"):
        m.validate()


def test_central_difference_needs_two_contact_substeps(tmp_path):
    """beta = 0: dt / T <= 1 / pi; half a contact period in one substep (0.5 T_c) is unstable."""
    m = sp.load_model(write_model(tmp_path, BASE))
    m.analysis.dt = 1e-4
    m.analysis.newmark = Newmark(beta=1e-12, gamma=0.5, contact_substeps=1)
    with pytest.raises(InputError) as info:
        m.validate()
    assert info.value.key == "analysis.contact_substeps" and "contact_substeps >= 2" in str(info.value)
    m.analysis.newmark.contact_substeps = 2
    m.validate()


def test_a_diverging_run_stops_with_the_time(tmp_path):
    """Run the kernel past the limit directly (the model check refuses it): simulate's guard names the time."""
    from seispound.simulation import _check_finite, prepare_ground_motion

    m = sp.load_model(write_model(tmp_path, BASE))
    m.analysis.duration = 20.0  # about 450 steps: the stiffest mode grows 6.9 times a step
    system = assemble(m.buildings, [], None)
    ag, _ = prepare_ground_motion(m)
    t_min = min(b.periods[-1] for b in m.buildings)
    nm = Newmark(beta=0.0 + 1e-9, gamma=0.5)
    dt = 1.5 * nm.stability_limit() * t_min
    n = int(20.0 / dt)
    ag = np.interp(np.arange(n + 1) * dt, np.arange(ag.size) * 0.005, ag)
    raw = integrate(system, ag, dt, n, nm, free_flight=False, scheme="newmark")  # (the exact scheme cannot diverge)
    bad = ~np.isfinite(raw.energy).all(axis=1)
    assert bad.any(), "the unstable run did not overflow: lengthen it"
    t_bad = raw.time[np.argmax(bad)]
    with pytest.raises(IntegrationError) as info:
        _check_finite(raw, dt)
    assert f"not finite at t = {t_bad:.6g} s" in str(info.value)
