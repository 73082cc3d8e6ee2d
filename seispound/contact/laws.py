"""Contact-force laws for pounding, one small class each.

A law knows only the penetration delta (positive in contact) and its rate; the
gap element that uses it knows the buildings, the floor and the gap size.  Like
scikit-learn estimators, a constructor only stores its parameters, so a study can
vary any of them by name (``law.set_params(restitution=0.5)``).

The force itself is evaluated by the compiled functions in ``_scalar.py`` (the
same code the integrator runs); the classes add units, references, validation
and the per-gap parameter row handed to the kernel.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from . import codes as S
from .restitution import Restitution, restitution_from

__all__ = [
    "ContactLaw",
    "LinearViscoelastic",
    "ModifiedLinearViscoelastic",
    "NonlinearViscoelastic",
    "UpdatedHertzdamp",
    "LinearHuntCrossley",
    "Hertz",
    "Hertzdamp",
    "HuntCrossley",
    "lve_damping_ratio",
    "mlve_damping_ratio",
    "nive_damping_ratio",
]


def lve_damping_ratio(e):
    """Damping ratio of the LVe dashpot, seed Eq. 3: xi = -ln e / sqrt(pi^2 + ln^2 e) [-]."""
    le = math.log(e)
    return -le / math.sqrt(math.pi**2 + le**2)


def mlve_damping_ratio(e):
    """Approach-only damping ratio of MLVe, seed Eq. 5: xi = (1 - e^2) / (pi e) [-]."""
    return (1.0 - e * e) / (math.pi * e)


def nive_damping_ratio(e):
    """Jankowski's (2005) xi-bar of NIVe, seed Eq. 6: 9 sqrt5 (1-e^2) / (2 e (e (9 pi - 16) + 16)) [-]."""
    return 9.0 * math.sqrt(5.0) / 2.0 * (1.0 - e * e) / (e * (e * (9.0 * math.pi - 16.0) + 16.0))


@dataclass(frozen=True)
class Param:
    """Description of one law parameter (for ``seispound laws`` and validation)."""

    name: str
    units: str
    doc: str


