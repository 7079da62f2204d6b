"""Margins a designer acts on (groundres.assess.margins): the damping each mode keeps over the
operating range and the run-up, against a required damping ratio, and the growth margin.

References are independent of the margins code: the damping ratios of a dense sweep (the
analysis' own roots at 4001 speeds), and the exact minimum lag damping found by bisection
on the roots (groundres.assess.damping_search), where the growth margin must change sign.
"""

import dataclasses
import json
import tomllib

import numpy as np
import pytest
from click.testing import CliRunner

from conftest import HAMMOND_TOML
from groundres import analyze, load_case, parse_case
from groundres.cli import main
from groundres.errors import CaseError

#: The Hammond (1974) rotor on its hub with an operating range around the body-y tuning
#: speed (245.8 rpm) and a requirement, in rpm.
OPERATING = HAMMOND_TOML.replace(
    'start = 0.5\nstop = 40.0\npoints = 60\nunit = "rad/s"',
    'start = 5.0\nstop = 400.0\npoints = 200\nunit = "rpm"\n'
    "operating_start = 200.0\noperating_stop = 320.0\nrequired_damping_ratio = 0.01",
)


def case_of(text, **sweep):
    data = tomllib.loads(text)
    data["sweep"].update(sweep)
    return parse_case(data)


@pytest.mark.parametrize(
    "keys, words",
    [
        (
            {"operating_start": 500.0},
            ["[sweep] operating_start = 500.0", "from start (5.0) to stop (400.0) rpm"],
        ),
        ({"operating_stop": 2.0}, ["[sweep] operating_stop = 2.0", "inside the sweep"]),
        (
            {"operating_start": 320.0, "operating_stop": 200.0},
            ["[sweep] operating_start = 320.0", "below operating_stop"],
        ),
        ({"required_damping_ratio": 1.5}, ["[sweep] required_damping_ratio = 1.5", "from 0 to below 1"]),
        ({"required_damping_ratio": -0.01}, ["required_damping_ratio = -0.01"]),
    ],
)
def test_bad_margin_keys_are_named(keys, words):
    with pytest.raises(CaseError) as err:
        case_of(OPERATING, **keys)
    for word in words:
        assert word in str(err.value)


def test_the_operating_range_and_run_up_in_si():
    sweep = case_of(OPERATING).sweep
    rpm = 2 * np.pi / 60
    assert sweep.operating_range == pytest.approx((200 * rpm, 320 * rpm))
    assert sweep.run_up == pytest.approx((5 * rpm, 200 * rpm))
    whole = case_of(HAMMOND_TOML).sweep
    assert whole.operating_range == (whole.start, whole.stop) and whole.run_up is None


@pytest.fixture(scope="module")
def hammond():
    return analyze(case_of(OPERATING), lag_damping_search=False)


def test_roots_neutral_at_rest_are_not_the_least_damped_mode_at_low_speed(hammond):
    """The articulated lag roots are zero at rest; overdamped at low speed, one of each pair
    creeps towards zero (-0.0059 1/s at 5 rpm). The largest real part of all roots keeps it,
    marked as not vibrating; the margins leave it out."""
    m = hammond.margins
    assert set(m.neutral_at_rest) == {
        "collective lag",
        "regressive lag",
        "progressive lag",
        "differential lag",
    }
    value, at = hammond.stability.max_real_part
    assert at < 1.0 and -0.01 < value < 0
    summary = hammond.summary()
    assert summary["max_real_part"]["vibrating"] is False and "vibrating_note" in summary["max_real_part"]
    least_up = m.least("run_up")
    assert least_up[0] > 0.05, least_up  # (it was 0.011 at 5 rpm: the creeping root seen from turning axes)
    growth, where, mode = m.growth_margin
    assert mode == "regressive lag" and 20 < where < 30 and -0.5 < growth < -0.1


def test_a_hingeless_rotor_has_no_roots_neutral_at_rest():
    result = analyze(load_case("soft-inplane-damped"), lag_damping_search=False)
    assert result.margins.neutral_at_rest == ()
    assert result.margins.vibrating.all()


def test_least_damping_ratios_agree_with_a_dense_sweep(hammond):
    """Each mode's least damping ratio over the operating range, refined between the sweep's
    200 speeds, against the analysis' damping ratios at 4001 speeds across that range."""
    lo, hi = hammond.case.sweep.operating_range
    dense = analyze(
        dataclasses.replace(hammond.case), speeds=np.linspace(lo, hi, 4001), lag_damping_search=False
    )
    for margin in hammond.margins.modes:
        if margin.operating is None:
            continue
        j = dense.labels.index(margin.mode)
        if dense.modes.exchange[:, j].any():  # (a label that moves branch: its least lies at the exchange)
            continue
        ratios = dense.damping_ratio[:, j]
        k = int(np.argmin(ratios))
        # the refined value can only be lower than the dense grid's, by at most the grid's own error
        assert margin.operating.value <= ratios[k] + 1e-12, margin
        assert margin.operating.value == pytest.approx(ratios[k], rel=1e-5, abs=1e-9), margin
        assert margin.operating.speed == pytest.approx(dense.rotor_speed[k], abs=2 * (hi - lo) / 4000)


