"""Contact laws against the seed paper's formulas (Khatiwada & Chouw, Section 2, Eqs. 1-9).

The expected values are written out here independently with NumPy; the Eq. 8
root is checked against a 60-digit ``decimal`` solution.
"""

from __future__ import annotations

from decimal import Decimal, localcontext

import numpy as np
import pytest

from seispound import InputError
from seispound.contact import (
    Hd,
    Hertz,
    Hertzdamp,
    LHC,
    LVe,
    MLVe,
    NIVe,
    get_law,
    law_names,
    make_law,
)

K_LIN = 5.0e7  # N/m
K_HZ = 2.75e9  # N/m^1.5
E = 0.65
M1, M2 = 1.2e5, 0.8e5
MEFF = M1 * M2 / (M1 + M2)
V0 = 0.35  # approach velocity at onset [m/s]

DELTA = np.array([1e-7, 1e-5, 3e-4, 2e-3, 1.5e-2])
RATE = np.array([-1.0, -0.3, -0.05, -1e-3, 0.0, 1e-3, 0.05, 0.3, 1.0])
D, R = np.meshgrid(DELTA, RATE, indexing="ij")


# -- the seed's formulas, written out independently -----------------------------------------
def xi_eq3(e):
    return -np.log(e) / np.sqrt(np.pi**2 + np.log(e) ** 2)


def xi_eq5(e):
    return (1 - e**2) / (np.pi * e)


def xibar_eq6(e):
    return 9 * np.sqrt(5) / 2 * (1 - e**2) / (e * (e * (9 * np.pi - 16) + 16))


def c_eq2(xi, k, m1, m2):
    return 2 * xi * np.sqrt(k * m1 * m2 / (m1 + m2))


def eq8_x(e, digits=60):
    """Root x = k / (zeta v0) > e of (1 + e) = x ln|(x + 1)/(x - e)| (seed Eq. 8), by bisection."""
    with localcontext() as ctx:
        ctx.prec = digits
        e = Decimal(e)
        one = Decimal(1)

        def f(x):
            return x * ((x + one) / (x - e)).ln() - (one + e)

        lo, hi = e * (one + Decimal(10) ** -40), Decimal(10) ** 6
        assert f(lo) > 0 > f(hi)
        for _ in range(400):
            mid = (lo + hi) / 2
            if f(mid) > 0:
                lo = mid
            else:
                hi = mid
        return (lo + hi) / 2


def eq8_residual(e, zeta, k, v0, digits=60):
    """(1 + e) - x ln|(x + 1)/(x - e)| at x = k/(zeta v0), in 60-digit arithmetic,
    and |d residual / d x| * x (its sensitivity to a relative change of x)."""
    with localcontext() as ctx:
        ctx.prec = digits
        e, x = Decimal(e), Decimal(k) / (Decimal(zeta) * Decimal(v0))
        one = Decimal(1)
        res = (one + e) - x * ((x + one) / (x - e)).ln()
        slope = ((x + one) / (x - e)).ln() + x * (one / (x + one) - one / (x - e))
        return float(res), float(abs(slope) * x)


def expected_force(name, d, r, k, e, v0, m1, m2):
    n = {"LVe": 1, "MLVe": 1, "LHC": 1}.get(name, 1.5)
    meff = m1 * m2 / (m1 + m2)
    if name == "LVe":  # Eq. 1-3
        F = k * d + c_eq2(xi_eq3(e), k, m1, m2) * r
    elif name == "MLVe":  # Eq. 4-5
        F = np.where(r >= 0, k * d + c_eq2(xi_eq5(e), k, m1, m2) * r, k * d)
    elif name == "NIVe":  # Eq. 6
        cbar = 2 * xibar_eq6(e) * np.sqrt(k * np.sqrt(d) * meff)
        F = np.where(r >= 0, k * d**1.5 + cbar * r, k * d**1.5)
    elif name in ("Hd", "LHC"):  # Eqs. 7-9, zeta from the 60-digit root of Eq. 8
        zeta = k / (float(eq8_x(e)) * v0)
        F = k * d**n + zeta * d**n * r
    elif name == "Hertz":
        F = k * d**1.5
    elif name == "Hertzdamp":  # Muthukumar & DesRoches (2006)
        zeta = 3 * k * (1 - e**2) / (4 * v0)
        F = k * d**1.5 + zeta * d**1.5 * r
    else:  # pragma: no cover
        raise AssertionError(name)
    return F


