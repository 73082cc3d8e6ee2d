"""Development checks of ``diagnose`` on recordings the package itself makes (1 % noise, 6 s of El Centro).

Not the proof: the simulator here agrees with itself.  The proof is the concealed-data benchmark
(``benchmarks/diagnose``), whose generator is an independent solver.  These checks guard the pipeline:
a control with only wrong parameters names no physics, and a yielding row is named inelastic.
"""

import json
import subprocess
import sys
import tomllib

import numpy as np
import obspy
import pytest

from seispound.calibrate.channels import Channel
from seispound.calibrate.observe import Observer, Trial
from seispound.calibrate.recording import Recording
from tests._models import short_copy


def _case(folder, effect):
    model = short_copy(folder, 6.0)
    data = tomllib.loads(model.read_text())
    chans = [Channel(f"XX.{b}.{f:02d}.HNX", "acceleration", b, f) for b, f in (("A", 2), ("A", 4), ("B", 4),
                                                                              ("B", 8))]
    overrides = []
    if effect == "inelastic-storey":
        for b in data["building"]:
            b["storey_law"] = {"kind": "bilinear", "yield_drift": 0.004, "post_yield_ratio": 0.05}
    else:  # wrong nominal parameters only
        overrides = [("building.A.storey_stiffness", 1.3092e8 * 1.15), ("gap.1.size", 0.015)]
    n = 1201
    sim = Observer(data, folder, chans, [Trial(Recording(0.005, {c.id: np.zeros(n) for c in chans}, []), "t")]
                   ).simulate(overrides)[0]
    rng = np.random.default_rng(11)
    st = obspy.Stream()
    for c in chans:
        x = sim[c.id] + 0.01 * np.sqrt(np.mean(sim[c.id] ** 2)) * rng.standard_normal(n)
        net, sta, loc, cha = c.id.split(".")
        st += obspy.Trace(x, header=dict(network=net, station=sta, location=loc, channel=cha, delta=0.005))
    st.write(str(folder / "rec.mseed"), format="MSEED", encoding="FLOAT64")
    (folder / "ch.toml").write_text("\n".join(
        f'[[channel]]\nid = "{c.id}"\nquantity = "acceleration"\nbuilding = "{c.building}"\nfloor = {c.floor}\n'
        for c in chans))
    return model


@pytest.mark.parametrize("effect", ["none", "inelastic-storey"])
def test_diagnose_names_the_effect_or_none(tmp_path, effect):
    model = _case(tmp_path, effect)
    report = tmp_path / "report.json"
    proc = subprocess.run([sys.executable, "-m", "seispound", "diagnose", str(model), str(tmp_path / "rec.mseed"),
                           "--channels", str(tmp_path / "ch.toml"), "--report", str(report), "--figure",
                           str(tmp_path / "fig.png"), "-q"], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    rep = json.loads(report.read_text())
    named = [x["physics"] for x in rep["left_out"]]
    print(f"MEASURED development case {effect}: named {named or 'nothing'}, NE {rep['fit']['before']:.4f} -> "
          f"{rep['fit']['after']:.4f}")
    assert named[:1] == ([] if effect == "none" else [effect])
    assert rep["fit"]["after"] <= 0.5 * rep["fit"]["before"]
    # measured 0.0251, 2.0 times the noise's 0.0124, under the joint search (the bilinear form's joint fit stops
    # short of the noise); the procedure before it reached 0.02 here: a regression that docs/diagnose.md records
    assert rep["fit"]["after"] <= 0.03
    assert set(rep) >= {"mismatch", "left_out", "recalibrated", "fit", "augmented_model"}
    per = [v for nes in rep["fit"]["per_channel"].values() for v in nes.values()]
    assert len(per) == 4 and abs(np.mean([v["before"] for v in per]) - rep["fit"]["before"]) < 1e-12
    assert abs(np.mean([v["after"] for v in per]) - rep["fit"]["after"]) < 1e-12
    assert all(set(m) >= {"channel", "t_start", "t_end", "band_hz", "residual_share"} for m in rep["mismatch"])
    from seispound.model import load_model

    load_model(rep["augmented_model"])  # the augmented model runs
    assert (tmp_path / "fig.png").read_bytes()[:4] == b"\x89PNG"
