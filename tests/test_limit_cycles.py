"""Limit cycles predicted from describing functions (issue 26, item 3): closed-form neutral
amplitudes.

A law whose equivalent stiffness is constant changes only the blades' damping with amplitude,
so a cycle sits where c_eq(A w) equals the linear critical damping c_crit at that speed: the
lag damping at which the linear system's least stable root is neutral. The second route finds
c_crit by bisection on the linear case (``lag_damping``) with the linear solver, and the
blade's frequency w = Omega - w_nr from that neutral root (the regressive whirl, which these
cases' cycles are); the closed forms then give the amplitude:

* Coulomb friction F beside c_v (regularised over 1e-8 rad/s: t(a) = 4 / pi to 1e-12):
  V* = 4 F / (pi (c_crit - c_v)), a threshold (c_eq falls with amplitude);
* bilinear: N(v_r / V*) = (c_crit - c2) / (c1 - c2) with the saturation function N; a
  threshold for a relief valve (c1 > c_crit > c2), a stable cycle for a progressive damper
  (c1 < c_crit < c2).
"""

import math
import tomllib

import numpy as np
import pytest
from scipy.optimize import brentq

from groundres.assess import limit_cycles
from groundres.methods import Method
from groundres.model.casefile import case_text
from groundres.model.schema import parse_case
from groundres.solve.solvers import solver_for

RPM = 2 * math.pi / 60
THRESHOLD = "small disturbances decay, a disturbance above the threshold grows without bound"
SETTLES = "grows from any small disturbance to a stable cycle (larger ones decay to it)"
SPEED = 260 * RPM  # (inside the Hammond (1974) rotor's ground-resonance range without dampers)


def _case(law: str):
    text, source = case_text("hammond-1974")
    text = text.replace("lag_damping = 4067.5           # [N m s/rad]", "") + "\n[rotor.lag_damper]\n" + law
    return parse_case(tomllib.loads(text), source, text)


def _linear(c: float):
    text, source = case_text("hammond-1974")
    text = text.replace("lag_damping = 4067.5", f"lag_damping = {c!r}")
    return parse_case(tomllib.loads(text), source, text)


def _critical(speed: float):
    """(c_crit [N m s/rad], the blade's frequency at it [rad/s]) by bisection on the linear case."""

    def largest(c):
        solver = solver_for(_linear(c), Method.MULTIBLADE)
        return float(solver.real_parts(np.array([speed])).max())

    c = brentq(largest, 1.0, 4067.5, xtol=1e-12, rtol=1e-14)
    roots = solver_for(_linear(c), Method.MULTIBLADE).roots(np.array([speed]))[0]
    neutral = roots[np.argmax(roots.real)]
    return c, speed - abs(neutral.imag)


@pytest.fixture(scope="module")
def critical():
    return _critical(SPEED)


def test_coulomb_threshold_is_four_f_over_pi_times_the_missing_damping(critical):
    c_crit, w = critical
    friction, viscous = 150.0, 100.0
    case = _case(
        f'law = "friction"\nfriction_moment = {friction}\nregularisation_velocity = 1e-8\n'
        f"damping = {viscous}\n"
    )
    found = limit_cycles.predict(case, [SPEED])
    (cycle,) = found.cycles
    rate = 4 * friction / (math.pi * (c_crit - viscous))
    assert cycle.frequency == pytest.approx(w, rel=1e-9)
    assert cycle.amplitude == pytest.approx(rate / w, rel=1e-8)
    assert not cycle.stable and found.verdict(0) == THRESHOLD
    assert cycle.equivalent_damping == pytest.approx(c_crit, rel=1e-8)


