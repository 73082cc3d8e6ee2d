"""Contact substeps chosen from the accuracy a user states (``[analysis] tolerance``).

Between impacts the exact scheme is exact for the record's piecewise-linear ground
motion, so what a run's accuracy depends on is how finely each impact is stepped:
``contact_substeps`` substeps per impact duration, Newmark's average acceleration rule
with Newton in the contact phase.  That error is the law's and the substep's alone and
scales out of the masses, the contact stiffness and (for the Hertz-type laws, whose
impacts are self-similar) the impact velocity.  So the package measures it on the law
itself: two equal bodies meet at two approach velocities, stepped by the integrator the
run uses at n and 2n substeps, and Richardson's extrapolation for a second-order scheme,
err(n) = 4/3 |q(n) - q(2n)| / |q(2n)|, estimates the error of the peak force and of the
rebound velocity (relative to the approach velocity) at n, checked against 4n as well.  The substep of the estimate
is exactly the impact duration / n, the longest the kernel ever takes for that n (its
power-of-two step levels take dur / n or shorter), so the estimate bounds the run's.

The run takes the smallest power of two n >= MIN_SUBSTEPS whose estimate is at most
SAFETY x the tolerance, per law, and the largest n over the laws of its gaps.  Estimates
are kept per law and n for the process: a study or a fit pays for them once.

Derived here, not read: the scheme's second order (Newmark's average acceleration rule,
Chopra, Dynamics of Structures, Sec. 5.4-5.5) gives the Richardson factors 4/3 (against 2n)
and 16/15 (against 4n).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["DEFAULT_TOLERANCE", "choose_contact_substeps", "impact_error"]

#: relative error accepted on the peak pounding force and the peak floor response when none is stated
DEFAULT_TOLERANCE = 0.01
#: the estimate must lie within this share of the tolerance (the rest covers what an isolated impact
#: does not see: impacts that overlap, grazing contacts, the event location)
SAFETY = 0.5
MIN_SUBSTEPS = 4
MAX_SUBSTEPS = 512
#: approach velocities [m/s] of the estimate's impacts (e(v) laws differ with v; the others do not)
APPROACH_VELOCITIES = (0.05, 0.5)
_MASS = 1000.0  # [kg] each body's; the error does not depend on it

_OUTCOMES: dict = {}  # (law key, stiffness, n, v0) -> (peak force [N], rebound velocity [m/s])
_ERRORS: dict = {}  # (law key, n) -> impact_error


def _law_key(law) -> tuple:
    """What the error of an impact depends on: the law's kind, its restitution and tension (not k)."""
    return (type(law).__name__, repr(law.restitution), law.allows_tension)


def _impact(law, n: int, v0: float) -> tuple[float, float]:
    """(peak force [N], rebound velocity [m/s]) of two free equal bodies meeting at ``v0``, stepped at
    exactly dur / n in contact by the package's integrator."""
    from .contact._scalar import contact_duration
    from .integrate import integrate
    from .integrate.settings import Newmark
    from .structure import Building, Gap, assemble
    from .structure.building import NoDamping

    tiny = 1e-9 * _MASS  # storeys [N/m] that do not matter during an impact
    bodies = [Building("A", [_MASS], [tiny], [1.0], NoDamping(), initial_velocity=v0),
              Building("B", [_MASS], [tiny], [1.0], NoDamping())]
    system = assemble(bodies, [Gap(("A", "B"), 0.0)], law)
    dur = contact_duration(int(system.gap_law[0]), system.gap_par[0], v0)
    dt = 4.0 * dur / n * (1.0 - 1e-9)  # its level 2 is dur / n, the longest substep n gives
    nsteps = int(math.ceil(3.0 * dur / dt)) + 2
    raw = integrate(system, np.zeros(nsteps + 1), dt, nsteps, Newmark(contact_substeps=n), free_flight=False,
                    multirate=False)
    imp = raw.impacts
    if imp["fmax"].size != 1 or not np.isfinite(imp["vout"][0]):
        return math.nan, math.nan
    return float(imp["fmax"][0]), float(imp["vout"][0])


def _outcome(law, n: int, v0: float) -> tuple[float, float]:
    key = (_law_key(law), float(law.stiffness), int(n), v0)  # forces [N] depend on k; their errors do not
    if key not in _OUTCOMES:
        _OUTCOMES[key] = _impact(law, n, v0)
    return _OUTCOMES[key]


def impact_error(law, n: int) -> float:
    """Estimated relative error of one impact under ``law`` at ``n`` contact substeps [-].

    For the peak force and for the rebound velocity (relative to the approach velocity), at
    each of :data:`APPROACH_VELOCITIES`, the larger of two estimates of the error at n: against
    2n by Richardson's factor 4/3, and against 4n by 16/15 (the peak force of the laws whose
    dashpot acts only on approach converges unevenly: one pair of counts alone can miss it).
    The largest of these; NaN if an isolated impact does not separate cleanly.  Kept per law
    (without its stiffness, which scales out of the error) and n.
    """
    key = (_law_key(law), int(n))
    if key not in _ERRORS:
        _ERRORS[key] = _impact_error(law, int(n))
    return _ERRORS[key]


def _impact_error(law, n: int) -> float:
    worst = 0.0
    for v0 in APPROACH_VELOCITIES:
        q1, q2, q4 = (np.array(_outcome(law, m, v0)) for m in (n, 2 * n, 4 * n))
        scale = np.array([abs(q4[0]), v0])
        err = np.maximum(4.0 / 3.0 * np.abs(q1 - q2), 16.0 / 15.0 * np.abs(q1 - q4)) / scale
        worst = max(worst, float(err.max())) if np.isfinite(err).all() else math.nan
    return worst


def choose_contact_substeps(laws, tolerance: float) -> tuple[int, float]:
    """(substeps, estimated error): the fewest power-of-two substeps whose estimate meets the tolerance.

    Parameters
    ----------
    laws : iterable of ContactLaw
        The laws of the row's gaps (repeats are measured once).
    tolerance : float
        Relative error accepted on the peak pounding force and the peak floor response, in (0, 0.5].

    Returns
    -------
    n : int
        The largest over the laws of the smallest power of two n >= MIN_SUBSTEPS with
        ``impact_error(law, n) <= SAFETY * tolerance`` (MAX_SUBSTEPS if none).
    estimate : float
        The largest of the laws' estimated errors at that n [-] (0 for a row without gaps).
    """
    n_all, est = MIN_SUBSTEPS, 0.0
    seen = {}
    for law in laws:
        seen.setdefault(_law_key(law), law)
    for law in seen.values():
        n = MIN_SUBSTEPS
        while n < MAX_SUBSTEPS and not impact_error(law, n) <= SAFETY * tolerance:
            n *= 2
        n_all = max(n_all, n)
    for law in seen.values():
        est = max(est, impact_error(law, n_all))
    return n_all, est
