"""Flexible foundations: a rigid footing that sways and rocks on the soil (springs, dashpots, Wolf's cones)."""

from .model import Foundation, Footing, Soil, cone_impedances, rocking_cone, rocking_cone_dynamic_stiffness

__all__ = ["Foundation", "Footing", "Soil", "cone_impedances", "rocking_cone", "rocking_cone_dynamic_stiffness"]
