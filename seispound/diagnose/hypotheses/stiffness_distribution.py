"""Wrong parameters beyond what recalibration spans: the storeys' stiffness distributed otherwise over the height.

Fitted beside the physics (an alternative, not a physics), so that a model whose parameters are wrong in a
way a factor cannot fix is not mistaken for missing physics (a soft first storey is a sway spring under the
base to within its radiation damping).
"""

from __future__ import annotations

from ._hypothesis import Hypothesis


def _stiffness_profile(d):
    # the storeys' stiffness distributed otherwise over the height than modelled (a soft first storey, a taper):
    # the first and the top storey's stiffness of every building of two or more storeys fitted on their own,
    # over a factor of 4 either way, while the building's stiffness factor scales the rest
    specs, null = [], {}
    for b in d["building"]:
        if not isinstance(b["storey_stiffness"], list) and int(b.get("floors", 1)) >= 2:
            b["storey_stiffness"] = [b["storey_stiffness"]] * int(b["floors"])  # one value for every storey
        k = b["storey_stiffness"]
        if not isinstance(k, list) or len(k) < 2:
            continue
        for j in (1, len(k)):
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
    forms=(_stiffness_profile,), why_not=_why_not, alternative=True)
