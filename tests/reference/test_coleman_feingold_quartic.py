"""Undamped isotropic hub: the classical quartic (Coleman & Feingold, NACA Report 1351, 1958).

With s = i w:  [nu^2 W^2 - (w - W)^2] (wh^2 - w^2) = mu w^4,  mu = N S^2 / (2 I M),
M the total translating mass (hub + blades), wh^2 = K/M. Instability = complex
roots. Both the roots and the unstable range come from the polynomial alone,
independently of groundres' derivation, transform and solver.
"""

import numpy as np
import pytest
from scipy.optimize import brentq, linear_sum_assignment

from conftest import make_case
from groundres import analyze
from groundres.model.system import System
from groundres.solve import modal

N, M_HUB, K_HUB = 4, 8026.6, 1240481.8
BLADE = dict(blade_mass=94.9, blade_static_moment=289.1, blade_inertia=1084.7, hinge_offset=0.3048)


def quartic_roots(speed, lag_stiffness=0.0):
    m_total = M_HUB + N * BLADE["blade_mass"]
    i, s, e = BLADE["blade_inertia"], BLADE["blade_static_moment"], BLADE["hinge_offset"]
    nu2 = lag_stiffness / (i * speed**2) + e * s / i
    mu = N * s**2 / (2 * i * m_total)
    wh2 = K_HUB / m_total
    # (nu^2 W^2 - (w - W)^2) = -w^2 + 2 W w + (nu^2 - 1) W^2
    a = np.array([-1.0, 2 * speed, (nu2 - 1) * speed**2])
    b = np.array([-1.0, 0.0, wh2])
    poly = np.polymul(a, b)
    poly[0] -= mu
    return np.roots(poly)


def isotropic_case(lag_stiffness=0.0, sweep=(2.0, 45.0, 300)):
    return make_case(
        blade=dict(lag_damping=0.0, lag_stiffness=lag_stiffness),
        body=dict(mass_y=M_HUB, damping_x=0.0, damping_y=0.0),
        sweep=sweep,
    )


@pytest.mark.parametrize("speed", [5.0, 15.0, 24.0, 40.0])
@pytest.mark.parametrize("lag_stiffness", [0.0, 3e5])
def test_coupled_block_roots_solve_the_quartic(speed, lag_stiffness):
    case = isotropic_case(lag_stiffness)
    system = System(case.rotor, case.body)
    mats = system.multiblade(np.array([speed]))
    names = [c.symbol for c in system.multiblade_coordinates()]
    idx = np.array([names.index(n) for n in ("x", "y", "lag_1c", "lag_1s")])
    block = modal.state_matrix(*(x[0][np.ix_(idx, idx)] for x in mats))
    eig = np.linalg.eigvals(block)
    w = quartic_roots(speed, lag_stiffness)
    expected = np.concatenate([1j * w, np.conj(1j * w)])
    distance = np.abs(eig[:, None] - expected[None, :])
    r, c = linear_sum_assignment(distance)
    # eigenvalues of order 1-50 rad/s; 1e-8 * Omega is round-off with a wide margin
    assert distance[r, c].max() < 1e-8 * speed, (eig, expected)


def quartic_unstable_ranges(lo, hi, lag_stiffness=0.0):
    def imag_max(w):
        return np.abs(quartic_roots(w, lag_stiffness).imag).max() / w - 1e-9

    grid = np.linspace(lo, hi, 4001)
    vals = np.array([imag_max(w) for w in grid])
    ranges, inside, start = [], False, None
    for i in range(1, len(grid)):
        if vals[i] > 0 and not inside:
            start, inside = brentq(imag_max, grid[i - 1], grid[i], xtol=1e-12), True
        elif vals[i] <= 0 and inside:
            ranges.append((start, brentq(imag_max, grid[i - 1], grid[i], xtol=1e-12)))
            inside = False
    return ranges


@pytest.mark.parametrize("lag_stiffness", [0.0, 3e5])
def test_unstable_range_matches_the_quartic(lag_stiffness):
    result = analyze(isotropic_case(lag_stiffness))
    expected = quartic_unstable_ranges(2.0, 45.0, lag_stiffness)
    got = result.stability.unstable_ranges
    assert len(got) == len(expected) == 1
    # the ends are found by root finding on the largest real part, to 1e-9
    # relative; undamped growth rises like sqrt(W - W_end), so the 1e-6/rad
    # threshold moves an end by far less than 1e-6 relative
    np.testing.assert_allclose(got, expected, rtol=1e-6)
