"""Explicit Runge-Kutta tableaux for the fixed-grid integration of the periodic equations.

DOP8 is the eighth-order method of Dormand and Prince. Its coefficients (DOP853), as
published with Hairer, Norsett and Wanner, "Solving Ordinary Differential Equations I"
(2nd ed., 1993) and used by SciPy's DOP853, are kept below: the twelve stages of the
eighth-order solution and the weights of its embedded fifth- and third-order error
estimators E5 and E3 (the eighth-order weights minus theirs; no dense output): groundres
uses them on a fixed grid.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction as _F

import numpy as np

# fmt: off
_DOP853_C = [0.0, 0.05260015195876773, 0.0789002279381516, 0.1183503419072274, 0.2816496580927726, 0.3333333333333333, 0.25, 0.3076923076923077, 0.6512820512820513, 0.6, 0.8571428571428571, 1.0]
_DOP853_A = [
    [],
    [0.05260015195876773],
    [0.0197250569845379, 0.0591751709536137],
    [0.02958758547680685, 0.0, 0.08876275643042054],
    [0.2413651341592667, 0.0, -0.8845494793282861, 0.924834003261792],
    [0.037037037037037035, 0.0, 0.0, 0.17082860872947386, 0.12546768756682242],
    [0.037109375, 0.0, 0.0, 0.17025221101954405, 0.06021653898045596, -0.017578125],
    [0.03709200011850479, 0.0, 0.0, 0.17038392571223998, 0.10726203044637328, -0.015319437748624402, 0.008273789163814023],
    [0.6241109587160757, 0.0, 0.0, -3.3608926294469414, -0.868219346841726, 27.59209969944671, 20.154067550477894, -43.48988418106996],
    [0.47766253643826434, 0.0, 0.0, -2.4881146199716677, -0.590290826836843, 21.230051448181193, 15.279233632882423, -33.28821096898486, -0.020331201708508627],
    [-0.9371424300859873, 0.0, 0.0, 5.186372428844064, 1.0914373489967295, -8.149787010746927, -18.52006565999696, 22.739487099350505, 2.4936055526796523, -3.0467644718982196],
    [2.273310147516538, 0.0, 0.0, -10.53449546673725, -2.0008720582248625, -17.9589318631188, 27.94888452941996, -2.8589982771350235, -8.87285693353063, 12.360567175794303, 0.6433927460157636],
]
_DOP853_B = [0.054293734116568765, 0.0, 0.0, 0.0, 0.0, 4.450312892752409, 1.8915178993145003, -5.801203960010585, 0.3111643669578199, -0.1521609496625161, 0.20136540080403034, 0.04471061572777259]
_DOP853_E5 = [0.01312004499419488, 0.0, 0.0, 0.0, 0.0, -1.2251564463762044, -0.4957589496572502, 1.6643771824549864, -0.35032884874997366, 0.3341791187130175, 0.08192320648511571, -0.022355307863886294]
_DOP853_E3 = [-0.18980075407240762, 0.0, 0.0, 0.0, 0.0, 4.450312892752409, 1.8915178993145003, -5.801203960010585, -0.4226823213237919, -0.1521609496625161, 0.20136540080403034, 0.02265179219836082]
# fmt: on

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
DOP8 = Tableau.from_lists(_DOP853_C, _DOP853_A, _DOP853_B, 8)
#: DOP8's embedded error estimators: weights of the fifth- and third-order estimates of the
#: local error (the compiled kernel controls its steps with them).
DOP8_E5, DOP8_E3 = np.array(_DOP853_E5), np.array(_DOP853_E3)
