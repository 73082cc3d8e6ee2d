"""Model description (dataclasses) and the TOML model-file reader."""

from .analysis import Analysis, Newmark
from .spec import BuildingMotion, GroundMotionSpec, Model
from .toml_loader import load_model, parse_model

__all__ = ["Analysis", "BuildingMotion", "Newmark", "GroundMotionSpec", "Model", "load_model", "parse_model"]
