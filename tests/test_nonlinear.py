"""Nonlinear time simulation with the damper laws (issue 26, item 5) against the limit cycles
predicted from describing functions (item 3).

The simulation integrates the periodic blade equations with each law's moment on its blade
(solve/nonlinear.py); it shares with the prediction only the case. Started along the
predicted cycle's motion (assess/limit_cycles.disturbance), below and above it:

* a stable cycle (a progressive bilinear damper, c1 below the critical damping, c2 above)
  is reached from both sides; the settled amplitude, measured as the prediction measures it
  (the largest component of a blade's lag in the rotating frame, least squares over the last
  quarter of the run), agrees to 1 %: the describing function's single harmonic leaves the
  second component (its ratio, 0.9 % here, also compared) and the law's harmonics out;
* an unstable cycle (a relief valve, c1 above, c2 below) is a threshold: 0.8 times it decays,
  1.25 times it grows;
* a linear law integrates exactly as the linear equations with lag_damping do;
* with one damper failed (the Floquet route, each blade at its own amplitude), the stable
  cycle is reached from both sides with every blade's amplitude and the hub's as predicted,
  each law dissipates per cycle the energy its describing function says at the amplitude the
  simulation settles on, and a threshold is bracketed.
"""

import math
import tomllib

import numpy as np
import pytest

from groundres.assess import confirm, limit_cycles
from groundres.model.casefile import case_text
from groundres.model.schema import parse_case
from groundres.model.system import System
from groundres.solve import nonlinear, simulate

SPEED = 260 * 2 * math.pi / 60


def _case(law: str):
    text, source = case_text("hammond-1974")
    text = text.replace("lag_damping = 4067.5           # [N m s/rad]", "") + "\n[rotor.lag_damper]\n" + law
    return parse_case(tomllib.loads(text), source, text)


def _settled(history, fraction=0.25):
    late = history.time >= history.time[-1] * (1 - fraction)
    return nonlinear.components(history.time[late], history.lag(1)[late])


@pytest.fixture(scope="module")
def progressive():
    case = _case('law = "bilinear"\ndamping = 300.0\nrelief_moment = 60.0\ndamping_after_relief = 4000.0\n')
    (cycle,) = limit_cycles.predict(case, [SPEED]).cycles
    return case, cycle


@pytest.mark.parametrize("factor", [0.5, 1.5])
def test_a_stable_cycle_is_reached_from_below_and_above(progressive, factor):
    case, cycle = progressive
    assert cycle.stable
    history = nonlinear.integrate(
        case, SPEED, 40.0, limit_cycles.disturbance(nonlinear.structure(case), cycle, factor)
    )
    (w, a), (w2, a2) = _settled(history)
    assert a == pytest.approx(cycle.amplitude, rel=0.01)
    assert w == pytest.approx(cycle.frequency, rel=1e-3)
    assert a2 / a == pytest.approx(cycle.second_component, rel=0.1)
    names = [c.short for c in history.coordinates]
    late = history.time >= 30.0
    for dof in ("x", "y"):
        ((_, hub),) = nonlinear.components(
            history.time[late], history.displacement[late, names.index(dof)], 1
        )
        assert hub == pytest.approx(cycle.hub[dof], rel=0.02)


def test_an_unstable_cycle_is_a_threshold_bracketed_by_simulation():
    """The threshold search starts the equations at 0.8 and 1.25 times the predicted unstable
    cycle (the first decays, the second grows) and bisects twice: the bracket holds the
    prediction (factor 1) to within the describing function's error."""
    case = _case('law = "bilinear"\ndamping = 4067.5\nrelief_moment = 813.5\ndamping_after_relief = 200.0\n')
    (cycle,) = limit_cycles.predict(case, [SPEED]).cycles
    assert not cycle.stable
    decays, grows = confirm.bracket_threshold(case, cycle, steps=2, duration=20.0)
    assert 0.8 <= decays < grows <= 1.25
    assert decays <= 1.02 and grows >= 0.98
    assert grows / decays == pytest.approx(math.sqrt(math.sqrt(1.25 / 0.8)), rel=1e-12)