class ContactLaw:
    """Base class: a force law F(delta, rate) with parameters stored verbatim.

    Subclasses set ``name``, ``code``, ``exponent``, ``reference``, ``formula``,
    ``tension_default`` and ``params``.
    """

    name: str = ""
    code: int = S.NONE
    exponent: float = 1.0
    reference: str = ""
    formula: str = ""
    tension_default = False
    tension_note = ""

    def __init__(self, stiffness: float, restitution: float = 1.0, tension: bool | None = None):
        self.stiffness = stiffness
        self.restitution = restitution
        self.tension = tension

    # -- scikit-learn style parameter access --------------------------------
    @classmethod
    def param_names(cls):
        return ("stiffness", "restitution", "tension")

    def get_params(self) -> dict:
        return {p: getattr(self, p) for p in self.param_names()}

    def set_params(self, **params) -> "ContactLaw":
        for key, value in params.items():
            if key not in self.param_names():
                raise InputError(f"unknown parameter of law {self.name}; known: "
                                 f"{', '.join(self.param_names())}", key=f"contact.{key}")
            setattr(self, key, value)
        return self

    def __repr__(self):
        args = ", ".join(f"{k}={v!r}" for k, v in self.get_params().items())
        return f"{type(self).__name__}({args})"

    @classmethod
    def describe_params(cls):
        units = "N/m" if cls.exponent == 1.0 else f"N/m^{cls.exponent:g}"
        return [
            Param("stiffness", units, "contact stiffness k"),
            Param("restitution", "-", "target coefficient of restitution e, 0 < e <= 1, or a function of the "
                                      "approach velocity {form = linear|exponential|power|table, ...}"),
            Param("tension", "bool", f"may the force become tensile (default {cls.tension_default})"),
        ]

    # -- validation and kernel parameters -----------------------------------
    @property
    def allows_tension(self) -> bool:
        return self.tension_default if self.tension is None else bool(self.tension)

    def validate(self, key: str = "contact") -> None:
        """Raise InputError naming ``key`` if a parameter is out of range."""
        self._validate_stiffness_and_tension(key)
        e = self.restitution
        if isinstance(e, dict):  # a form given as a table (from Python or a study path)
            self.restitution = e = restitution_from(e, f"{key}.restitution")
        if isinstance(e, Restitution):
            e.validate(f"{key}.restitution")
        elif not _is_real(e) or not (0.0 < e <= 1.0):
            raise InputError(f"restitution must be in (0, 1], got {e!r}", key=f"{key}.restitution")

    def _validate_stiffness_and_tension(self, key: str) -> None:
        k = self.stiffness
        if not _is_real(k) or not k > 0 or not math.isfinite(k):
            raise InputError(f"stiffness must be a finite number > 0, got {k!r}", key=f"{key}.stiffness")
        if self.tension is not None and not isinstance(self.tension, bool):
            raise InputError(f"tension must be true or false, got {self.tension!r}", key=f"{key}.tension")

    def damping_ratio(self) -> float:
        """Damping ratio derived from e (laws with a dashpot of fixed ratio)."""
        return 0.0

    @property
    def velocity_dependent(self) -> bool:
        """Is e a function of the approach velocity (set at each impact's onset)?"""
        return isinstance(self.restitution, Restitution)

    def restitution_at(self, approach_velocity):
        """The e this law is given for an impact at ``approach_velocity`` [m/s] (array_like)."""
        if self.velocity_dependent:
            return self.restitution(approach_velocity)
        return np.full(np.shape(approach_velocity), float(self.restitution))

    def kernel_params(self, m1: float, m2: float) -> np.ndarray:
        """Parameter row for the kernel, shape (N_PAR,), for floors of mass m1, m2 [kg]."""
        row = self._common_row(m1, m2)
        if self.velocity_dependent:  # e and the damping from it are set at each onset
            row[S.P_E] = np.nan
            self.restitution.kernel_columns(row)
        else:
            row[S.P_E] = float(self.restitution)
            row[S.P_XI] = self.damping_ratio()
        return row

    def _common_row(self, m1: float, m2: float) -> np.ndarray:
        """The columns every law fills: stiffness, effective mass, tension, exponent."""
        row = np.zeros(S.N_PAR)
        row[S.P_K] = float(self.stiffness)
        row[S.P_MEFF] = m1 * m2 / (m1 + m2)
        row[S.P_TENSION] = 1.0 if self.allows_tension else 0.0
        row[S.P_EXPONENT] = float(self.exponent)
        return row

    # -- evaluation from Python ----------------------------------------------
    def onset_damping(self, approach_velocity: float, m1: float = 1.0, m2: float = 1.0) -> float:
        """Damping parameter that the kernel fixes at the onset of an impact (see ``_scalar.onset_damping``)."""
        from . import _scalar  # compiled on first use: reading a model file compiles nothing

        return _scalar.onset_state(self.code, self.kernel_params(m1, m2), float(approach_velocity))[0]

    def force(self, delta, rate, approach_velocity, m1=1.0, m2=1.0):
        """Contact force [N] for penetration ``delta`` [m] and rate [m/s].

        Parameters
        ----------
        delta, rate : array_like
            Penetration (positive in contact) and its rate (positive on approach).
        approach_velocity : float
            d(delta)/dt at the onset of this impact [m/s] (sets zeta for Hd, LHC, Hertzdamp).
        m1, m2 : float
            Masses of the two colliding floors [kg] (LVe, MLVe, NIVe).

        Returns
        -------
        ndarray
            Force, same shape as the broadcast inputs; zero where delta <= 0.
        """
        par = self.kernel_params(m1, m2)
        from . import _scalar

        zeta = _scalar.onset_state(self.code, par, float(approach_velocity))[0]
        d, r = np.broadcast_arrays(np.asarray(delta, float), np.asarray(rate, float))
        out = np.zeros(d.shape)
        for idx in np.ndindex(d.shape):
            if d[idx] > 0.0:
                out[idx] = _scalar.contact_force(self.code, par, d[idx], r[idx], zeta)[0]
        return out


def _is_real(x):
    return isinstance(x, (int, float, np.floating, np.integer)) and not isinstance(x, bool)


class LinearViscoelastic(ContactLaw):
    """Linear viscoelastic law LVe (Anagnostopoulos 1988), seed Eqs. 1-3.

    F = k delta + c rate,  c = 2 xi sqrt(k m1 m2 / (m1 + m2)),
    xi = -ln e / sqrt(pi^2 + ln^2 e).

    Tension: allowed by default, as the seed defines the law.  The dashpot then
    pulls at the end of every impact and the two-body restitution equals e
    exactly (half a damped period).  With ``tension=False`` the force is clamped
    at F >= 0, the bodies separate when k delta + c rate = 0, earlier and faster,
    and the restitution exceeds e (verified against the closed form in the tests).
    """

    name = "LVe"
    code = S.LVE
    exponent = 1.0
    reference = "Anagnostopoulos (1988) EESD 16(3):443-456; seed Eqs. 1-3"
    formula = "F = k*delta + c*rate, c = 2*xi*sqrt(k*m1*m2/(m1+m2)), xi = -ln(e)/sqrt(pi^2+ln(e)^2)"
    tension_default = True
    tension_note = "tensile at the end of impact by default (exact e); tension=false clamps F >= 0"

    def damping_ratio(self):
        return lve_damping_ratio(self.restitution) if not self.velocity_dependent else np.nan