def test_verdicts_against_the_requirement(hammond):
    """Regressive lag keeps 1.77 % at 252 rpm: it meets 1 %, not 2 %; a failed damper makes
    the rotor unstable whatever is required."""
    m = hammond.margins
    least, at, mode = m.least("operating")
    assert mode == "regressive lag" and 0.017 < least < 0.018
    assert m.verdict == "meets the requirement" and m.margin == pytest.approx(least - 0.01)
    stricter = analyze(case_of(OPERATING, required_damping_ratio=0.02), lag_damping_search=False)
    assert stricter.margins.verdict == "stable but below it"
    by_mode = {x.mode: x.verdict for x in stricter.margins.modes}
    assert by_mode["regressive lag"] == "stable but below it" and by_mode["body x"] == "meets the requirement"
    failed = OPERATING.replace("[body]", "[[rotor.blade]]\nindex = 1\nlag_damping = 0.0\n[body]")
    broken = analyze(case_of(failed), lag_damping_search=False)
    assert broken.margins.verdict == "unstable"
    assert {x.mode for x in broken.margins.modes if x.grows} == {"regressive lag"}


@pytest.mark.parametrize("name", ["hammond-1974", "hammond-1974-one-damper"])
def test_the_growth_margin_changes_sign_at_the_exact_minimum_lag_damping(name):
    """Two independent routes to the stability boundary: the damping search bisects on the
    roots, the growth margin of the vibrating modes is continuous across it. Just above the
    exact minimum every vibrating mode decays, just below one grows."""
    case = load_case(name)
    if name == "hammond-1974-one-damper":  # (stiffer hub damping: a finite minimum exists)
        body = dataclasses.replace(
            case.body, damping_x=2 * case.body.damping_x, damping_y=2 * case.body.damping_y
        )
        case = dataclasses.replace(case, body=body, sweep=dataclasses.replace(case.sweep, points=60))
    exact = analyze(case).exact_lag_damping
    assert exact and exact > 0
    rtol = 2e-3 if name.endswith("one-damper") else 2e-4

    def growth(c_lag):
        blades = tuple(
            dataclasses.replace(b, lag_damping=c_lag) if b.lag_damping > 0 else b for b in case.rotor.blades
        )
        varied = dataclasses.replace(case, rotor=dataclasses.replace(case.rotor, blades=blades))
        return analyze(varied, lag_damping_search=False).margins.growth_margin[0]

    above, below = growth(exact * (1 + rtol)), growth(exact * (1 - rtol))
    assert below > 0 > above or abs(above) < 1e-6, (below, above)
    assert abs(above) < 0.01 and abs(below) < 0.01  # (continuous: both near zero)


def run(*args):
    return CliRunner().invoke(main, [str(a) for a in args], catch_exceptions=False)


def test_terminal_and_summary_show_margins_and_open_ranges(tmp_path):
    """A five-bladed soft in-plane rotor on a pitch-roll body swept to 350 rpm, unstable up to
    the sweep's stop: the range is marked open there, the Deutsch table says the rotor is
    unstable above its per-mode verdicts, and the margins table gives every mode's verdict."""
    text = load_case("soft-inplane-pitch-roll").text
    text = text.replace("blades = 3", "blades = 5").replace("lag_damping = 0.0", "lag_damping = 1500.0")
    text = text.replace(
        "stiffness_roll = 102425.0",
        "stiffness_roll = 102425.0\ndamping_pitch = 20000.0\ndamping_roll = 10000.0",
    )
    text = text.replace("stop = 400.0", "stop = 350.0")
    path = tmp_path / "five.toml"
    path.write_text(text)
    result = run("run", path, "--out", tmp_path / "out")
    assert result.exit_code == 0, result.output
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    last = summary["unstable_ranges"][-1]
    assert last["open_end"] is True and "sweep's stop" in last["end_note"]
    out = " ".join(result.output.split())
    assert ">= 350 (2.258 ref)" in out and "the range may continue above it" in out
    assert "Note: the analysis finds the rotor unstable" in out
    assert out.index("Note: the analysis finds the rotor unstable") < out.index("Lag damping by the Deutsch")
    assert summary["lag_damping"]["deutsch_overall"].startswith("the analysis finds the rotor unstable")
    margins = summary["margins"]
    assert margins["verdict"] == "unstable" and "Damping of each mode over the sweep" in out
    assert {m["mode"]: m["verdict"] for m in margins["modes"]}["regressive lag"] == "unstable"