@pytest.mark.parametrize("c1, c2, stable", [(4067.5, 200.0, False), (300.0, 4000.0, True)])
def test_bilinear_cycle_is_where_the_saturation_function_meets_the_critical_damping(critical, c1, c2, stable):
    c_crit, w = critical
    relief = 0.2 * c1  # (v_r = 0.2 rad/s)
    case = _case(f'law = "bilinear"\ndamping = {c1}\nrelief_moment = {relief}\ndamping_after_relief = {c2}\n')
    found = limit_cycles.predict(case, [SPEED])
    (cycle,) = found.cycles
    target = (c_crit - c2) / (c1 - c2)
    r = brentq(
        lambda r: 2 / math.pi * (math.asin(r) + r * math.sqrt(1 - r * r)) - target, 0.0, 1.0, xtol=1e-15
    )
    assert cycle.amplitude * cycle.frequency == pytest.approx(0.2 / r, rel=1e-8)
    assert cycle.frequency == pytest.approx(w, rel=1e-9)
    assert cycle.stable is stable
    assert found.verdict(0) == (SETTLES if stable else THRESHOLD)


# -- blades that differ: the Floquet route ------------------------------------------------------


@pytest.mark.parametrize(
    "law",
    [
        'law = "bilinear"\ndamping = 4067.5\nrelief_moment = 813.5\ndamping_after_relief = 406.75\n',
        'law = "friction-link"\nfriction_moment = 300.0\nlink_stiffness = 2.0e4\n'
        "regularisation_damping = 5.0\ndamping = 500.0\n",
    ],
)
def test_the_floquet_route_finds_the_multiblade_route_s_cycles_on_identical_blades(law):
    """Two routes to one answer: the Floquet analysis of the periodic equations with each blade at
    its own amplitude (the route of a failed damper) and the multiblade eigen-analysis share only
    the case and the describing functions. On identical blades every blade moves alike and both
    find the same cycles, to the Floquet exponents' accuracy (the bracket of 1e-9 in log amplitude,
    and the periodic eigenvector's harmonics). The friction link also runs through the stiffness
    directions of the Floquet kernel."""
    case = _case(law)
    speeds = np.array([200.0, 264.34, 330.0]) * RPM
    eigen = limit_cycles.predict(case, speeds)
    floquet = limit_cycles.predict(case, speeds, periodic=True)
    assert eigen.cycles and len(eigen.cycles) == len(floquet.cycles)
    for a, b in zip(eigen.cycles, floquet.cycles):
        assert (a.speed, a.stable) == (b.speed, b.stable)
        assert b.amplitude == pytest.approx(a.amplitude, rel=1e-7)
        assert b.frequency == pytest.approx(a.frequency, rel=1e-8)
        assert b.nonrotating_frequency == pytest.approx(a.nonrotating_frequency, rel=1e-8)
        assert b.peak == pytest.approx(a.peak, rel=1e-6)
        assert b.second_component == pytest.approx(a.second_component, rel=1e-5, abs=1e-9)
        for dof in a.hub:
            assert b.hub[dof] == pytest.approx(a.hub[dof], rel=1e-6)
        assert [x.amplitude for x in b.blades] == pytest.approx([a.amplitude] * 4, rel=1e-7)
        assert b.equivalent_damping == pytest.approx(a.equivalent_damping, rel=1e-6)
        assert b.equivalent_stiffness == pytest.approx(a.equivalent_stiffness, rel=1e-6, abs=1e-6)
        # the same motion: the starting states agree once their arbitrary phase is set alike
        phase = np.vdot(a.start, b.start) / abs(np.vdot(a.start, b.start))
        assert np.abs(b.start - phase * a.start).max() <= 1e-6 * np.abs(a.start).max()


def test_a_failed_damper_s_blade_swings_most_and_each_blade_has_its_own_amplitude():
    """Blade 1 without its relief valve: its neighbours (blades 2 and 4, mirror images about it)
    swing alike, blade 3 differently, and the cycle's amplitude is blade 1's. Each working blade's
    damper is the describing function at its own amplitude and frequency."""
    from groundres.model.describing import equivalent

    case = _case(
        'law = "bilinear"\ndamping = 4067.5\nrelief_moment = 813.5\ndamping_after_relief = 406.75\n'
        '\n[[rotor.blade]]\nindex = 1\nlag_damper = "failed"\n'
    )
    law = case.rotor.lag_laws[1].law
    found = limit_cycles.predict(case, [330.0 * RPM])
    (cycle,) = found.cycles
    assert not cycle.stable and cycle.dissimilar
    one, two, three, four = cycle.blades
    assert cycle.amplitude == pytest.approx(one.amplitude, rel=1e-14)
    assert one.amplitude > 1.2 * max(two.amplitude, three.amplitude)
    assert two.amplitude == pytest.approx(four.amplitude, rel=1e-8)
    assert abs(two.amplitude - three.amplitude) > 0.05 * two.amplitude
    assert one.damping is None
    for blade in (two, three, four):
        c, k = equivalent(law, blade.amplitude, blade.frequency)
        assert blade.damping == pytest.approx(float(c), rel=1e-7)