LAWS = {"LVe": (LVe, K_LIN), "MLVe": (MLVe, K_LIN), "NIVe": (NIVe, K_HZ), "Hd": (Hd, K_HZ),
        "LHC": (LHC, K_LIN), "Hertz": (Hertz, K_HZ), "Hertzdamp": (Hertzdamp, K_HZ)}


def make(name, **kw):
    cls, k = LAWS[name]
    e = 1.0 if name == "Hertz" else E
    return cls(stiffness=k, restitution=e, **kw), k, e


def test_registry_lists_the_eight_laws():
    assert law_names() == ["LVe", "MLVe", "NIVe", "Hd", "LHC", "Hertz", "Hertzdamp", "HC"]


@pytest.mark.parametrize("name", list(LAWS))
def test_force_equals_the_seed_formula(name):
    law, k, e = make(name)
    got = law.force(D, R, V0, M1, M2)
    exp = expected_force(name, D, R, k, e, V0, M1, M2)
    if not law.allows_tension:
        exp = np.maximum(exp, 0.0)
    # |elastic term| + |force|: the bound for entries where the elastic and damping terms cancel
    scale = np.abs(k * D ** law.exponent) + np.abs(exp)
    assert np.all(np.abs(got - exp) <= 1e-12 * scale)
    rel = np.abs(got - exp) / np.where(exp != 0, np.abs(exp), 1.0)
    big = np.abs(exp) > 1e-6 * scale  # no cancellation: plain relative error
    assert big.sum() >= 0.8 * exp.size
    assert rel[big].max() <= 1e-12
    assert got.shape == D.shape


@pytest.mark.parametrize("name", list(LAWS))
def test_force_is_zero_without_contact(name):
    law, _, _ = make(name)
    d = np.array([0.0, -1e-9, -1e-4, -0.02])
    for r in (-0.5, 0.0, 0.5):
        np.testing.assert_array_equal(law.force(d, r, V0, M1, M2), 0.0)


def test_damping_ratios_eqs_3_5_6():
    from seispound.contact import lve_damping_ratio, mlve_damping_ratio, nive_damping_ratio

    for e in (0.05, 0.2, 0.5, 0.65, 0.9, 0.99):
        assert lve_damping_ratio(e) == pytest.approx(xi_eq3(e), rel=1e-14)
        assert mlve_damping_ratio(e) == pytest.approx(xi_eq5(e), rel=1e-14)
        assert nive_damping_ratio(e) == pytest.approx(xibar_eq6(e), rel=1e-14)
        assert LVe(1.0, e).damping_ratio() == lve_damping_ratio(e)
        assert MLVe(1.0, e).damping_ratio() == mlve_damping_ratio(e)
        assert NIVe(1.0, e).damping_ratio() == nive_damping_ratio(e)
    # spot values: e = 0.65
    assert xi_eq3(0.65) == pytest.approx(0.13585, abs=5e-5)
    assert xi_eq5(0.65) == pytest.approx(0.28281, abs=5e-5)
    assert xibar_eq6(0.65) == pytest.approx(0.37284, abs=5e-5)
    # e = 1 is elastic for every ratio
    assert lve_damping_ratio(1.0) == 0.0 and mlve_damping_ratio(1.0) == 0.0 and nive_damping_ratio(1.0) == 0.0


def test_onset_damping_of_the_linear_dashpots():
    # c = 2 xi sqrt(k m1 m2/(m1+m2)) (Eq. 2), fixed for the whole impact
    assert LVe(K_LIN, E).onset_damping(V0, M1, M2) == pytest.approx(c_eq2(xi_eq3(E), K_LIN, M1, M2), rel=1e-14)
    assert MLVe(K_LIN, E).onset_damping(V0, M1, M2) == pytest.approx(c_eq2(xi_eq5(E), K_LIN, M1, M2), rel=1e-14)
    assert NIVe(K_HZ, E).onset_damping(V0, M1, M2) == pytest.approx(xibar_eq6(E), rel=1e-14)


