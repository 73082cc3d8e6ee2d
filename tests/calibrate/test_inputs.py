"""Channel maps, recordings and trials: what they accept, and one-line errors (CLI exit 2, nothing written)."""

import subprocess
import sys

import numpy as np
import obspy
import pytest

from seispound.calibrate import calibrate, load_channels, read_recording
from seispound.errors import InputError
from seispound.model import load_model
from tests._models import short_copy

MAP = '''[[channel]]
id = "XX.A.00.HN4"
quantity = "acceleration"
building = "A"
floor = 4

[[channel]]
id = "XX.B.00.HN0"
quantity = "acceleration"
building = "B"
floor = 0
units = "g"

[[channel]]
id = "XX.AB.00.FRC"
quantity = "force"
gap = "A|B"
floor = 2
units = "kN"
'''


def _write(folder, n=401, dt=0.005, nan=False, other_dt=False, drop=None):
    st = obspy.Stream()
    for cid in ("XX.A.00.HN4", "XX.B.00.HN0", "XX.AB.00.FRC"):
        if cid == drop:
            continue
        net, sta, loc, cha = cid.split(".")
        x = np.sin(np.arange(n) * dt * 7.0)
        if nan and cid == "XX.A.00.HN4":
            x[17] = np.nan
        d = 0.01 if other_dt and cid == "XX.B.00.HN0" else dt
        st += obspy.Trace(x, header=dict(network=net, station=sta, location=loc, channel=cha, delta=d))
    path = folder / "rec.mseed"
    st.write(str(path), format="MSEED", encoding="FLOAT64")
    return path


@pytest.fixture
def model(tmp_path):
    return load_model(short_copy(tmp_path, 2.0))


def test_a_channel_map_resolves_against_the_model(tmp_path, model):
    (tmp_path / "ch.toml").write_text(MAP)
    chans = load_channels(tmp_path / "ch.toml", model)
    assert [c.quantity for c in chans] == ["acceleration", "acceleration", "force"]
    assert chans[1].factor == pytest.approx(9.80665) and chans[2].factor == 1e3
    assert chans[2].gap == 1  # A|B at A's floor 2: the second gap element
    rec = read_recording(_write(tmp_path), chans)
    assert rec.dt == 0.005 and rec.npts == 401
    np.testing.assert_allclose(rec.data["XX.AB.00.FRC"], 1e3 * np.sin(np.arange(401) * 0.005 * 7.0))


@pytest.mark.parametrize("edit, key", [
    (lambda t: t.replace('building = "A"', 'building = "Q"'), "channel.1.building"),
    (lambda t: t.replace("floor = 4", "floor = 9"), "channel.1.floor"),
    (lambda t: t.replace('quantity = "acceleration"\nbuilding = "B"\nfloor = 0',
                         'quantity = "displacement"\nbuilding = "B"\nfloor = 0'), "channel.2.quantity"),
    (lambda t: t.replace('units = "kN"', 'units = "furlongs"'), "channel.3.units"),
    (lambda t: t.replace("floor = 2\n", ""), "channel.3.gap"),
    (lambda t: t.replace('quantity = "force"', 'quantity = "strain"'), "channel.3.quantity"),
    (lambda t: t.replace('id = "XX.B.00.HN0"', 'id = "XX.A.00.HN4"'), "channel.2.id"),
    (lambda t: t.replace("floor = 4", "floor = 4\nposition = 0.5"), "channel.1.position"),
    (lambda t: t + "\n[[channel]]\nid = 'x'\nquantity = 'force'\ngap = 7\n", "channel.4.gap"),
])
def test_bad_channel_maps_name_their_key(tmp_path, model, edit, key):
    (tmp_path / "ch.toml").write_text(edit(MAP))
    with pytest.raises(InputError) as err:
        load_channels(tmp_path / "ch.toml", model)
    assert err.value.key == key and err.value.file.endswith("ch.toml")


@pytest.mark.parametrize("kw, key", [(dict(nan=True), "XX.A.00.HN4"), (dict(other_dt=True), "XX.B.00.HN0"),
                                     (dict(drop="XX.AB.00.FRC"), "XX.AB.00.FRC")])
def test_bad_recordings_name_the_trace(tmp_path, model, kw, key):
    (tmp_path / "ch.toml").write_text(MAP)
    chans = load_channels(tmp_path / "ch.toml", model)
    with pytest.raises(InputError) as err:
        read_recording(_write(tmp_path, **kw), chans)
    assert err.value.key == key and "rec.mseed" in err.value.file


def test_cli_bad_fit_path_is_one_line_and_writes_nothing(tmp_path):
    path = short_copy(tmp_path, 2.0)
    (tmp_path / "ch.toml").write_text(MAP)
    rec = _write(tmp_path)
    out = tmp_path / "cal.toml"
    proc = subprocess.run([sys.executable, "-m", "seispound", "calibrate", str(path), str(rec), "--channels",
                           str(tmp_path / "ch.toml"), "--fit", "building.A.storey_stifness", "-o", str(out)],
                          capture_output=True, text=True)
    assert proc.returncode == 2
    assert proc.stderr.strip().count("\n") == 0 and "building.A.storey_stifness" in proc.stderr
    assert not out.exists()