# -- the pipeline and groundres cycles ----------------------------------------------------------


def _cli(*args):
    from click.testing import CliRunner

    from groundres.cli import main

    return CliRunner().invoke(main, list(args))


def _file(tmp_path, law: str, extra: str = "") -> str:
    text, _ = case_text("hammond-1974")
    text = text.replace("lag_damping = 4067.5           # [N m s/rad]", "")
    path = tmp_path / "case.toml"
    path.write_text(text + "\n[rotor.lag_damper]\n" + law + "\n[limit_cycle]\npoints = 12\n" + extra)
    return str(path)


def test_groundres_cycles_writes_the_diagram_the_json_and_the_threshold_in_words(tmp_path):
    import json

    from groundres import limit_cycles as pipeline
    from groundres.model.schema import load_case

    path = _file(
        tmp_path, 'law = "bilinear"\ndamping = 4067.5\nrelief_moment = 813.5\ndamping_after_relief = 200.0\n'
    )
    out = tmp_path / "out"
    result = _cli("cycles", path, "--out", str(out))
    assert result.exit_code == 0, result.output
    assert {p.name for p in out.iterdir()} == {
        "limit_cycles.png",
        "limit_cycles.json",
        "limit_cycles.nc",
        "case.toml",
        "provenance.json",
    }
    data = json.loads((out / "limit_cycles.json").read_text())
    found = pipeline(load_case(path), linear=False)
    worst = found.smallest_threshold()
    assert "Smallest threshold: " + found.threshold_words(worst).replace("\n", " ") in " ".join(
        result.output.split()
    )
    assert len(data["speeds"]) == 12 and data["amplitude_unit"] == "deg"
    assert [c["amplitude"] for c in data["cycles"]] == [
        math.degrees(c.amplitude) for c in found.prediction.cycles
    ]
    assert all(not c["stable"] for c in data["cycles"])
    import xarray as xr

    with xr.open_dataset(out / "limit_cycles.nc") as ds:  # (the same cycles, SI, with their branches)
        assert ds.cycle_amplitude.attrs["units"] == "rad" and ds.hub_y.attrs["units"] == "m"
        np.testing.assert_allclose(
            np.degrees(ds.cycle_amplitude.values), [c["amplitude"] for c in data["cycles"]]
        )
        np.testing.assert_allclose(ds.blade_amplitude.values[:, 0], ds.cycle_amplitude.values, rtol=1e-12)
        assert ds.growth.shape == (12, ds.sizes["amplitude"]) and (ds.branch.values >= 0).all()


@pytest.mark.parametrize(
    "law, extra, message",
    [
        ('law = "linear"\ndamping = 4067.5\n', "", "limit cycles need a nonlinear lag damper law"),
    ],
)
def test_groundres_cycles_refuses_what_it_cannot_predict_with_exit_2(tmp_path, law, extra, message):
    result = _cli("cycles", _file(tmp_path, law, extra), "--out", str(tmp_path / "out"))
    assert result.exit_code == 2, result.output
    assert message in result.output and "Traceback" not in result.output
    assert not (tmp_path / "out").exists()


def test_a_law_survives_the_air_and_its_cycles_are_predicted_there():
    text, source = case_text("model-rotor-hover-9deg")
    assert "lag_damping" in text
    line = next(s for s in text.splitlines() if s.startswith("lag_damping"))
    c = float(line.split("=")[1].split("#")[0])
    text = (
        text.replace(line, "")
        + f'\n[rotor.lag_damper]\nlaw = "bilinear"\ndamping = {c}\nrelief_moment = {0.05 * c}\n'
    )
    text += f"damping_after_relief = {0.1 * c}\n"
    case = parse_case(tomllib.loads(text), source, text)
    assert case.rotor.aero is not None and case.rotor.nonlinear
    speeds = np.linspace(case.sweep.start, case.sweep.stop, 6)[1:]
    found = limit_cycles.predict(case, speeds)
    assert found.growth.shape == (5, len(found.amplitudes))
    assert np.isfinite(found.growth).all()