def test_a_linear_law_integrates_as_the_linear_equations():
    case = _case('law = "linear"\ndamping = 4067.5\n')
    text, source = case_text("hammond-1974")
    linear = parse_case(tomllib.loads(text), source, text)
    system = System.in_mass_unit(linear.rotor, linear.body)
    q0 = np.zeros(system.size)
    q0[[c.short for c in system.coordinates].index("lag1")] = 0.02
    q0[0] = 0.01
    start = (q0, np.zeros(system.size))
    ours = nonlinear.integrate(case, SPEED, 5.0, start, rtol=1e-11, points=500)
    theirs = simulate.integrate(system, SPEED, 5.0, start, rtol=1e-11, points=500)
    scale = np.abs(theirs.displacement).max(axis=0)
    np.testing.assert_allclose(ours.displacement / scale, theirs.displacement / scale, atol=1e-7)
    assert ours.method == "DOP853"


def test_components_finds_two_sinusoids_and_their_amplitudes():
    t = np.linspace(0.0, 30.0, 6001)
    x = 0.3 + 2.0 * np.cos(7.3 * t + 0.4) + 0.05 * np.sin(41.7 * t)
    (w1, a1), (w2, a2) = nonlinear.components(t, x)
    assert (w1, a1) == pytest.approx((7.3, 2.0), rel=1e-6)
    assert (w2, a2) == pytest.approx((41.7, 0.05), rel=1e-4)


@pytest.mark.parametrize("law", ["bilinear", "friction", "tanh", "friction-link"])
def test_the_jacobian_of_the_equations_is_their_derivative(law):
    """Equations.jacobian (what the implicit integration is given) against central differences of
    Equations.rhs, at a state where the bilinear damper has relieved and the link slips."""
    from test_damper_laws import LAWS

    keys = LAWS[law]
    table = "\n".join(f"{k} = {v!r}".replace("'", '"') for k, v in keys.items()) + "\n"
    equations = nonlinear.Equations(_case(table), SPEED)
    n, n_s = equations.n, len(equations.sliders)
    rng = np.random.default_rng(2)
    x = np.concatenate([rng.normal(0, 0.02, n), rng.normal(0, 0.5, n), rng.normal(0, 0.001, n_s)])
    lag1 = [c.short for c in equations.system.coordinates].index("lag1")
    x[n + lag1] = 0.4  # (blade 1's lag rate beyond the bilinear knee; its link slipping)
    x[lag1] = 0.02
    t = 0.37
    exact = equations.jacobian(t, x)
    step = 1e-7 * np.maximum(np.abs(x), 1e-3)
    numeric = np.stack(
        [
            (equations.rhs(t, x + h * e) - equations.rhs(t, x - h * e)) / (2 * h)
            for h, e in zip(step, np.eye(len(x)))
        ],
        axis=1,
    )
    np.testing.assert_allclose(exact, numeric, rtol=1e-5, atol=1e-6 * np.abs(numeric).max())


def test_the_friction_link_settles_on_its_stable_cycle_implicitly():
    """hammond-friction-link at the speed of its largest stable cycle: the stiff slider takes
    the implicit path; from 1.5 times the cycle the settled amplitude agrees to 1.5 % (the
    describing function is the ideal slider's: the regularised one slips c_reg A w / F = 0.24 %
    above it, and the single harmonic leaves the rest)."""
    from groundres import limit_cycles as pipeline
    from groundres.model.schema import load_case

    case = load_case("hammond-friction-link")
    cycle = pipeline(case, linear=False).largest_stable()
    history = nonlinear.integrate(
        case, cycle.speed, 30.0, limit_cycles.disturbance(nonlinear.structure(case), cycle, 1.5)
    )
    assert history.method == "Radau"
    (w, a), *_ = _settled(history)
    assert a == pytest.approx(cycle.amplitude, rel=0.015)
    assert w == pytest.approx(cycle.frequency, rel=2e-3)


