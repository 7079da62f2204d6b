"""Values computed once per rotor speed and looked up afterwards, batched both ways.

A sweep's scans, refinements and searches come back to the same speeds many
times (a damping search's trials all scan the same probe speeds), and in air
each speed costs a hover trim and the long matrices of the blades in air.
:class:`SpeedTable` keeps what a function gave at each speed: a call with
speeds looks them all up at once (a sorted array and a binary search, no
loop per speed), computes the missing ones together and merges them in.
"""

from __future__ import annotations

import numpy as np


class SpeedTable:
    """Arrays kept per rotor speed.

    The arrays are stored in the order their speeds were computed, in room that
    doubles as it fills (a new speed costs its own rows, not a copy of the
    table); the speeds are kept sorted with each one's row.

    Parameters
    ----------
    compute : callable
        ``compute(speeds, table) -> tuple of arrays``, each with one row per speed
        (``speeds``: sorted, unique, none of them kept yet; ``table``: this table, whose
        kept values may serve as a starting guess).
    limit : int
        Most speeds kept; beyond it the table starts afresh.
    """

    def __init__(self, compute, limit: int = 100_000):
        self.compute, self.limit = compute, limit
        #: The speeds kept [rad/s], sorted (None: none yet).
        self.speeds: np.ndarray | None = None
        self._rows = np.zeros(0, int)  # (the row of each sorted speed in the store)
        self._store: tuple = ()
        self._count = 0

    @property
    def values(self) -> tuple | None:
        """The arrays at :attr:`speeds` (rows in that order)."""
        if self.speeds is None:
            return None
        return tuple(v[self._rows] for v in self._store)

    def __call__(self, speeds) -> tuple:
        """The arrays at ``speeds`` (any order, repeats allowed), rows in that order."""
        speeds = np.asarray(speeds, dtype=float).reshape(-1)
        if self.speeds is None:
            hit = np.zeros(speeds.shape, bool)
        else:
            at = np.clip(np.searchsorted(self.speeds, speeds), 0, len(self.speeds) - 1)
            hit = self.speeds[at] == speeds
        if not hit.all() or self.speeds is None:
            new = np.unique(speeds[~hit])
            self._keep(new, tuple(self.compute(new, self)))
        at = np.searchsorted(self.speeds, speeds)
        rows = self._rows[at]
        return tuple(v[rows] for v in self._store)

    def _keep(self, new, found) -> None:
        """Store ``found`` (arrays, a row per speed) at the sorted speeds ``new``."""
        if self.speeds is None or self._count + len(new) > self.limit:
            self.speeds, self._rows, self._count = None, np.zeros(0, int), 0
            self._store = tuple(np.empty((max(len(new), 16),) + a.shape[1:], a.dtype) for a in found)
        end = self._count + len(new)
        if end > len(self._store[0]):  # (room doubled: each row is copied O(1) times on average)
            room = max(2 * len(self._store[0]), end)
            grown = tuple(np.empty((room,) + v.shape[1:], v.dtype) for v in self._store)
            for g, v in zip(grown, self._store):
                g[: self._count] = v[: self._count]
            self._store = grown
        for v, a in zip(self._store, found):
            v[self._count : end] = a
        rows = np.arange(self._count, end)
        self._count = end
        if self.speeds is None:
            self.speeds, self._rows = new, rows
            return
        kept = np.concatenate([self.speeds, new])
        order = np.argsort(kept, kind="stable")
        self.speeds, self._rows = kept[order], np.concatenate([self._rows, rows])[order]
