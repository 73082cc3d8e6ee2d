"""Storey laws: the lateral force of a storey as a function of its drift and history."""

from .laws import StoreyLaw

__all__ = ["StoreyLaw"]
