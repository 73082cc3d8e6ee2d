"""seispound against OpenSees (OpenSeesPy) on the small peer cases (CI; the large ones: benchmarks/peer).

Both programs are built from one description (``benchmarks.peer.cases``): a
3 + 5 storey pair, 5 s of El Centro 180 (bundled) after a zero sample, gaps of
1 cm, each law that both programs have (LVe <-> ViscoelasticGap, NIVe <->
JankowskiImpact n = 1.5, MLVe <-> JankowskiImpact n = 1) and no contact.
OpenSees has no event location, so it runs at dt = 6.25e-5 s, where its peak
forces and impact counts have converged (``docs/peer.md``); seispound runs at the
same step so that the histories share one time grid.  Targets of the issue:
peaks within 1 %, impact counts equal.
"""

import numpy as np
import pytest

from benchmarks.peer.cases import PAIR, PeerCase
from benchmarks.peer.compare import compare_case
from benchmarks.peer.opensees import run_opensees


@pytest.fixture(scope="module", autouse=True)
def opensees():
    try:
        from benchmarks.peer.opensees import import_opensees

        return import_opensees()
    except (ImportError, RuntimeError) as exc:  # the peer extra is not installed here
        pytest.skip(f"openseespy unavailable ({exc}); install the 'peer' extra")


DT = 6.25e-5


def case(law, duration=5.0):
    return PeerCase(f"pair, El Centro 180, {law}", PAIR, 0.01, law, "elcentro_180", duration)


@pytest.mark.parametrize("law", ["LVe", "NIVe", "MLVe", None])
def test_peaks_impacts_and_histories_agree(law):
    r = compare_case(case(law), DT)
    print(f"MEASURED peer {law}: peak displacement {r['peak_displacement_max_rel']:.2e}, peak force "
          f"{r['peak_force_max_rel']:.2e}, displacement history {r['history_displacement_max_rel']:.2e}, "
          f"force history {r['history_force_max_rel']:.2e}, impacts {r['impacts_seispound']}")
    assert r["peak_displacement_max_rel"] <= 0.01
    assert r["peak_force_max_rel"] <= 0.01
    assert r["impacts_equal"]
    assert r["history_displacement_max_rel"] <= 0.01
    assert r["unconverged_opensees_steps"] == 0
    if law is not None:
        assert sum(r["impacts_seispound"]) >= 10  # the comparison is about pounding
    else:
        assert r["peak_displacement_max_rel"] <= 1e-9  # linear: the same Newmark recurrence


def test_opensees_is_converged_at_the_comparison_step():
    """Halving OpenSees' step changes its peak force by < 1 % and no impact count."""
    c = case("LVe", 4.0)
    out = []
    for dt in (2 * DT, DT):
        ag, n = c.ground(dt)
        out.append(run_opensees(c.model(dt), ag, dt, n))
    f2, f1 = out[0].peak_force.max(), out[1].peak_force.max()
    print(f"MEASURED OpenSees LVe peak force {f2:.6g} (dt {2 * DT}) -> {f1:.6g} (dt {DT})")
    assert abs(f2 - f1) <= 0.01 * f1
    assert np.array_equal(out[0].impacts, out[1].impacts)


def test_opensees_starts_newmark_from_zero_acceleration():
    """By design OpenSees starts from a(0) = 0; seispound from equilibrium a(0) = -a_g(0).

    With a record whose first sample a_g(0) is not zero the linear responses
    differ in proportion to it (1e-6 for a_g(0) = 0.001 m/s^2, 1e-5 for El
    Centro's raw 0.0098 m/s^2); after a leading zero sample (what the peer
    cases use) they agree to round-off.
    """
    c = case(None, 4.0)
    dt = 0.001
    ag, n = c.ground(dt)
    shifted = ag.copy()
    shifted[:-1] = ag[1:]  # drop the leading zero: the motion now starts at a_g(0) = 0.001 m/s^2
    assert shifted[0] != 0.0
    for acc, lo, hi in ((ag, 0.0, 1e-9), (shifted, 1e-7, 1e-3)):
        o = run_opensees(c.model(dt), acc, dt, n)
        s = _seispound_with(c, acc, dt, n)
        d = np.max(np.abs(o.displacement - s)) / np.max(np.abs(s))
        print(f"MEASURED a_g(0) = {acc[0]:.4g}: linear history difference {d:.2e}")
        assert lo <= d <= hi


def _seispound_with(c, ag, dt, n):
    from seispound.integrate import integrate
    from seispound.structure import assemble

    m = c.model(dt)
    return integrate(assemble(m.buildings, m.gaps, m.contact), ag, dt, n, scheme="newmark").displacement