def test_in_air_every_equivalent_system_moves_about_the_small_motion_trim_and_is_linear_in_the_damper():
    """F0 + c dC + k dK equals the form built directly for a damper c and spring k on the lag, both
    about the small-motion system's hover trim (the trim depends on the lag spring: without a
    held trim the form was 1.6 % off at 20 times the reference spring)."""
    from dataclasses import replace

    text, source = case_text("model-rotor-hover-9deg")
    line = next(s for s in text.splitlines() if s.startswith("lag_damping"))
    text = text.replace(line, "") + (
        '\n[rotor.lag_damper]\nlaw = "friction-link"\nfriction_moment = 5.0\nlink_stiffness = 400.0\n'
        "regularisation_damping = 0.01\ndamping = 0.2\n"
    )
    case = parse_case(tomllib.loads(text), source, text)
    equivalent = limit_cycles.EquivalentSystem(case)
    speeds = np.linspace(case.sweep.stop / 3, case.sweep.stop, 4)
    f0, d_c, d_k = equivalent.directions(speeds)
    n = case.rotor.n_blades
    for c, k in ((0.7, 20 * equivalent.k_ref), (3.0, 0.01 * equivalent.k_ref)):
        direct = solver_for(replace(case, rotor=case.rotor.equivalent([c] * n, [k] * n)), Method.MULTIBLADE)
        direct.system.holding_trim_of(solver_for(case, Method.MULTIBLADE).system)
        form = direct.form(speeds)
        assert np.abs(f0 + c * d_c + k * d_k - form).max() <= 1e-9 * np.abs(form).max()


def test_a_friction_link_s_cycles_say_how_far_its_regularisation_may_move_them():
    from groundres import limit_cycles as pipeline
    from groundres.model.describing import link_regularisation
    from groundres.model.schema import load_case

    found = pipeline(load_case("hammond-friction-link"), linear=False)
    data = found.to_dict()
    law = found.case.rotor.lag_laws[0].law
    for entry, cycle in zip(data["cycles"], found.prediction.cycles):
        assert entry["link_regularisation"] == float(
            link_regularisation(law, cycle.amplitude, cycle.frequency)
        )


def test_in_air_a_failed_damper_s_equivalent_reassembles_the_small_motion_equations():
    """Blade 1 failed, friction links on the others, hovering: the split equations plus each
    working blade's small-motion damper and link spring along its directions are the linear
    equations of the case at every azimuth. The failed blade trims to another lag angle than
    the sprung ones; the equations without dampers once took every blade at blade 1's trim
    (their blades alike), 6e-4 off, and `groundres cycles` stopped with exit 1."""
    from groundres.assess.periodic_cycles import PeriodicEquivalent

    text, source = case_text("helicopter-hover")
    line = next(s for s in text.splitlines() if s.startswith("lag_damping"))
    text = text.replace(line, "") + (
        '\n[rotor.lag_damper]\nlaw = "friction-link"\nfriction_moment = 200.0\nlink_stiffness = 2.0e4\n'
        'regularisation_damping = 5.0\ndamping = 253.0\n\n[[rotor.blade]]\nindex = 1\nlag_damper = "failed"\n'
    )
    case = parse_case(tomllib.loads(text), source, text)
    equivalent = PeriodicEquivalent(case)
    split = equivalent.system
    linear = solver_for(case, Method.FLOQUET).system
    assert not linear.trims_alike and equivalent.working == [1, 2, 3] == equivalent.sprung
    speeds, psi = np.array([30.0, 44.4]), np.array([0.0, 0.9, 2.5])[:, None]
    m, c, k = split.matrices(speeds, psi)
    values = [
        (lin.lag_damping - off.lag_damping, lin.lag_stiffness - off.lag_stiffness)
        for lin, off in zip(linear.rotor.blades, split.rotor.blades)
    ]
    directions = split.damping_directions
    for j, blade in enumerate(equivalent.working):
        c = c + values[blade][0] * directions[j]
        k = k + values[blade][1] * directions[len(equivalent.working) + j]
    want = linear.matrices(speeds, psi)
    assert values[0] == (0.0, 0.0) and min(v[1] for v in values[1:]) > 0
    for got, wanted in zip((m, c, k), want):
        assert np.abs(got - wanted).max() <= 1e-10 * np.abs(wanted).max()


