"""The half bandwidth, the envelope and an envelope-reducing order of assembled element tables (plain numpy,
no numba)."""

from __future__ import annotations

import numpy as np

__all__ = ["bandwidth", "envelope", "profile_order"]


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


def envelope(n, *dof_tables) -> np.ndarray:
    """first (n,) int64: the first column of each row's lower envelope in the matrices the element tables
    assemble (an element couples every pair of its DOFs, so row i reaches down to the lowest DOF of any
    element on i; a row with no coupling below the diagonal starts at itself)."""
    first = np.arange(n, dtype=np.int64)
    for dof in dof_tables:
        if dof.size == 0:
            continue
        lo = np.where(dof >= 0, dof, n).min(axis=1)
        for k in range(dof.shape[1]):
            used = dof[:, k] >= 0
            np.minimum.at(first, dof[used, k], lo[used])
    return first


def _profile_cost(first) -> int:
    """The factorisation's work in a profile (sum of the squared row widths)."""
    w = np.arange(first.size) - first + 1
    return int(np.sum(w * w))


def profile_order(n, root, *dof_tables, gain=0.7):
    """An order of the DOFs whose envelope costs less to factor: perm (n,) int64 with perm[new] = old, or
    None if the DOFs' own order is within ``gain`` of the best found.

    Each building (``root`` (n,): a root DOF per building, every building a contiguous run) is ordered
    alone and stays where it is, so that the row stays block diagonal in the same blocks: its own
    order, that order reversed, or reverse Cuthill-McKee (Cuthill & McKee 1969; George & Liu 1981,
    Sec. 4.3; ``scipy.sparse.csgraph.reverse_cuthill_mckee``), whichever costs least
    (``_profile_cost``).  A foundation numbered before its floors couples each floor to its sway and
    rocking DOFs, a full envelope; reversed, the floors are tridiagonal and two rows are full.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import reverse_cuthill_mckee

    start = [0] + [i for i in range(1, n) if root[i] != root[i - 1]] + [n]
    if len(set(root[start[:-1]])) != len(start) - 1:
        return None  # a building in two runs
    rows, cols = [], []
    for dof in dof_tables:
        for k1 in range(dof.shape[1]):
            for k2 in range(dof.shape[1]):
                used = (dof[:, k1] >= 0) & (dof[:, k2] >= 0)
                rows.append(dof[used, k1])
                cols.append(dof[used, k2])
    r, c = np.concatenate(rows), np.concatenate(cols)
    graph = coo_matrix((np.ones(r.size), (r, c)), shape=(n, n)).tocsr()
    perm = np.arange(n, dtype=np.int64)
    own_cost = best_cost = 0
    for a, b in zip(start[:-1], start[1:]):
        block = graph[a:b, a:b]
        own = np.arange(b - a)
        cands = [own, own[::-1], reverse_cuthill_mckee(block, symmetric_mode=True).astype(np.int64)]
        costs = [_profile_cost(_first_of(block, cand)) for cand in cands]
        best = int(np.argmin(costs))
        perm[a:b] = a + cands[best]
        own_cost += costs[0]
        best_cost += costs[best]
    return perm if best_cost < gain * own_cost else None


def _first_of(graph, order) -> np.ndarray:
    """The envelope's first column of each row of the symmetric pattern ``graph`` renumbered by ``order``
    (order[new] = old)."""
    sub = graph[order][:, order].tocoo()
    first = np.arange(order.size, dtype=np.int64)
    np.minimum.at(first, sub.row, sub.col)
    return first
