"""Catalogue of the ground-motion records bundled in ``ground_motions/``.

The catalogue (``ground_motions/catalogue.toml``) lists, for every bundled
file, its sha256, source, event, station, component, units, dt, npts and peak
acceleration, and the licence situation.  The folder lives at the top of the
source tree, next to ``seispound/``, so it is available from a source checkout
or an editable install.
"""

from __future__ import annotations

import sys
from pathlib import Path

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

from seispound.errors import InputError

__all__ = ["GROUND_MOTIONS_DIR", "CATALOGUE_FILE", "bundled_records", "bundled_path"]

#: Folder holding the bundled records and ``catalogue.toml``.
GROUND_MOTIONS_DIR = Path(__file__).resolve().parents[2] / "ground_motions"
#: The catalogue file.
CATALOGUE_FILE = GROUND_MOTIONS_DIR / "catalogue.toml"


def bundled_records() -> list[dict]:
    """Return the parsed catalogue: one dict per bundled record.

    Returns
    -------
    list of dict
        Keys ``name``, ``file``, ``sha256``, ``source``, ``source_path``,
        ``rsn``, ``event``, ``date``, ``station``, ``component``, ``units``,
        ``dt`` (s), ``npts``, ``pga_g`` (g) and ``licence``.

    Raises
    ------
    InputError
        If the catalogue is missing (e.g. an installed wheel without the
        source tree) or is not valid TOML.
    """
    try:
        with open(CATALOGUE_FILE, "rb") as fh:
            table = tomllib.load(fh)
    except FileNotFoundError:
        raise InputError("bundled ground-motion catalogue not found (it ships with "
                         "the source tree, not the wheel)",
                         file=CATALOGUE_FILE, key="file") from None
    except tomllib.TOMLDecodeError as err:
        raise InputError(f"invalid TOML: {err}", file=CATALOGUE_FILE, key="record") from None
    return [dict(r) for r in table.get("record", [])]


def bundled_path(name: str) -> Path:
    """Return the path of a bundled record.

    Parameters
    ----------
    name : str
        Catalogue ``name`` (``"elcentro_180"``), file name
        (``"RSN6_IMPVALL.I_I-ELC180-hor1.AT2"``) or file name without suffix.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    InputError
        Key ``record`` if *name* is not in the catalogue (the message lists the
        available names).
    """
    records = bundled_records()
    for rec in records:
        if name in (rec.get("name"), rec["file"], Path(rec["file"]).stem):
            return GROUND_MOTIONS_DIR / rec["file"]
    available = ", ".join(str(r.get("name", r["file"])) for r in records)
    raise InputError(f"no bundled record {name!r}; available: {available}",
                     file=CATALOGUE_FILE, key="record")
