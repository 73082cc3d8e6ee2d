"""Analysis settings: the step, the duration and the time-integration scheme (plain data, no numba).

The integrator (:mod:`seispound.integrate`) reads these; the model package never imports it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..errors import InputError

__all__ = ["Analysis", "Newmark", "SCHEMES", "DEFAULT_CONTACT_SUBSTEPS", "DEFAULT_TOLERANCE"]

#: time-integration schemes (``[analysis] scheme``)
SCHEMES = ("exact", "newmark")
#: contact substeps of a direct ``integrate`` call whose Newmark settings leave them unset
DEFAULT_CONTACT_SUBSTEPS = 32
#: relative error accepted on the peak pounding force and peak floor response when none is stated
DEFAULT_TOLERANCE = 0.01


@dataclass
class Newmark:
    """Newmark-beta settings.

    Parameters
    ----------
    beta, gamma : float
        Newmark parameters (default 1/4, 1/2: average acceleration,
        unconditionally stable, no numerical damping; Newmark 1959).
    contact_substeps : int or None
        Substeps per estimated impact duration while a gap is closed.  None (the default of a
        model file without ``[analysis] contact_substeps``): chosen for each run from the
        analysis' ``tolerance`` (:mod:`seispound.accuracy`); a direct ``integrate`` call
        takes DEFAULT_CONTACT_SUBSTEPS.
    rtol : float
        Newton residual tolerance relative to the largest force term.
    max_iter : int
        Newton iterations before the step is cut by 4.
    """

    beta: float = 0.25
    gamma: float = 0.5
    contact_substeps: int | None = None
    rtol: float = 1e-10
    max_iter: int = 30

    def validate(self, key: str = "analysis.newmark") -> None:
        for name in ("beta", "gamma", "rtol"):
            val = getattr(self, name)
            if not isinstance(val, (int, float)) or isinstance(val, bool) or not math.isfinite(val) or val <= 0:
                raise InputError(f"must be a finite number > 0, got {val!r}", key=f"{key}.{name}")
        if self.gamma < 0.5:
            raise InputError(f"gamma < 1/2 gives negative numerical damping (unstable); got {self.gamma}",
                             key=f"{key}.gamma")
        for name in ("contact_substeps", "max_iter"):
            val = getattr(self, name)
            if val is None and name == "contact_substeps":
                continue
            if not isinstance(val, int) or isinstance(val, bool) or val < 1:
                raise InputError(f"must be an integer >= 1, got {val!r}", key=f"{key}.{name}")

    def stability_limit(self) -> float:
        """Largest stable dt/T_n (inf if 2 beta >= gamma; Chopra Eq. 5.5.1 generalised)."""
        if 2.0 * self.beta >= self.gamma:
            return math.inf
        return 1.0 / (math.pi * math.sqrt(2.0) * math.sqrt(self.gamma - 2.0 * self.beta))


@dataclass
class Analysis:
    """Analysis settings: step ``dt`` [s], ``duration`` [s], Newmark parameters, the scheme and the tolerance.

    ``tolerance`` [-]: the relative error the user accepts on the peak pounding force and the
    peak floor response, in (0, 0.5] (default 0.01); the contact substeps are chosen from it
    unless ``newmark.contact_substeps`` is given (:mod:`seispound.accuracy`).

    ``scheme``: "exact" (default) marches every step in which all gaps are open
    exactly for the piecewise-linear ground acceleration (mode by mode, Nigam &
    Jennings 1969) and takes Newmark steps in contact; "newmark" uses Newmark
    throughout, for comparison with other programs (OpenSees).
    """

    dt: float
    duration: float
    newmark: Newmark = field(default_factory=Newmark)
    scheme: str = "exact"
    tolerance: float = DEFAULT_TOLERANCE

    def validate(self, key: str = "analysis") -> None:
        for name in ("dt", "duration"):
            val = getattr(self, name)
            if not isinstance(val, (int, float)) or isinstance(val, bool) or not math.isfinite(val) or val <= 0:
                raise InputError(f"must be a finite number > 0, got {val!r}", key=f"{key}.{name}")
        if self.scheme not in SCHEMES:
            raise InputError(f"must be one of {', '.join(SCHEMES)}, got {self.scheme!r}", key=f"{key}.scheme")
        tol = self.tolerance
        if not isinstance(tol, (int, float)) or isinstance(tol, bool) or not math.isfinite(tol) or not 0 < tol <= 0.5:
            raise InputError(f"must be a relative error in (0, 0.5], got {tol!r}", key=f"{key}.tolerance")
        if self.duration < self.dt:
            raise InputError(f"duration {self.duration} is shorter than dt {self.dt}", key=f"{key}.duration")
        self.newmark.validate(f"{key}.newmark")

    @property
    def nsteps(self) -> int:
        """Analysis steps: enough to cover ``duration`` (the last one may end past it)."""
        return int(math.ceil(self.duration / self.dt - 1e-9))
