"""A rigid foundation on springs and dashpots: given directly, or from the soil and the footing by cone models.

Degrees of freedom (``structure.assembly``): the foundation's sway u0 and rocking
theta; every floor displacement is taken relative to the free field (not to
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

__all__ = ["Foundation", "Soil", "Footing", "cone_impedances"]


@dataclass
class Soil:
    """An elastic half-space: shear-wave velocity [m/s], density [kg/m^3], Poisson's ratio [-].

    ``radiation`` [-], in [0, 1]: the share of the half-space's radiation damping that the
    site radiates (default 1).  A soil layer on much stiffer rock radiates almost nothing
    below its fundamental frequency Vs / 4H (Gazetas 1991, Sec. 15.5, "Foundations on a
    soil stratum"; Wolf 1994, Sec. 5.2), so its foundation dashpots are a fraction of the
    cone's while the springs stay close to the half-space's.
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


def cone_impedances(soil: Soil, footing: Footing) -> dict:
    """Springs, dashpots and trapped rotary inertia of a rigid surface disk on a half-space (cone models).

    Wolf (1994), Table 2-3A (also Wolf & Deeks 2004, Table 2.1), for a disk of radius r0 on a
    half-space of shear modulus G = rho c_s^2 and Poisson's ratio nu:

    * sway: K_x = 8 G r0 / (2 - nu), C_x = rho c_s pi r0^2;
    * rocking: K_theta = 8 G r0^3 / (3 (1 - nu)), C_theta = rho c I0, I0 = pi r0^4 / 4,
      with c = c_p = c_s sqrt(2 (1 - nu) / (1 - 2 nu)) for nu <= 1/3 and c = 2 c_s with a
      trapped rotary inertia Delta M_theta = 1.2 (nu - 1/3) rho I0 r0 for 1/3 < nu < 1/2.

    The static springs are the exact half-space values (Gazetas 1991, Table 1, circular
    footing); the dashpots are the cones' frequency-independent ones.  A rectangular footing
    uses the equivalent radii of :meth:`Footing.equivalent_radii` (sway and rocking apart).
    Both dashpots are scaled by ``soil.radiation`` (a stratum on rock, :class:`Soil`).
    Returns sway_stiffness [N/m], sway_damping [N s/m], rocking_stiffness [N m/rad],
    rocking_damping [N m s/rad], trapped_rotary_inertia [kg m^2].
    """
    cs, rho, nu = soil.shear_wave_velocity, soil.density, soil.poisson
    G = rho * cs * cs
    rx, rt = footing.equivalent_radii()
    i0 = math.pi * rt ** 4 / 4.0
    if nu <= 1.0 / 3.0:
        c, trapped = cs * math.sqrt(2.0 * (1.0 - nu) / (1.0 - 2.0 * nu)), 0.0
    else:
        c, trapped = 2.0 * cs, 1.2 * (nu - 1.0 / 3.0) * rho * i0 * rt
    r = soil.radiation
    return {"sway_stiffness": 8.0 * G * rx / (2.0 - nu), "sway_damping": r * rho * cs * math.pi * rx * rx,
            "rocking_stiffness": 8.0 * G * rt ** 3 / (3.0 * (1.0 - nu)), "rocking_damping": r * rho * c * i0,
            "trapped_rotary_inertia": trapped}


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
        [N/m], [N s/m], [N m/rad], [N m s/rad]; or leave them out and give ``soil`` and
        ``footing`` (:func:`cone_impedances`).
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
        """sway/rocking stiffness and damping, and the trapped rotary inertia (0 unless a cone gives one)."""
        if self.soil is not None:
            return cone_impedances(self.soil, self.footing)
        return {f: float(getattr(self, f)) for f in self._DIRECT} | {"trapped_rotary_inertia": 0.0}

    def rocking_inertia(self, n_floors) -> float:
        """Inertia of the rocking DOF [kg m^2]: foundation + floors + trapped soil."""
        trapped = self.impedances()["trapped_rotary_inertia"] if (self.soil and self.footing) else 0.0
        return float(self.rotary_inertia + self.floor_inertias(n_floors).sum() + trapped)
