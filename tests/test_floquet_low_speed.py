"""Floquet analysis at low rotor speed and at rest: the lifted problem for
periods over which the roots span many decades, and the rotor at rest."""

import numpy as np
import pytest

from conftest import make_case
from groundres import analyze
from groundres.errors import SpeedRangeError
from groundres.model.system import System
from groundres.solve import modal
from groundres.solve.floquet import exponents

ISOTROPIC = dict(mass_y=8026.6, damping_y=51078.7)


def reference(system, speeds, frame):
    """Eigenvalues of the time-invariant form (multiblade or rotating axes)."""
    mats = system.multiblade(speeds) if frame == "multiblade" else system.rotating_axes(speeds)
    return np.linalg.eigvals(modal.state_matrix(*mats))


@pytest.mark.parametrize(
    "case, frame",
    [
        (make_case(), "multiblade"),
        (make_case(n_blades=2, body=ISOTROPIC), "rotating"),
        (make_case(n_blades=3, blade=dict(lag_damping=40675.0)), "multiblade"),
    ],
    ids=["4 blades", "2 blades, isotropic hub", "3 blades, ten times the lag damping"],
)
@pytest.mark.parametrize("speed", [0.1, 0.3])
def test_lifted_real_parts_equal_the_time_invariant_ones(case, frame, speed):
    """At 0.1 and 0.3 rad/s a period is 20 to 60 s and the roots span up to
    e^2400 over it: the real parts (which are unique) equal the time-invariant
    ones root for root, to 1e-7 of the largest (the lifted problem keeps every
    part within e^14), including the overdamped roots with negative
    multipliers that have two K-th roots on the edge of the sector."""
    system = System(case.rotor, case.body)
    fs = exponents.solve(system, np.array([speed]), harmonics=0)
    assert fs.lifted.all()
    ours = np.sort(fs.exponent[0].real)
    theirs = np.sort(reference(system, np.array([speed]), frame)[0].real)
    np.testing.assert_allclose(ours, theirs, rtol=0, atol=1e-7 * np.abs(theirs).max())


def test_a_speed_too_slow_to_resolve_is_refused_with_the_reason():
    """Body damping 5e5 N s/m at 0.1 rad/s: the roots span about 3700 e-folds
    in one period, beyond the lifted problem's size: a clear error, not
    wrong roots."""
    case = make_case(n_blades=3, body=dict(damping_x=5e5, damping_y=5e5))
    with pytest.raises(SpeedRangeError, match="e-folds"):
        exponents.solve(System(case.rotor, case.body), np.array([0.1]), harmonics=0)


@pytest.mark.parametrize("points", [13, 40])
def test_floquet_from_the_rotor_at_rest(points):
    """start = 0: the rotor at rest is solved as it is; just above it the
    periods are long and the lifted problem keeps the damped roots. Identical
    blades, so the multiblade eigen-analysis is the reference at every speed;
    the pairs of real roots at rest (a degenerate cluster) do not decide the
    pairs that follow."""
    case = make_case(sweep=(0.0, 12.0, points))
    eigen = analyze(case)
    flq = analyze(case, method="floquet")
    assert flq.labels == eigen.labels
    # 1e-8 of the root's size (at 0.3 rad/s a period is 20 s and the damped
    # roots come from the lifted problem, to about 1e-7 1/s)
    size = np.maximum(np.abs(eigen.modes.eigenvalue), np.maximum(eigen.rotor_speed, 1.0)[:, None])
    for field in ("frequency_nonrotating", "real_part", "damping_ratio"):
        a, b = getattr(eigen.modes, field), getattr(flq.modes, field)
        both = np.isfinite(a) & np.isfinite(b)
        assert (np.isfinite(a) == np.isfinite(b)).all(), field
        assert (np.abs(a - b)[both] <= 1e-8 * size[both]).all(), field
    assert flq.modes.real_part[1].min() < -3.0  # damped roots survived the long periods


@pytest.mark.parametrize("method", ["auto", "floquet"])
def test_neutral_roots_at_rest_are_not_an_instability(method):
    """An articulated rotor at rest has zero roots (free hinges); round-off
    puts them at +1e-16, which must not count as growth."""
    case = make_case(n_blades=3, flap=True, blade=dict(flap_stiffness=1e5), sweep=(0.0, 12.0, 13))
    result = analyze(case, method=method)
    assert result.stability.stable and result.summary()["stable"]


def test_a_single_speed_at_rest():
    result = analyze(make_case(), speeds=[0.0])
    assert result.modes.frequency_nonrotating.shape == (1, 6)
    assert result.stability.stable
