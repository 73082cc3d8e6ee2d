"""A rectangular footing's equivalent radii: the closed forms, their use in the assembled model, and how good
the equivalent disk's rocking stiffness is against Gazetas' rectangle formulas.

Kinds: closed form (1, 2) and published result (3).

1. Closed form (Wolf 1994, Foundation Vibration Analysis Using Simple Physical Models, Sec. 2.1, as
   quoted in ``Footing.equivalent_radii``): the disk of equal area sways like the rectangle,
   r_sway = sqrt(A / pi); the disk of equal second moment of area about the rocking axis rocks like
   it, pi r_rock^4 / 4 = I, so r_rock = (4 I / pi)^(1/4), I = length width^3 / 12 (``width`` along
   the row, the plane of rocking; the axis along ``length``).  Written again here; swapping width
   and length keeps r_sway and changes r_rock as width^(3/4) length^(1/4).
2. Closed form (the model uses it): the rocking elements the assembly builds for a rectangle (the
   cone's spring to the ground, its dashpot to the internal DOF, that DOF's inertia, and for
   nu > 1/3 the trapped inertia on the footing) are those of the disk Footing(radius=r_rock), and the
   static rocking stiffness is the half-space disk's 8 G r_rock^3 / (3 (1 - nu)) (Gazetas 1991,
   Table 1, circle; Veletsos & Wei 1971); the sway spring and dashpot are 8 G r_sway / (2 - nu) and
   rho V_s pi r_sway^2 (Gazetas 1991, Table 1; Wolf 1994, Ch. 2).
3. Published result: Gazetas, G. (1991), "Formulas and charts for impedances of surface and embedded
   foundations", J. Geotech. Eng. 117(9):1363-1381, Table 1, static rocking stiffness of a rigid
   surface footing of plan 2L x 2B (L >= B, x along L) on a half-space:
       about x (the long axis):  K_rx = G / (1 - nu) I_bx^0.75 (L/B)^0.25 (2.4 + 0.5 B/L),
       about y (the short axis): K_ry = 3 G / (1 - nu) I_by^0.75 (L/B)^0.15,
   I_bx, I_by the area moments about those axes.  What was verified, and where: the paper itself
   was not reachable here; the formulas are those of the issue and agree, term by term and in which
   axis takes which moment, with an independent implementation, eng-tools/geofound,
   ``geofound/stiffness/gazetas_1991.py`` (``calc_rot_via_gazetas_1991``: rotation about the long
   axis uses I = length width^3 / 12 with the (L/B)^0.25 (2.4 + 0.5 B/L) factor, the other the
   3 (L/B)^0.15 factor).  The package's rocking is in the plane of the row, about the axis along
   ``length``: with width <= length that is Gazetas' x axis (K_rx), with width > length his y axis
   (K_ry); in both I_b = length width^3 / 12 = pi r_rock^4 / 4, so the equivalent disk's
   8 G r^3 / (3 (1 - nu)) = (8/3) (4/pi)^(3/4) G / (1 - nu) I^0.75 = 3.196 G / (1 - nu) I^0.75
   (derived) against Gazetas' 2.9 (square, K_rx), 3.0 (square, K_ry), 3.15 and 3.57 (width:length
   1:2 and 1:4, about the long axis), 3.33 and 3.69 (2:1 and 4:1, about the short axis): the disk is
   10 % stiffer for a square and up to 13 % softer for a 4:1 strip (the percentages printed; a ratio
   of shape factors, independent of G, nu and size).
"""

import math

import numpy as np
import pytest

from seispound.foundation import Footing, Foundation, Soil, cone_impedances
from seispound.structure import Building, NoDamping, assemble

VS, RHO = 200.0, 1900.0
CONE, SWAY, ROCK = 5, 1, 2  # structure._layout: the cone's internal DOF, the footing's sway and rocking DOFs
SHAPES = [(15.0, 15.0), (10.0, 20.0), (20.0, 10.0), (10.0, 40.0), (40.0, 10.0)]  # (width along the row, length)


def _radii(width, length):
    """(r_sway, r_rock) written here: equal area, equal second moment about the axis along ``length``."""
    inertia = length * width ** 3 / 12.0
    return math.sqrt(width * length / math.pi), (4.0 * inertia / math.pi) ** 0.25


