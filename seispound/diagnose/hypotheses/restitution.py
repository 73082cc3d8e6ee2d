"""Velocity-dependent restitution: e as a linear, exponential or power law of the impact velocity."""

from __future__ import annotations

from ._hypothesis import Hypothesis, needs_gaps


def _velocity_restitution(d):
    e = d["contact"].get("restitution", 0.65)
    e = float(e) if isinstance(e, (int, float)) else 0.65
    d["contact"]["restitution"] = {"form": "linear", "e0": e, "slope": 0.0, "min": 0.05, "max": 0.99}
    # impacts between storeys close at 0.05-1 m/s: a slope above 5 s/m would span e's whole range within 0.2 m/s;
    # e levels off at a floor (min) for the fastest impacts
    return (["contact.restitution.e0=0.1:0.99", "contact.restitution.slope=0:5", "contact.restitution.min=0.05:0.9"],
            {"contact.restitution.e0": e, "contact.restitution.slope": 0.0, "contact.restitution.min": 0.05})


def _exponential_restitution(d):
    # e falls from e0 at slow impacts to e_inf at fast ones over a velocity scale v_c (null: e0 = e_inf = e)
    e = _constant_e(d)
    d["contact"]["restitution"] = {"form": "exponential", "e0": e, "e_inf": e, "v_c": 0.3}
    return (["contact.restitution.e0=0.1:0.99", "contact.restitution.e_inf=0.05:0.99",
             "contact.restitution.v_c=0.02:2"],
            {"contact.restitution.e0": e, "contact.restitution.e_inf": e, "contact.restitution.v_c": 0.3})


def _power_restitution(d):
    # e = e_ref (v / 0.3 m/s)^-exponent, capped at 0.99 (null: exponent 0); Johnson's plastic impact gives 1/4
    e = _constant_e(d)
    d["contact"]["restitution"] = {"form": "power", "e_ref": e, "v_ref": 0.3, "exponent": 0.0, "max": 0.99}
    return (["contact.restitution.e_ref=0.05:0.99", "contact.restitution.exponent=0:1.5"],
            {"contact.restitution.e_ref": e, "contact.restitution.exponent": 0.0})


def _constant_e(d):
    e = d["contact"].get("restitution", 0.65)
    return float(e) if isinstance(e, (int, float)) else 0.65


# impact velocities at which a fitted e(v) is read as a constant e: storeys close at 0.05-1 m/s
NEAREST_VELOCITIES = (0.1, 0.2, 0.3, 0.5, 0.7, 1.0)


def _nearest_constant(table) -> list[dict]:
    # the constant e nearest a fitted e(v): its value at each of the impact velocities above, one candidate each
    from ...contact.restitution import restitution_from

    law = restitution_from(table["contact"]["restitution"], "contact.restitution")
    return [{"contact.restitution": float(law(v))} for v in NEAREST_VELOCITIES]


HYPOTHESIS = Hypothesis(
    "velocity-dependent-restitution", "a coefficient of restitution that changes with the impact velocity",
    "residual concentrated in the impacts, their rebound velocities wrong in opposite directions for strong "
    "and weak impacts",
    forms=(_velocity_restitution, _exponential_restitution, _power_restitution),
    why_not=needs_gaps("whose restitution could vary"), reduce=_nearest_constant)
