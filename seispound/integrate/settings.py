"""The integrator's settings: Newmark's parameters, Newton's tolerances and the contact substeps (plain data).

Plain dataclasses without numba, so that a model file can be read and validated
(``model.analysis.Analysis`` holds a :class:`Newmark`) without loading the kernels.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ..errors import InputError

__all__ = ["Newmark", "DEFAULT_CONTACT_SUBSTEPS"]

#: contact substeps of a direct ``integrate`` call whose Newmark settings leave them unset
DEFAULT_CONTACT_SUBSTEPS = 32


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