class ModifiedLinearViscoelastic(ContactLaw):
    """Modified linear viscoelastic law MLVe (Mahmoud 2008), seed Eqs. 4-5.

    F = k delta + c rate while approaching (rate >= 0), F = k delta on
    restitution; c = 2 xi sqrt(k m_eff) with xi = (1 - e^2)/(pi e).  The force
    is never tensile.  The resulting restitution differs from e (tabulated in
    the README and checked against the closed form exp(-xi acos(xi)/sqrt(1-xi^2)).
    """

    name = "MLVe"
    code = S.MLVE
    exponent = 1.0
    reference = "Mahmoud (2008) 14WCEE; seed Eqs. 4-5"
    formula = "F = k*delta + c*rate (rate >= 0), k*delta (rate < 0); xi = (1-e^2)/(pi*e)"
    tension_note = "never tensile"

    def damping_ratio(self):
        return mlve_damping_ratio(self.restitution) if not self.velocity_dependent else np.nan


class NonlinearViscoelastic(ContactLaw):
    """Nonlinear viscoelastic law NIVe (Jankowski 2005), seed Eq. 6.

    F = k delta^1.5 + c-bar rate (rate >= 0), k delta^1.5 (rate < 0),
    c-bar = 2 xi-bar sqrt(k sqrt(delta) m_eff),
    xi-bar = 9 sqrt5 (1 - e^2) / (2 e (e (9 pi - 16) + 16)).  Never tensile.
    """

    name = "NIVe"
    code = S.NIVE
    exponent = 1.5
    reference = "Jankowski (2005) EESD 34(6):595-611; seed Eq. 6"
    formula = "F = k*delta^1.5 + cbar*rate (rate >= 0), k*delta^1.5 (rate < 0)"
    tension_note = "never tensile"

    def damping_ratio(self):
        return nive_damping_ratio(self.restitution) if not self.velocity_dependent else np.nan


class UpdatedHertzdamp(ContactLaw):
    """Updated Hertzdamp law Hd, seed Eqs. 7-8.

    F = k delta^1.5 + zeta delta^1.5 rate, with zeta solved at the onset of
    every impact from that impact's approach velocity v0 by the exact
    Hunt-Crossley relation (seed Eq. 8); see ``_scalar.hunt_crossley_s`` for
    the root branch (0 < zeta < k/(e v0), every 0 < e < 1).  On that branch
    k + zeta rate > 0 throughout the impact, so the force is never tensile and
    the two-body restitution equals e for any mass and any exponent.
    """

    name = "Hd"
    code = S.HD
    exponent = 1.5
    reference = "Khatiwada & Chouw (seed) Eqs. 7-8; Hunt & Crossley (1975)"
    formula = "F = k*delta^1.5 + zeta*delta^1.5*rate, zeta from Eq. 8 at each impact"
    tension_note = "never tensile on the valid branch of Eq. 8"


class LinearHuntCrossley(ContactLaw):
    """Linear Hunt-Crossley law LHC, seed Eq. 9: F = k delta + zeta delta rate, zeta from Eq. 8."""

    name = "LHC"
    code = S.LHC
    exponent = 1.0
    reference = "Khatiwada & Chouw (seed) Eqs. 8-9; Zhang & Sharf (2009)"
    formula = "F = k*delta + zeta*delta*rate, zeta from Eq. 8 at each impact"
    tension_note = "never tensile on the valid branch of Eq. 8"


class Hertz(ContactLaw):
    """Elastic Hertz law F = k delta^1.5 (Hertz 1882; no dissipation, e = 1)."""

    name = "Hertz"
    code = S.HERTZ
    exponent = 1.5
    reference = "Hertz (1882); Johnson, Contact Mechanics (1985)"
    formula = "F = k*delta^1.5"
    tension_note = "never tensile"

    def __init__(self, stiffness: float, restitution: float = 1.0, tension: bool | None = None):
        super().__init__(stiffness, restitution, tension)

    @classmethod
    def describe_params(cls):
        params = super().describe_params()
        params[1] = Param("restitution", "-", "must be 1 (elastic)")
        return params

    def validate(self, key="contact"):
        super().validate(key)
        if self.restitution != 1.0:
            raise InputError("the Hertz law is elastic: restitution must be 1 (use Hd for damping)",
                             key=f"{key}.restitution")


