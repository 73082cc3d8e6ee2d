"""Flexible foundations: a rigid footing that sways and rocks on the soil (springs and dashpots)."""

from .model import Foundation, Footing, Soil, cone_impedances

__all__ = ["Foundation", "Footing", "Soil", "cone_impedances"]
