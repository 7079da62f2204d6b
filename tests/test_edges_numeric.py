"""Edges of the numerics: valid input computes or is refused with its range, nothing
hangs, and the numbers do not contradict each other (issue 9, items 14-16).

Each input the issue found failing has a test here. Reference figures come from
independent paths: the time-invariant eigen-analysis for Floquet, a brute-force
scan with plain ``numpy.linalg.eigvals`` for ranges, 40-digit eigenvalues
(mpmath) for a narrow range, and the exact invariance of the roots under a
uniform scale of all mass-like parameters.
"""

import os
import subprocess
import sys
import time
import tomllib
from dataclasses import replace
from importlib import resources

import mpmath
import numpy as np
import pytest

from groundres import ModelRangeError, analyze
from groundres.assess.stability import growth_threshold
from groundres.errors import SpeedRangeError
from groundres.methods import time_invariant
from groundres.model.casefile import shipped_cases
from groundres.model.schema import parse_case
from groundres.model.system import System
from groundres.modes import identify
from groundres.solve import modal
from groundres.solve.floquet import cost

MASS_LIKE_ROTOR = ("blade_mass", "blade_static_moment", "blade_inertia", "lag_stiffness", "lag_damping")
MASS_LIKE_BODY = ("mass_x", "mass_y", "stiffness_x", "stiffness_y", "damping_x", "damping_y")


def shipped(name, **changes):
    """A shipped case with keys changed: ``table__key=value``."""
    text = (resources.files("groundres") / "cases" / f"{name}.toml").read_text()
    data = tomllib.loads(text)
    for key, value in changes.items():
        table, k = key.split("__")
        data[table][k] = value
    return parse_case(data)


def brute_force_ranges(case, points=20001):
    """Unstable ranges from plain eigenvalues of the multiblade state matrix on a fine grid."""
    system = System(case.rotor, case.body)
    w = np.linspace(case.sweep.speeds[0], case.sweep.speeds[-1], points)
    growth = np.concatenate(
        [
            np.linalg.eigvals(modal.state_matrix(*system.multiblade(x))).real.max(-1)
            for x in np.array_split(w, 20)
        ]
    )
    grows = growth > growth_threshold(w)
    edges = np.flatnonzero(np.diff(grows.astype(int)))
    starts = [w[e + 1] for e in edges if grows[e + 1]] + ([w[0]] if grows[0] else [])
    ends = [w[e] for e in edges if not grows[e + 1]] + ([w[-1]] if grows[-1] else [])
    return list(zip(sorted(starts), sorted(ends))), w[1] - w[0]


def refused_at_once(case, errors, match, **kw):
    """``analyze`` raises at once (within 10 s, the equations already derived)."""
    System(case.rotor, case.body).matrices(np.array([1.0]))  # (the derivation is not timed)
    t = time.perf_counter()
    with pytest.raises(errors, match=match):
        analyze(case, **kw)
    assert time.perf_counter() - t < 10


def consistent(result):
    """Installed damping >= exact minimum exactly when the sweep is stable (the damper the
    search sizes: the blades' lag dampers, or the damper rods where the case has them)."""
    exact = result.exact_lag_damping
    installed = max(System(result.case.rotor, result.case.body).damper_values(), default=0.0)
    if exact is None:
        return not result.stability.stable
    return (installed >= exact) == result.stability.stable