E_GRID = [0.05, 0.07, 0.1, 0.2, 0.3, 0.5, 0.65, 0.8, 0.9, 0.95, 0.99]


@pytest.mark.parametrize("cls, k", [(Hd, K_HZ), (LHC, K_LIN)])
@pytest.mark.parametrize("e", E_GRID)
def test_eq8_root(cls, k, e):
    v0 = 0.27
    zeta = cls(k, e).onset_damping(v0)
    # on the physical branch 0 < zeta < k / (e v0)
    assert 0.0 < zeta < k / (e * v0)
    res, sens = eq8_residual(e, zeta, k, v0)
    # residual below 1e-10 apart from the unavoidable part from rounding zeta to a double
    # (Eq. 8 is steep near x = e: for e = 0.05, one ulp of zeta moves the residual by ~3e-10)
    assert abs(res) < 1e-10 + 4 * 2.2e-16 * sens, (res, sens)
    if sens < 1e4:
        assert abs(res) < 1e-10
    # and zeta agrees with the 60-digit root (as e -> 1 the root s -> 0 and the package's
    # t-form of Eq. 8 loses digits to cancellation: 8e-13 at e = 0.99, 1.5e-10 at e = 0.999)
    zeta_ref = float(Decimal(k) / (eq8_x(e) * Decimal(v0)))
    assert zeta == pytest.approx(zeta_ref, rel=1e-13 if e <= 0.9 else 1e-11)


@pytest.mark.parametrize("e", [0.05, 0.3, 0.65, 0.99])
def test_zeta_v0_over_k_is_independent_of_v0(e):
    law = Hd(K_HZ, e)
    s = [law.onset_damping(v0) * v0 / K_HZ for v0 in (1e-4, 1e-2, 0.1, 1.0, 7.5)]
    np.testing.assert_allclose(s, s[0], rtol=1e-14)
    s_lhc = [LHC(K_LIN, e).onset_damping(v0) * v0 / K_LIN for v0 in (1e-4, 0.1, 7.5)]
    np.testing.assert_allclose(s_lhc, s[0], rtol=1e-14)  # the same Eq. 8 for both laws
    # s rises as e falls: more damping for a more plastic impact
    assert s[0] > 0


def test_eq8_limits():
    assert Hd(K_HZ, 1.0).onset_damping(0.3) == 0.0
    s = [Hd(1.0, e).onset_damping(1.0) for e in E_GRID]
    assert all(a > b for a, b in zip(s, s[1:]))  # decreasing in e
    # near e = 1 Eq. 8 approaches the Lankarani-Nikravesh value 3(1 - e)/2 ... to first order
    e = 0.999
    assert Hd(1.0, e).onset_damping(1.0) == pytest.approx(1.5 * (1 - e), rel=2e-3)


@pytest.mark.parametrize("e", [0.3, 0.65, 0.95])
def test_classic_hertzdamp_zeta(e):
    for v0 in (0.01, 0.3, 2.0):
        assert Hertzdamp(K_HZ, e).onset_damping(v0) == pytest.approx(3 * K_HZ * (1 - e**2) / (4 * v0), rel=1e-14)


# -- registry and validation ------------------------------------------------------------------------
def test_get_law_is_case_insensitive():
    assert get_law("hd") is Hd
    assert get_law("HD") is Hd
    assert get_law("Hd") is Hd
    assert get_law("lve") is LVe
    assert get_law("hertzDAMP") is Hertzdamp
    assert get_law("lhc") is LHC


def test_unknown_law():
    with pytest.raises(InputError) as info:
        get_law("Kelvin")
    assert info.value.key == "contact.law"
    assert "contact.law" in str(info.value) and "Kelvin" in str(info.value)
    with pytest.raises(InputError) as info:
        make_law("nope", stiffness=1.0)
    assert info.value.key == "contact.law"


