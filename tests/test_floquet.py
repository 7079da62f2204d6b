"""Floquet analysis: monodromy accuracy, the symmetry shortcut, frequency
identification, and agreement with the eigen-analyses and a time simulation."""

from dataclasses import replace

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import linear_sum_assignment

from conftest import PITCH_ROLL, make_case
from groundres import analyze
from groundres.model.system import System
from groundres.solve import modal, simulate
from groundres.solve.floquet import exponents


def one_damper(case, blade=1):
    return replace(case, rotor=case.rotor.with_blade(blade, lag_damping=0.0))


CASES = {
    "four blades, one damper inoperative": lambda: one_damper(make_case()),
    "two blades, anisotropic hub": lambda: make_case(n_blades=2),
    "three blades with flap, one stiffer": lambda: replace(
        make_case(n_blades=3, flap=True, blade=dict(lag_stiffness=2e5, flap_stiffness=1e5)),
        rotor=make_case(
            n_blades=3, flap=True, blade=dict(lag_stiffness=2e5, flap_stiffness=1e5)
        ).rotor.with_blade(2, lag_stiffness=3e5),
    ),
    "pitch, roll, x, y with flap, one damper inoperative": lambda: one_damper(
        make_case(flap=True, dofs=("pitch", "roll", "x", "y"), body=PITCH_ROLL)
    ),
}


def reference_monodromy(system, speed):
    """Full-revolution transition matrix of [q; q'] by DOP853 at rtol 1e-13 (time domain)."""
    harmonics = system.blade_harmonics(np.array([speed]))
    n = system.size

    def rhs(t, y):
        m, c, k = system.matrices(np.array([speed]), np.array([speed * t]), harmonics)[:, 0]
        return (modal.state_matrix(m, c, k) @ y.reshape(2 * n, 2 * n)).ravel()

    sol = solve_ivp(
        rhs, (0, 2 * np.pi / speed), np.eye(2 * n).ravel(), method="DOP853", rtol=1e-13, atol=1e-14
    )
    return sol.y[:, -1].reshape(2 * n, 2 * n)


def matched(a, b):
    """Distances of an optimal one-to-one match of two sets of complex numbers."""
    d = np.abs(a[:, None] - b[None, :])
    r, c = linear_sum_assignment(d)
    return d[r, c]


@pytest.mark.parametrize("name", CASES)
@pytest.mark.parametrize("speed", [4.0, 15.0, 30.0])
@pytest.mark.parametrize("compiled", [True, False], ids=["compiled kernel", "numpy"])
def test_multipliers_to_1e_9_against_a_tight_reference(name, speed, compiled):
    system = System(CASES[name]().rotor, CASES[name]().body)
    ours = np.linalg.eigvals(exponents.monodromy(system, np.array([speed]), compiled=compiled)[0])
    ref = np.linalg.eigvals(reference_monodromy(system, speed))
    assert matched(ours, ref).max() <= 1e-9 * max(1.0, np.abs(ref).max())


@pytest.mark.parametrize("n_blades", [2, 3, 4, 5])
def test_identical_blades_repeat_every_1_over_n_revolution(n_blades):
    system = System(make_case(n_blades=n_blades).rotor, make_case().body)
    sym = exponents.symmetry(system)
    assert sym.shift == 1 and np.isclose(sym.angle, 2 * np.pi / n_blades)
    speed, psi = np.array([17.0]), 0.37
    now = system.matrices(speed, np.array([psi]))[:, 0]
    later = system.matrices(speed, np.array([psi + sym.angle]))[:, 0]
    for a, b in zip(now, later):
        np.testing.assert_allclose(sym.g.T @ b @ sym.g, a, atol=1e-9 * np.abs(a).max())


def test_a_failed_damper_leaves_no_shortcut():
    system = System(one_damper(make_case()).rotor, make_case().body)
    assert exponents.symmetry(system).shift == 4


@pytest.mark.parametrize(
    "case",
    [
        make_case(sweep=(3.0, 42.0, 80)),
        make_case(
            n_blades=3, flap=True, blade=dict(lag_stiffness=2e5, flap_stiffness=1e5), sweep=(3.0, 42.0, 80)
        ),
    ],
    ids=["hammond", "three blades with flap"],
)
def test_floquet_equals_multiblade_eigen_for_identical_blades(case):
    eigen = analyze(case)
    flq = analyze(case, method="floquet")
    assert eigen.method == "multiblade-eigen" and flq.method == "floquet"
    assert flq.labels == eigen.labels
    # real parts to 1e-8 [1/s]; frequencies after identification to 1e-8 relative
    np.testing.assert_allclose(flq.real_part, eigen.real_part, rtol=0, atol=1e-8)
    np.testing.assert_allclose(flq.frequency, eigen.frequency, rtol=1e-8, atol=1e-8)
    np.testing.assert_allclose(flq.stability.unstable_ranges, eigen.stability.unstable_ranges, rtol=1e-7)


