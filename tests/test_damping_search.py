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

from groundres import analyze, floquet, limits
from groundres.config import parse_case
from groundres.stability import growth_threshold


def case(name, **body_scale):
    data = tomllib.loads((resources.files("groundres") / "cases" / f"{name}.toml").read_text())
    for key, factor in body_scale.items():
        data["body"][key] *= factor
    data["sweep"]["points"] = 60
    return parse_case(data)


def brute_force_excess(c, lag_damping):
    """Largest real part minus the threshold over the sweep by plain Floquet exponents of
    the system rebuilt with that lag damping: 400 uniform speeds, then 200 around the worst."""
    system, unit = limits.system_in_mass_unit(c.rotor, c.body)
    system = system.with_lag_damping(lag_damping / unit)
    lo, hi = c.sweep.speeds[0], c.sweep.speeds[-1]

    def excess(w):
        return floquet.solve(system, w, harmonics=0, lift=False).exponent.real.max(-1) - growth_threshold(w)

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
