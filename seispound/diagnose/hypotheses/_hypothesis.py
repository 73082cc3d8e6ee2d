"""What a hypothesis is: a physics (or a wrong-parameter form) with the augmentations that add it."""

from __future__ import annotations

import copy
from dataclasses import dataclass, field
from typing import Callable

__all__ = ["Context", "Hypothesis", "needs_buildings", "needs_gaps", "reads_recording"]


@dataclass(frozen=True)
class Hypothesis:
    """A physics a model may have left out, and the forms in which ``diagnose`` adds it.

    Parameters
    ----------
    name : str
        Its key: in reports, ``diagnose(hypotheses=...)`` and the docs.
    what : str
        What was left out, in words.
    signature : str
        What the residual should show.
    forms : tuple of callables
        The augmentations: each edits a copy of the model file's table in place and returns
        (the fit specs ``PATH=lo:hi``, the null point ``{PATH: value}``); each is fitted, the best kept.
    why_not : callable, optional
        ``why_not(table)``: why the physics cannot apply to a model, or None when it can.
    alternative : bool
        A wrong-parameter form fitted beside the physics (it explains a misfit without naming a physics).
    reduce : callable, optional
        ``reduce(fitted_table)``: the base model's own values nearest a fitted form, as candidates
        ``[{PATH: value}, ...]`` for the base parameters that the form replaced (a constant e for an e(v)):
        where the base model is refitted from the physics's fit (``api._base_from_physics``).
    refine : tuple, optional
        Per form, None or ``refine(fitted_table, context)``: a finer model of the same physics built from a
        screened fit (rod floors with more segments, where the recording's band holds their higher modes),
        edited in place, or None when the fit is fine enough.  ``diagnose`` polishes the finer model and the
        screened one and goes on from the better (``api._polish``).
    warm : bool
        Whether the forms share quantities enough that each may start from another's fit (a yield drift per
        building and the post-yield ratio): once the physics is accepted, its other forms are polished from
        the leading form's values (``api._warm_forms``).
    warm_only : tuple of int
        Forms left out of the search's screen and polished only from the leading form's values, where a
        start from the scan does not reach their basin: Iwan's sliders, whose piecewise-linear response
        makes the short fits from the scan end above the null point (``inelastic``).
    """

    name: str
    what: str
    signature: str
    forms: tuple = ()
    why_not: Callable | None = None
    alternative: bool = False
    reduce: Callable | None = None
    refine: tuple = ()
    warm: bool = False
    warm_only: tuple = ()

    def applies(self, data: dict) -> str | None:
        """Why this physics cannot apply to the model file's table ``data``, or None when it can."""
        return self.why_not(data) if self.why_not else None

    def refiner(self, variant: int) -> Callable | None:
        """Form ``variant``'s ``refine`` (None where it has none)."""
        return self.refine[variant] if variant < len(self.refine) else None

    @property
    def screened(self) -> tuple:
        """The forms the search screens and polishes from its starts (all but ``warm_only``)."""
        return tuple(v for v in range(len(self.forms)) if v not in self.warm_only)

    @property
    def variants(self) -> int:
        """How many forms the augmentation takes (each fitted; the best is kept)."""
        return len(self.forms)

    def augment(self, data: dict, variant: int = 0, context: Context | None = None) -> tuple[dict, list, dict]:
        """(the augmented model table, the fit specs PATH=lo:hi, the null point {PATH: value}); a form marked
        ``reads_recording`` is also given ``context`` (what the recording holds beside the fitted channels)."""
        out = copy.deepcopy(data)
        form = self.forms[variant]
        specs, null = form(out, context or Context()) if getattr(form, "reads_recording", False) else form(out)
        return out, specs, null


@dataclass(frozen=True)
class Context:
    """What a recording holds beside the channels a fit compares: the accelerations recorded at buildings'
    bases, which drive no channel of the model but may drive the building, and the band its residual occupies.

    Parameters
    ----------
    base_records : dict
        building name -> {"file": absolute path of the file holding the trace, "trace": its id,
        "scale": the channel map's factor to m/s^2}.  Empty for several trials (each has its own).
    band_top_hz : float or None
        The highest frequency [Hz] at which the recalibrated base model's residual stands above the sensor
        noise (``locate``: the top of the bands of the channels that hold the residual); None before it is
        located.
    """

    base_records: dict = field(default_factory=dict)
    band_top_hz: float | None = None


def reads_recording(form: Callable) -> Callable:
    """Mark a form that reads the :class:`Context` (called as ``form(table, context)``)."""
    form.reads_recording = True
    return form


def needs_gaps(what: str) -> Callable:
    """A ``why_not`` for a physics of the impacts: a model without gaps has no impact ``what``."""
    return lambda d: None if d.get("gap") else f"the model has no gap element, so no impact {what}"


def needs_buildings(d: dict) -> str | None:
    """A ``why_not`` for a physics of the buildings."""
    return None if d.get("building") else "the model has no building"