def test_fit_paths_and_bounds(tmp_path, model):
    from seispound.calibrate.fit import parse_fit
    import tomllib

    data = tomllib.loads(model.text)
    data["building"][0]["storey_stiffness"] = [1.3e8] * 4  # a list: one factor is fitted on it
    ps = parse_fit(["building.A.storey_stiffness", "contact.restitution=0.3:0.9", "gap.1.size",
                    "building.B.storey_stiffness"], data)
    assert ps[0].factor and ps[0].log and (ps[0].lo, ps[0].hi) == (0.2, 5.0)
    assert ps[0].value_at([1.0, 2.0], 1.5) == [1.5, 3.0]
    assert not ps[3].factor and ps[3].log and ps[3].hi == pytest.approx(10 * 1.1593e8)
    assert not ps[1].log and (ps[1].lo, ps[1].hi) == (0.3, 0.9)
    assert ps[2].lo == 0.0 and not ps[2].log
    for bad, key in (("contact.restitution=0.7:0.9", "contact.restitution"), ("contact.law", "contact.law"),
                     ("contact.restitution=a:b", "contact.restitution")):
        with pytest.raises(InputError) as err:
            parse_fit([bad], data)
        assert err.value.key == key


def test_trials_differ_in_initial_velocity(tmp_path):
    """Two pendulum trials (the bundled slab test) from one recording each, through the trials file."""
    from seispound import simulate

    text = (short_copy.__globals__["REPO"] / "models" / "slab_pendulum.toml").read_text()
    (tmp_path / "pendulum.toml").write_text(text)
    model = load_model(tmp_path / "pendulum.toml")
    names = [b.name for b in model.buildings]
    lines = []
    for k, v in enumerate((0.3, 0.5)):
        model.buildings[0].initial_velocity = np.array([v])
        ds = simulate(model, twin=False)
        f = ds.pounding_force.values[:, 0]
        tr = obspy.Trace(f.copy(), header=dict(network="XX", station="LAB", location="00", channel="FRC",
                                               delta=float(ds.attrs["dt"])))
        obspy.Stream([tr]).write(str(tmp_path / f"t{k}.mseed"), format="MSEED", encoding="FLOAT64")
        lines.append(f'[[trial]]\nname = "v{v}"\nrecording = "t{k}.mseed"\n'
                     f'initial_velocity = {{ {names[0]} = [{v}] }}\n')
    (tmp_path / "trials.toml").write_text("\n".join(lines))
    (tmp_path / "ch.toml").write_text('[[channel]]\nid = "XX.LAB.00.FRC"\nquantity = "force"\ngap = 1\n')
    res = calibrate(tmp_path / "pendulum.toml", channels=tmp_path / "ch.toml", trials=tmp_path / "trials.toml",
                    fit=["contact.stiffness"], progress=False)
    assert set(res.ne_after) == {"v0.3", "v0.5"}
    print(f"MEASURED trials: NE after {res.ne_mean_after:.1e}, stiffness {res.parameters['contact.stiffness']}")
    assert res.ne_mean_after <= 1e-6  # the model made the recordings: the fit stays where it started
    # the same from the command line: the calibrated model is written and runs
    out = tmp_path / "calibrated.toml"
    proc = subprocess.run([sys.executable, "-m", "seispound", "calibrate", str(tmp_path / "pendulum.toml"),
                           "--trials", str(tmp_path / "trials.toml"), "--channels", str(tmp_path / "ch.toml"),
                           "--fit", "contact.stiffness", "-o", str(out)], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert "contact.stiffness" in proc.stdout and "written to" in proc.stdout
    assert load_model(out).contact.stiffness == pytest.approx(3.2e9, rel=1e-6)


def test_an_unknown_building_in_a_trials_file_names_the_file_and_the_key(tmp_path):
    """A trial's initial velocity for a building the model lacks: one line naming the trials file."""
    from seispound.calibrate.api import load_inputs
    from seispound.calibrate.observe import Observer

    text = (short_copy.__globals__["REPO"] / "models" / "slab_pendulum.toml").read_text()
    (tmp_path / "pendulum.toml").write_text(text)
    model = load_model(tmp_path / "pendulum.toml")
    ds = __import__("seispound").simulate(model, twin=False)
    tr = obspy.Trace(ds.pounding_force.values[:, 0].copy(), header=dict(network="XX", station="LAB", location="00",
                                                                        channel="FRC", delta=float(ds.attrs["dt"])))
    obspy.Stream([tr]).write(str(tmp_path / "t.mseed"), format="MSEED", encoding="FLOAT64")
    (tmp_path / "trials.toml").write_text('[[trial]]\nrecording = "t.mseed"\ninitial_velocity = { Nobody = [0.3] }\n')
    (tmp_path / "ch.toml").write_text('[[channel]]\nid = "XX.LAB.00.FRC"\nquantity = "force"\ngap = 1\n')
    model, chans, trials = load_inputs(tmp_path / "pendulum.toml", None, tmp_path / "ch.toml", tmp_path / "trials.toml")
    with pytest.raises(InputError) as err:
        Observer(__import__("tomllib").loads(model.text), tmp_path, chans, trials).simulate([])
    assert err.value.file == str(tmp_path / "trials.toml") and err.value.key == "trial.1.initial_velocity.Nobody"
    assert "unknown building 'Nobody'" in str(err.value) and "\n" not in str(err.value)
