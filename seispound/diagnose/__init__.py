"""``seispound diagnose``: where a simulation and a recording differ, and what physics the model left out.

``diagnose`` and ``Diagnosis`` load on first use (PEP 562), so that reading the hypotheses'
registry (the CLI's help, ``seispound diagnose --hypotheses``) does not import the fitting code.
"""

from .hypotheses import HYPOTHESES

__all__ = ["diagnose", "Diagnosis", "HYPOTHESES"]


def __getattr__(name):
    if name in ("diagnose", "Diagnosis"):
        from . import api

        return getattr(api, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
