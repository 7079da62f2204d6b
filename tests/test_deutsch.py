"""Deutsch criterion against the exact minimum lag damping from the eigenvalues.

Scaling the blade static moment S by eps (and the hinge offset by 1/eps, so
that nu stays the same) and the body damping by eps makes all damping light as
eps -> 0, where the criterion becomes exact. At eps = 0.1 the damping is light
enough for 1 % (measured: 0.02 %); the bisection runs to 1e-4.
"""

import numpy as np
import pytest

from groundres import Blade, Body, Case, Rotor, Sweep, analyze

N, INERTIA, M_BLADE = 4, 1084.7, 94.9
M, K = 8026.6, 1240481.8


def light_case(eps, isotropic):
    s, e = 289.1 * eps, 0.3048 / eps
    cx = 51078.7 * eps
    blade = Blade(M_BLADE, s, INERTIA, e, 0.0, 1.0)
    if isotropic:
        body = Body(("x", "y"), mass_x=M, mass_y=M, stiffness_x=K, stiffness_y=K, damping_x=cx, damping_y=cx)
    else:
        body = Body(("x",), mass_x=M, stiffness_x=K, damping_x=cx)
    wb = np.sqrt(K / (M + N * M_BLADE))
    tuning = wb / (1 - np.sqrt(e * s / INERTIA))
    return Case(Rotor.uniform(N, blade), body, Sweep(0.7 * tuning, 1.3 * tuning, 300))


@pytest.mark.parametrize("isotropic", [False, True])
def test_deutsch_approaches_the_exact_minimum_for_light_damping(isotropic):
    result = analyze(light_case(0.1, isotropic))
    (entry,) = result.deutsch
    assert entry.form == ("isotropic" if isotropic else "planar")
    assert np.isclose(result.exact_lag_damping, entry.required_lag_damping, rtol=0.01)


def test_isotropic_needs_twice_the_planar_damping():
    planar = analyze(light_case(0.1, False)).deutsch[0].required_lag_damping
    iso = analyze(light_case(0.1, True)).deutsch[0].required_lag_damping
    assert np.isclose(iso, 2 * planar, rtol=1e-12)


def test_no_body_damping_needs_infinite_lag_damping():
    case = light_case(1.0, False)
    body = Body(("x",), mass_x=M, stiffness_x=K, damping_x=0.0)
    result = analyze(Case(case.rotor, body, case.sweep))
    assert np.isinf(result.deutsch[0].required_lag_damping)
    assert result.exact_lag_damping is None
