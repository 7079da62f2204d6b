"""Multiblade transform: round trip, time invariance, decoupling."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from conftest import make_case
from groundres.model import mbc
from groundres.model.system import System


@given(n=st.integers(2, 12), phase=st.floats(-10, 10))
@settings(max_examples=60, deadline=None)
def test_round_trip(n, phase):
    """Blade -> multiblade -> blade gives back the blade motion (the basis is invertible)."""
    basis, _, _ = mbc.multiblade_basis(n, phase)
    q = np.random.default_rng(n).normal(size=n)
    p = np.linalg.solve(basis, q)
    np.testing.assert_allclose(basis @ p, q, atol=1e-12)
    # the explicit inverse: 1/N, 2/N cos, 2/N sin, 1/N (-1)^(k-1)
    scale = np.array([1.0 if name in ("0", "d") else 2.0 for name, _ in mbc.multiblade_names(n)]) / n
    np.testing.assert_allclose((basis.T * scale[:, None]) @ basis, np.eye(n), atol=1e-12)


@given(phase=st.floats(0, 2 * np.pi))
@settings(max_examples=20, deadline=None)
def test_derivatives_match_finite_differences(phase):
    # central differences: truncation ~ h^2 n^4/12, round-off ~ 1e-16/h^2
    h = 1e-4
    b0, d1, d2 = mbc.multiblade_basis(5, phase)
    bp, _, _ = mbc.multiblade_basis(5, phase + h)
    bm, _, _ = mbc.multiblade_basis(5, phase - h)
    np.testing.assert_allclose((bp - bm) / (2 * h), d1, atol=1e-6)
    np.testing.assert_allclose((bp - 2 * b0 + bm) / h**2, d2, atol=1e-6)


def test_multiblade_equations_are_time_invariant_for_n_at_least_3():
    for n in (3, 4, 5, 6):
        system = System(
            *_rotor_body(
                make_case(
                    n_blades=n,
                    flap=True,
                    dofs=("x", "y", "pitch", "roll"),
                    body=dict(
                        inertia_pitch=2e4,
                        inertia_roll=8e3,
                        stiffness_pitch=3e6,
                        stiffness_roll=2e6,
                        hub_height=1.5,
                    ),
                )
            )
        )
        speeds = np.array([5.0, 20.0, 35.0])
        a = system.multiblade(speeds, 0.0)
        b = system.multiblade(speeds, 1.234)
        assert np.abs(a - b).max() <= 1e-9 * np.abs(a).max()


def test_two_bladed_rotor_stays_periodic_in_multiblade_coordinates():
    system = System(*_rotor_body(make_case(n_blades=2)))
    speeds = np.array([20.0])
    a = system.multiblade(speeds, 0.0)
    b = system.multiblade(speeds, 0.7)
    assert np.abs(a - b).max() > 1e-3 * np.abs(a).max()


def test_rotating_axes_are_time_invariant_for_an_isotropic_hub_and_any_blades():
    case = make_case(n_blades=2, body=dict(mass_y=8026.6, damping_y=51078.7))
    rotor = case.rotor.with_blade(1, lag_damping=0.0)
    system = System(rotor, case.body)
    speeds = np.array([10.0, 25.0])
    a = system.rotating_axes(speeds, 0.0)
    b = system.rotating_axes(speeds, 2.1)
    assert np.abs(a - b).max() <= 1e-9 * np.abs(a).max()


def _rotor_body(case):
    return case.rotor, case.body