def _gazetas(width, length, G, nu):
    """Gazetas (1991) Table 1 static rocking stiffness [N m/rad] in the plane of ``width`` (see the docstring)."""
    big, small = max(width, length), min(width, length)
    ratio = big / small  # L / B
    inertia = length * width ** 3 / 12.0
    if width <= length:  # about the long axis: K_rx
        return G / (1.0 - nu) * inertia ** 0.75 * ratio ** 0.25 * (2.4 + 0.5 / ratio)
    return G / (1.0 - nu) * inertia ** 0.75 * 3.0 * ratio ** 0.15  # about the short axis: K_ry


def _system(footing, nu):
    soil = Soil(VS, RHO, nu)
    f = Foundation(mass=1e6, rotary_inertia=2e7, soil=soil, footing=footing)
    return assemble([Building("A", [3e6], [4.7e8], [20.0], NoDamping(), foundation=f)], [])


def _elements(system):
    """The foundation's elements as assembled: sway (k, c) to the ground, the rocking spring to the ground,
    the cone's dashpot (rocking DOF to internal DOF), the internal DOF's inertia, the rocking DOF's inertia."""
    kind = system.dof_kind
    rock, sway, cone = (int(np.flatnonzero(kind == k)[0]) for k in (ROCK, SWAY, CONE))
    el_c = np.zeros(system.el_i.size) if system.el_c is None else system.el_c
    third = np.full(system.el_i.size, -1) if system.el_third is None else system.el_third

    def pick(i, j):
        e = [q for q in range(system.el_i.size)
             if {int(system.el_i[q]), int(system.el_j[q])} == {i, j} and third[q] < 0]
        assert len(e) == 1
        return float(system.el_k[e[0]]), float(el_c[e[0]])

    ks, cs = pick(sway, -1)
    kr, cr0 = pick(rock, -1)
    kc, cc = pick(cone, rock)
    assert cr0 == 0.0 and kc == 0.0  # the spring to the ground, the dashpot to the internal DOF only
    return dict(sway_k=ks, sway_c=cs, rock_k=kr, cone_c=cc, cone_m=float(system.mass[cone]),
                rock_m=float(system.mass[rock]))


@pytest.mark.parametrize("width, length", SHAPES)
def test_equivalent_radii_closed_forms(width, length):
    r_sway, r_rock = Footing(width=width, length=length).equivalent_radii()
    ref = _radii(width, length)
    err = max(abs(r_sway / ref[0] - 1), abs(r_rock / ref[1] - 1))
    print(f"MEASURED equivalent radii {width} x {length} m: r_sway {r_sway:.6f} m, r_rock {r_rock:.6f} m, "
          f"against the closed forms {err:.1e}")
    assert err <= 4.5e-16  # measured <= 2.2e-16 (one rounding)
    assert Footing(radius=7.0).equivalent_radii() == (7.0, 7.0)


def test_swapping_width_and_length():
    """r_sway is symmetric; r_rock scales as width^(3/4) length^(1/4), so the 4:1 strip along the row has
    r_rock twice the 1:4 one's ((4^3 / 4)^(1/4) = 2), and doubling the width alone multiplies it by 2^(3/4)."""
    a, b = Footing(width=10.0, length=40.0).equivalent_radii(), Footing(width=40.0, length=10.0).equivalent_radii()
    r1, r2, r3 = (Footing(width=w, length=l).equivalent_radii()[1] for w, l in ((12.0, 20.0), (24.0, 20.0),
                                                                                 (12.0, 40.0)))
    errs = [b[0] / a[0] - 1, b[1] / a[1] / 2.0 - 1, r2 / r1 / 2 ** 0.75 - 1, r3 / r1 / 2 ** 0.25 - 1]
    print("MEASURED swap 10x40 -> 40x10: r_sway ratio - 1, r_rock ratio / 2 - 1; width x2: / 2^(3/4) - 1; "
          "length x2: / 2^(1/4) - 1: " + ", ".join(f"{e:+.1e}" for e in errs))
    assert max(abs(e) for e in errs) <= 7e-16  # measured <= 2.2e-16


