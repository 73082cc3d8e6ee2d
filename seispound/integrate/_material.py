"""The nonlinear element protocol: what the kernel asks of a force law with state.

After OpenSees's UniaxialMaterial (setTrialStrain / getStress / getTangent /
commitState / revertToLastCommit): a law knows only its deformation, its rate
and its state; the element that links two DOFs computes the deformation
(``_contact._gap_kinematics`` for a gap); the driver knows neither.

* ``material_onset(code, par, v0, state)``: per-event quantities (an impact's
  damping and restitution, from its approach velocity v0), written to the
  committed state;
* ``material_trial(code, par, committed, trial, delta, rate)``: force and
  tangents (dF/d delta, dF/d rate) at a trial deformation, the trial state
  written to ``trial`` from ``committed`` (never the other way), so a redone
  step simply calls it again: that is the revert;
* ``material_commit(committed, trial)``: the step is accepted.

State rows have N_STATE entries.  Contact laws (codes of ``contact.codes``)
keep (zeta, e) set at onset and do not change within an impact.  The bilinear
storey law with kinematic hardening (BILINEAR) is the first law with history;
hysteretic storey springs will use this protocol in the kernel.
"""

from __future__ import annotations

from numba import njit

from ..contact._scalar import law_force, onset_state
from ..contact.codes import P_EXPONENT, P_K, P_MEFF, P_TENSION

# state columns: contact laws
ST_ZETA, ST_E = 0, 1
# state columns: hysteretic laws (plastic deformation, hysteretic force)
ST_PLASTIC, ST_Q = 0, 1
N_STATE = 2

# codes of history-carrying laws (beyond the contact codes)
BILINEAR = 20
# parameter columns of BILINEAR: initial stiffness k [N/m], yield force fy [N], post-yield ratio alpha [-]
B_K, B_FY, B_ALPHA = 0, 1, 2


@njit(cache=True)
def material_onset(code, par, v0, state):
    """Set the per-event state of a contact law from the approach velocity v0 [m/s] (``onset_state``)."""
    state[ST_ZETA], state[ST_E] = onset_state(code, par, v0)


@njit(cache=True)
def material_trial(code, par, committed, trial, delta, rate):
    """Force [N] and tangents (dF/d delta [N/m], dF/d rate [N s/m]) at a trial deformation.

    Contact laws: ``law_force`` with the impact's zeta (committed at onset).
    BILINEAR: kinematic hardening, F = alpha k delta + (1 - alpha) q with the
    hysteretic force q = k (delta - delta_p) limited to |q| <= fy by a return
    map (Simo & Hughes, Computational Inelasticity, 1998, Sec. 1.4: exact for a
    deformation that moves linearly within the step), tangent k inside the
    elastic range and alpha k once it yields.
    """
    for s in range(committed.size):
        trial[s] = committed[s]
    if code == BILINEAR:
        k = par[B_K]
        fy = par[B_FY]
        alpha = par[B_ALPHA]
        q = k * (delta - committed[ST_PLASTIC])
        kt = k
        if q > fy:
            q = fy
            kt = alpha * k
        elif q < -fy:
            q = -fy
            kt = alpha * k
        trial[ST_PLASTIC] = delta - q / k
        trial[ST_Q] = q
        return alpha * k * delta + (1.0 - alpha) * q, kt, 0.0
    return law_force(code, par[P_K], par[P_EXPONENT], par[P_MEFF], par[P_TENSION], delta, rate,
                     committed[ST_ZETA])


@njit(cache=True)
def material_commit(committed, trial):
    """Accept the trial state."""
    for s in range(committed.size):
        committed[s] = trial[s]
