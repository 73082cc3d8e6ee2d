"""Coefficient of restitution as a function of the approach velocity v0.

Measured restitution falls as impacts get harder (Goldsmith, Impact, 1960,
Ch. 6; for concrete Jankowski 2010, EESD 39:1157-1179; Zhang & Sharf 2009 for
the contact-law side).  A law whose damping is set from e (LVe, MLVe, NIVe, Hd,
LHC, Hertzdamp) may take, instead of a number, one of the forms below; the
kernel evaluates it at each impact's approach velocity and sets that impact's
damping from the result (its ``onset`` hook), and the impact catalogue keeps
the e used.  Like the laws, a form's constructor only stores its parameters.

Forms (v0 [m/s] > 0; e is dimensionless):

* ``linear``: e = clip(e0 - slope v0, min, max)
* ``exponential``: e = e_inf + (e0 - e_inf) exp(-v0 / v_c)
* ``power``: e = min(max, e_ref (v0 / v_ref)^-exponent)
* ``table``: linear between the points (velocity, e), constant outside them
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError
from . import codes as S

__all__ = ["Restitution", "LinearRestitution", "ExponentialRestitution", "PowerRestitution", "TableRestitution",
           "restitution_from", "FORMS"]


def _real(x) -> bool:
    return isinstance(x, (int, float, np.floating, np.integer)) and not isinstance(x, bool) and math.isfinite(x)


class Restitution:
    """Base of the velocity-dependent forms: ``e(v0)``, validation and the kernel's parameter columns."""

    form = ""
    code = S.E_CONSTANT
    fields: tuple = ()

    def __init__(self, **params):
        for name in self.fields:
            setattr(self, name, params.get(name))

    def get_params(self) -> dict:
        return {"form": self.form, **{f: getattr(self, f) for f in self.fields}}

    def __repr__(self):
        return f"{type(self).__name__}({', '.join(f'{f}={getattr(self, f)!r}' for f in self.fields)})"

    def __eq__(self, other):
        return type(self) is type(other) and self.get_params() == other.get_params()

    def __hash__(self):
        return hash(repr(self))

    def _need(self, key, name, ok, what):
        val = getattr(self, name)
        if not _real(val) or not ok(val):
            raise InputError(f"must be {what}, got {val!r}", key=f"{key}.{name}")
        return float(val)

    def _unit(self, key, name):
        return self._need(key, name, lambda x: 0.0 < x <= 1.0, "a coefficient of restitution in (0, 1]")

    def validate(self, key: str) -> None:  # pragma: no cover - every form overrides it
        raise NotImplementedError

    def __call__(self, v0):
        """e at approach velocity ``v0`` [m/s] (array_like; v0 <= 0 counts as 0)."""
        v = np.maximum(np.asarray(v0, dtype=float), 0.0)
        return self._evaluate(v)

    def kernel_columns(self, row) -> None:
        """Write the form into a gap's parameter row (columns P_EFORM ... of ``contact.codes``)."""
        row[S.P_EFORM] = self.code
        for col, name in zip((S.P_EA, S.P_EB, S.P_EC, S.P_ED), self.fields):
            row[col] = float(getattr(self, name))


class LinearRestitution(Restitution):
    """e = clip(e0 - slope v0, min, max); slope [s/m]."""

    form = "linear"
    code = S.E_LINEAR
    fields = ("e0", "slope", "min", "max")

    def validate(self, key):
        self._unit(key, "e0")
        self._need(key, "slope", lambda x: x >= 0.0, "a number >= 0 in s/m")
        lo, hi = self._unit(key, "min"), self._unit(key, "max")
        if lo > hi:
            raise InputError(f"min {lo} exceeds max {hi}", key=f"{key}.min")

    def _evaluate(self, v):
        return np.clip(self.e0 - self.slope * v, self.min, self.max)