class Hertzdamp(ContactLaw):
    """Classic Hertzdamp law (Muthukumar & DesRoches 2006).

    F = k delta^1.5 + zeta delta^1.5 rate with the approximate
    zeta = 3 k (1 - e^2) / (4 v0) (their Eq. 13, after Lankarani & Nikravesh),
    accurate only for e close to 1; kept so that its error can be compared with Hd.
    """

    name = "Hertzdamp"
    code = S.HERTZDAMP
    exponent = 1.5
    reference = "Muthukumar & DesRoches (2006) EESD 35(7):811-828"
    formula = "F = k*delta^1.5 + zeta*delta^1.5*rate, zeta = 3k(1-e^2)/(4 v0)"
    tension_note = "never tensile"


class HuntCrossley(ContactLaw):
    """Hunt-Crossley law with a fixed material damping constant c (Hunt & Crossley 1975).

    F = k delta^n (1 + 3/2 c rate) = delta^n (k + zeta rate), zeta = 3/2 c k,
    with c [s/m] a property of the material, not of the impact (Hunt &
    Crossley 1975, J. Appl. Mech. 42(2):440-445, Eq. 8 and their alpha = 3/2 c;
    Marhefka & Orin 1999, IEEE SMC-A 29(6):566-572).  Its restitution therefore
    falls with the approach velocity by itself: for two free bodies, exactly
    e(v0) with s = zeta v0 / k = 3/2 c v0 in seed Eq. 8 (any mass, any n;
    ``_scalar.restitution_from_s``), about 1 - c v0 for small c v0.  Never
    tensile: k + zeta rate > 0 during restitution on that branch.
    """

    name = "HC"
    code = S.HC
    exponent = 1.5
    reference = "Hunt & Crossley (1975) J. Appl. Mech. 42(2):440-445; Marhefka & Orin (1999)"
    formula = "F = k*delta^n*(1 + 1.5*c*rate), c fixed: e falls with the approach velocity"
    tension_note = "never tensile"

    def __init__(self, stiffness: float, damping_constant: float = 0.0, exponent: float = 1.5,
                 tension: bool | None = None):
        self.stiffness = stiffness
        self.damping_constant = damping_constant
        self.exponent = exponent
        self.tension = tension

    @classmethod
    def param_names(cls):
        return ("stiffness", "damping_constant", "exponent", "tension")

    @classmethod
    def describe_params(cls):
        return [
            Param("stiffness", "N/m^n", "contact stiffness k"),
            Param("damping_constant", "s/m", "material damping constant c (Hunt-Crossley alpha = 3/2 c); "
                                            "e ~ 1 - c v0"),
            Param("exponent", "-", "exponent n of delta (default 1.5, Hertz)"),
            Param("tension", "bool", "may the force become tensile (default false)"),
        ]

    def validate(self, key: str = "contact") -> None:
        self._validate_stiffness_and_tension(key)
        c, n = self.damping_constant, self.exponent
        if not _is_real(c) or not c >= 0 or not math.isfinite(c):
            raise InputError(f"damping_constant must be a number >= 0 in s/m, got {c!r}",
                             key=f"{key}.damping_constant")
        if not _is_real(n) or not 1.0 <= n <= 3.0:
            raise InputError(f"exponent must lie in [1, 3], got {n!r}", key=f"{key}.exponent")

    @property
    def velocity_dependent(self) -> bool:
        return True

    def restitution_at(self, approach_velocity):
        """Exact two-body e(v0) of seed Eq. 8 with s = 3/2 c v0 (array_like v0 [m/s])."""
        from . import _scalar

        v = np.asarray(approach_velocity, dtype=float)
        out = np.empty(v.shape)
        for idx in np.ndindex(v.shape):
            out[idx] = _scalar.restitution_from_s(1.5 * float(self.damping_constant) * max(float(v[idx]), 0.0))
        return out

    def kernel_params(self, m1: float, m2: float) -> np.ndarray:
        row = self._common_row(m1, m2)
        row[S.P_E] = np.nan  # set at each onset from the approach velocity
        row[S.P_XI] = float(self.damping_constant)
        return row
