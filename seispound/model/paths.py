"""Dotted paths into a parsed model file: how a study, a fit and a diagnosis name the parameter they vary.

A path walks the TOML tables of a model file.  Arrays of tables are indexed
1-based (``gap.1.size``), buildings also by name (``building.A.storey_stiffness``),
gaps also by the names of the buildings they join (``gap.A|B.size``, either order),
``*`` stands for every entry (``gap.*.size``: all gaps at once), and a final number picks one
entry of a list of numbers, 1-based (``building.A.storey_stiffness.1``: the first storey's).
Examples: ``contact.law``, ``contact.restitution``, ``ground_motion.scale``,
``analysis.dt``, ``building.B.damping.ratio``.
"""

from __future__ import annotations

import copy
import math

from ..errors import InputError

__all__ = ["resolve", "get_value", "set_value", "scaled"]

# arrays of tables in a model file, and the key that can name an entry
_ARRAYS = {"building": "name", "gap": None}


def resolve(data: dict, path: str) -> list[tuple[dict, str]]:
    """The (table, key) pairs a path designates in ``data`` (several with ``*``).

    The final key may be absent from its table (an optional model key that the
    study sets); every table on the way must exist.  Raises InputError(key=path).
    """
    parts = path.split(".")
    if not path or any(not p for p in parts):
        raise InputError("is not a dotted path like contact.law or gap.1.size", key=path)
    tables = [data]
    i = 0
    while i < len(parts) - 1:
        part = parts[i]
        if i == len(parts) - 2 and parts[-1].isdigit() and _numbers(tables[0].get(part)):
            return [_element(t[part], int(parts[-1]), path) for t in tables]  # one entry of a list of numbers
        if isinstance(tables[0].get(part), list):  # an array of tables: the next part picks entries
            if part not in _ARRAYS:
                raise InputError(f"{part!r} is not a table that a study can vary", key=path)
            if i + 2 > len(parts) - 1:
                raise InputError(f"names a [[{part}]] entry but no key inside it "
                                 f"(for example {part}.1.{'size' if part == 'gap' else 'floor_masses'})", key=path)
            tables = [e for t in tables for e in _entries(t[part], parts[i + 1], part, path)]
            i += 2
            continue
        nxt = []
        for t in tables:
            val = t.get(part)
            if not isinstance(val, dict):
                raise InputError(f"no table {'.'.join(parts[:i + 1])!r} in the model file", key=path)
            nxt.append(val)
        tables = nxt
        i += 1
    return [(t, parts[-1]) for t in tables]


def _numbers(value) -> bool:
    return isinstance(value, list) and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)


def _element(values: list, k: int, path: str) -> tuple[list, int]:
    """(the list, its 0-based index) for entry ``k`` (1-based) of a list of numbers: the storey_stiffness.1 of a
    soft first storey."""
    if not 1 <= k <= len(values):
        raise InputError(f"the list has {len(values)} entries (1-based index)", key=path)
    return values, k - 1


def _entries(items: list, sel: str, part: str, path: str) -> list[dict]:
    if sel == "*":
        return [t for t in items if isinstance(t, dict)]
    if sel.isdigit():
        k = int(sel)
        if not 1 <= k <= len(items):
            raise InputError(f"the model file has {len(items)} [[{part}]] entries (1-based index)", key=path)
        return [items[k - 1]]
    if part == "gap" and "|" in sel:  # gap.A|B: the gap whose `between` names both
        pair = sorted(x.strip() for x in sel.split("|"))
        hits = [t for t in items if isinstance(t, dict) and isinstance(t.get("between"), list)
                and sorted(t["between"]) == pair]
        if hits:
            return hits
        have = ", ".join("|".join(map(str, t.get("between", []))) for t in items if isinstance(t, dict))
        raise InputError(f"no gap between {' and '.join(pair)} (gaps: {have})", key=path)
    name_key = _ARRAYS[part]
    if name_key:
        hits = [t for t in items if isinstance(t, dict) and t.get(name_key) == sel]
        if hits:
            return hits
        names = ", ".join(str(t.get(name_key)) for t in items if isinstance(t, dict))
        raise InputError(f"no {part} named {sel!r} (have: {names})", key=path)
    raise InputError(f"[[{part}]] entries are chosen by 1-based index, * or the buildings' names (gap.A|B), "
                     f"got {sel!r}", key=path)


def get_value(data: dict, path: str):
    """The value at ``path`` (the first one for a ``*`` path); KeyError if absent."""
    table, key = resolve(data, path)[0]
    return table[key]


def set_value(data: dict, path: str, value) -> None:
    """Set ``path`` to ``value`` in place (every entry for a ``*`` path)."""
    for table, key in resolve(data, path):
        table[key] = copy.deepcopy(value)


def scaled(base, factor: float, path: str):
    """``base`` times ``factor``: a number, or every number of a list (storey stiffnesses ...)."""
    if isinstance(base, bool) or not isinstance(factor, (int, float)) or isinstance(factor, bool) \
            or not math.isfinite(factor):
        raise InputError(f"a factor must be a finite number, got {factor!r}", key=path)
    if isinstance(base, (int, float)):
        return base * factor
    if isinstance(base, list) and all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in base):
        return [x * factor for x in base]
    raise InputError(f"factors apply to numbers or lists of numbers; the model has {base!r}", key=path)