def test_a_two_bladed_rotor_s_hub_is_reported_at_both_omega_minus_and_plus_the_lag_frequency():
    """Two blades on an anisotropic hub: a blade lagging at w in the rotating frame moves the hub
    at Omega - w and Omega + w alike (the frame change of a two-bladed rotor). The hub's frequency
    is its largest body component's (it was the root's dominant harmonic over every coordinate,
    which can be a blade's), and the second is reported beside it."""
    text, source = case_text("two-bladed")
    text = text.replace("lag_damping = 300.0            # [N m s/rad]\n", "")
    assert "lag_damping" not in text
    text += '\n[rotor.lag_damper]\nlaw = "bilinear"\ndamping = 800.0\nrelief_moment = 100.0\n'
    text += "damping_after_relief = 100.0\n"
    case = parse_case(tomllib.loads(text), source, text)
    found = limit_cycles.predict(case, np.array([300.0, 330.0]) * 2 * math.pi / 60)
    assert len(found.cycles) == 2
    for cycle in found.cycles:
        both = sorted([cycle.nonrotating_frequency, cycle.nonrotating_second])
        want = sorted([abs(cycle.speed - cycle.frequency), cycle.speed + cycle.frequency])
        assert both == pytest.approx(want, rel=1e-9)
    relief = _case(
        'law = "bilinear"\ndamping = 4067.5\nrelief_moment = 813.5\ndamping_after_relief = 406.75\n'
    )
    (identical,) = limit_cycles.predict(relief, [330 * RPM]).cycles
    assert identical.nonrotating_second is None


def test_the_fixed_point_search_returns_what_it_evaluated_and_keeps_shares_in_0_1():
    """Anderson acceleration (periodic_cycles._settle) on a map whose fixed point has a share of
    1.5 (out of range) and that never settles: every point returns the x its last step was
    evaluated at (the state describes that x; the step limit once left an unevaluated x), and no
    share leaves [0, 1]."""
    from groundres.assess import periodic_cycles

    last = {}

    def step(active, x):
        for p, row in zip(active, x):
            last[int(p)] = row.copy()
        assert (x[:, :2] >= 0).all() and (x[:, :2] <= 1).all()
        target = np.array([1.5, 0.5, 0.3, 0.2])
        rotate = np.array([[0.0, -0.99], [0.99, 0.0]])  # (a slow spiral in the frequencies)
        mapped = x + 0.5 * (target - x)
        mapped[:, 2:] = 0.25 + (x[:, 2:] - 0.25) @ rotate.T
        return mapped, np.ones(len(x))

    x = np.array([[1.0, 0.2, 0.0, 0.0], [0.5, 0.5, 1.0, 1.0]])
    out = periodic_cycles._settle(step, x, sign_only=False)
    for p in range(len(x)):
        np.testing.assert_array_equal(out[p], last[p])
    assert (out[:, :2] >= 0).all() and (out[:, :2] <= 1).all()


@pytest.mark.parametrize("name, failed", [("hammond-friction-link", False), ("hammond-relief-valve", True)])
def test_small_motion_growth_is_the_linear_analysis_s_least_stable_root(name, failed):
    """Whether small motion grows is the linear analysis's answer (each law at its slope at rest):
    the growth each route of the prediction computes for it equals the largest real part of the
    linear solver's roots on the same case (multiblade on identical blades, Floquet with blade 1's
    damper failed), and the Floquet route agrees with the multiblade one on identical blades.
    Tolerance: the Floquet exponents' accuracy, 1e-8 of the speed."""
    text, source = case_text(name)
    if failed:
        text += '\n[[rotor.blade]]\nindex = 1\nlag_damper = "failed"\n'
    case = parse_case(tomllib.loads(text), source, text)
    speeds = np.array([150.0, 230.0, 300.0, 380.0]) * RPM
    method = Method.FLOQUET if failed else Method.MULTIBLADE
    linear = solver_for(case, method).real_parts(speeds).max(axis=1)
    found = limit_cycles.predict(case, speeds, per_decade=2)
    assert np.abs(found.small_growth - linear).max() <= 1e-8 * speeds.max()
    if not failed:
        floquet = limit_cycles.predict(case, speeds, per_decade=2, periodic=True)
        assert np.abs(floquet.small_growth - linear).max() <= 1e-8 * speeds.max()
    assert (linear > 0).any() and (linear < 0).any()  # (both verdicts are tried)


