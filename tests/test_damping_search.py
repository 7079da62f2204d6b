"""The Floquet damping search against a brute-force bisection.

The search reuses one set of node matrices for every trial damping (the
equations are affine in it), looks only near the tuning speeds and the
unstable ranges, and follows the peaks it has seen. The brute force rebuilds
the system for each damping and scans the whole sweep on a uniform grid,
refined around its worst point: the search's answer must be stable by it,
and 2e-3 below it unstable (the search's bisection stops at 1e-3; a grid of
400 points then 200 around the worst spans the peak well within that).
"""

import tomllib
from importlib import resources

import numpy as np
import pytest

from groundres import analyze
from groundres.assess.stability import growth_threshold
from groundres.model.schema import parse_case
from groundres.model.system import System
from groundres.solve.floquet import exponents


def case(name, **body_scale):
    data = tomllib.loads((resources.files("groundres") / "cases" / f"{name}.toml").read_text())
    for key, factor in body_scale.items():
        data["body"][key] *= factor
    data["sweep"]["points"] = 60
    return parse_case(data)


def brute_force_excess(c, lag_damping):
    """Largest real part minus the threshold over the sweep by plain Floquet exponents of
    the system rebuilt with that lag damping: 400 uniform speeds, then 200 around the worst."""
    system = System.in_mass_unit(c.rotor, c.body)
    system = system.with_lag_damping(system.mass_unit.from_si(lag_damping))
    lo, hi = c.sweep.speeds[0], c.sweep.speeds[-1]

    def excess(w):
        return exponents.solve(system, w, harmonics=0, lift=False).exponent.real.max(-1) - growth_threshold(w)

    w = np.linspace(max(lo, 1e-3), hi, 400)
    top = w[np.argmax(excess(w))]
    near = np.linspace(max(lo, top - (w[1] - w[0])), min(hi, top + (w[1] - w[0])), 200)
    return max(excess(near).max(), excess(w).max())


@pytest.mark.slow
@pytest.mark.parametrize(
    "name, scale",
    [("two-bladed", {}), ("hammond-1974-one-damper", {"damping_x": 2.0, "damping_y": 2.0})],
    ids=["two blades", "one damper failed, stiffer hub damping"],
)
def test_floquet_search_equals_a_brute_force_bisection(name, scale):
    c = case(name, **scale)
    result = analyze(c, method="floquet")
    exact = result.exact_lag_damping
    assert result.method == "floquet" and exact is not None
    assert brute_force_excess(c, exact) <= 0
    assert brute_force_excess(c, exact * (1 - 2e-3)) > 0


@pytest.mark.slow
def test_no_damping_helps_a_failed_damper_and_the_search_says_so():
    """Hammond (1974) with one damper failed: the other three cannot stabilise
    the rotor; the search stops at its cap and names it, and the brute force
    finds the sweep unstable there too."""
    c = case("hammond-1974-one-damper")
    result = analyze(c)
    assert result.exact_lag_damping is None
    why, cap = result.no_exact_lag_damping
    assert why == "cap" and cap > 10 * 4067.5
    assert brute_force_excess(c, cap) > 0


@pytest.mark.parametrize("name", ["hammond-1974-one-damper", "soft-inplane-pitch-roll", "two-bladed"])
def test_a_rough_scan_bounds_the_growth_at_full_tolerance(name):
    """The damping search's scans look at SCAN_TOLERANCE; the bound they carry must hold
    the largest real part at the full tolerance (which decides), and be honest about
    the rough value's own error."""
    from groundres.assess.stability import growth_of, rough_growth_of
    from groundres.solve.solvers import Floquet

    c = case(name)
    system = System.in_mass_unit(c.rotor, c.body)
    solver = Floquet(system)
    w = np.linspace(c.sweep.speeds[1], c.sweep.speeds[-1], 24)
    for neutral in (True, False):
        value, lower, upper = rough_growth_of(solver)(w, neutral)
        exact = growth_of(solver)(w, neutral)
        assert np.all((lower <= exact) & (exact <= upper))
        assert np.all(np.abs(value - exact) <= np.minimum(upper - value, value - lower))
    rough = exponents.solve(system, w, harmonics=0, lift=False, tolerance=exponents.SCAN_TOLERANCE)
    full = exponents.solve(system, w, harmonics=0, lift=False)
    assert np.all(rough.steps <= full.steps)  # (the fewest steps allowed serve most speeds of both)


def test_zoom_with_a_rough_look_returns_values_of_the_exact_function():
    from groundres.assess.scan import zoom_many

    def exact(w):
        return -np.minimum((w - 3.1) ** 2, 0.5 * (w - 7.3) ** 2)

    def rough(w):  # (exact with an error far below the peaks' curvature over the bracket)
        return exact(w) + 1e-9 * np.sin(977.0 * w)

    found = zoom_many(exact, [(1.0, 5.0), (6.0, 9.0)], 1e-6, rough=rough)
    for (value, at), peak in zip(found, (3.1, 7.3)):
        assert value == exact(np.array([at]))[0]
        assert abs(at - peak) < 1e-3


def test_peak_watch_with_a_rough_look_reaches_the_same_verdicts():
    """Two peaks over speed, one rising with the parameter faster than the other; a
    rough look with a bounded error must give every full scan's verdict unchanged."""
    from groundres.assess.scan import PeakWatch

    def fun(p, w):
        w = np.asarray(w, float)
        return np.maximum(0.3 * p - 1 - 4 * (w - 2.0) ** 2, p - 2 - 9 * (w - 5.37) ** 2)

    def rough(p, w):
        err = 1e-4 * np.cos(31.0 * np.asarray(w, float))
        return fun(p, w) + err, fun(p, w) + err - 2e-4, fun(p, w) + err + 2e-4

    grid = np.linspace(0.5, 8.0, 16)
    plain_watch, rough_watch = PeakWatch(fun, grid, True), PeakWatch(fun, grid, True, rough=rough)
    for p in np.linspace(0.0, 4.0, 41):
        plain = PeakWatch(fun, grid, True).full(p)
        looked = PeakWatch(fun, grid, True, rough=rough).full(p)
        assert (plain > 0) == (looked > 0), p
        # and the watched peaks of a scan at the previous parameter
        assert (plain_watch.watched(p) > 0) == (rough_watch.watched(p) > 0), p
        plain_watch.full(p), rough_watch.full(p)


def test_a_periodic_search_stops_at_the_strongest_damper_a_floquet_scan_can_follow():
    """The Hammond rotor with one damper inoperative swept from 5 to 1e7 rpm: no lag damping
    on the working blades makes it stable, and the search's doubling damper soon makes the
    periodic equations too stiff for the integrator at the resonance (about 1e6 steps a period
    at 27 rad/s). The search stops at the strongest damper a scan can follow within the work
    limit, estimated before it is tried, and says so: the analysis ends in seconds with an
    answer instead of running on and refusing the whole sweep at a speed that is no fault of
    the sweep's start."""
    import time

    from groundres.results.summary import no_exact_reason

    text = resources.files("groundres.cases").joinpath("hammond-1974-one-damper.toml").read_text()
    data = tomllib.loads(text)
    data["sweep"].update(start=5.0, stop=1e7)
    started = time.perf_counter()
    result = analyze(parse_case(data))
    assert time.perf_counter() - started < 30  # (measured about 2 s alone on two cores)
    assert result.exact_lag_damping is None
    kind, value = result.no_exact_lag_damping
    assert kind == "afforded" and 1e5 < value < 1e7
    assert "cannot follow a stronger damper within its work limit" in no_exact_reason(result, str)
