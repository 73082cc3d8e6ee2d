"""Borrowed arrays (``seispound.integrate._borrow``): the kernel's aliases without reference counts.

A borrowed array must be the same memory as its owner (reads, writes, views and
aliases all reach the owner's data), and the kernel must give the same results
as with counted arrays: the same run through the kernel's own reference
(``tests/reference_twin.py``) is checked elsewhere; here the semantics.
"""

import gc

import numpy as np
from numba import njit

from seispound.integrate._borrow import borrow, borrow_all, keep_alive


@njit(cache=True)
def _write_through(a, b2):
    x = borrow(a)
    y = borrow(b2)
    x[3] = 7.0  # a write through the borrowed array
    row = y[1]  # a view of a borrowed array is borrowed too
    row[2] = -1.5
    alias = x  # an alias of it
    alias[0] += 1.0
    return x.shape[0], y.shape[0], y.shape[1], y.strides[0], x.sum()


def test_a_borrowed_array_is_its_owner():
    a = np.arange(6.0)
    b = np.zeros((3, 4))
    n, r, c, stride, total = _write_through(a, b)
    assert (n, r, c, stride) == (6, 3, 4, 32)
    assert a[3] == 7.0 and a[0] == 1.0
    assert b[1, 2] == -1.5 and np.count_nonzero(b) == 1
    assert total == a.sum()


@njit(cache=True)
def _owned_work(n, reps):
    w = np.zeros(n)  # owned here, used only through its borrowed alias
    owners = (w,)
    w = borrow(w)
    s = 0.0
    for r in range(reps):
        for i in range(n):
            w[i] += i * (r + 1)
        scratch = np.ones(n)  # allocations in between would reuse freed memory
        s += scratch.sum()
    out = w.sum()
    keep_alive(owners)
    return out, s


def test_the_owner_tuple_keeps_the_work_array_alive():
    """If the owner were freed at its last named use, the allocations inside the loop
    would reuse its memory and the sum would come out wrong."""
    n, reps = 1000, 50
    out, s = _owned_work(n, reps)
    gc.collect()
    assert out == sum(i * (r + 1) for r in range(reps) for i in range(n))
    assert s == n * reps


@njit(cache=True)
def _group_work(n, reps):
    owners = (np.zeros(n), (np.zeros((2, n)), 3, 0.5), np.zeros(n, np.int64))  # a nested named group
    w, (w2, k, x), idx = borrow_all(owners)
    s = 0.0
    for r in range(reps):
        for i in range(n):
            w[i] += i * (r + 1)
            w2[1, i] += k * x
            idx[i] = i
        scratch = np.ones(n)  # allocations in between would reuse freed memory
        s += scratch.sum()
    keep_alive(owners)
    return owners[0].sum(), owners[1][0].sum(), owners[1][0][1].sum(), owners[2].sum(), s


def test_a_borrowed_group_is_its_owners():
    """``borrow_all``: every array of a nested tuple borrowed, scalars as they are; writes reach the owners,
    which the owner tuple keeps alive."""
    n, reps = 1000, 50
    w, w2, row1, idx, s = _group_work(n, reps)
    gc.collect()
    assert w == sum(i * (r + 1) for r in range(reps) for i in range(n))
    assert w2 == row1 == n * reps * 1.5
    assert idx == n * (n - 1) // 2
    assert s == n * reps