@pytest.mark.parametrize("n_blades", [2, 4])
def test_floquet_equals_rotating_axes_eigen_for_an_isotropic_hub(n_blades):
    case = one_damper(
        make_case(n_blades=n_blades, body=dict(mass_y=8026.6, damping_y=51078.7), sweep=(3.0, 42.0, 60))
    )
    eigen = analyze(case)
    flq = analyze(case, method="floquet")
    assert eigen.method == "rotating-eigen" and flq.method == "floquet"
    system = System(case.rotor, case.body)
    speeds = eigen.rotor_speed
    roots = np.linalg.eigvals(modal.state_matrix(*system.rotating_axes(speeds)))
    floquet_exponents = exponents.solve(system, speeds, harmonics=0).exponent
    for i, w in enumerate(speeds):
        # the roots: real parts to 1e-8, imaginary parts equal modulo Omega
        d_re = np.abs(roots[i].real[:, None] - floquet_exponents[i].real[None, :])
        k = (roots[i].imag[:, None] - floquet_exponents[i].imag[None, :]) / w
        r, c = linear_sum_assignment(d_re + w * np.abs(k - np.round(k)))
        assert d_re[r, c].max() < 1e-8 and np.abs(k - np.round(k))[r, c].max() < 1e-8
        # frequencies identified from the harmonics agree in both frames for every
        # mode whose dominant harmonic is clear (an overdamped root at zero
        # frequency in one frame splits evenly between harmonics in the other)
        clear = eigen.modes.participation[i].max(-1) > 0.55
        for frame in ("frequency_nonrotating", "frequency_rotating"):
            fa, fb = getattr(eigen.modes, frame)[i], getattr(flq.modes, frame)[i]
            assert np.abs(fa[clear][:, None] - fb[None, :]).min(1).max() < 1e-7 * w
    np.testing.assert_allclose(flq.stability.unstable_ranges, eigen.stability.unstable_ranges, rtol=1e-7)


def test_two_opposite_working_dampers_give_minus_c_over_2i():
    """Blade 1 without damper: blades 2 and 4 (opposite, both damped) moving
    together shift no mass and keep the single-blade root -C/(2I) +- i sqrt(...)."""
    case = one_damper(make_case())
    system = System(case.rotor, case.body)
    b = case.rotor.blades[1]
    sigma = b.lag_damping / (2 * b.blade_inertia)
    for speed in (10.0, 25.0, 40.0):
        floquet_exponents = exponents.solve(system, np.array([speed]), harmonics=0).exponent[0]
        nu_w = b.lag_frequency(speed) * speed
        expected = -sigma + 1j * np.sqrt(nu_w**2 - sigma**2)
        k = (floquet_exponents.imag - expected.imag) / speed
        distance = np.abs(floquet_exponents.real - expected.real) + speed * np.abs(k - np.round(k))
        assert distance.min() < 1e-8


@pytest.mark.parametrize("speed", [24.0, 28.0])
def test_simulated_growth_matches_the_largest_exponent(speed):
    """A time simulation (DOP853) of the periodic equations grows at max Re(lambda), to 1 %."""
    case = one_damper(make_case())
    system = System(case.rotor, case.body)
    predicted = exponents.solve(system, np.array([speed]), harmonics=0).exponent.real.max()
    assert predicted > 0.05  # inside the unstable range: one mode dominates
    start = simulate.initial_state(system, {"x": 0.01, "y": 0.01, "lag1": 0.01})
    run = simulate.integrate(system, speed, 40.0, start, rtol=1e-9)
    assert run.growth_rate() == pytest.approx(predicted, rel=0.01)


def test_identified_frequencies_follow_the_dominant_harmonic():
    """In the unstable range of the failed-damper case the growing mode is the
    regressive lag coalescing with body y: seen from nonrotating axes it
    whirls at about Omega (1 - nu), and its harmonic of largest share says so."""
    result = analyze(one_damper(make_case(sweep=(24.0, 30.0, 13))))
    w = result.rotor_speed
    i = np.argmax(result.real_part, axis=1)
    f = result.frequency[np.arange(len(w)), i]
    nu = result.case.rotor.blades[0].lag_frequency(w)
    np.testing.assert_allclose(f, w * (1 - nu), rtol=0.15)
    share = result.modes.participation[np.arange(len(w)), i].max(-1)
    assert (share > 0.4).all()
