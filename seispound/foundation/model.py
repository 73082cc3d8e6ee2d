"""A rigid foundation on springs and dashpots: given directly, or from the soil and the footing by cone models.

Degrees of freedom (``structure.assembly``): the foundation's sway u0 and rocking
theta, and with soil and footing the rocking cone's internal rotational DOF (Wolf 1994,
:func:`rocking_cone`; not a floor, no output of its own); every floor displacement is taken relative to the free field (not to
the foundation), so the mass matrix stays diagonal and a storey's deformation
is w_i - w_(i-1) - (h_i - h_(i-1)) theta (w_0 = u0, h_0 = 0).  The free field
is the building's ground motion: kinematic interaction is neglected (the
foundation input motion equals the free-field motion).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError, finite_number, number_array

__all__ = ["Foundation", "Soil", "Footing", "cone_impedances", "rocking_cone", "rocking_cone_dynamic_stiffness"]


@dataclass
class Soil:
    """An elastic half-space: shear-wave velocity [m/s], density [kg/m^3], Poisson's ratio [-].

    ``radiation`` [-], in [0, 1]: the share of the half-space's radiation damping that the
    site radiates (default 1).  A soil layer on much stiffer rock radiates almost nothing
    below its fundamental frequency Vs / 4H (Gazetas 1991, Sec. 15.5, "Foundations on a
    soil stratum"; Wolf 1994, Sec. 5.2), so its foundation dashpots are a fraction of the
    cone's while the springs stay close to the half-space's.  It scales the sway dashpot and
    the rocking cone's dashpot-and-internal-inertia branch (:func:`cone_impedances`), i.e. the
    imaginary part of both dynamic stiffnesses, by exactly ``radiation`` at every frequency.
    """

    shear_wave_velocity: float
    density: float
    poisson: float
    radiation: float = 1.0

    def validate(self, key="soil"):
        finite_number(self.shear_wave_velocity, f"{key}.shear_wave_velocity", positive=True)
        finite_number(self.density, f"{key}.density", positive=True)
        nu = finite_number(self.poisson, f"{key}.poisson")
        if not 0.0 <= nu < 0.5:
            raise InputError(f"must lie in [0, 0.5), got {nu:g}", key=f"{key}.poisson")
        r = finite_number(self.radiation, f"{key}.radiation")
        if not 0.0 <= r <= 1.0:
            raise InputError(f"must lie in [0, 1] (a share of the half-space's radiation damping), got {r:g}",
                             key=f"{key}.radiation")


@dataclass
class Footing:
    """A rigid surface footing: ``radius`` [m], or ``width`` (along the row, the line of impact) and ``length`` [m]."""

    width: float | None = None
    length: float | None = None
    radius: float | None = None

    def validate(self, key="footing"):
        if self.radius is not None:
            if self.width is not None or self.length is not None:
                raise InputError("give a radius, or a width and a length, not both", key=f"{key}.radius")
            finite_number(self.radius, f"{key}.radius", positive=True)
            return
        for f in ("width", "length"):
            if getattr(self, f) is None:
                raise InputError("is required (or give a radius)", key=f"{key}.{f}")
            finite_number(getattr(self, f), f"{key}.{f}", positive=True)

    def equivalent_radii(self) -> tuple[float, float]:
        """(r_sway, r_rock) [m]: the disk of equal area and the disk of equal second moment about the rocking axis.

        Wolf (1994), Foundation Vibration Analysis Using Simple Physical Models, Sec. 2.1:
        r_sway = sqrt(A / pi), r_rock = (4 I / pi)^(1/4), I = length width^3 / 12 (rocking in
        the plane of the row).
        """
        if self.radius is not None:
            return self.radius, self.radius
        area = self.width * self.length
        inertia = self.length * self.width ** 3 / 12.0
        return math.sqrt(area / math.pi), (4.0 * inertia / math.pi) ** 0.25


def rocking_cone(soil: Soil, footing: Footing) -> dict:
    """Wolf's rotational cone under the footing: wave velocity, apex height and its three lumped elements.

    J. P. Wolf, *Foundation Vibration Analysis Using Simple Physical Models*, Prentice Hall
    1994, Ch. 2 (the rotational cone and its properties; the issue cites Table 2-3) and App. B
    (the discrete-element representation of the translational and rotational cones as
    springs, dashpots and masses with extra internal nodes); also Wolf & Deeks, *Foundation
    Vibration Analysis: A Strength-of-Materials Approach*, Elsevier 2004, Ch. 2.  For a disk of
    radius r0 (the rocking-equivalent radius of :meth:`Footing.equivalent_radii`), I0 = pi r0^4 / 4:

    * wave velocity c = c_p = c_s sqrt(2 (1 - nu) / (1 - 2 nu)) for nu <= 1/3; c = 2 c_s for
      1/3 < nu < 1/2, with a trapped mass moment of inertia 1.2 (nu - 1/3) rho I0 r0 moving with
      the footing;
    * apex height z0 = r0 (9 pi / 32) (1 - nu) (c / c_s)^2, chosen so that the cone's static
      spring 3 rho c^2 I0 / z0 equals the exact half-space value 8 G r0^3 / (3 (1 - nu));
    * lumped model: the spring K_theta = 3 rho c^2 I0 / z0 from the footing to the ground; the
      dashpot C_theta = rho c I0 from the footing to an internal rotational DOF that carries
      M_theta = rho I0 z0 and has no other element.

    Its dynamic stiffness, with b0 = omega z0 / c, is (:func:`rocking_cone_dynamic_stiffness`)

        S(omega) = K_theta [k(b0) + i b0 c(b0)],  k = 1 - b0^2 / (3 (1 + b0^2)),  c = b0^2 / (3 (1 + b0^2)).

    What was read and what was derived: the search tools here returned the book's appendix
    abstract (the discrete-element representations of the rotational cone with internal
    nodes) but not Ch. 2's text, so the values above are as recalled from Wolf (1994) and as
    the package already carried them (c, the nu > 1/3 rule and the trapped inertia); the
    closed form S was derived here from the rotational cone's equation of motion
    d/dz (rho c^2 I(z) d theta/dz) = rho I(z) theta'' with I(z) = I0 (z / z0)^4 (outgoing waves
    theta ~ (1 + i omega z / c) exp(-i omega z / c) / z^3), and eliminating the internal DOF of
    the lumped model at frequency omega gives the same S exactly (derived; checked to round-off
    in ``tests/verification/test_rocking_cone.py``).

    Returns wave_velocity c [m/s], apex_height z0 [m], stiffness K_theta [N m/rad], dashpot
    C_theta [N m s/rad], internal_inertia M_theta [kg m^2], trapped_inertia [kg m^2], all for
    the half-space (``soil.radiation`` is applied by :func:`cone_impedances`).
    """
    cs, rho, nu = soil.shear_wave_velocity, soil.density, soil.poisson
    r0 = footing.equivalent_radii()[1]
    i0 = math.pi * r0 ** 4 / 4.0
    if nu <= 1.0 / 3.0:
        c, trapped = cs * math.sqrt(2.0 * (1.0 - nu) / (1.0 - 2.0 * nu)), 0.0
    else:
        c, trapped = 2.0 * cs, 1.2 * (nu - 1.0 / 3.0) * rho * i0 * r0
    z0 = r0 * 9.0 * math.pi / 32.0 * (1.0 - nu) * (c / cs) ** 2
    return {"wave_velocity": c, "apex_height": z0, "stiffness": 3.0 * rho * c * c * i0 / z0,
            "dashpot": rho * c * i0, "internal_inertia": rho * i0 * z0, "trapped_inertia": trapped}


def rocking_cone_dynamic_stiffness(soil: Soil, footing: Footing, omega) -> np.ndarray:
    """The rocking cone's dynamic stiffness S(omega) [N m/rad], complex, shape of ``omega`` [rad/s].

    S = K_theta [1 - r b0^2 / (3 (1 + i b0))], b0 = omega z0 / c, r = ``soil.radiation``: with
    r = 1 Wolf's rotational cone (:func:`rocking_cone`; real part K_theta k(b0), imaginary
    K_theta b0 c(b0)); a stratum's r < 1 scales the dashpot-and-internal-inertia branch, hence
    the imaginary part (the radiation damping) by exactly r at every frequency.  The trapped
    inertia of nu > 1/3 moves with the footing and is not part of S.
    """
    cone = rocking_cone(soil, footing)
    b0 = np.asarray(omega, float) * cone["apex_height"] / cone["wave_velocity"]
    return cone["stiffness"] * (1.0 - soil.radiation * b0 * b0 / (3.0 * (1.0 + 1j * b0)))


def cone_impedances(soil: Soil, footing: Footing) -> dict:
    """Springs, dashpots and inertias of a rigid surface footing on a half-space (Wolf's cones).

    Sway, the translational (horizontal) cone, exact as a spring and a dashpot to the ground
    (Wolf 1994, Ch. 2; z0 / r0 = (pi / 8) (2 - nu), c = c_s, no trapped mass):
    K_x = 8 G r0 / (2 - nu), C_x = rho c_s pi r0^2, r0 the sway-equivalent radius.

    Rocking, the rotational cone (:func:`rocking_cone`): K_theta = 8 G r0^3 / (3 (1 - nu)) to
    the ground, and C_theta = rho c I0 NOT to the ground but to an internal rotational DOF of
    inertia M_theta = rho I0 z0, so that the rocking radiation damping Im S / omega =
    C_theta b0^2 / (1 + b0^2) vanishes at low frequency (b0 = omega z0 / c) and tends to
    C_theta at high frequency; plus, for nu > 1/3, a trapped inertia on the footing.

    The static springs are the exact half-space values (Gazetas 1991, Table 1, circular
    footing).  A rectangular footing uses the equivalent radii of
    :meth:`Footing.equivalent_radii` (sway and rocking apart).  ``soil.radiation`` r (a stratum
    on rock, :class:`Soil`) scales the sway dashpot and the rocking cone's dashpot-and-internal-
    inertia branch together (C_theta and M_theta both times r), so that both radiation dampings
    are r times the half-space's at every frequency.

    Returns
    -------
    dict of float
        sway_stiffness [N/m], sway_damping [N s/m], rocking_stiffness [N m/rad],
        rocking_damping [N m s/rad] (C_theta, acting through the internal DOF),
        rocking_cone_inertia [kg m^2] (M_theta of the internal DOF; 0: no internal DOF),
        trapped_rotary_inertia [kg m^2], rocking_apex_height z0 [m], rocking_wave_velocity c [m/s].
    """
    cs, rho, nu = soil.shear_wave_velocity, soil.density, soil.poisson
    G = rho * cs * cs
    rx = footing.equivalent_radii()[0]
    cone = rocking_cone(soil, footing)
    r = soil.radiation
    return {"sway_stiffness": 8.0 * G * rx / (2.0 - nu), "sway_damping": r * rho * cs * math.pi * rx * rx,
            "rocking_stiffness": cone["stiffness"], "rocking_damping": r * cone["dashpot"],
            "rocking_cone_inertia": r * cone["internal_inertia"], "trapped_rotary_inertia": cone["trapped_inertia"],
            "rocking_apex_height": cone["apex_height"], "rocking_wave_velocity": cone["wave_velocity"]}


@dataclass
class Foundation:
    """A rigid foundation that sways and rocks under a building.

    Parameters
    ----------
    mass : float, [kg]
        Foundation mass (> 0: the sway DOF carries it).
    rotary_inertia : float, [kg m^2]
        The foundation's mass moment of inertia about the rocking axis (>= 0).
    floor_rotary_inertia : float or list, [kg m^2]
        Each floor's own mass moment of inertia about its centroid (one value or one per
        floor); the floors rotate with the foundation.  The rocking DOF's inertia is the
        sum of all three (plus a cone's trapped inertia) and must be > 0.
    sway_stiffness, sway_damping, rocking_stiffness, rocking_damping : float
        [N/m], [N s/m], [N m/rad], [N m s/rad], springs and dashpots straight to the ground;
        or leave them out and give ``soil`` and ``footing`` (:func:`cone_impedances`: the
        rocking dashpot then acts through the rotational cone's internal DOF, Wolf 1994).
    soil : Soil, optional
    footing : Footing, optional
    """

    mass: float
    rotary_inertia: float = 0.0
    floor_rotary_inertia: object = 0.0
    sway_stiffness: float | None = None
    sway_damping: float | None = None
    rocking_stiffness: float | None = None
    rocking_damping: float | None = None
    soil: Soil | None = None
    footing: Footing | None = None

    _DIRECT = ("sway_stiffness", "sway_damping", "rocking_stiffness", "rocking_damping")

    def validate(self, n_floors: int, key: str = "foundation") -> None:
        finite_number(self.mass, f"{key}.mass", positive=True)
        finite_number(self.rotary_inertia, f"{key}.rotary_inertia", nonnegative=True)
        self.floor_inertias(n_floors, key)
        direct = [f for f in self._DIRECT if getattr(self, f) is not None]
        if self.soil is not None or self.footing is not None:
            if direct:
                raise InputError("give the springs and dashpots, or soil and footing, not both",
                                 key=f"{key}.{direct[0]}")
            if self.soil is None or self.footing is None:
                missing = "soil" if self.soil is None else "footing"
                raise InputError("is required with the other (the cone impedances need both)", key=f"{key}.{missing}")
            self.soil.validate(f"{key}.soil")
            self.footing.validate(f"{key}.footing")
        else:
            for f in self._DIRECT:
                if getattr(self, f) is None:
                    raise InputError("is required (or give soil and footing)", key=f"{key}.{f}")
                if f.endswith("stiffness"):
                    finite_number(getattr(self, f), f"{key}.{f}", positive=True)
                else:
                    finite_number(getattr(self, f), f"{key}.{f}", nonnegative=True)
        if self.rocking_inertia(n_floors) <= 0.0:
            raise InputError("the rocking DOF needs inertia: give rotary_inertia or floor_rotary_inertia > 0",
                             key=f"{key}.rotary_inertia")

    def floor_inertias(self, n_floors, key="foundation") -> np.ndarray:
        arr = number_array(self.floor_rotary_inertia, f"{key}.floor_rotary_inertia")
        if arr.size not in (1, n_floors) or not np.all(np.isfinite(arr)) or np.any(arr < 0):
            raise InputError(f"give one finite value >= 0 or {n_floors} (one per floor)",
                             key=f"{key}.floor_rotary_inertia")
        return np.broadcast_to(arr, (n_floors,)).astype(float)

    def impedances(self) -> dict:
        """Sway/rocking stiffness and damping, the rocking cone's internal inertia and the trapped inertia.

        With soil and footing, :func:`cone_impedances` (the rocking dashpot acts through the
        cone's internal DOF); given directly, the springs and dashpots act straight to the
        ground (rocking_cone_inertia and trapped_rotary_inertia 0).
        """
        if self.soil is not None:
            return cone_impedances(self.soil, self.footing)
        return {f: float(getattr(self, f)) for f in self._DIRECT} | {"rocking_cone_inertia": 0.0,
                                                                     "trapped_rotary_inertia": 0.0}

    def rocking_inertia(self, n_floors) -> float:
        """Inertia of the rocking DOF [kg m^2]: foundation + floors + trapped soil."""
        trapped = self.impedances()["trapped_rotary_inertia"] if (self.soil and self.footing) else 0.0
        return float(self.rotary_inertia + self.floor_inertias(n_floors).sum() + trapped)