def test_a_threshold_below_the_amplitudes_searched_is_said_and_bounds_a_study_s_threshold():
    """hammond-relief-valve's thresholds are near 2.4 deg. Searched from 5 deg, a disturbance of 5
    deg grows at those speeds while small motion decays: the threshold lies below the amplitudes
    searched. It used to be read from the growth at 5 deg alone as 'grows from any disturbance',
    and a study recorded a threshold of 0. Now those speeds are named, no speed is unbounded, and
    a study records 5 deg, the bound the search supports, with the count of such speeds."""
    from groundres.results.limit_cycles import LimitCycleResult
    from groundres.studies.measures import cycle_measures

    text, source = case_text("hammond-relief-valve")
    text = text.replace("amplitude_min = 0.01 ", "amplitude_min = 5.0 ").replace(
        "points = 100", "points = 12"
    )
    case = parse_case(tomllib.loads(text), source, text)
    speeds = np.linspace(case.sweep.start, case.sweep.stop, 12)
    full = limit_cycles.predict(case, speeds, searched=(math.radians(0.01), math.radians(30.0)))
    found = limit_cycles.predict(case, speeds, searched=case.limit_cycle.searched)
    small = [
        i
        for i in range(12)
        if any(not c.stable and c.amplitude < math.radians(5) for c in full.at(speeds[i]))
    ]
    assert small and found.below_searched() == small and not found.unbounded()
    said = "small motion decays; a threshold lies below 5 deg, the smallest searched: a disturbance above it"
    assert all(found.verdict(i).startswith(said) for i in small)
    words = LimitCycleResult(case, found).below_words()
    assert f"at {len(small)} of the 12 speeds" in words and "5 deg" in words
    ds = LimitCycleResult(case, found).to_xarray()
    assert np.array_equal(ds.small_motion_growth.values, found.small_growth)
    assert ds.small_motion_growth.attrs["units"] == "1/s"
    measures = cycle_measures(case)
    assert measures["smallest_threshold"] == pytest.approx(math.radians(5.0), rel=1e-12)
    assert measures["smallest_threshold_speed"] == speeds[small[0]]
    assert measures["below_searched_speed_count"] == len(small) and measures["unbounded_speed_count"] == 0


def test_speeds_that_grow_from_any_disturbance_are_named_range_by_range():
    """Speeds that are not neighbours are not joined into one range ('from the first to the
    last'): each run of neighbouring speeds is its own range."""
    from groundres.results.limit_cycles import LimitCycleResult

    case = _case('law = "bilinear"\ndamping = 4067.5\nrelief_moment = 813.5\ndamping_after_relief = 406.75\n')
    speeds = np.array([100.0, 150.0, 200.0, 250.0, 300.0, 350.0]) * RPM
    grows = np.array([1.0, 1.0, -1.0, 1.0, -1.0, 1.0])
    found = limit_cycles.LimitCycles(speeds, np.array([1e-4, 0.5]), np.stack([grows, grows], 1), grows)
    words = LimitCycleResult(case, found).unbounded_words()
    assert words.startswith("at 4 of the 6 speeds, from 100 rpm") and " to 150 rpm" in words
    assert ", at 250 rpm (" in words and " and at 350 rpm (" in words


