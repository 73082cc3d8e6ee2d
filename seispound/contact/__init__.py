"""Contact-force laws: LVe, MLVe, NIVe, Hd, LHC (seed paper) plus Hertz and classic Hertzdamp."""

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
    lve_damping_ratio,
    mlve_damping_ratio,
    nive_damping_ratio,
)
from .registry import get_law, law_names, make_law, register
from .restitution import (
    ExponentialRestitution,
    LinearRestitution,
    PowerRestitution,
    Restitution,
    TableRestitution,
    restitution_from,
)

LVe = LinearViscoelastic
MLVe = ModifiedLinearViscoelastic
NIVe = NonlinearViscoelastic
Hd = UpdatedHertzdamp
LHC = LinearHuntCrossley
HC = HuntCrossley

__all__ = [
    "ContactLaw", "Hertz", "Hertzdamp", "LinearHuntCrossley", "LinearViscoelastic",
    "ModifiedLinearViscoelastic", "NonlinearViscoelastic", "UpdatedHertzdamp",
    "HuntCrossley", "LVe", "MLVe", "NIVe", "Hd", "LHC", "HC", "get_law", "law_names", "make_law", "register",
    "lve_damping_ratio", "mlve_damping_ratio", "nive_damping_ratio",
    "Restitution", "LinearRestitution", "ExponentialRestitution", "PowerRestitution", "TableRestitution",
    "restitution_from",
]
