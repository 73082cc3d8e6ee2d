"""The physics a model may have left out: each with the augmentations that add it and the parameters it fits.

An augmentation edits the model file's table (never the base model's own values) and
names the dotted paths to fit with their bounds, in the calibration's ``PATH=lo:hi`` form
(``building.*.KEY`` ties one value across the row), and its *null point*: the values at which
the augmented model reduces to the base model (rigid floors, constant e, rigid soil, storeys
that never yield, no delay).  Every hypothesis nests the base model, so a fit started at its
null point can only improve on it.  Where a physics needs a quantity the base model does not
state (a floor's length along the line of impact, a footing's size), the augmentation assumes
a stated default and fits the parameter that the data can see instead.

One file per hypothesis, each defining ``HYPOTHESIS`` (:class:`Hypothesis`); ``REGISTRY`` below is
the one place a hypothesis is named.  Adding one is a new file and a line there; ``diagnose``,
its reports, the conformance tests (``tests/diagnose/test_forms_conformance.py``) and the
benchmarks read the registry.
"""

from __future__ import annotations

from . import distributed_mass, inelastic, restitution, soil, spatial, stiffness_distribution
from ._hypothesis import Context, Hypothesis

__all__ = ["ALTERNATIVES", "HYPOTHESES", "REGISTRY", "Context", "Hypothesis"]

# in the order diagnose submits their fits
REGISTRY = (
    distributed_mass.HYPOTHESIS,
    restitution.HYPOTHESIS,
    soil.HYPOTHESIS,
    inelastic.HYPOTHESIS,
    spatial.HYPOTHESIS,
    stiffness_distribution.HYPOTHESIS,
)

HYPOTHESES = {h.name: h for h in REGISTRY if not h.alternative}  # the physics
ALTERNATIVES = {h.name: h for h in REGISTRY if h.alternative}  # wrong parameters beyond recalibration
