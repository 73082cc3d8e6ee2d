"""Units of ground-acceleration records (no heavy imports: the model reader uses it)."""

from __future__ import annotations

from seispound.errors import InputError

#: Standard acceleration of gravity, m/s² (3rd CGPM, 1901).
G_STANDARD = 9.80665

#: Factor from each supported unit to m/s² ("counts" needs a calibration).
UNIT_FACTORS = {"g": G_STANDARD, "m/s2": 1.0, "cm/s2": 1.0e-2, "mm/s2": 1.0e-3}

_UNIT_ALIASES = {
    "g": "g",
    "m/s2": "m/s2", "mps2": "m/s2", "m/s/s": "m/s2", "m/sec2": "m/s2",
    "cm/s2": "cm/s2", "gal": "cm/s2", "gals": "cm/s2", "cm/s/s": "cm/s2",
    "cm/sec2": "cm/s2",
    "mm/s2": "mm/s2", "mm/s/s": "mm/s2", "mm/sec2": "mm/s2",
    "counts": "counts", "count": "counts",
}


def _canonical_units(units, file) -> str:
    if isinstance(units, str):
        key = "".join(units.lower().split()).replace("**", "").replace("^", "")
        if key == "auto" or key in _UNIT_ALIASES:
            return "auto" if key == "auto" else _UNIT_ALIASES[key]
    raise InputError(
        f"unknown units {units!r}; use 'g', 'm/s2', 'cm/s2' (or 'gal'), 'mm/s2' or "
        "'counts' (with calibration in m/s2 per count)", file=file, key="units")
