"""Buildings, gap elements and their assembly into kernel arrays."""

from .assembly import SystemArrays, assemble
from .building import Building, NoDamping, RayleighDamping
from .gap import Gap, GapLink

__all__ = ["Building", "RayleighDamping", "NoDamping", "Gap", "GapLink", "SystemArrays", "assemble"]