@pytest.mark.parametrize("bad, key", [
    (dict(stiffness=0.0, restitution=0.5), "contact.stiffness"),
    (dict(stiffness=-1.0, restitution=0.5), "contact.stiffness"),
    (dict(stiffness=float("nan"), restitution=0.5), "contact.stiffness"),
    (dict(stiffness=float("inf"), restitution=0.5), "contact.stiffness"),
    (dict(stiffness="big", restitution=0.5), "contact.stiffness"),
    (dict(stiffness=1e9, restitution=0.0), "contact.restitution"),
    (dict(stiffness=1e9, restitution=-0.2), "contact.restitution"),
    (dict(stiffness=1e9, restitution=1.2), "contact.restitution"),
    (dict(stiffness=1e9, restitution=float("nan")), "contact.restitution"),
    (dict(stiffness=1e9, restitution=0.5, tension="yes"), "contact.tension"),
])
@pytest.mark.parametrize("name", ["LVe", "MLVe", "NIVe", "Hd", "LHC", "Hertzdamp"])
def test_invalid_parameters(name, bad, key):
    with pytest.raises(InputError) as info:
        make_law(name, **bad)
    assert info.value.key == key
    assert key in str(info.value)
    law = get_law(name)(**bad)
    with pytest.raises(InputError) as info:
        law.validate(key="gap.3")
    assert info.value.key == key.replace("contact", "gap.3")


def test_hertz_is_elastic():
    make_law("Hertz", stiffness=K_HZ)  # restitution defaults to 1
    make_law("Hertz", stiffness=K_HZ, restitution=1.0)
    for e in (0.5, 0.99):
        with pytest.raises(InputError) as info:
            make_law("Hertz", stiffness=K_HZ, restitution=e)
        assert info.value.key == "contact.restitution"


def test_unknown_parameter_to_make_law():
    with pytest.raises(InputError) as info:
        make_law("Hd", stiffness=K_HZ, restitution=0.5, damping=3.0)
    assert "damping" in str(info.value)


def test_get_set_params_round_trip():
    law = Hd(K_HZ, 0.65)
    assert law.get_params() == {"stiffness": K_HZ, "restitution": 0.65, "tension": None}
    params = law.get_params()
    other = Hd(1.0, 0.1).set_params(**params)
    assert other.get_params() == params
    assert law.set_params(restitution=0.4) is law
    assert law.restitution == 0.4 and law.get_params()["restitution"] == 0.4
    # the new value is used: zeta follows Eq. 8 for e = 0.4
    assert law.onset_damping(1.0) == pytest.approx(K_HZ / float(eq8_x(0.4)), rel=1e-13)
    with pytest.raises(InputError) as info:
        law.set_params(stifness=1.0)
    assert "stifness" in str(info.value)
    assert law.get_params() == {"stiffness": K_HZ, "restitution": 0.4, "tension": None}
    assert repr(law) == f"UpdatedHertzdamp(stiffness={K_HZ!r}, restitution=0.4, tension=None)"


def test_tension_defaults():
    defaults = {name: make(name)[0].allows_tension for name in LAWS}
    assert defaults == {"LVe": True, "MLVe": False, "NIVe": False, "Hd": False, "LHC": False,
                        "Hertz": False, "Hertzdamp": False}
    assert LVe(K_LIN, E, tension=False).allows_tension is False
    assert Hd(K_HZ, E, tension=True).allows_tension is True


def test_lve_is_tensile_by_default_and_clamped_without_tension():
    d, r = D, R
    free = LVe(K_LIN, E).force(d, r, V0, M1, M2)
    clamped = LVe(K_LIN, E, tension=False).force(d, r, V0, M1, M2)
    assert free.min() < 0  # the dashpot pulls while the bodies separate
    assert clamped.min() >= 0.0
    np.testing.assert_array_equal(clamped, np.maximum(free, 0.0))
    # a point where k d + c r < 0: delta = 1e-5, rate = -0.3
    c = c_eq2(xi_eq3(E), K_LIN, M1, M2)
    f = K_LIN * 1e-5 + c * -0.3
    assert f < 0
    assert LVe(K_LIN, E).force(1e-5, -0.3, V0, M1, M2) == pytest.approx(f, rel=1e-12)
    assert LVe(K_LIN, E, tension=False).force(1e-5, -0.3, V0, M1, M2) == 0.0


def test_hd_never_tensile_on_the_branch():
    # during an impact the rate stays >= -e v0 (restitution), so k + zeta rate > 0 (zeta < k / (e v0))
    for e in (0.05, 0.5, 0.9):
        law = Hd(K_HZ, e)
        r = np.linspace(-e * V0, V0, 101)
        f = law.force(1e-3, r, V0)
        assert f.min() > 0
