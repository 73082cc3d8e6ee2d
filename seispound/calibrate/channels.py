"""Channel maps: which model quantity each recorded trace measures.

A channel map is a TOML file of ``[[channel]]`` tables::

    [[channel]]
    id = "XX.STA.00.HNE"          # the trace id in the recording
    quantity = "acceleration"      # acceleration (absolute), velocity, displacement (relative to the
                                   # ground under the building), or force
    building = "A"
    floor = 3                      # 0: the ground under the building (acceleration only)
    # position = 0.25              # optional, on a rod floor: fraction of its length from the left face

    [[channel]]
    id = "XX.LAB.00.FRC"
    quantity = "force"
    gap = 1                        # the 1-based gap element, or "A|B" (with floor = the left floor
                                   # when the pair has several elements)

Units: SI (m/s^2, m/s, m, N) unless ``units`` says otherwise (``"g"``, ``"cm/s2"``, ``"mm"``,
``"kN"``, ...); ``scale`` multiplies after conversion.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from ..errors import InputError

__all__ = ["Channel", "load_channels", "QUANTITIES"]

QUANTITIES = ("acceleration", "velocity", "displacement", "force")
_KEYS = {"id", "quantity", "building", "floor", "position", "gap", "units", "scale"}
G = 9.80665
UNITS = {
    "acceleration": {"m/s2": 1.0, "m/s^2": 1.0, "g": G, "cm/s2": 0.01, "gal": 0.01, "mm/s2": 0.001},
    "velocity": {"m/s": 1.0, "cm/s": 0.01, "mm/s": 0.001},
    "displacement": {"m": 1.0, "cm": 0.01, "mm": 0.001},
    "force": {"n": 1.0, "kn": 1e3, "mn": 1e6},
}
DEFAULT_UNITS = {"acceleration": "m/s2", "velocity": "m/s", "displacement": "m", "force": "N"}


@dataclass(frozen=True)
class Channel:
    """One recorded trace and the model quantity it measures (module docstring).

    ``gap`` is resolved to the 0-based gap element of the assembled row; ``factor``
    converts the trace's units to SI.
    """

    id: str
    quantity: str
    building: str | None = None
    floor: int | None = None
    position: float | None = None
    gap: int | None = None
    factor: float = 1.0

    @property
    def label(self) -> str:
        where = f"gap {self.gap + 1}" if self.quantity == "force" else f"{self.building} floor {self.floor}"
        return f"{self.id} ({self.quantity}, {where})"


def load_channels(path, model) -> list[Channel]:
    """Read a channel map and check it against ``model``; InputError names the file and ``channel.<i>.<key>``."""
    from ..model.toml_loader import read_toml

    path = Path(path)
    _, data = read_toml(path, "channel map")
    try:
        return parse_channels(data, model)
    except InputError as err:
        raise err.located(file=path) from None


def parse_channels(data: dict, model) -> list[Channel]:
    if set(data) - {"channel"}:
        bad = sorted(set(data) - {"channel"})[0]
        raise InputError("unknown key; a channel map holds [[channel]] tables only", key=bad)
    tables = data.get("channel")
    if not isinstance(tables, list) or not tables:
        raise InputError("at least one [[channel]] table is required", key="channel")
    names = {b.name: b for b in model.buildings}
    links = model.assembled().links
    out, seen = [], set()
    for i, t in enumerate(tables):
        key = f"channel.{i + 1}"
        if not isinstance(t, dict):
            raise InputError("must be a table", key=key)
        for k in t:
            if k not in _KEYS:
                raise InputError(f"unknown key; allowed: {', '.join(sorted(_KEYS))}", key=f"{key}.{k}")
        cid = t.get("id")
        if not isinstance(cid, str) or not cid:
            raise InputError("is required: the trace id (NET.STA.LOC.CHA)", key=f"{key}.id")
        if cid in seen:
            raise InputError(f"trace {cid} is mapped twice", key=f"{key}.id")
        seen.add(cid)
        q = t.get("quantity")
        if q not in QUANTITIES:
            raise InputError(f"must be one of {', '.join(QUANTITIES)}, got {q!r}", key=f"{key}.quantity")
        if q == "force":
            gap = _gap(t, links, names, key)
            out.append(Channel(cid, q, gap=gap, factor=_factor(t, q, key)))
            continue
        b = t.get("building")
        if b not in names:
            raise InputError(f"unknown building {b!r}; buildings: {', '.join(names)}", key=f"{key}.building")
        fl = t.get("floor")
        nf = names[b].n_floors
        if not (isinstance(fl, int) and not isinstance(fl, bool) and 0 <= fl <= nf):
            raise InputError(f"must be an integer floor in 0..{nf} (0: the ground), got {fl!r}", key=f"{key}.floor")
        if fl == 0 and q != "acceleration":
            raise InputError(f"the ground (floor 0) is recorded as an acceleration; {q} is relative to it",
                             key=f"{key}.quantity")
        pos = t.get("position")
        if pos is not None:
            if names[b].floor_model is None:
                raise InputError(f"{b}'s floors are lumped: a position needs a rod floor_model", key=f"{key}.position")
            if not (isinstance(pos, (int, float)) and not isinstance(pos, bool) and 0.0 <= pos <= 1.0):
                raise InputError(f"must be a fraction of the floor's length in [0, 1], got {pos!r}",
                                 key=f"{key}.position")
        out.append(Channel(cid, q, building=b, floor=fl, position=None if pos is None else float(pos),
                           factor=_factor(t, q, key)))
    return out


def _factor(t, q, key) -> float:
    units = t.get("units", DEFAULT_UNITS[q])
    table = UNITS[q]
    if not isinstance(units, str) or units.lower() not in {u.lower() for u in table}:
        raise InputError(f"must be one of {', '.join(table)} for {q}, got {units!r}", key=f"{key}.units")
    scale = t.get("scale", 1.0)
    if not (isinstance(scale, (int, float)) and not isinstance(scale, bool) and scale > 0):
        raise InputError(f"must be a number > 0, got {scale!r}", key=f"{key}.scale")
    return float({u.lower(): f for u, f in table.items()}[units.lower()] * scale)


def _gap(t, links, names, key) -> int:
    g = t.get("gap")
    if isinstance(g, int) and not isinstance(g, bool):
        if not 1 <= g <= len(links):
            raise InputError(f"must be a gap element 1..{len(links)}, got {g}", key=f"{key}.gap")
        return g - 1
    if isinstance(g, str) and "|" in g:
        a, b = (x.strip() for x in g.split("|", 1))
        for n in (a, b):
            if n not in names:
                raise InputError(f"unknown building {n!r}", key=f"{key}.gap")
        order = list(names)
        left, right = sorted((order.index(a), order.index(b)))
        hits = [i for i, l in enumerate(links) if (l.left, l.right) == (left, right)]
        if not hits:
            raise InputError(f"no gap element between {a} and {b}", key=f"{key}.gap")
        fl = t.get("floor")
        if fl is not None:
            hits = [i for i in hits if links[i].left_floor == fl]
            if not hits:
                raise InputError(f"no gap element of {a}|{b} at the left building's floor {fl}", key=f"{key}.floor")
        if len(hits) > 1:
            raise InputError(f"{a}|{b} has {len(hits)} gap elements: give floor = the left building's floor",
                             key=f"{key}.gap")
        return hits[0]
    raise InputError(f'is required for a force: a 1-based gap element or "A|B", got {g!r}', key=f"{key}.gap")