@pytest.mark.parametrize("nu", [0.3, 0.45])  # 0.45: c = 2 c_s and a trapped inertia on the footing
@pytest.mark.parametrize("width, length", SHAPES[1:])
def test_assembled_rectangle_rocks_as_the_disk_of_radius_r_rock(width, length, nu):
    r_sway, r_rock = _radii(width, length)
    rect = _elements(_system(Footing(width=width, length=length), nu))
    disk = _elements(_system(Footing(radius=r_rock), nu))
    G = RHO * VS ** 2
    rock = ("rock_k", "cone_c", "cone_m", "rock_m")
    err_disk = max(abs(rect[k] / disk[k] - 1) for k in rock)
    err_static = rect["rock_k"] / (8 * G * r_rock ** 3 / (3 * (1 - nu))) - 1
    err_sway = max(abs(rect["sway_k"] / (8 * G * r_sway / (2 - nu)) - 1),
                   abs(rect["sway_c"] / (RHO * VS * math.pi * r_sway ** 2) - 1))
    trapped = rect["rock_m"] - 2e7
    print(f"MEASURED {width} x {length} m, nu {nu}: rocking elements against the disk r = {r_rock:.4f} m "
          f"{err_disk:.1e}; K_theta against 8 G r^3 / (3 (1 - nu)) {err_static:+.1e}; sway against r_sway = "
          f"{r_sway:.4f} m {err_sway:.1e}; trapped inertia {trapped:.4g} kg m^2")
    assert err_disk <= 4.5e-16  # measured <= 2.2e-16: the same numbers
    assert abs(err_static) <= 1e-15 and err_sway <= 1e-15  # measured <= 3.3e-16
    if nu > 1 / 3:  # Wolf's trapped inertia 1.2 (nu - 1/3) rho I0 r0 with the rocking radius
        i0 = math.pi * r_rock ** 4 / 4
        assert trapped == pytest.approx(1.2 * (nu - 1 / 3) * RHO * i0 * r_rock, rel=1e-12)
    else:
        assert trapped == 0.0
    imp = cone_impedances(Soil(VS, RHO, nu), Footing(width=width, length=length))
    assert imp["rocking_stiffness"] == rect["rock_k"]


def test_equivalent_disk_against_gazetas_rectangle():
    """The assembled static rocking stiffness of rectangles (aspect 1, 2, 4, both orientations) against
    Gazetas' (1991) K_rx / K_ry; for the square, against both (his two fits differ by 3.4 % there)."""
    nu, G = 0.3, RHO * VS ** 2
    rows = {}
    for width, length in SHAPES:
        k_pkg = _elements(_system(Footing(width=width, length=length), nu))["rock_k"]
        rows[(width, length)] = k_pkg / _gazetas(width, length, G, nu) - 1
    inertia = 15.0 ** 4 / 12
    square_ry = _elements(_system(Footing(width=15.0, length=15.0), nu))["rock_k"] / (
        3.0 * G / (1 - nu) * inertia ** 0.75) - 1
    print("MEASURED equivalent disk / Gazetas (1991) - 1, (width along the row x length): "
          + ", ".join(f"{w:g}x{l:g} {d:+.2%}" for (w, l), d in rows.items())
          + f"; square against K_ry {square_ry:+.2%}")
    # measured: 15x15 +10.22 % (K_rx; +6.54 % against K_ry), 10x20 +1.43 %, 20x10 -3.98 %, 10x40 -10.49 %,
    # 40x10 -13.46 %: the equivalent disk is within 14 % of Gazetas for aspect ratios up to 4.  The values
    # are a ratio of shape factors (no discretisation): pinned to their printed digits, and bounded by 15 %
    expected = {(15.0, 15.0): 0.1022, (10.0, 20.0): 0.0143, (20.0, 10.0): -0.0398, (10.0, 40.0): -0.1049,
                (40.0, 10.0): -0.1346}
    for shape, d in rows.items():
        assert d == pytest.approx(expected[shape], abs=1e-4)
        assert abs(d) <= 0.15
    assert square_ry == pytest.approx(0.0654, abs=1e-4)
