"""Wrong parameters beyond what recalibration spans: the storeys' stiffness distributed otherwise over the height.

Three forms: the first and the top storey's stiffness set free of the building's factor (a soft first storey, a
soft or stiff top), a smooth (log-quadratic) taper over the height (``storey_stiffness_taper``), and every
storey's stiffness on its own (any distribution over the height: the storey stiffnesses are a shear building's
parameters, as in model updating).  The search judges the alternative by its form with the best information
criterion, so that the most parsimonious wrong-parameter explanation is the one a physics must beat.

Fitted beside the physics (an alternative, not a physics), so that a model whose parameters are wrong in a
way a factor cannot fix is not mistaken for missing physics (a soft first storey is a sway spring under the
base to within its radiation damping).
"""

from __future__ import annotations

from ._hypothesis import Hypothesis


def _storey_list(b) -> list | float:
    """The building's storey stiffnesses as a list, one value per storey where ``floors`` gives one for all."""
    if not isinstance(b["storey_stiffness"], list) and int(b.get("floors", 1)) >= 2:
        b["storey_stiffness"] = [b["storey_stiffness"]] * int(b["floors"])  # one value for every storey
    return b["storey_stiffness"]


def _stiffness_profile(d):
    # the storeys' stiffness distributed otherwise over the height than modelled (a soft first storey, a taper):
    # the first and the top storey's stiffness of every building of two or more storeys fitted on their own,
    # over a factor of 4 either way, while the building's stiffness factor scales the rest
    specs, null = [], {}
    for b in d["building"]:
        k = _storey_list(b)
        if not isinstance(k, list) or len(k) < 2:
            continue
        for j in (1, len(k)):
            path = f"building.{b['name']}.storey_stiffness.{j}"
            specs.append(f"{path}={0.25 * k[j - 1]!r}:{4.0 * k[j - 1]!r}")
            null[path] = k[j - 1]
    return specs, null


def _stiffness_taper(d):
    # a stiffness that falls (or rises) smoothly over the height than modelled: each building of two or more
    # storeys times a log-quadratic factor (storey_stiffness_taper: its value at mid-height and at the top, 1/4 to
    # 4; the top's alone for two storeys), fitted with the building's factor on the whole: a linear or otherwise
    # smooth redistribution is near one of these
    specs, null = [], {}
    for b in d["building"]:
        k = b["storey_stiffness"]
        n = len(k) if isinstance(k, list) else int(b.get("floors", 1))
        if n < 2 or "storey_stiffness_taper" in b:
            continue
        path = f"building.{b['name']}.storey_stiffness_taper"
        b["storey_stiffness_taper"] = {"top": 1.0, "middle": 1.0} if n >= 3 else {"top": 1.0}
        for key in b["storey_stiffness_taper"]:
            specs.append(f"{path}.{key}=0.25:4.0")
            null[f"{path}.{key}"] = 1.0
    return specs, null


def _every_storey(d):
    # any distribution over the height: storeys 2..N of every building of two or more storeys fitted on their own,
    # over a factor of 4 either way; the first storey follows the building's stiffness factor (fitted with the
    # base parameters), so that no direction of the fit is redundant
    specs, null = [], {}
    for b in d["building"]:
        k = _storey_list(b)
        if not isinstance(k, list) or len(k) < 2:
            continue
        for j in range(2, len(k) + 1):
            path = f"building.{b['name']}.storey_stiffness.{j}"
            specs.append(f"{path}={0.25 * k[j - 1]!r}:{4.0 * k[j - 1]!r}")
            null[path] = k[j - 1]
    return specs, null


def _why_not(d):
    multi = [b for b in d.get("building", []) if int(b.get("floors", 1)) >= 2 or
             (isinstance(b.get("storey_stiffness"), list) and len(b["storey_stiffness"]) >= 2)]
    return None if multi else "no building has two or more storeys whose stiffness could be distributed otherwise"


HYPOTHESIS = Hypothesis(
    "stiffness-distribution", "the storeys' stiffness distributed otherwise over the height than modelled",
    "a building's modes off in ratio to one another, which one stiffness factor cannot set right",
    forms=(_stiffness_profile, _stiffness_taper, _every_storey), why_not=_why_not, alternative=True)
