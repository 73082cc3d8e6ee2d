"""What the variants of one model share: its buildings, read and laid out once.

A fit evaluates one model at hundreds of parameter values, and a study runs it at every
point of its axes; each variant differs from the model file in a few values.  Reading a
variant afresh validates and lays out every building again, though most of them did not
change: on a two-building pair that was about a quarter of a study run and a fifth of a
fit evaluation (``python -m benchmarks.reuse``).  :class:`Parts` keeps, for the buildings'
tables as the variants give them, the :class:`~seispound.structure.Building` read from each
and its layouts in the row, so that a variant reads and lays out only the buildings that
differ.

The models read with a ``Parts`` are the caller's own: their parts are shared with other
variants and must not be changed after reading (``Observer.simulate`` and the study's
workers run them and let them go).  A model a user can reach is read without one.
"""

from __future__ import annotations

import threading
from collections import OrderedDict

__all__ = ["Parts", "frozen", "REUSE"]

REUSE = True  # the off switch: False reads every variant afresh (what the tests and the benchmark compare against)


def frozen(value):
    """A hashable image of a TOML value: tables and arrays as tuples, each scalar with its type (so that
    ``floors = 3`` and ``floors = 3.0``, which validation tells apart, are different keys)."""
    if isinstance(value, dict):
        return ("{", tuple(sorted((k, frozen(v)) for k, v in value.items())))
    if isinstance(value, list):
        return ("[", tuple(frozen(v) for v in value))
    return (type(value).__name__, value)


class Parts:
    """Buildings read from their tables, and their layouts, kept for the variants of one model.

    Parameters
    ----------
    size : int
        How many buildings it keeps (least recently used go first): a fit that moves one
        building's stiffness makes a new one at every evaluation, and only the latest are
        worth keeping.
    """

    def __init__(self, size: int = 32):
        self.size = size
        self._kept = OrderedDict()  # key -> [building, {(first DOF, faces): layout}]
        self._ids = {}  # id(building) -> key, for the buildings kept now
        self._lock = threading.Lock()  # a dask worker may run a study's runs on several threads
        self.hits = 0
        self.misses = 0

    def building(self, key, make):
        """The building kept for ``key`` (the table's :func:`frozen` image and what it is read against), or
        ``make()``'s, kept."""
        with self._lock:
            entry = self._kept.get(key)
            if entry is not None:
                self._kept.move_to_end(key)
                self.hits += 1
                return entry[0]
            self.misses += 1
            b = make()
            self._kept[key] = [b, {}]
            self._ids[id(b)] = key
            while len(self._kept) > self.size:
                _, (gone, _) = self._kept.popitem(last=False)
                self._ids.pop(id(gone), None)
            return b

    def owns(self, building) -> bool:
        """Whether ``building`` is one kept here (validated when it was read, and not changed since)."""
        return id(building) in self._ids

    def layout(self, building, start: int, faces: tuple, make):
        """The layout of a kept ``building`` with its first DOF at ``start`` and neighbours ``faces``, or
        ``make()``'s, kept beside it."""
        with self._lock:
            key = self._ids.get(id(building))
            if key is None:  # not kept here (read afresh, or let go): laid out, not kept
                return make()
            layouts = self._kept[key][1]
            lay = layouts.get((start, faces))
            if lay is None:
                lay = layouts[(start, faces)] = make()
            return lay
