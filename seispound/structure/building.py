"""Shear buildings: lumped floor masses, storey springs, Rayleigh damping."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.linalg import eigh

from ..errors import InputError, number_array

__all__ = ["Building", "RayleighDamping", "NoDamping"]


@dataclass
class RayleighDamping:
    """Rayleigh damping C = a0 M + a1 K with ratio ``ratio`` in modes i and j (1-based).

    a0 = 2 ratio w_i w_j / (w_i + w_j), a1 = 2 ratio / (w_i + w_j)
    (Chopra, Dynamics of Structures, 4th ed., Eq. 11.4.9 with equal ratios).
    i = j gives a0 = ratio w_i, a1 = ratio / w_i (the limit), which is how a
    one-storey building gets the ratio in its only mode.
    """

    ratio: float = 0.05
    modes: tuple | None = None  # default (1, 2), or (1, 1) for a one-storey building
    kind: str = "rayleigh"


@dataclass
class NoDamping:
    """No structural damping (pendulum impact tests)."""

    kind: str = "none"
    ratio: float = 0.0


@dataclass
class Building:
    """A shear building: floors numbered 1..N from the ground up.

    Parameters
    ----------
    name : str
        Unique name in the row.
    floor_masses : sequence of float, shape (N,)
        Lumped mass of each floor [kg], > 0.
    storey_stiffness : sequence of float, shape (N,)
        Lateral stiffness of each storey [N/m], > 0; storey i joins floor i-1 (0 = ground) to floor i.
    storey_heights : sequence of float, shape (N,)
        Height of each storey [m], > 0.  Floor elevations are their cumulative sums.
    damping : RayleighDamping or NoDamping
    initial_velocity : float or sequence of float, shape (N,), optional
        Floor velocities relative to the ground at t = 0 [m/s].
    position : float, optional
        Position along the row [m] (with ``[ground_motion] apparent_velocity``:
        the wave reaches the building position / velocity after the record).
    ground_motion : BuildingMotion, optional
        The ground motion under this building when it differs from the row's
        (:class:`seispound.model.BuildingMotion`); None: the row's record.
    storey_law : StoreyLaw, optional
        The storeys' force-drift law (:class:`seispound.storey.StoreyLaw`:
        bilinear or Bouc-Wen, per building or per storey); None: elastic.
        ``storey_stiffness`` is then the initial stiffness, and the Rayleigh
        damping is computed from it.
    floor_model : RodFloor, optional
        Every floor as an axial rod along the line of impact (:class:`seispound.floor.RodFloor`),
        with an optional attachment on each face toward a neighbour; None: lumped floors.
    foundation : Foundation, optional
        A rigid foundation that sways and rocks on the soil
        (:class:`seispound.foundation.Foundation`); None: a fixed base.  The
        periods, modes and Rayleigh coefficients stay those of the fixed-base building.
    """

    name: str
    floor_masses: list
    storey_stiffness: list
    storey_heights: list
    damping: object = field(default_factory=RayleighDamping)
    initial_velocity: object = 0.0
    position: float | None = None
    ground_motion: object = None
    storey_law: object = None
    foundation: object = None
    floor_model: object = None

    def __post_init__(self):
        self.validate()

    # -- validation -----------------------------------------------------------
    def validate(self, key: str | None = None) -> None:
        """Check every field; InputError names ``building.<name>.<field>``."""
        key = key or f"building.{self.name}"
        if not isinstance(self.name, str) or not self.name.strip():
            raise InputError("name must be a non-empty string", key=f"{key}.name")
        arrays = {}
        for fld in ("floor_masses", "storey_stiffness", "storey_heights"):
            arr = _positive_vector(getattr(self, fld), f"{key}.{fld}")
            arrays[fld] = arr
        n = arrays["floor_masses"].size
        for fld in ("storey_stiffness", "storey_heights"):
            if arrays[fld].size != n:
                raise InputError(f"has {arrays[fld].size} entries but floor_masses has {n}",
                                 key=f"{key}.{fld}")
        self.floor_masses = arrays["floor_masses"]
        self.storey_stiffness = arrays["storey_stiffness"]
        self.storey_heights = arrays["storey_heights"]
        v0 = self.initial_velocity
        v = number_array(v0, f"{key}.initial_velocity")
        if v.size not in (1, n):
            raise InputError(f"must be a number or a list of {n} numbers, got {v.size}", key=f"{key}.initial_velocity")
        v = np.broadcast_to(v, (n,)).copy()
        if not np.all(np.isfinite(v)):
            raise InputError("must be finite", key=f"{key}.initial_velocity")
        self.initial_velocity = v
        p = self.position
        if p is not None and not (isinstance(p, (int, float)) and not isinstance(p, bool) and math.isfinite(p)):
            raise InputError(f"must be a finite number of metres, got {p!r}", key=f"{key}.position")
        if self.ground_motion is not None:
            self.ground_motion.validate(f"{key}.ground_motion")
        if self.storey_law is not None:
            from ..storey import StoreyLaw

            if not isinstance(self.storey_law, StoreyLaw):
                raise InputError("must be a StoreyLaw", key=f"{key}.storey_law")
            self.storey_law.validate(n, f"{key}.storey_law")
        if self.foundation is not None:
            from ..foundation import Foundation

            if not isinstance(self.foundation, Foundation):
                raise InputError("must be a Foundation", key=f"{key}.foundation")
            self.foundation.validate(n, f"{key}.foundation")
        if self.floor_model is not None:
            from ..floor import RodFloor

            if not isinstance(self.floor_model, RodFloor):
                raise InputError("must be a RodFloor", key=f"{key}.floor_model")
            self.floor_model.validate(f"{key}.floor_model")
        d = self.damping
        if isinstance(d, RayleighDamping):
            if not (isinstance(d.ratio, (int, float)) and 0.0 <= d.ratio < 1.0):
                raise InputError(f"ratio must be in [0, 1), got {d.ratio!r}", key=f"{key}.damping.ratio")
            modes = (1, min(2, n)) if d.modes is None else tuple(d.modes)
            if len(modes) != 2 or not all(isinstance(m, int) and not isinstance(m, bool) for m in modes):
                raise InputError(f"modes must be two integers [i, j], got {list(modes)!r}",
                                 key=f"{key}.damping.modes")
            if not all(1 <= m <= n for m in modes):
                raise InputError(f"modes must lie in 1..{n} (the building has {n} modes), got {list(modes)}",
                                 key=f"{key}.damping.modes")
            d.modes = modes
        elif not isinstance(d, NoDamping):
            raise InputError("damping must be RayleighDamping or NoDamping", key=f"{key}.damping")

    # -- properties -------------------------------------------------------------
    @property
    def n_floors(self) -> int:
        return int(self.floor_masses.size)

    @property
    def floor_heights(self) -> np.ndarray:
        """Elevation of each floor above the ground [m], shape (N,)."""
        return np.cumsum(self.storey_heights)

    def mass_matrix(self) -> np.ndarray:
        """Diagonal mass matrix [kg], shape (N, N)."""
        return np.diag(self.floor_masses)

    def stiffness_matrix(self) -> np.ndarray:
        """Tridiagonal shear-building stiffness matrix [N/m], shape (N, N) (Chopra Eq. 9.2.4)."""
        return shear_stiffness_matrix(self.storey_stiffness)

    def modes(self):
        """Natural circular frequencies [rad/s], shape (N,), and mass-normalised mode shapes, shape (N, N).

        Kept for the current masses and stiffnesses (validation, the guards, damping and the
        result's periods all ask for them on every run); recomputed when either changes.
        """
        key = (np.asarray(self.floor_masses, float).tobytes(), np.asarray(self.storey_stiffness, float).tobytes())
        memo = self.__dict__.get("_modes")
        if memo is None or memo[0] != key:
            w2, phi = eigh(self.stiffness_matrix(), self.mass_matrix())
            memo = (key, np.sqrt(w2), phi)
            self.__dict__["_modes"] = memo
        return memo[1], memo[2].copy()

    def __getstate__(self):
        """Pickled without the kept modes (recomputed on demand): a model's content, which keys what
        ``Model.assembled`` keeps, is its parts' pickle, and the memo's arrays tripled its cost."""
        return {k: v for k, v in self.__dict__.items() if k != "_modes"}

    @property
    def periods(self) -> np.ndarray:
        """Natural periods [s], shape (N,), longest first."""
        return 2.0 * math.pi / self.modes()[0]

    def rayleigh_coefficients(self) -> tuple[float, float]:
        """(a0 [1/s], a1 [s]) of C = a0 M + a1 K."""
        d = self.damping
        if isinstance(d, NoDamping) or d.ratio == 0.0:
            return 0.0, 0.0
        w = self.modes()[0]
        wi, wj = w[d.modes[0] - 1], w[d.modes[1] - 1]
        return 2.0 * d.ratio * wi * wj / (wi + wj), 2.0 * d.ratio / (wi + wj)

    def damping_matrix(self) -> np.ndarray:
        a0, a1 = self.rayleigh_coefficients()
        return a0 * self.mass_matrix() + a1 * self.stiffness_matrix()


def shear_stiffness_matrix(storey_stiffness) -> np.ndarray:
    """Tridiagonal stiffness matrix [N/m], shape (N, N), of a fixed-base shear building whose storey i
    [N/m] joins floor i-1 to floor i (floor 0 the ground; Chopra, Dynamics of Structures, Eq. 9.2.4)."""
    k = np.asarray(storey_stiffness, float)
    n = k.size
    K = np.zeros((n, n))
    for i in range(n):
        K[i, i] += k[i]
        if i + 1 < n:
            K[i, i] += k[i + 1]
            K[i, i + 1] = K[i + 1, i] = -k[i + 1]
    return K


def _positive_vector(value, key) -> np.ndarray:
    arr = number_array(value, key)
    if arr.size == 0:
        raise InputError("must be a non-empty list of numbers", key=key)
    bad = np.flatnonzero(~(np.isfinite(arr) & (arr > 0)))
    if bad.size:
        raise InputError(f"every entry must be a finite number > 0; entry {bad[0] + 1} is {float(arr[bad[0]]):g}",
                         key=key)
    return arr
