"""The half bandwidth of assembled element tables (plain numpy, no numba)."""

from __future__ import annotations

import numpy as np

__all__ = ["bandwidth"]


def bandwidth(n, *dof_tables) -> int:
    """Half bandwidth of the matrices the element tables ``dof_tables`` (each (ne, slots), -1 for an unused
    slot) assemble on ``n`` DOFs: the largest spread of one element's DOFs."""
    p = 0
    for dof in dof_tables:
        d = np.where(dof >= 0, dof, -1)
        if d.size == 0:
            continue
        hi = d.max(axis=1)
        lo = np.where(d >= 0, d, n).min(axis=1)
        used = hi >= 0
        if used.any():
            p = max(p, int((hi[used] - lo[used]).max()))
    return p
