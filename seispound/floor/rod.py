"""A floor (or a test body) as an axial chain along the line of impact: wave propagation and internal vibration.

The floor of length L, axial rigidity EA and mass m is cut into N equal segments:
N + 1 nodes with lumped masses m/N (m/2N at the two faces) joined by springs
EA N / L (Cook et al. 2002, Concepts and Applications of Finite Element
Analysis, Sec. 11.3: bar elements with lumped mass).  Its free-free axial
modes converge to f_j = j c / (2 L), c = sqrt(EA / (m / L)), from below as
O(1/N^2).  Stiffness-proportional damping on the axial springs gives the
ratio ``axial_damping`` in the first axial mode.  A floor whose mass gathers toward one face
(``centre_of_mass`` off the middle) carries a linear mass density 1 + g (x / L - 1/2) per unit mean,
g = 12 (x_c / L - 1/2), lumped on each node over its tributary length; the storey below stays
shared by tributary length (the columns stand where they stand).  An attachment is a bolted
pounding element on the contact face: its own mass on a joint spring and dashpot.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError, finite_number

__all__ = ["RodFloor", "Attachment"]


@dataclass
class Attachment:
    """A bolted pounding element on a floor's contact face: mass [kg] on a joint [N/m], [N s/m]."""

    mass: float
    joint_stiffness: float
    joint_damping: float = 0.0

    def validate(self, key="attachment"):
        finite_number(self.mass, f"{key}.mass", positive=True)
        finite_number(self.joint_stiffness, f"{key}.joint_stiffness", positive=True)
        finite_number(self.joint_damping, f"{key}.joint_damping", nonnegative=True)


@dataclass
class RodFloor:
    """Every floor of a building as an axial rod of ``segments`` segments.

    Parameters
    ----------
    segments : int
        N >= 1 (N + 1 nodes).
    length : float, [m]
        Along the line of impact.
    axial_stiffness : float, [N]
        EA; or give ``youngs_modulus`` [Pa] and ``area`` [m^2].
    axial_damping : float
        Damping ratio of the first free-free axial mode (stiffness-proportional, axial springs only).
    sensor : float or "attachment"
        The floor's output point: a fraction of the length from the left face (0.5: the
        middle), or "attachment" for a sensor on the attachment.
    attachment : Attachment, optional
        On every face of the floor that faces a neighbour.
    centre_of_mass : float
        The floor's centre of mass as a fraction of the length from the left face, in (1/3, 2/3)
        (0.5: uniform; the linear density stays positive inside these bounds).
    """

    segments: int
    length: float
    axial_stiffness: float | None = None
    youngs_modulus: float | None = None
    area: float | None = None
    axial_damping: float = 0.0
    sensor: object = 0.5
    attachment: Attachment | None = None
    centre_of_mass: float = 0.5
    kind: str = "rod"

    def validate(self, key="floor_model"):
        n = self.segments
        if not (isinstance(n, int) and not isinstance(n, bool) and 1 <= n <= 1000):
            raise InputError(f"must be an integer in 1..1000, got {n!r}", key=f"{key}.segments")
        finite_number(self.length, f"{key}.length", positive=True)
        if self.axial_stiffness is not None:
            if self.youngs_modulus is not None or self.area is not None:
                raise InputError("give axial_stiffness, or youngs_modulus and area, not both",
                                 key=f"{key}.axial_stiffness")
            finite_number(self.axial_stiffness, f"{key}.axial_stiffness", positive=True)
        else:
            for f in ("youngs_modulus", "area"):
                if getattr(self, f) is None:
                    raise InputError("is required (or give axial_stiffness)", key=f"{key}.{f}")
                finite_number(getattr(self, f), f"{key}.{f}", positive=True)
        zeta = finite_number(self.axial_damping, f"{key}.axial_damping", nonnegative=True)
        if zeta >= 1.0:
            raise InputError(f"must be < 1, got {zeta:g}", key=f"{key}.axial_damping")
        if self.sensor == "attachment":
            if self.attachment is None:
                raise InputError('"attachment" needs an attachment', key=f"{key}.sensor")
        else:
            s = finite_number(self.sensor, f"{key}.sensor")
            if not 0.0 <= s <= 1.0:
                raise InputError(f'must lie in [0, 1] (fraction of the length from the left face) or be '
                                 f'"attachment", got {s:g}', key=f"{key}.sensor")
        if self.attachment is not None:
            self.attachment.validate(f"{key}.attachment")
        c = finite_number(self.centre_of_mass, f"{key}.centre_of_mass")
        if not 1.0 / 3.0 < c < 2.0 / 3.0:
            raise InputError(f"must lie strictly between 1/3 and 2/3 of the length (a linear mass density that "
                             f"stays positive), got {c:g}", key=f"{key}.centre_of_mass")

    @property
    def ea(self) -> float:
        """EA [N]."""
        return float(self.axial_stiffness if self.axial_stiffness is not None else self.youngs_modulus * self.area)

    def tributary_shares(self) -> np.ndarray:
        """Each node's share of the floor's length, shape (N + 1,): 1/N inside, 1/(2N) at the faces.

        The storey below a floor is shared by these (its columns stand along the length)."""
        w = np.full(self.segments + 1, 1.0 / self.segments)
        w[[0, -1]] *= 0.5
        return w

    def node_shares(self) -> np.ndarray:
        """Each node's share of the floor's mass, shape (N + 1,), summing to 1.

        The linear density 1 + g (x - 1/2) (x = position / L, g = 12 (centre_of_mass - 1/2): a density
        with that centroid, derived) integrated over each node's tributary interval [a, b]:
        (b - a) (1 + g ((a + b) / 2 - 1/2)).  Uniform (g = 0): the tributary shares."""
        w = self.tributary_shares()
        g = 12.0 * (float(self.centre_of_mass) - 0.5)
        if g == 0.0:
            return w
        x = np.arange(self.segments + 1) / self.segments
        h = 0.5 / self.segments
        mid = (np.clip(x - h, 0.0, 1.0) + np.clip(x + h, 0.0, 1.0)) / 2.0  # each tributary interval's middle
        return w * (1.0 + g * (mid - 0.5))

    def segment_stiffness(self) -> float:
        """EA N / L [N/m]."""
        return self.ea * self.segments / self.length

    def wave_speed(self, mass) -> float:
        """c = sqrt(EA L / m) [m/s] for a floor of mass m [kg]."""
        return math.sqrt(self.ea * self.length / mass)

    def first_axial_omega(self, mass) -> float:
        """First nonzero free-free circular frequency [rad/s] of the discretised rod of mass m."""
        from scipy.linalg import eigh

        n = self.segments
        k = self.segment_stiffness()
        K = np.zeros((n + 1, n + 1))
        for s in range(n):
            K[s:s + 2, s:s + 2] += k * np.array([[1.0, -1.0], [-1.0, 1.0]])
        w2 = eigh(K, np.diag(mass * self.node_shares()), eigvals_only=True)
        return math.sqrt(w2[1])

    def sensor_weights(self) -> dict:
        """{node: weight} of the sensor's position (linear between the two nodes around it)."""
        x = float(self.sensor) * self.segments
        p = min(int(math.floor(x)), self.segments - 1)
        f = x - p
        return {p: 1.0 - f, p + 1: f} if f > 0.0 else {p: 1.0}