# -- 14: valid input never crashes ---------------------------------------------


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(shipped_cases()))
def test_floquet_from_rest_on_every_shipped_case(name):
    """start = 0 with method = "floquet" (a LinAlgError before the rotor at rest
    was solved as it is); where the case has a time-invariant form its
    unstable ranges are the eigen-analysis ones (ends to 1e-7: Floquet
    exponents to about 1e-9 1/s), but for an undamped coalescence narrower
    than Floquet's internal grid (soft-inplane-pitch-roll's 0.011 rad/s at
    9.31 rad/s), which only the eigen-analysis follows to where its roots meet."""
    case = shipped(name, sweep__start=0.0, sweep__points=9)
    flq = analyze(case, method="floquet")
    assert np.isfinite(flq.modes.damping_ratio).all()
    if time_invariant(case) is not None:  # (else the case's own analysis is this Floquet one)
        eig = analyze(case, lag_damping_search=False)  # (its ranges are compared, not its damper)
        spacing = case.sweep.stop / (48 - 9 // 2)
        wide = [r for r in eig.stability.unstable_ranges if r[1] - r[0] > spacing]
        found = [r for r in flq.stability.unstable_ranges if r[1] - r[0] > spacing]
        np.testing.assert_allclose(found, wide, rtol=1e-7)
        assert len(flq.stability.unstable_ranges) <= len(eig.stability.unstable_ranges)
    assert consistent(flq)


@pytest.mark.slow
def test_seventeen_dissimilar_blades():
    """17 blades, one damper out (a ZeroDivisionError in the damping search
    before): the sweep computes; on an isotropic hub the rotating-axes
    eigen-analysis is an independent path to the same range (ends to 1e-7)."""
    result = analyze(shipped("hammond-1974-one-damper", rotor__blades=17))
    assert result.method == "floquet" and not result.stability.stable and consistent(result)
    iso = shipped(
        "hammond-1974-one-damper",
        rotor__blades=17,
        sweep__points=40,
        body__mass_y=8026.6,
        body__damping_y=51078.7,
    )
    flq, eig = analyze(iso, method="floquet"), analyze(iso)
    assert eig.method == "rotating-eigen"
    np.testing.assert_allclose(flq.stability.unstable_ranges, eig.stability.unstable_ranges, rtol=1e-7)


@pytest.mark.slow
def test_twenty_identical_blades_with_floquet():
    """method = "floquet" at N = 20 (it crashed before): its unstable range is the
    multiblade eigen-analysis one (ends to 1e-7: Floquet exponents to about
    1e-9 1/s), and so is the exact minimum (to the Floquet bisection's 1e-3)."""
    case = shipped("hammond-1974", rotor__blades=20, sweep__points=5)
    flq, eig = analyze(case, method="floquet"), analyze(case)
    assert eig.method == "multiblade-eigen" and len(eig.stability.unstable_ranges) == 1
    np.testing.assert_allclose(flq.stability.unstable_ranges, eig.stability.unstable_ranges, rtol=1e-7)
    np.testing.assert_allclose(flq.exact_lag_damping, eig.exact_lag_damping, rtol=2e-3)
    assert consistent(flq) and consistent(eig)


def test_negligible_body_damping_is_no_damping():
    """damping_x = 1e-300 (a LinAlgError: the Deutsch value 1e303 was tried as a
    lag damper): the same sweep as damping_x = 0 (ranges to 1e-12), and no lag
    damping stabilises an undamped body direction."""
    tiny = analyze(shipped("hammond-1974", body__damping_x=1e-300))
    zero = analyze(shipped("hammond-1974", body__damping_x=0.0))
    np.testing.assert_allclose(tiny.stability.unstable_ranges, zero.stability.unstable_ranges, rtol=1e-12)
    assert tiny.exact_lag_damping is None and zero.exact_lag_damping is None


@pytest.mark.parametrize("height", [1e-200, 1e-160])
def test_hub_at_the_pivot(height):
    """hub_height = 1e-200 (a ZeroDivisionError) and 1e-160 (a NaN body
    frequency that broke printing): the hub does not move with body rotation,
    so the hub-referred Deutsch rows do not apply, and the roots are those of
    hub_height = 0 (ranges to 1e-12)."""
    small = analyze(shipped("soft-inplane-pitch-roll", body__hub_height=height))
    zero = analyze(shipped("soft-inplane-pitch-roll", body__hub_height=0.0))
    assert small.deutsch == [] and all(np.isfinite(e.body_frequency) for e in small.deutsch)
    np.testing.assert_allclose(small.stability.unstable_ranges, zero.stability.unstable_ranges, rtol=1e-12)
    np.testing.assert_allclose(small.real_part, zero.real_part, rtol=0, atol=1e-12)


@pytest.mark.parametrize(
    "key, value",
    [("body__stiffness_x", 1e50), ("rotor__lag_stiffness", 1e50), ("body__damping_y", 1e300)],
)
def test_rates_beyond_resolution_are_refused_naming_the_key(key, value):
    """A spring of 1e50 sets a rate of 1e23 1/s, whose round-off (1e8 1/s)
    swamps any growth (before: "block of 2 coordinates has labels"): refused,
    with the key and the largest value this case resolves."""
    name = key.split("__")[1]
    with pytest.raises(ModelRangeError, match=rf"{name} = .*allowed here: {name} up to about"):
        analyze(shipped("hammond-1974", **{key: value}))


def test_a_uniform_scale_of_all_masses_changes_nothing():
    """Every mass-like parameter times 1e300 (several keys at 1e300 overflowed
    before): the roots are invariant under a uniform scale, so the ranges,
    the largest real part and the exact minimum (scaled) are those of the
    case itself."""
    base = shipped("hammond-1974", sweep__points=60)
    big = shipped(
        "hammond-1974",
        sweep__points=60,
        **{f"rotor__{k}": 1e300 * getattr(base.rotor.blades[0], k) for k in MASS_LIKE_ROTOR},
        **{f"body__{k}": 1e300 * getattr(base.body, k) for k in MASS_LIKE_BODY},
    )
    a, b = analyze(base), analyze(big)
    assert b.stability.unstable_ranges == a.stability.unstable_ranges == []
    np.testing.assert_allclose(b.stability.max_real_part, a.stability.max_real_part, rtol=1e-9)
    np.testing.assert_allclose(b.exact_lag_damping, 1e300 * a.exact_lag_damping, rtol=2e-4)
    np.testing.assert_allclose(b.real_part, a.real_part, rtol=0, atol=1e-9)


def test_refusals_exit_2_with_the_range(tmp_path):
    """The command line maps a case outside the model's range to exit 2, one line, no traceback."""
    text = (resources.files("groundres") / "cases" / "hammond-1974.toml").read_text()
    path = tmp_path / "stiff.toml"
    path.write_text(text.replace("stiffness_x = 1240481.8", "stiffness_x = 1e50"))
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    run = subprocess.run(
        [sys.executable, "-m", "groundres.cli", "run", str(path), "--out", str(tmp_path / "out")],
        capture_output=True,
        text=True,
        env=env,
    )
    assert run.returncode == 2, run.stderr
    assert "stiffness_x" in run.stderr and "Traceback" not in run.stderr


# -- 15: nothing hangs ---------------------------------------------------------


@pytest.mark.parametrize(
    "changes",
    [
        dict(sweep__unit="rad/s", sweep__start=1e-6, sweep__stop=1e-3),
        dict(sweep__start=0.05, sweep__stop=0.2),
        dict(sweep__start=0.1, sweep__stop=2.0),
        dict(sweep__points=100000),
    ],
    ids=["1e-6 to 1e-3 rad/s", "0.05 to 0.2 rpm", "0.1 to 2 rpm", "100000 points"],
)
def test_costly_floquet_sweeps_are_refused_at_once_with_the_estimate(changes):
    """Floquet sweeps that took minutes to hours (undamped case): the work is
    estimated before any integration and refused with what to change."""
    refused_at_once(
        shipped("hammond-undamped", **changes), (ModelRangeError, SpeedRangeError), "steps", method="floquet"
    )


# -- 16: no contradictory numbers ---------------------------------------------


def brute_force_growth(case, lag_damping):
    """Largest real part minus the threshold, maximised over speed by plain eigenvalues
    of the multiblade state matrix: a 4001-point grid, then 2001 points around its peak."""
    blades = tuple(replace(b, lag_damping=lag_damping) for b in case.rotor.blades)
    system = System(replace(case.rotor, blades=blades), case.body)

    def excess(w):
        return np.linalg.eigvals(modal.state_matrix(*system.multiblade(w))).real.max(-1) - growth_threshold(w)

    w = np.linspace(case.sweep.speeds[0], case.sweep.speeds[-1], 4001)
    top = w[np.argmax(excess(w))]
    near = np.linspace(top - (w[1] - w[0]), top + (w[1] - w[0]), 2001)
    return excess(near).max()


def test_exact_minimum_does_not_depend_on_the_sweep_spacing():
    """hammond-1974 with points = 3 gave 1644.8: the search has its own speeds.
    Three points give the 400-point figure to the bisection's 1e-4, and a
    brute-force scan of plain eigenvalues finds the sweep stable there and
    unstable 2e-4 below it (the figure is the stable end of the bisection)."""
    fine = analyze(shipped("hammond-1974"))
    coarse = analyze(shipped("hammond-1974", sweep__points=3))
    np.testing.assert_allclose(coarse.exact_lag_damping, fine.exact_lag_damping, rtol=1e-4)
    assert brute_force_growth(fine.case, fine.exact_lag_damping) <= 0
    assert brute_force_growth(fine.case, fine.exact_lag_damping * (1 - 2e-4)) > 0


@pytest.mark.slow
def test_sweep_verdict_and_exact_minimum_agree():
    """hammond-1974 from 100 to 1e5 rpm in 30 points with a 578 N m s/rad damper,
    Floquet: it was reported unstable with an exact minimum of 577.86, below
    the damper. Unstable, and the exact minimum is the eigen-analysis one for
    the same sweep (to the Floquet bisection's 1e-3)."""
    changes = dict(sweep__start=100.0, sweep__stop=1e5, sweep__points=30, rotor__lag_damping=578.0)
    flq = analyze(shipped("hammond-1974", **changes), method="floquet")
    eig = analyze(shipped("hammond-1974", **changes))
    assert not flq.stability.stable and not eig.stability.stable
    assert flq.exact_lag_damping > 578.0 and consistent(flq) and consistent(eig)
    np.testing.assert_allclose(flq.exact_lag_damping, eig.exact_lag_damping, rtol=2e-3)


def test_two_points_find_both_ranges():
    """hammond-undamped with points = 2 reported one of its two ranges: both, with
    the ends of the 400-point sweep (1e-9) and of a brute-force scan of plain
    eigenvalues (to its spacing)."""
    coarse = analyze(shipped("hammond-undamped", sweep__points=2)).stability.unstable_ranges
    fine = analyze(shipped("hammond-undamped")).stability.unstable_ranges
    np.testing.assert_allclose(coarse, fine, rtol=1e-9)
    brute, step = brute_force_ranges(shipped("hammond-undamped"))
    np.testing.assert_allclose(coarse, brute, rtol=0, atol=step)


def test_a_range_narrower_than_the_grid():
    """soft-inplane-pitch-roll (undamped) has a second range 0.011 rad/s wide at
    9.31 rad/s where the regressive lag and flap modes coalesce: found with
    any spacing; checked by 40-digit eigenvalues of the coupled block inside
    and outside it, and by a brute-force scan."""
    case = shipped("soft-inplane-pitch-roll")
    for points in (400, 7):
        ranges = analyze(shipped("soft-inplane-pitch-roll", sweep__points=points)).stability.unstable_ranges
        assert len(ranges) == 2
        (a, b), _ = ranges
        assert 9.30 < a < b < 9.33 and b - a < 0.012
    system = System(case.rotor, case.body)
    mpmath.mp.dps = 40
    for w, grows in ((9.30, False), (9.315, True), (9.33, False)):
        mats = system.multiblade(np.array([w]))
        block = modal.coupling_blocks(*mats)[0]
        a = modal.state_matrix(*(x[:, block[:, None], block] for x in mats))[0]
        top = max(mpmath.re(e) for e in mpmath.eig(mpmath.matrix(a.tolist()), left=False, right=False))
        assert (top > growth_threshold(w)) == grows
    brute, step = brute_force_ranges(case, 40001)
    np.testing.assert_allclose(ranges, brute, rtol=0, atol=step)


@pytest.mark.parametrize("lag_damping", [1e14, 1e16])
def test_round_off_at_extreme_dampers_is_refused(lag_damping):
    """lag_damping = 1e14 was reported unstable (8.2e-6 1/s at 1.30 rad/s), 1e16
    with seven ranges: round-off of eps times the damper's rate, refused."""
    with pytest.raises(ModelRangeError, match="lag_damping"):
        analyze(shipped("hammond-1974", rotor__lag_damping=lag_damping))


def test_a_strong_damper_within_resolution_is_stable():
    """1e10 N m s/rad (rate 9e6 1/s, round-off 2e-8 1/s) is resolved: stable, and
    the exact minimum is the case's own."""
    strong = analyze(shipped("hammond-1974", rotor__lag_damping=1e10))
    assert strong.stability.stable and consistent(strong)
    own = analyze(shipped("hammond-1974")).exact_lag_damping
    np.testing.assert_allclose(strong.exact_lag_damping, own, rtol=2e-4)


def test_a_root_at_the_origin_is_neutral():
    """damping_ratio was NaN for every zero root: 0 (neutral), never NaN."""
    assert identify.damping_ratio(np.array([0.0 + 0.0j, -1.0 + 0.0j]))[0] == 0.0
    assert identify.damping_ratio(np.array([0.0j]))[0] == 0.0
    result = analyze(shipped("hammond-1974", sweep__start=0.0, sweep__points=5))
    ratios = result.modes.damping_ratio
    assert np.isfinite(ratios).all()
    assert ratios[0].min() == 0.0  # the free lag hinge at rest


@pytest.mark.parametrize("name", ["hammond-1974", "soft-inplane-damped", "hammond-undamped", "soft-inplane"])
@pytest.mark.parametrize("points", [2, 5])
def test_verdict_and_exact_minimum_never_contradict(name, points):
    assert consistent(analyze(shipped(name, sweep__points=points)))


# -- a range that begins between rest and the sweep's first turning speed -----------

#: Four articulated blades without dampers (nu = 0.152/rev) on a body that moves
#: fore-aft and rolls, swept 0, 4, ..., 16 rad/s: some root grows from about
#: 0.24 rad/s up, far below the sweep's first turning speed (generated by the
#: property test; the independent brute-force scan below finds the same start).
LOW_START = """
title = "low start"
[rotor]
blades = 4
hinge_offset = 0.073
blade_mass = 115.8
blade_static_moment = 323.7
blade_inertia = 1024.0
lag_stiffness = 0.0
lag_damping = 0.0
[body]
dofs = ["roll", "x"]
mass_x = 1009.0
stiffness_x = 1302000.0
damping_x = 2703.0
inertia_roll = 5360.0
stiffness_roll = 229200.0
damping_roll = 3274.0
hub_height = 2.833
[sweep]
start = 0.0
stop = 16.0
points = 5
"""


def test_range_starting_below_the_first_turning_speed_is_followed_down():
    """The start lies between rest and 4 rad/s: eigen and Floquet find it (to the
    crossing's 1e-10 and Floquet's ~1e-9 accuracy), where it was once reported at
    half the first internal speed (1.0 and 1.07 rad/s)."""
    case = parse_case(tomllib.loads(LOW_START))
    eig = analyze(case, method="eigen")
    flq = analyze(case, method="floquet")
    (start, end), *_ = eig.stability.unstable_ranges
    ranges, step = brute_force_ranges(replace(case, sweep=replace(case.sweep, stop=1.0)), points=4001)
    assert abs(ranges[0][0] - start) <= step  # the fine grid's own resolution
    assert 0.2 < start < 0.3 and end == 16.0
    np.testing.assert_allclose(flq.stability.unstable_ranges[0][0], start, rtol=1e-8)
    assert eig.stability.open_below is None and flq.stability.open_below is None


def test_range_open_at_the_lowest_affordable_floquet_speed_says_so(monkeypatch):
    """With a work budget that stops the descent near 0.5 rad/s the range still
    grows there: its start is reported as a bound, in summary.json too."""
    from groundres.results.summary import summary

    case = parse_case(tomllib.loads(LOW_START))
    system = System(case.rotor, case.body)
    work, _ = cost.floquet_work_per_speed(system, np.array([0.5]), lift=False)
    monkeypatch.setattr(cost, "REST_BUDGET", float(work[0]) * 1.01)
    flq = analyze(case, method="floquet")
    first = flq.stability.unstable_ranges[0][0]
    assert flq.stability.open_below == first and 0.4 <= first <= 1.0
    out = summary(flq)["unstable_ranges"][0]
    assert "may begin lower" in out["start_note"]


#: Six blades, one blade's damper changed, on a body with all four dofs, swept in
#: Hz by Floquet theory (generated by the property test, from 0.2625 Hz: once 436 s
#: of work, now about 50 s; from 0.03 Hz its estimate is above the limit).
SIX_BLADES_HZ = """
title = "six blades in Hz"
[rotor]
blades = 6
hinge_offset = 0.45
blade_mass = 65.0
blade_static_moment = 15.27
blade_inertia = 159.4
lag_stiffness = 68740.0
lag_damping = 16350.0
[[rotor.blade]]
index = 3
lag_damping = 177.2
[body]
dofs = ["roll", "y", "x", "pitch"]
mass_x = 3016.0
stiffness_x = 1171000.0
damping_x = 7516.0
mass_y = 1252.0
stiffness_y = 211900.0
damping_y = 0.0
inertia_pitch = 7208.0
stiffness_pitch = 944500.0
damping_pitch = 20420.0
inertia_roll = 13560.0
stiffness_roll = 278700.0
damping_roll = 0.0
hub_height = 0.6625
[sweep]
start = 0.03
stop = 1.91782
points = 5
unit = "Hz"
method = "floquet"
"""


def test_floquet_refusal_speaks_the_case_unit_and_fits_its_advice():
    """That case has no time-invariant form: the refusal (at once, from the
    estimate) names the speed in Hz as the case does, and does not advise
    method = 'auto' (which would be Floquet again); a case that has one is
    advised to use it."""
    case = parse_case(tomllib.loads(SIX_BLADES_HZ))
    with pytest.raises(ModelRangeError) as err:
        analyze(case)
    message = str(err.value)
    assert "0.03 Hz (0.1885 rad/s)" in message and "method = 'auto'" not in message
    with pytest.raises(ModelRangeError, match="time-invariant form: method = 'auto'"):
        cost.check_floquet_work(3e6, np.ones(2), np.ones(2), time_invariant=True)


def test_smallest_damping_ratio_does_not_depend_on_the_sweep_spacing():
    """With two sweep points soft-inplane reported a smallest damping ratio of
    -2e-16 at 3.14 rad/s beside a largest real part of +1.43 1/s at 24.7 rad/s:
    the worst speeds of the real part (from the internal grid) are looked at
    too, so 2, 5 and 400 points give the same figure (to the refinement's 1e-6
    relative in speed, the ratio to 1e-9)."""
    fine = analyze(shipped("soft-inplane")).stability.min_damping_ratio
    for points in (2, 5):
        coarse = analyze(shipped("soft-inplane", sweep__points=points)).stability.min_damping_ratio
        np.testing.assert_allclose(coarse[0], fine[0], rtol=1e-9)
        np.testing.assert_allclose(coarse[1], fine[1], rtol=1e-6)
    assert fine[0] < -0.1


def test_no_exact_minimum_without_body_damping_says_why():
    """A free body (gear springs of 0.01 N/m) without damping under an
    articulated rotor: the Deutsch criterion asks for infinite lag damping, and
    no damper makes the sweep stable; that answer does not depend on the
    sweep's spacing, and the reason names the undamped body mode."""
    from groundres.results.summary import summary

    changes = dict(sweep__start=0.0, body__stiffness_x=0.01, body__stiffness_y=0.01, rotor__lag_stiffness=0.0)
    for points in (2, 400):
        result = analyze(shipped("soft-inplane", sweep__points=points, **changes))
        assert result.exact_lag_damping is None and result.no_exact_lag_damping[0] == "cap"
    reason = summary(result)["lag_damping"]["exact_minimum_reason"]
    assert "x-y" in reason and "no body damping" in reason


def test_the_damping_search_can_be_left_out():
    """phasors ran the search and threw its answer away: without it the modes
    and ranges are the same and the result says the search was not run."""
    from groundres.results.summary import summary

    case = shipped("hammond-1974", sweep__points=40)
    full = analyze(case)
    bare = analyze(case, lag_damping_search=False)
    np.testing.assert_array_equal(bare.modes.eigenvalue, full.modes.eigenvalue)
    assert bare.stability.unstable_ranges == full.stability.unstable_ranges
    assert bare.exact_lag_damping is None and full.exact_lag_damping > 0
    assert summary(bare)["lag_damping"]["exact_minimum_reason"] == "the search for it was not run"