class ExponentialRestitution(Restitution):
    """e = e_inf + (e0 - e_inf) exp(-v0 / v_c); v_c [m/s]."""

    form = "exponential"
    code = S.E_EXPONENTIAL
    fields = ("e0", "e_inf", "v_c")

    def validate(self, key):
        self._unit(key, "e0")
        self._unit(key, "e_inf")
        self._need(key, "v_c", lambda x: x > 0.0, "a velocity > 0 in m/s")

    def _evaluate(self, v):
        return self.e_inf + (self.e0 - self.e_inf) * np.exp(-v / self.v_c)


class PowerRestitution(Restitution):
    """e = min(max, e_ref (v0 / v_ref)^-exponent); v_ref [m/s]."""

    form = "power"
    code = S.E_POWER
    fields = ("e_ref", "v_ref", "exponent", "max")

    def validate(self, key):
        self._unit(key, "e_ref")
        self._need(key, "v_ref", lambda x: x > 0.0, "a velocity > 0 in m/s")
        self._need(key, "exponent", lambda x: x >= 0.0, "a number >= 0")
        self._unit(key, "max")

    def _evaluate(self, v):
        with np.errstate(divide="ignore"):
            e = self.e_ref * (v / self.v_ref) ** (-self.exponent)
        return np.minimum(self.max, np.where(v > 0.0, e, np.inf))


class TableRestitution(Restitution):
    """Linear between the points (velocity [m/s], e), constant beyond the first and the last."""

    form = "table"
    code = S.E_TABLE
    fields = ("velocity", "e")

    def validate(self, key):
        v, e = self.velocity, self.e
        for name, arr in (("velocity", v), ("e", e)):
            if not isinstance(arr, (list, tuple, np.ndarray)) or not all(_real(x) for x in arr):
                raise InputError(f"must be a list of numbers, got {arr!r}", key=f"{key}.{name}")
        if not 2 <= len(v) <= S.MAX_TABLE:
            raise InputError(f"must have 2 to {S.MAX_TABLE} points, got {len(v)}", key=f"{key}.velocity")
        if len(e) != len(v):
            raise InputError(f"has {len(e)} entries but velocity has {len(v)}", key=f"{key}.e")
        if v[0] < 0.0 or np.any(np.diff(np.asarray(v, float)) <= 0.0):
            raise InputError("must be >= 0 and strictly increasing", key=f"{key}.velocity")
        if not all(0.0 < x <= 1.0 for x in e):
            raise InputError("every entry must lie in (0, 1]", key=f"{key}.e")

    def _evaluate(self, v):
        return np.interp(v, np.asarray(self.velocity, float), np.asarray(self.e, float))

    def kernel_columns(self, row) -> None:
        row[S.P_EFORM] = self.code
        n = len(self.velocity)
        row[S.P_NTAB] = n
        row[S.P_TAB:S.P_TAB + n] = self.velocity
        row[S.P_TAB + S.MAX_TABLE:S.P_TAB + S.MAX_TABLE + n] = self.e


FORMS = {cls.form: cls for cls in (LinearRestitution, ExponentialRestitution, PowerRestitution, TableRestitution)}


def restitution_from(value, key: str):
    """A number (returned as it is) or a table ``{form = ..., ...}`` (a validated form object)."""
    if isinstance(value, Restitution):
        value.validate(key)
        return value
    if not isinstance(value, dict):
        return value
    form = value.get("form")
    if form not in FORMS:
        raise InputError(f"form must be one of {', '.join(FORMS)}, got {form!r}", key=f"{key}.form")
    cls = FORMS[form]
    unknown = set(value) - {"form", *cls.fields}
    if unknown:
        raise InputError(f"unknown key; a {form} restitution takes {', '.join(cls.fields)}",
                         key=f"{key}.{sorted(unknown)[0]}")
    missing = [f for f in cls.fields if f not in value]
    if missing:
        raise InputError("is required", key=f"{key}.{missing[0]}")
    obj = cls(**{f: value[f] for f in cls.fields})
    obj.validate(key)
    return obj
