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
        At-rest separation [m], >= 0 (0 = touching); one value for every common
        level, or one per common level from the ground up.
    law : ContactLaw, optional
        Law for this gap; defaults to the model's ``[contact]`` law.
    """

    between: tuple
    size: object
    law: object = None


@dataclass(frozen=True)
class GapLink:
    """One gap element: left floor, right floor, at-rest size.

    Attributes
    ----------
    left, right : int
        Indices of the buildings in the row (left < right).
    left_floor, right_floor : int
        1-based floor numbers.
    height : float
        Elevation of the level [m].
    size : float
        At-rest gap [m].
    law : ContactLaw
    gap_index : int
        Index of the :class:`Gap` this element came from.
    """

    left: int
    right: int
    left_floor: int
    right_floor: int
    height: float
    size: float
    law: object
    gap_index: int


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
    ha, hb = a.floor_heights, b.floor_heights
    levels = [(fa, fb, ha[fa]) for fa in range(ha.size) for fb in range(hb.size)
              if abs(ha[fa] - hb[fb]) <= HEIGHT_TOLERANCE]
    if not levels:
        raise InputError(f"{a.name} and {b.name} have no floor at a common level", key=f"{key}.between")
    sizes = number_array(gap.size, f"{key}.size")
    if sizes.size not in (1, len(levels)):
        raise InputError(f"give one size or {len(levels)} (one per common level), got {sizes.size}",
                         key=f"{key}.size")
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
    return [GapLink(i, j, fa + 1, fb + 1, float(h), float(s), law, gap_index)
            for (fa, fb, h), s in zip(levels, sizes)]
