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
        #: The speeds kept [rad/s], sorted, and the arrays at them (rows in that order).
        self.speeds: np.ndarray | None = None
        self.values: tuple | None = None

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
            found = tuple(self.compute(new, self))
            if self.speeds is None or len(self.speeds) + len(new) > self.limit:
                kept, values = new, found
            else:
                kept = np.concatenate([self.speeds, new])
                values = tuple(np.concatenate([a, b]) for a, b in zip(self.values, found))
            order = np.argsort(kept, kind="stable")
            self.speeds, self.values = kept[order], tuple(v[order] for v in values)
        at = np.searchsorted(self.speeds, speeds)
        return tuple(v[at] for v in self.values)
