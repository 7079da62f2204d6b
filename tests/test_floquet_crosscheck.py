"""Multiblade eigenvalues against Floquet exponents of the untransformed equations.

The blade-coordinate equations have periodic coefficients. Their transition
matrix over one revolution is integrated here with SciPy's DOP853 at tight
tolerance, independently of the multiblade transform; its eigenvalues
(multipliers) give exponents lambda = ln(mu)/T, unique in real part and unique
in imaginary part only up to multiples of Omega. Every multiblade eigenvalue
must appear among them.
"""

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import linear_sum_assignment

from conftest import PITCH_ROLL, make_case
from groundres.model.system import System
from groundres.solve import modal


def floquet_exponents(system, speed):
    harmonics = system.blade_harmonics(np.array([speed]))
    n = system.size

    def rhs(t, y):
        m, c, k = system.matrices(np.array([speed]), np.array([speed * t]), harmonics)[:, 0]
        a = modal.state_matrix(m, c, k)
        return (a @ y.reshape(2 * n, 2 * n)).ravel()

    period = 2 * np.pi / speed
    sol = solve_ivp(rhs, (0, period), np.eye(2 * n).ravel(), method="DOP853", rtol=1e-12, atol=1e-13)
    multipliers = np.linalg.eigvals(sol.y[:, -1].reshape(2 * n, 2 * n))
    return np.log(multipliers.astype(complex)) / period


def multiblade_eigenvalues(system, speed):
    mats = system.multiblade(np.array([speed]))
    return np.linalg.eigvals(modal.state_matrix(*mats[:, 0]))


def match(eigen, floquet, speed):
    """Optimal one-to-one match; distance = |d Re| + Omega * distance of d Im / Omega to an integer."""
    d_re = np.abs(eigen.real[:, None] - floquet.real[None, :])
    k = (eigen.imag[:, None] - floquet.imag[None, :]) / speed
    cost = d_re + speed * np.abs(k - np.round(k))
    r, c = linear_sum_assignment(cost)
    return d_re[r, c], np.abs(k - np.round(k))[r, c]


CASES = {
    "hammond, damped": dict(),
    "hammond, one lag damper weak": dict(blade=dict(lag_damping=300.0)),
    "three blades, flap, soft in-plane": dict(
        n_blades=3, flap=True, blade=dict(lag_stiffness=2e5, flap_stiffness=1e5, flap_damping=500.0)
    ),
    "five blades, hub x only": dict(n_blades=5, dofs=("x",)),
    "four blades, pitch and roll with flap": dict(
        flap=True,
        dofs=("pitch", "roll"),
        body=PITCH_ROLL,
    ),
}


@pytest.mark.parametrize("name", CASES)
@pytest.mark.parametrize("speed", [8.0, 21.0, 33.0])
def test_multiblade_eigenvalues_are_floquet_exponents(name, speed):
    case = make_case(**CASES[name])
    system = System(case.rotor, case.body)
    eigen = multiblade_eigenvalues(system, speed)
    floquet = floquet_exponents(system, speed)
    d_re, d_im = match(eigen, floquet, speed)
    # Monodromy from DOP853 at rtol 1e-12 gives multipliers to ~1e-10, i.e.
    # exponents to ~1e-10/T; 1e-8 (1/s) leaves a margin of about 50.
    assert d_re.max() < 1e-8
    assert d_im.max() < 1e-8
