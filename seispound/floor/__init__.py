"""Floor models: a floor as one lumped mass, or as an axial rod along the line of impact (with an attachment)."""

from .rod import Attachment, RodFloor

__all__ = ["RodFloor", "Attachment"]
