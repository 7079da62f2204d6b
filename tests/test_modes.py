"""Mode labels, tracking and the decoupled blade modes."""

import numpy as np

from conftest import make_case
from groundres import analyze


def test_labels_follow_the_physics_through_a_crossing():
    """Weak coupling: regressive lag crosses body x; each label keeps its line."""
    case = make_case(
        dofs=("x",),
        blade=dict(blade_static_moment=20.0, hinge_offset=4.4, lag_damping=50.0),
        body=dict(damping_x=500.0),
        sweep=(2.0, 40.0, 400),
    )
    result = analyze(case)
    w = result.rotor_speed
    blade = case.rotor.blades[0]
    nu = blade.lag_frequency(w)
    wx = np.sqrt(case.body.stiffness_x / (case.body.mass_x + 4 * blade.blade_mass))
    crossings = (wx / (1 - nu[0]), wx / (1 + nu[0]))  # regressive and progressive lag meet body x
    away = np.all([np.abs(w - c) > 0.08 * c for c in crossings], axis=0)
    assert away.sum() > 250
    f = dict(zip(result.labels, result.frequency.T))
    np.testing.assert_allclose(f["regressive lag"][away], (w * (1 - nu))[away], rtol=0.02)
    np.testing.assert_allclose(f["progressive lag"][away], (w * (1 + nu))[away], rtol=0.02)
    np.testing.assert_allclose(f["body x"][away], wx, rtol=0.02)
    np.testing.assert_allclose(f["collective lag"], w * nu, rtol=1e-3)


def test_collective_and_differential_lag_eigenvalues():
    """-C/(2I) +- i sqrt((nu W)^2 - (C/2I)^2), uncoupled from the hub."""
    case = make_case(blade=dict(lag_stiffness=2e5))
    result = analyze(case)
    b = case.rotor.blades[0]
    w = result.rotor_speed
    sigma = b.lag_damping / (2 * b.blade_inertia)
    expected = -sigma + 1j * np.sqrt((b.lag_frequency(w) * w) ** 2 - sigma**2 + 0j)
    for label in ("collective lag", "differential lag"):
        lam = result.modes.eigenvalue[:, result.labels.index(label)]
        np.testing.assert_allclose(lam, expected, rtol=1e-9)


def test_every_label_once_and_flap_labels_with_flap():
    result = analyze(make_case(n_blades=5, flap=True))
    assert len(set(result.labels)) == len(result.labels) == 2 + 2 * 5
    for label in ("coning", "regressive flap", "progressive flap", "regressive lag 2", "progressive flap 2"):
        assert label in result.labels


def test_isotropic_hub_modes_are_whirls():
    result = analyze(make_case(body=dict(mass_y=8026.6, damping_y=51078.7)))
    assert "body forward whirl" in result.labels and "body backward whirl" in result.labels


def test_rotating_frame_frequencies():
    """Cyclic lag seen from the rotating frame is the rotating lag frequency nu W (uncoupled)."""
    case = make_case(
        dofs=("x",),
        blade=dict(blade_static_moment=5.0, hinge_offset=17.6, lag_damping=0.0),
        body=dict(damping_x=0.0),
        sweep=(30.0, 40.0, 20),
    )
    result = analyze(case)
    w = result.rotor_speed
    nu = case.rotor.blades[0].lag_frequency(w)
    f_rot = dict(zip(result.labels, result.modes.frequency_rotating.T))
    for label in ("regressive lag", "progressive lag", "collective lag"):
        np.testing.assert_allclose(f_rot[label], nu * w, rtol=1e-3)
