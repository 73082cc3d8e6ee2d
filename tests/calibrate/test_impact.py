"""The seed's procedure for impact tests (``seispound.calibrate.impact``, ``seispound impact``)."""

import subprocess
import sys
import tomllib

import numpy as np
import obspy
import pytest

from seispound import InputError
from seispound.calibrate.channels import Channel
from seispound.calibrate.impact import first_pulse, impact_study, velocity_at
from seispound.calibrate.observe import Observer, Trial
from seispound.calibrate.recording import Recording
from tests._models import REPO

MODEL = REPO / "models" / "slab_pendulum.toml"


def test_first_pulse_and_its_start():
    dt = 1e-4
    t = np.arange(200) * dt
    f = np.where((t > 0.00525) & (t < 0.00925), 1e3 * np.sin(np.pi * (t - 0.00525) / 0.004), 0.0)
    f[130:] -= 50.0 * np.sin(np.arange(70))  # ringing after the pulse
    i0, i1, t0 = first_pulse(f, dt)
    assert f[i0] > 20.0 and f[i0 - 1] <= 20.0 and f[i1 + 1] <= 20.0
    assert abs(t0 - 0.00525) <= dt  # back to zero along the chord: within the sample it lies in


def test_velocity_from_a_displacement_line():
    x = 0.3 + 0.125 * np.arange(50) * 1e-3
    assert velocity_at(x, 1e-3, 10, 40) == pytest.approx(0.125, rel=1e-12)


def _recordings(folder, k=3.2e9, e=0.7, velocities=(0.05, 0.15)):
    """Force and both displacements of the lumped pendulum pair itself (Hd at k, e)."""
    data = tomllib.loads(MODEL.read_text())
    data["contact"].update(stiffness=k, restitution=e)
    chans = [Channel("XX.LAB.00.FRC", "force", gap=0), Channel("XX.A.00.LDX", "displacement", "striker", 1),
             Channel("XX.B.00.LDX", "displacement", "struck", 1)]
    lines = []
    for n, v0 in enumerate(velocities):
        rec = Recording(1e-4, {c.id: np.zeros(801) for c in chans}, [])
        obs = Observer(data, MODEL.parent, chans, [Trial(rec, "t", initial_velocity={"striker": [v0]})])
        sim = obs.simulate([("gap.1.size", v0 * 0.01), ("analysis.dt", 1e-4)])[0]
        st = obspy.Stream([obspy.Trace(sim[c.id].copy(), header=dict(
            network="XX", station=c.id.split(".")[1], location="00", channel=c.id.split(".")[3], delta=1e-4))
            for c in chans])
        st.write(str(folder / f"t{n}.mseed"), format="MSEED", encoding="FLOAT64")
        lines.append(f'[[trial]]\nname = "{v0}"\nrecording = "t{n}.mseed"\n')
    (folder / "trials.toml").write_text("\n".join(lines))
    (folder / "ch.toml").write_text(
        '[[channel]]\nid = "XX.LAB.00.FRC"\nquantity = "force"\ngap = 1\n\n'
        '[[channel]]\nid = "XX.A.00.LDX"\nquantity = "displacement"\nbuilding = "striker"\nfloor = 1\n\n'
        '[[channel]]\nid = "XX.B.00.LDX"\nquantity = "displacement"\nbuilding = "struck"\nfloor = 1\n')


def test_the_law_that_made_the_recording_is_recovered(tmp_path):
    _recordings(tmp_path)
    study = impact_study(MODEL, tmp_path / "trials.toml", tmp_path / "ch.toml", laws=("Hd", "LVe", "MLVe"))
    for t in study.trials:
        hd = t.laws["Hd"]
        print(f"MEASURED trial {t.name} m/s: e from displacements {t.restitution:.5f}, Hd k {hd.stiffness:.5g} "
              f"(3.2e9), NE Hd {hd.ne:.1e}, LVe {t.laws['LVe'].ne:.1%}, MLVe {t.laws['MLVe'].ne:.1%}")
        assert t.velocity == pytest.approx(float(t.name), rel=2e-3)
        assert t.restitution == pytest.approx(0.7, rel=2e-3)
        assert hd.stiffness == pytest.approx(3.2e9, rel=1e-2)
        assert hd.ne <= 0.01 < t.laws["LVe"].ne < t.laws["MLVe"].ne
    assert "| best |" in study.table() and study.table().count("| Hd |") == 2


def test_cli_writes_table_and_figure(tmp_path):
    _recordings(tmp_path, velocities=(0.1,))
    out, fig = tmp_path / "table.md", tmp_path / "fig.png"
    proc = subprocess.run([sys.executable, "-m", "seispound", "impact", str(MODEL), "--trials",
                           str(tmp_path / "trials.toml"), "--channels", str(tmp_path / "ch.toml"), "--laws", "Hd,LVe",
                           "-o", str(out), "--figure", str(fig), "-q"], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert "NE Hd" in out.read_text() and fig.read_bytes()[:4] == b"\x89PNG"
    bad = subprocess.run([sys.executable, "-m", "seispound", "impact", str(MODEL), "--trials",
                          str(tmp_path / "trials.toml"), "--channels", str(tmp_path / "ch.toml"), "--laws", "Hx"],
                         capture_output=True, text=True)
    assert bad.returncode == 2 and "--laws" in bad.stderr and bad.stderr.strip().count("\n") == 0


def test_a_multi_storey_row_is_refused_naming_the_model_file(tmp_path):
    with pytest.raises(InputError) as err:
        impact_study(REPO / "models" / "two_buildings.toml", tmp_path / "trials.toml", tmp_path / "ch.toml")
    assert err.value.file == str(REPO / "models" / "two_buildings.toml") and err.value.key == "gap"
    assert "multi-storey row" in str(err.value)