def test_a_nearly_undamped_rotor_is_neutral_where_the_linear_analysis_says_so():
    """Bilinear dampers of 1e-3 N m s/rad on the undamped Hammond rotor: outside its ground-
    resonance ranges every root is within the linear analysis's growth threshold of zero, and a
    growth of 1e-8 1/s there no longer reads as 'decays' or 'grows from any disturbance'; inside
    them every disturbance grows."""
    text, source = case_text("hammond-undamped")
    text = text.replace("lag_damping = 0.0", "") + (
        '\n[rotor.lag_damper]\nlaw = "bilinear"\ndamping = 1e-3\nrelief_moment = 1e-4\n'
        "damping_after_relief = 1e-5\n"
    )
    case = parse_case(tomllib.loads(text), source, text)
    speeds = np.linspace(case.sweep.start, case.sweep.stop, 30)
    found = limit_cycles.predict(case, speeds, per_decade=2)
    neutral = [i for i in range(30) if found.small_sign(i) == 0]
    growing = [i for i in range(30) if found.small_sign(i) > 0]
    assert neutral and growing and len(neutral) + len(growing) == 30
    assert all(found.verdict(i).startswith("neutral at every amplitude searched") for i in neutral)
    assert found.unbounded() == growing and not found.below_searched()


def test_each_speed_is_said_from_small_motion_up_through_the_amplitudes_searched():
    """Synthetic scans (no cycles): the verdict and the lists of speeds read the small-motion growth
    and the first amplitude that is not neutral (within the growth threshold, 1e-6 x Omega + 1e-9
    1/s, a growth is neutral), so no row contradicts its numbers."""
    speeds = np.array([10.0, 20.0, 30.0, 40.0, 50.0])
    amplitudes = np.radians([0.01, 0.1, 1.0])
    tiny = 1e-7  # (within the threshold at these speeds)
    growth = np.array(
        [
            [-0.5, -0.5, -0.5],  # small motion grows: a stable cycle below the amplitudes searched
            [tiny, 0.3, 0.4],  # small motion decays, growth from 0.1 deg: a threshold below it
            [tiny, -tiny, tiny],  # neutral throughout (round-off changes sign: no cycle)
            [tiny, 0.3, 0.4],  # small motion grows, so do the amplitudes searched
            [0.2, 0.2, 0.2],  # small motion neutral, the amplitudes searched grow
        ]
    )
    small = np.array([0.1, -0.1, 0.0, 0.1, tiny])
    found = limit_cycles.LimitCycles(speeds, amplitudes, growth, small)
    assert found.stable_below_searched() == [0] and found.below_searched() == [1, 4]
    assert found.unbounded() == [3]
    assert found.verdict(0) == (
        "small motion grows to a stable cycle below 0.01 deg, the smallest searched (larger ones decay to it)"
    )
    assert found.verdict(
        1
    ) == "small motion decays; a threshold lies below 0.1 deg: a disturbance above it " + (
        "grows without bound"
    )
    assert found.verdict(2).startswith("neutral at every amplitude searched")
    assert found.verdict(3) == "grows from any disturbance"
    assert found.verdict(
        4
    ) == "small motion is neutral; from 0.01 deg, the smallest searched, a disturbance " + (
        "grows without bound"
    )
    s_i, _ = limit_cycles._crossings(growth, speeds)
    assert not len(s_i)  # (row 2's sign changes are within the threshold)


def test_a_study_names_the_speed_of_a_threshold_below_the_amplitudes_searched_from_a_sweep_at_rest():
    """A sweep from rest: its speed 0 has no cycle and is left out of the prediction, so the study's
    speeds are the prediction's own (they were the sweep's, one step too low)."""
    from groundres.studies.measures import cycle_measures

    text, source = case_text("hammond-relief-valve")
    text = text.replace("amplitude_min = 0.01 ", "amplitude_min = 5.0 ").replace("points = 100", "points = 6")
    text = text.replace("start = ", "start = 0.0 #", 1)
    case = parse_case(tomllib.loads(text), source, text)
    assert case.sweep.start == 0.0
    found = limit_cycles.predict(
        case, np.linspace(0.0, case.sweep.stop, 6), searched=case.limit_cycle.searched
    )
    below = [float(found.speeds[i]) for i in found.below_searched()]
    measures = cycle_measures(case)
    assert below and measures["smallest_threshold_speed"] == below[0]
