"""Model description (dataclasses) and the TOML model-file reader."""

from .spec import Analysis, GroundMotionSpec, Model
from .toml_loader import load_model, parse_model

__all__ = ["Analysis", "GroundMotionSpec", "Model", "load_model", "parse_model"]
