"""Analysis settings: the step, the duration and the time-integration scheme (plain data, no numba).

The integrator (:mod:`seispound.integrate`) reads these; the model package never imports it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..errors import InputError

__all__ = ["Analysis", "Newmark", "SCHEMES"]

#: time-integration schemes (``[analysis] scheme``)
SCHEMES = ("exact", "newmark")


@dataclass
class Newmark:
    """Newmark-beta settings.

    Parameters
    ----------
    beta, gamma : float
        Newmark parameters (default 1/4, 1/2: average acceleration,
        unconditionally stable, no numerical damping; Newmark 1959).
    contact_substeps : int
        Substeps per estimated impact duration while a gap is closed.
    rtol : float
        Newton residual tolerance relative to the largest force term.
    max_iter : int
        Newton iterations before the step is cut by 4.
    """

    beta: float = 0.25
    gamma: float = 0.5
    contact_substeps: int = 32
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
            if not isinstance(val, int) or isinstance(val, bool) or val < 1:
                raise InputError(f"must be an integer >= 1, got {val!r}", key=f"{key}.{name}")

    def stability_limit(self) -> float:
        """Largest stable dt/T_n (inf if 2 beta >= gamma; Chopra Eq. 5.5.1 generalised)."""
        if 2.0 * self.beta >= self.gamma:
            return math.inf
        return 1.0 / (math.pi * math.sqrt(2.0) * math.sqrt(self.gamma - 2.0 * self.beta))


@dataclass
class Analysis:
    """Analysis settings: step ``dt`` [s], ``duration`` [s], Newmark parameters and the scheme.

    ``scheme``: "exact" (default) marches every step in which all gaps are open
    exactly for the piecewise-linear ground acceleration (mode by mode, Nigam &
    Jennings 1969) and takes Newmark steps in contact; "newmark" uses Newmark
    throughout, for comparison with other programs (OpenSees).
    """

    dt: float
    duration: float
    newmark: Newmark = field(default_factory=Newmark)
    scheme: str = "exact"

    def validate(self, key: str = "analysis") -> None:
        for name in ("dt", "duration"):
            val = getattr(self, name)
            if not isinstance(val, (int, float)) or isinstance(val, bool) or not math.isfinite(val) or val <= 0:
                raise InputError(f"must be a finite number > 0, got {val!r}", key=f"{key}.{name}")
        if self.scheme not in SCHEMES:
            raise InputError(f"must be one of {', '.join(SCHEMES)}, got {self.scheme!r}", key=f"{key}.scheme")
        if self.duration < self.dt:
            raise InputError(f"duration {self.duration} is shorter than dt {self.dt}", key=f"{key}.duration")
        self.newmark.validate(f"{key}.newmark")

    @property
    def nsteps(self) -> int:
        """Analysis steps: enough to cover ``duration`` (the last one may end past it)."""
        return int(math.ceil(self.duration / self.dt - 1e-9))
