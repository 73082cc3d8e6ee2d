"""``seispound diagnose``: where a simulation and a recording differ, and what physics the model left out."""

from .api import Diagnosis, diagnose
from .hypotheses import HYPOTHESES

__all__ = ["diagnose", "Diagnosis", "HYPOTHESES"]
