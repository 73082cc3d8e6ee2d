"""Analysis settings: the step, the duration and the time-integration scheme (plain data, no numba).

The integrator (:mod:`seispound.integrate`) reads these.  The Newmark settings are the
integrator's own (:mod:`seispound.integrate.settings`, plain data like this module); the model
package imports nothing else of it, so reading a model loads no numba.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..errors import InputError
from ..integrate.settings import DEFAULT_CONTACT_SUBSTEPS, Newmark

__all__ = ["Analysis", "Newmark", "SCHEMES", "DEFAULT_CONTACT_SUBSTEPS", "DEFAULT_TOLERANCE"]

#: time-integration schemes (``[analysis] scheme``)
SCHEMES = ("exact", "newmark")
#: relative error accepted on the peak pounding force and peak floor response when none is stated
DEFAULT_TOLERANCE = 0.01


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
