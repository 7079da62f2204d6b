"""Symbolic derivation checked against hand-derived matrices (exact, SymPy)."""

import numpy as np
import pytest
import sympy as sp

from groundres.symbolic.codegen import BLADE_ARGUMENTS, blade_equations, blade_function
from groundres.symbolic.derive import BLADE_SYMBOLS, BODY_SYMBOLS, LOCAL_DOFS, rotor_speed
from groundres.symbolic.multiblade import multiblade_equations

B, BO, W = BLADE_SYMBOLS, BODY_SYMBOLS, rotor_speed


@pytest.fixture(scope="module")
def equations():
    return blade_equations()


def hand_derived(n):
    """physics.md: q = [lag_1c, lag_1s, x, y], lag rows times N/2, total masses."""
    m, s, i, e = B["blade_mass"], B["blade_static_moment"], B["blade_inertia"], B["hinge_offset"]
    kz, cz = B["lag_stiffness"], B["lag_damping"]
    mx, my = BO["mass_x"] + n * m, BO["mass_y"] + n * m
    nu2 = kz / (i * W**2) + e * s / i
    mass = sp.Matrix(
        [
            [n * i / 2, 0, 0, -n * s / 2],
            [0, n * i / 2, n * s / 2, 0],
            [0, n * s / 2, mx, 0],
            [-n * s / 2, 0, 0, my],
        ]
    )
    damping = sp.Matrix(
        [
            [n * cz / 2, n * i * W, 0, 0],
            [-n * i * W, n * cz / 2, 0, 0],
            [0, 0, BO["damping_x"], 0],
            [0, 0, 0, BO["damping_y"]],
        ]
    )
    k = n * i * (nu2 - 1) * W**2 / 2
    stiffness = sp.Matrix(
        [
            [k, n * cz * W / 2, 0, 0],
            [-n * cz * W / 2, k, 0, 0],
            [0, 0, BO["stiffness_x"], 0],
            [0, 0, 0, BO["stiffness_y"]],
        ]
    )
    return mass, damping, stiffness


@pytest.mark.parametrize("n", [3, 4, 5, 6])
def test_multiblade_matrices_equal_hand_derived(equations, n):
    names, *mats = multiblade_equations(equations, n, ("x", "y"), False)
    idx = [names.index(c) for c in ("lag_1c", "lag_1s", "x", "y")]
    for derived, hand in zip(mats, hand_derived(n)):
        assert sp.simplify(derived.extract(idx, idx) - hand) == sp.zeros(4, 4)


@pytest.mark.parametrize("n", [3, 4, 5, 6])
def test_collective_differential_and_higher_cyclic_lag_decouple(equations, n):
    names, mass, damping, stiffness = multiblade_equations(equations, n, ("x", "y"), True)
    coupled = {"x", "y", "lag_1c", "lag_1s"}
    for i, a in enumerate(names):
        for j, b in enumerate(names):
            if (a in coupled) != (b in coupled):
                assert mass[i, j] == 0 and damping[i, j] == 0 and stiffness[i, j] == 0, (a, b)
    # collective lag: I z'' + C z' + (K + e S Omega^2) z = 0, times N
    k = names.index("lag_0")
    i_, s, e = B["blade_inertia"], B["blade_static_moment"], B["hinge_offset"]
    assert sp.simplify(mass[k, k] - n * i_) == 0
    assert sp.simplify(damping[k, k] - n * B["lag_damping"]) == 0
    assert sp.simplify(stiffness[k, k] - n * (B["lag_stiffness"] + e * s * W**2)) == 0


def test_rotating_blade_frequencies(equations):
    """Rigid body: nu_lag^2 = eS/I + K/(I W^2), nu_flap^2 = 1 + eS/I + K/(I W^2)."""
    lag, flap = LOCAL_DOFS.index("lag"), LOCAL_DOFS.index("flap")
    i_, s, e = B["blade_inertia"], B["blade_static_moment"], B["hinge_offset"]
    m0, k0 = equations.mass[0], equations.stiffness[0]
    nu_lag2 = sp.simplify(k0[lag, lag] / (m0[lag, lag] * W**2))
    nu_flap2 = sp.simplify(k0[flap, flap] / (m0[flap, flap] * W**2))
    assert sp.simplify(nu_lag2 - (e * s / i_ + B["lag_stiffness"] / (i_ * W**2))) == 0
    assert sp.simplify(nu_flap2 - (1 + e * s / i_ + B["flap_stiffness"] / (i_ * W**2))) == 0


def test_flap_does_not_couple_with_hub_translation(equations):
    flap = LOCAL_DOFS.index("flap")
    for group in (equations.mass, equations.damping, equations.stiffness):
        for mat in group:
            for body in (0, 1):
                assert mat[flap, body] == 0 and mat[body, flap] == 0


def test_generated_code_equals_symbolic(equations):
    rng = np.random.default_rng(1)
    values = dict(zip(BLADE_ARGUMENTS, rng.uniform(0.5, 3.0, len(BLADE_ARGUMENTS))))
    numeric = blade_function()(**values)
    subs = {W: values["rotor_speed"], **{B[k]: v for k, v in values.items() if k in B}}
    for g, group in enumerate((equations.mass, equations.damping, equations.stiffness)):
        for h, mat in enumerate(group):
            expected = np.array(mat.subs(subs).evalf(), dtype=float)
            np.testing.assert_allclose(numeric[g, h], expected, rtol=1e-13, atol=1e-12)