FAILED = '\n[[rotor.blade]]\nindex = 1\nlag_damper = "failed"\n'


@pytest.fixture(scope="module")
def failed_progressive():
    """A progressive damper (c1 300, c2 12000 N m s/rad) with blade 1's failed, at 350 rpm: the
    failed blade's motion grows until its neighbours' dampers are on their steep slope."""
    speed = 350 * 2 * math.pi / 60
    law = 'law = "bilinear"\ndamping = 300.0\nrelief_moment = 60.0\ndamping_after_relief = 12000.0\n'
    case = _case(law + FAILED)
    (cycle,) = limit_cycles.predict(case, [speed]).cycles
    return case, cycle


@pytest.mark.parametrize("factor", [0.6, 1.4])
def test_with_a_failed_damper_every_blade_settles_on_its_own_predicted_amplitude(failed_progressive, factor):
    """Blade 1 (failed) swings at about 1.5 times its neighbours. The settled amplitudes agree with
    the prediction to 2.5 % (measured 1.6 % at most, the law's third harmonic that the single-
    harmonic describing function leaves out), the frequency to 0.3 %, the hub to 2.5 %. And each
    working blade's law dissipates, per cycle, pi c_eq w A^2 of its describing function at the
    simulated amplitude and frequency, to 1 %: the energy balance of the settled cycle."""
    from groundres.model.describing import equivalent

    case, cycle = failed_progressive
    assert cycle.stable and cycle.dissimilar
    history = nonlinear.integrate(
        case, cycle.speed, 40.0, limit_cycles.disturbance(nonlinear.structure(case), cycle, factor)
    )
    late = history.time >= 30.0
    names = [c.short for c in history.coordinates]
    law = case.rotor.lag_laws[1].law
    for k, predicted in enumerate(cycle.blades, start=1):
        (w, a), _ = nonlinear.components(history.time[late], history.lag(k)[late])
        assert a == pytest.approx(predicted.amplitude, rel=0.025)
        assert w == pytest.approx(predicted.frequency, rel=3e-3)
        if predicted.damping is None:
            continue
        rate = history.velocity[late, names.index(f"lag{k}")]
        power = np.mean(law.moment(history.lag(k)[late], rate) * rate)  # (over many cycles)
        c_eq, _ = equivalent(law, a, w)
        assert power * 2 * math.pi / w == pytest.approx(math.pi * float(c_eq) * w * a * a, rel=0.01)
    for dof in ("x", "y"):  # (the hub at its largest component's frequency: 25.05 vs 25.07 rad/s)
        (w, hub), (_, second) = nonlinear.components(
            history.time[late], history.displacement[late, names.index(dof)], 2
        )
        assert hub == pytest.approx(cycle.hub[dof], rel=0.025)
        assert w == pytest.approx(cycle.nonrotating_frequency, rel=3e-3)
        assert cycle.nonrotating_second is None and second < 0.2 * hub


def test_with_a_failed_damper_a_threshold_is_bracketed_by_simulation():
    """Relief valves with blade 1's failed, at 330 rpm: the failed blade's cycle of about 3.4 deg
    is a threshold; 0.8 times it decays and 1.25 times it grows (judged on blade 1)."""
    law = 'law = "bilinear"\ndamping = 4067.5\nrelief_moment = 813.5\ndamping_after_relief = 406.75\n'
    case = _case(law + FAILED)
    (cycle,) = limit_cycles.predict(case, [330 * 2 * math.pi / 60]).cycles
    assert not cycle.stable and cycle.blades[0].amplitude == max(b.amplitude for b in cycle.blades)
    assert confirm.bracket_threshold(case, cycle, steps=0, duration=20.0) == (0.8, 1.25)
