"""Registry of contact laws by name (case-insensitive)."""

from __future__ import annotations

from ..errors import InputError
from .laws import (
    ContactLaw,
    Hertz,
    Hertzdamp,
    HuntCrossley,
    LinearHuntCrossley,
    LinearViscoelastic,
    ModifiedLinearViscoelastic,
    NonlinearViscoelastic,
    UpdatedHertzdamp,
)

_REGISTRY: dict[str, type[ContactLaw]] = {}


def register(cls: type[ContactLaw]) -> type[ContactLaw]:
    """Register a law class under ``cls.name`` (usable as a decorator)."""
    _REGISTRY[cls.name.lower()] = cls
    return cls


for _cls in (LinearViscoelastic, ModifiedLinearViscoelastic, NonlinearViscoelastic,
             UpdatedHertzdamp, LinearHuntCrossley, Hertz, Hertzdamp, HuntCrossley):
    register(_cls)


def law_names() -> list[str]:
    """Registered law names in registration order."""
    return [cls.name for cls in _REGISTRY.values()]


def get_law(name: str) -> type[ContactLaw]:
    """Law class registered under ``name``; InputError (key ``contact.law``) if unknown."""
    try:
        return _REGISTRY[str(name).lower()]
    except KeyError:
        raise InputError(f"unknown contact law {name!r}; known: {', '.join(law_names())}",
                         key="contact.law") from None


def make_law(name: str, **params) -> ContactLaw:
    """Instantiate and validate law ``name`` with ``params``."""
    cls = get_law(name)
    unknown = set(params) - set(cls.param_names())
    if unknown:
        raise InputError(f"unknown parameter(s) {sorted(unknown)} for law {cls.name}; "
                         f"known: {', '.join(cls.param_names())}", key="contact")
    law = cls(**params)
    law.validate()
    return law