def test_a_stable_case_has_no_deutsch_caveat(hammond):
    assert "deutsch_overall" not in hammond.summary()["lag_damping"]


def test_a_mode_that_grows_only_between_the_sweeps_speeds_shows_its_growth():
    """The soft in-plane rotor on its pitch-roll body, swept from 30 to 120 rpm (0.9375 rpm
    apart), has one flap-lag instability, about 0.1 rpm wide near 88.9 rpm, between two of the
    sweep's speeds. The range names the mode that grows at its peak as identified there on its
    own, as a dense sweep across the range names it; that mode's least damping ratio and largest
    real part are searched inside the range, so that its row reads negative where its verdict
    reads unstable. Reference: the analysis' own roots at 2001 speeds across the range
    (independent of the margins' search), to the golden section's tolerance."""
    data = tomllib.loads(load_case("soft-inplane-pitch-roll").text)
    data["sweep"].update(start=30.0, stop=120.0, points=97)
    case = parse_case(data)
    result = analyze(case, lag_damping_search=False)
    [(start, end)] = result.stability.unstable_ranges
    assert end - start < 0.2 and not ((result.rotor_speed >= start) & (result.rotor_speed <= end)).any()
    dense = analyze(case, speeds=np.linspace(start, end, 2001), lag_damping_search=False)
    peak = int(np.argmax(dense.real_part.max(axis=1)))
    grower = dense.labels[int(np.argmax(dense.real_part[peak]))]
    assert result.unstable_modes(start, end) == [grower]
    row = next(m for m in result.margins.modes if m.mode == grower)
    assert row.verdict == "unstable" and row.grows
    assert row.operating.value < 0 and not row.operating.neutral
    assert row.operating.value == pytest.approx(dense.damping_ratio.min(), rel=1e-4)
    assert row.largest_real_part.value == pytest.approx(dense.real_part.max(), rel=1e-4)
    assert start <= row.operating.speed <= end
    assert result.margins.growth_margin[0] == pytest.approx(dense.real_part.max(), rel=1e-4)


def test_a_coarse_periodic_sweep_from_rest_still_sees_the_resonance():
    """The Hammond rotor with one damper inoperative swept from rest to 1e7 rpm in 400 speeds
    (25,000 rpm apart): the resonance lies between the sweep's first two speeds. The tuning
    speeds' probes are kept whatever the spacing, so the unstable range, its growing mode and
    the worst values are those of the shipped case's dense sweep (5 to 400 rpm; the same
    rotor), to the refinements' tolerance (ends 1e-8, extremes 1e-4 of the speed)."""
    text = load_case("hammond-1974-one-damper").text
    data = tomllib.loads(text)
    data["sweep"].update(start=0.0, stop=1e7, points=400)
    coarse = analyze(parse_case(data), lag_damping_search=False)
    shipped = analyze(load_case("hammond-1974-one-damper"), lag_damping_search=False)
    (a, b), (c, d) = coarse.stability.unstable_ranges[0], shipped.stability.unstable_ranges[0]
    assert len(coarse.stability.unstable_ranges) == 1
    assert (a, b) == pytest.approx((c, d), rel=1e-6)
    assert coarse.unstable_modes(a, b) == shipped.unstable_modes(c, d) == ["regressive lag"]
    assert coarse.stability.max_real_part[0] == pytest.approx(shipped.stability.max_real_part[0], rel=1e-6)
    assert coarse.stability.min_damping_ratio[0] == pytest.approx(
        shipped.stability.min_damping_ratio[0], rel=1e-4
    )
    summary = coarse.summary()
    assert summary["max_real_part"]["mode"] == "regressive lag" and summary["max_real_part"]["vibrating"]
    assert not summary["min_damping_ratio"]["neutral"]


def test_golden_section_stops_at_its_tolerance_of_the_bracket_s_upper_speed():
    """A minimum at the lower end of [0.001, 10] rad/s (a margin that closes on rest, where a periodic
    analysis costs most): the search stops once its bracket is 1e-4 of 10 rad/s wide, not 1e-4 of
    the 0.001 rad/s it closes on (three times the evaluations, each the dearest of the sweep)."""
    import numpy as np

    from groundres.assess.refine import golden

    calls = []

    def f(x):
        calls.append(1)
        return np.asarray(x, float).copy()

    value, at = golden(f, np.array([0.001]), np.array([10.0]), 1e-4)
    assert at[0] - 0.001 <= 1e-4 * 10.0 and value[0] == at[0]
    assert len(calls) <= 2 + int(np.ceil(np.log(1e-4) / np.log(0.618))) + 1
