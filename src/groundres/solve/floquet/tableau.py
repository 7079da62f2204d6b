"""Explicit Runge-Kutta tableaux for the fixed-grid integration of the periodic equations."""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction as _F

import numpy as np

from . import _dop853

# Butcher (1964) sixth-order, seven-stage explicit Runge-Kutta method.
_C = [0, _F(1, 3), _F(2, 3), _F(1, 3), _F(1, 2), _F(1, 2), 1]
_A = [
    [],
    [_F(1, 3)],
    [0, _F(2, 3)],
    [_F(1, 12), _F(1, 3), _F(-1, 12)],
    [_F(-1, 16), _F(9, 8), _F(-3, 16), _F(-3, 8)],
    [0, _F(9, 8), _F(-3, 8), _F(-3, 4), _F(1, 2)],
    [_F(9, 44), _F(-9, 11), _F(63, 44), _F(18, 11), 0, _F(-16, 11)],
]
_B = [_F(11, 120), 0, _F(27, 40), _F(27, 40), _F(-4, 15), _F(-4, 15), _F(11, 120)]


@dataclass(frozen=True)
class Tableau:
    """An explicit Runge-Kutta method: nodes c, matrix a (lower triangular), weights b."""

    c: np.ndarray
    a: np.ndarray
    b: np.ndarray
    order: int

    @classmethod
    def from_lists(cls, c, a, b, order):
        s = len(c)
        mat = np.zeros((s, s))
        for i, row in enumerate(a):
            mat[i, : len(row)] = [float(v) for v in row]
        return cls(np.array([float(v) for v in c]), mat, np.array([float(v) for v in b]), order)


BUTCHER6 = Tableau.from_lists(_C, _A, _B, 6)
#: Dormand-Prince eighth-order method (DOP853's twelve stages) on a fixed grid:
#: for multipliers to 1e-10 it needs three to five times fewer stage
#: evaluations than BUTCHER6 on the shipped cases (benchmarks/bench_floquet.py).
DOP8 = Tableau.from_lists(_dop853.C, _dop853.A, _dop853.B, 8)
