"""Gap elements: the links between neighbouring buildings at common floor levels."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError, number_array

__all__ = ["Gap", "GapLink", "HEIGHT_TOLERANCE"]

#: Two floors are at the same level when their elevations differ by less than this [m].
HEIGHT_TOLERANCE = 1e-6


@dataclass
class Gap:
    """Separation between two neighbouring buildings.

    One gap element (:class:`GapLink`) is created at every floor level that both
    buildings have (equal elevation within ``HEIGHT_TOLERANCE``).

    Parameters
    ----------
    between : (str, str)
        Names of two buildings that are neighbours in the row (either order).
    size : float or sequence of float
        At-rest separation [m], >= 0 (0 = touching); one value for every gap
        element, or one per element from the ground up.
    law : ContactLaw, optional
        Law for this gap; defaults to the model's ``[contact]`` law.
    levels : {"lower", "floors", "all"}
        Where gap elements are: "lower" (default), every floor of the lower
        neighbour (the one with the lower roof) against whatever it faces, a
        floor at the same level or the storey (columns) between two floors;
        "floors", only floors at a common level; "all", every floor of either
        building up to the lower roof against whatever it faces (also the
        default when the two roofs are level).
    """

    between: tuple
    size: object
    law: object = None
    levels: str = "lower"


@dataclass(frozen=True)
class GapLink:
    """One gap element: left floor, right floor, at-rest size.

    Attributes
    ----------
    left, right : int
        Indices of the buildings in the row (left < right).
    left_floor, right_floor : int
        1-based floor numbers; for a side struck on a storey, the floor above the point.
    height : float
        Elevation of the level [m].
    size : float
        At-rest gap [m].
    law : ContactLaw
    gap_index : int
        Index of the :class:`Gap` this element came from.
    left_weight, right_weight : float
        1 for a floor; for a storey, the point's height above the floor below as a
        fraction of the storey height: its displacement is (1 - w) u_below + w u_floor
        (linear interpolation of the columns between the two floors).
    """

    left: int
    right: int
    left_floor: int
    right_floor: int
    height: float
    size: float
    law: object
    gap_index: int
    left_weight: float = 1.0
    right_weight: float = 1.0

    @property
    def kind(self) -> str:
        """"floor-to-floor" or "floor-to-storey"."""
        return "floor-to-floor" if self.left_weight == 1.0 and self.right_weight == 1.0 else "floor-to-storey"


def expand_gap(gap: Gap, gap_index: int, buildings, default_law, key: str | None = None) -> list[GapLink]:
    """Create the gap elements of ``gap`` at every common floor level.

    Raises InputError (key ``gap.<i>.between`` / ``gap.<i>.size``) if the
    buildings are unknown or not neighbours, share no level, or the sizes are
    negative or of the wrong length.
    """
    key = key or f"gap.{gap_index + 1}"
    names = [b.name for b in buildings]
    pair = list(gap.between) if isinstance(gap.between, (list, tuple)) else None
    if pair is None or len(pair) != 2 or not all(isinstance(p, str) for p in pair):
        raise InputError(f"must name two buildings, got {gap.between!r}", key=f"{key}.between")
    for p in pair:
        if p not in names:
            raise InputError(f"unknown building {p!r}; buildings: {', '.join(names)}", key=f"{key}.between")
    i, j = sorted(names.index(p) for p in pair)
    if j - i != 1:
        raise InputError(f"{pair[0]} and {pair[1]} are not neighbours in the row "
                         f"({', '.join(names)}); pounding links only adjacent buildings",
                         key=f"{key}.between")
    a, b = buildings[i], buildings[j]
    if gap.levels not in LEVELS:
        raise InputError(f"must be one of {', '.join(repr(x) for x in LEVELS)}, got {gap.levels!r}",
                         key=f"{key}.levels")
    levels = gap_levels(a.floor_heights, b.floor_heights, gap.levels)
    if not levels:
        raise InputError(f"{a.name} and {b.name} have no floor at a common level", key=f"{key}.between")
    sizes = number_array(gap.size, f"{key}.size")
    if sizes.size not in (1, len(levels)):
        raise InputError(f"give one size or {len(levels)} (one per gap element from the ground up), got "
                         f"{sizes.size}", key=f"{key}.size")
    if not np.all(np.isfinite(sizes)):
        raise InputError("must be finite", key=f"{key}.size")
    if np.any(sizes < 0):
        raise InputError(f"must be >= 0 (a negative gap means the buildings overlap at rest), got "
                         f"{float(sizes[sizes < 0][0]):g}", key=f"{key}.size")
    sizes = np.broadcast_to(sizes, (len(levels),))
    law = gap.law if gap.law is not None else default_law
    if law is None:
        raise InputError("no contact law given (set [contact] law or the gap's own law)", key=f"{key}.law")
    law.validate(key=f"{key}" if gap.law is not None else "contact")
    return [GapLink(i, j, fa, fb, float(h), float(s), law, gap_index, wa, wb)
            for (fa, wa, fb, wb, h), s in zip(levels, sizes)]


LEVELS = ("lower", "floors", "all")


def _facing(heights, h):
    """What points at heights h face on a building with floor elevations ``heights``: (floors, weights).

    A floor within HEIGHT_TOLERANCE: (its 1-based number, 1.0); else the storey below the
    first floor above h: (that floor, fraction of the storey height from the floor below).
    Vectorised over h (the assembly runs on every simulate).
    """
    k = np.searchsorted(heights, h - HEIGHT_TOLERANCE)  # first floor at or above each point
    top = heights[k]
    below = np.where(k > 0, heights[np.maximum(k - 1, 0)], 0.0)
    on_floor = np.abs(top - h) <= HEIGHT_TOLERANCE
    return k + 1, np.where(on_floor, 1.0, (h - below) / (top - below))


def gap_levels(ha, hb, levels="lower") -> list:
    """Gap elements between buildings with floor elevations ha (left) and hb (right), from the ground up.

    Returns (left floor, left weight, right floor, right weight, height) per element
    (``GapLink``'s convention); see :class:`Gap` for ``levels``.
    """
    ha, hb = np.asarray(ha, float), np.asarray(hb, float)
    top = min(ha[-1], hb[-1]) + HEIGHT_TOLERANCE
    equal_roofs = abs(ha[-1] - hb[-1]) <= HEIGHT_TOLERANCE  # neither is the lower: both count
    if levels == "floors":
        shared = np.abs(ha[:, None] - hb[None, :]).min(axis=1) <= HEIGHT_TOLERANCE
        heights = ha[shared]
    elif levels == "all" or equal_roofs:
        heights = np.sort(np.concatenate([ha[ha <= top], hb[hb <= top]]))
        keep = np.concatenate([[True], np.diff(heights) > HEIGHT_TOLERANCE])  # a floor of both, listed once
        heights = heights[keep]
    else:
        heights = ha if ha[-1] <= hb[-1] else hb
    fa, wa = _facing(ha, heights)
    fb, wb = _facing(hb, heights)
    return list(zip(fa.tolist(), wa.tolist(), fb.tolist(), wb.tolist(), heights.tolist()))
