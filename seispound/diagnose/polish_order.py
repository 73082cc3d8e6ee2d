"""Which polishes a diagnosis still needs once a physics explains the data.

``api._fit_all`` polishes (fits to convergence, with the base parameters) every form whose short fit beats the
recalibrated base and every form whose short fit is within WITHIN of the best: a short fit may stop far from its
optimum, so a ranking of short fits must not drop a form that can still win.  Once a polished physics form fits
the data to the noise (its NE within ``at``, the report's own "explains the data"), some of those polishes can no
longer change what is named:

* **siblings**: a form whose hypothesis has a form ranked ahead of it that explains the data (the hypothesis is
  named by that form; a second form of it could only move the reported quantities within the noise).  Siblings
  rank by their short fits' information criterion at the effective sample size where it is given (``criterion``;
  BIC, Schwarz 1978, as the search judges physics: n_eff ln RSS + p ln n_eff), else by their short fits' NE: a
  form with more parameters whose short fit is better by less than its parameters cost ranks behind (on
  ``benchmarks.diagnose.speed``'s yielding case the degrading form's short fit, 9 parameters, came out 0.08 %
  better than the Bouc-Wen form's, 4, or 0.9 % worse, as round-off in the integrator moved it; ranked ahead, it
  was polished beside the others' short fits although the Bouc-Wen form already explained the data, and the
  diagnosis took 104-115 s instead of 60 s);
* **far forms**: a form whose short fit is more than WITHIN times the best short fit (polished only because it
  beat the recalibrated base), when a physics form within WITHIN explains the data.

Those are not used, and not run where the order of the work lets them be skipped: a form waits while a sibling
with a better short fit is being polished, and a far form waits until every form within WITHIN is polished; a
worker that would otherwise idle takes a waiting form all the same (``speculate``), and the search stops waiting
for it once it is known not to be needed (``settled``).  What is used is decided on the short fits and on the
polishes of the forms ranked ahead, never on which worker finished first, so the outcome is the same with one
worker or several; a polish that ran but is not needed is discarded (its form keeps its short fit).  The best
short fit so far, when it is clearly better than the recalibrated base, is polished on one worker while the
others go on with the short fits (``early``), so that its polish does not run alone after them.  With ``at``
None every polish is needed (``_fit_all`` without a noise estimate).
"""

from __future__ import annotations

__all__ = ["PolishOrder"]


class PolishOrder:
    """The order of a search's polishes and which of them are needed.

    Parameters
    ----------
    screen : dict
        form -> its best short fit's mean NE [-], filled as the short fits come in (the caller's dict, read live).
    within : float
        WITHIN: forms whose short fit is within this factor of the best are polished in any case.
    at : float or None
        The NE [-] at which a polish explains the data (EXPLAINED times the noise's NE); None: no rule applies.
    alternatives : collection of str
        Hypothesis names that are wrong-parameter alternatives: they never explain for this purpose and have no
        sibling rule (an alternative keeps its most parsimonious form, which needs all of them).
    criterion : dict, optional
        form -> the information criterion of its best short fit (the caller's dict, filled with ``screen``): the
        order of a hypothesis's forms for the sibling rule.  None: they rank by ``screen``.
    """

    def __init__(self, screen: dict, within: float, at: float | None, alternatives=(), criterion=None):
        self.screen, self.within, self.at, self.alternatives = screen, within, at, set(alternatives)
        self.criterion = criterion
        self.results: dict = {}  # form -> NE of its returned polish
        self.running: set = set()
        self.waiting: set = set()
        self.screened = False  # every form's short fits are in

    def _rank(self, form):
        return self.screen[form], form

    def _explains(self, form) -> bool:
        return (self.at is not None and form[0] not in self.alternatives and form in self.results
                and self.results[form] <= self.at)

    def _sibling_rank(self, form):
        if self.criterion is not None and form in self.criterion:
            return self.criterion[form], form
        return self._rank(form)

    def _better_siblings(self, form):
        if form[0] in self.alternatives:
            return []
        return [g for g in self.screen
                if g[0] == form[0] and g != form and self._sibling_rank(g) < self._sibling_rank(form)]

    def far(self, form) -> bool:
        """Is the form's short fit over ``within`` times the best so far (it stays so: the best only falls)?"""
        return self.screen[form] > self.within * min(self.screen.values())

    def needed(self, form) -> bool | None:
        """Is the form's polish needed: True, False, or None while it cannot yet be told."""
        if self.at is None:
            return True
        if any(self._explains(g) for g in self._better_siblings(form)):
            return False
        if self.far(form):
            near = [g for g in self.screen if not self.far(g)]
            if any(self._explains(g) for g in near):
                return False
            if not self.screened or any(g in self.running or g in self.waiting for g in near):
                return None
        return True

    def ready(self, form) -> bool:
        """May the form's polish start now: no sibling ranked ahead of it still to be polished, and, for a far
        form, every form within ``within`` polished."""
        if self.at is None:
            return True
        if any(g in self.running or g in self.waiting for g in self._better_siblings(form)):
            return False
        return self.needed(form) is True

    def request(self, form) -> None:
        """The form is to be polished when ``next`` gives it."""
        self.waiting.add(form)

    def next(self):
        """(the waiting form whose polish may start now, or None; the waiting forms no longer needed, which leave
        the queue), in rank order: asked when a worker is free, so that what is decided meanwhile counts."""
        dropped = []
        for form in sorted(self.waiting, key=self._rank):
            if self.needed(form) is False:
                self.waiting.discard(form)
                dropped.append(form)
            elif self.ready(form):
                self.waiting.discard(form)
                self.running.add(form)
                return form, dropped
        return None, dropped

    def early(self, clearly: float):
        """A waiting form to polish before the short fits still queued, or None: the best short fit so far, if it
        is below ``clearly`` (the recalibrated base's NE over WITHIN: a physics whose short fit already cuts the
        misfit by that much will be polished in any case unless a better one turns up) and may start now.  Its
        polish then runs beside the remaining short fits instead of alone after them; like ``speculate``, this
        changes what the search costs, never what it finds."""
        if not self.waiting:
            return None
        form = min(self.waiting, key=self._rank)
        ne = self.screen[form]
        if ne > clearly or ne > min(self.screen.values()) or not self.ready(form):
            return None
        self.waiting.discard(form)
        self.running.add(form)
        return form

    def speculate(self):
        """A waiting form to polish on a worker that would otherwise idle, or None: the best-ranked one that may
        still be needed.  Its result is used only where ``needed`` says so at the end, so starting it early
        changes what the search costs, never what it finds."""
        for form in sorted(self.waiting, key=self._rank):
            if self.needed(form) is not False:
                self.waiting.discard(form)
                self.running.add(form)
                return form
        return None

    def settled(self, pending) -> bool:
        """Is nothing left to wait for: no form waiting, and every polish in ``pending`` (forms) not needed?"""
        return not self.waiting and all(self.needed(f) is False for f in pending)

    def done(self, form, ne: float) -> None:
        """The form's polish returned with mean NE ``ne`` [-]."""
        self.running.discard(form)
        self.results[form] = ne
