"""Runs of the nonlinear equations for a user (issue 26, item 5): `groundres simulate` with the
laws, the threshold search, `[simulation]`, and `[limit_cycle] confirm` in `groundres cycles`.

The physics of a run (the equations with the laws, the measure, the settled cycles against the
prediction) is checked in tests/test_nonlinear.py; here: what a user gives and reads. The runs
are on hammond-relief-valve at 264.34 rpm, where its smallest threshold, 2.38 deg, sits: below
it a run decays, above it the run grows until a blade passes 90 deg, where it stops.
"""

import json
import math
import tomllib

import pytest
from click.testing import CliRunner

from groundres import run_nonlinear, search_threshold
from groundres.cli import main
from groundres.errors import CaseError
from groundres.model.casefile import case_text
from groundres.model.schema import load_case, parse_case

RPM = 2 * math.pi / 60
SPEED = 264.34 * RPM


def _cli(*args):
    return CliRunner().invoke(main, list(args))


def _simulate(out, *options):
    """groundres simulate on hammond-relief-valve at its smallest threshold's speed, 20 s runs."""
    return _cli(
        "simulate", "hammond-relief-valve", "--speed", "264.34", *options, "--time", "20", "--out", str(out)
    )


def _text(extra: str = "", case: str = "hammond-relief-valve") -> str:
    text, _ = case_text(case)
    return text + extra


def _file(tmp_path, extra: str = "", case: str = "hammond-relief-valve") -> str:
    path = tmp_path / "case.toml"
    path.write_text(_text(extra, case))
    return str(path)


@pytest.fixture(scope="module")
def relief():
    return load_case("hammond-relief-valve")


def test_a_run_along_a_threshold_decays_below_it_and_grows_above_it_until_it_stops(relief):
    below = run_nonlinear(relief, SPEED, along_cycle=0.9, duration=30.0)
    assert below.measured.verdict == "decays" and below.history.stopped is None
    assert len(below.predicted) == 1 and not below.predicted[0].stable
    above = run_nonlinear(relief, SPEED, along_cycle=1.1, duration=30.0)
    assert above.measured.verdict == "grows" and above.history.stopped is not None
    assert above.history.stopped < 30.0 and "where the run stopped" in above.words()
    data = above.to_dict()
    assert data["stopped"] == above.history.stopped and data["verdict"] == "grows"
    assert json.loads(json.dumps(data, allow_nan=False))["predicted"][0]["amplitude"] == pytest.approx(
        2.38, abs=0.01
    )


def test_motion_that_decays_to_the_integration_s_resolution_is_not_printed_as_a_result(relief):
    run = run_nonlinear(relief, SPEED, along_cycle=0.5, duration=80.0)
    assert not run.resolved and "resolution" in run.words()
    data = run.to_dict()
    assert data["amplitude"] is None and data["blades"] is None and data["hub"] is None


def test_the_simulation_table_sets_the_start_the_duration_and_the_window():
    text = _text(
        "\n[simulation]\nduration = 12.0\nwindow = 3.0\n\n[simulation.initial]\nx = 0.002\nlag2 = 0.01\n"
    )
    case = parse_case(tomllib.loads(text), "relief", text)
    assert case.simulation.initial == (("x", 0.002), ("lag2", 0.01))
    run = run_nonlinear(case, SPEED)
    assert run.time[-1] == pytest.approx(12.0) and run.measured.window == 3.0
    assert run.start == "x = 0.002 m, lag2 = 0.01 rad"


@pytest.mark.parametrize(
    "extra, words",
    [
        ("\n[simulation]\nduration = -1.0\n", ["[simulation] duration = -1.0", "> 0 and at most 3600"]),
        (
            "\n[simulation]\nduration = 10.0\nwindow = 6.0\n",
            ["[simulation] window = 6.0", "half the duration"],
        ),
        ("\n[simulation]\nalong_cycle = 0.0\n", ["[simulation] along_cycle = 0.0", "> 0"]),
        ("\n[simulation]\nspeed = 3.0\n", ["unknown key 'speed'", "[simulation]"]),
        ("\n[simulation.initial]\nx = 2.0\n", ["[simulation.initial] x = 2.0", "small angles"]),
        ('\n[simulation.initial]\nx = "far"\n', ["[simulation.initial] x = 'far'", "must be a number"]),
        ("\n[simulation]\nalong_cycle = 1.1\n[simulation.initial]\nx = 0.01\n", ["along_cycle", "either"]),
    ],
)
def test_a_bad_simulation_table_is_refused_naming_the_key(tmp_path, extra, words):
    result = _cli("simulate", _file(tmp_path, extra), "--speed", "264.34", "--out", str(tmp_path / "out"))
    assert result.exit_code == 2, result.output
    text = " ".join(result.output.split())
    assert all(w in text for w in words), text
    assert "Traceback" not in result.output and not (tmp_path / "out").exists()


def test_confirm_speeds_are_in_the_sweep_s_unit_and_bounded(tmp_path):
    text = _text("confirm = [264.34, 300.0]\n")  # (the case's [limit_cycle] table is last in the file)
    case = parse_case(tomllib.loads(text), "relief", text)
    assert case.limit_cycle.confirm == pytest.approx((264.34 * RPM, 300.0 * RPM))
    result = _cli(
        "cycles", _file(tmp_path, "confirm = [1.0, 2, 3, 4, 5, 6, 7, 8, 9]\n"), "--out", str(tmp_path / "o")
    )
    assert result.exit_code == 2 and "[limit_cycle] confirm" in result.output and "at most 8" in result.output


def test_groundres_simulate_runs_the_laws_and_writes_what_the_run_shows(tmp_path):
    out = tmp_path / "out"
    result = _simulate(out, "--along", "0.9")
    assert result.exit_code == 0, result.output
    assert {p.name for p in out.iterdir()} == {
        "simulation.png",
        "simulation.csv",
        "nonlinear.json",
        "case.toml",
        "provenance.json",
    }
    data = json.loads((out / "nonlinear.json").read_text())
    assert data["verdict"] == "decays" and data["start"].startswith(
        "0.9 times the predicted threshold of 2.38 deg"
    )
    assert "predicted threshold: 2.38 deg" in result.output and "evaluations" in result.output


def test_groundres_simulate_brackets_a_threshold(tmp_path):
    out = tmp_path / "out"
    result = _simulate(out, "--threshold", "--steps", "0")
    assert result.exit_code == 0, result.output
    data = json.loads((out / "threshold.json").read_text())
    assert (data["below_at"], data["beyond_at"]) == (0.8, 1.25)
    assert data["bracket"] == pytest.approx([0.8 * data["predicted"], 1.25 * data["predicted"]])
    assert "simulated threshold lies between 0.8 and 1.25 times the predicted 2.38 deg" in " ".join(
        result.output.split()
    )


@pytest.mark.parametrize(
    "args, words",
    [
        (["hammond-1974", "--speed", "30", "--along", "1.1"], ["--along", "nonlinear lag dampers"]),
        (["hammond-relief-valve", "--speed", "100", "--along", "1.1"], ["--along = 1.1", "no limit cycle"]),
        (["hammond-relief-valve", "--speed", "100", "--threshold"], ["--speed", "no threshold is predicted"]),
        (
            ["hammond-relief-valve", "--speed", "264.34", "--threshold", "--along", "1.1"],
            ["leave out --along"],
        ),
        (
            ["hammond-relief-valve", "--speed", "264.34", "--threshold", "--steps", "40"],
            ["--steps = 40", "0 to 12"],
        ),
        (
            ["hammond-relief-valve", "--speed", "264.34", "--time", "10", "--window", "6"],
            ["--window = 6.0", "half"],
        ),
        (["hammond-relief-valve", "--speed", "264.34", "--initial", "x=3"], ["--initial", "+-1"]),
        (["hammond-relief-valve", "--speed", "264.34", "--steps", "3"], ["--steps 3", "give --threshold"]),
        (["hammond-1974", "--speed", "30", "--steps", "3"], ["--steps need nonlinear lag dampers"]),
        (["hammond-relief-valve", "--speed", "264.34", "--time", "0"], ["--time = 0.0", "> 0 and at most"]),
    ],
)
def test_groundres_simulate_refuses_what_a_nonlinear_run_cannot_do(tmp_path, args, words):
    """Each value named where it came from: the command line's option."""
    result = _cli("simulate", *args, "--out", str(tmp_path / "out"))
    assert result.exit_code == 2, result.output
    text = " ".join(result.output.split())
    assert all(w in text for w in words), text
    assert "Traceback" not in result.output and not (tmp_path / "out").exists()


def test_a_table_law_cannot_be_run_and_says_why(tmp_path):
    law = (
        '\n[rotor.lag_damper]\nlaw = "table"\namplitudes = [0.1, 1.0]\nstorage_stiffness = [1e4, 8e3]\n'
        "loss_stiffness = [2e4, 3e4]\nreference_frequency = 1.0\n"
    )
    text, _ = case_text("hammond-1974")
    path = tmp_path / "case.toml"
    path.write_text(text.replace("lag_damping = 4067.5           # [N m s/rad]", "") + law)
    result = _cli("simulate", str(path), "--speed", "260", "--out", str(tmp_path / "out"))
    assert result.exit_code == 2 and "cannot be simulated" in " ".join(result.output.split())
    # confirming runs asked for in the case file: refused as the case is read, before any work
    path.write_text(path.read_text() + "\n[limit_cycle]\nconfirm = [260.0]\n")
    result = _cli("cycles", str(path), "--out", str(tmp_path / "cycles"))
    said = " ".join(result.output.split())
    assert result.exit_code == 2 and "[limit_cycle] confirm = [260.0]" in said and 'law = "table"' in said
    assert "Traceback" not in result.output and not (tmp_path / "cycles").exists()


def test_groundres_cycles_confirms_the_listed_speeds_by_simulation(tmp_path):
    """264.34 rpm: the smallest threshold, confirmed; 100 rpm: no cycle, said so (it was dropped)."""
    path = _file(tmp_path, "confirm = [264.34, 100.0]\n\n[simulation]\nduration = 20.0\n")
    text = (tmp_path / "case.toml").read_text().replace("points = 100", "points = 4")
    (tmp_path / "case.toml").write_text(text)
    out = tmp_path / "out"
    result = _cli("cycles", path, "--out", str(out))
    assert result.exit_code == 0, result.output
    none, entry = json.loads((out / "limit_cycles.json").read_text())["confirmations"]
    assert entry["confirmed"] and not entry["stable"]
    assert [r["verdict"] for r in entry["runs"]] == ["decays", "grows"]
    assert [r["beyond"] for r in entry["runs"]] == [False, True]
    said = " ".join(result.output.split())
    assert (
        "the threshold of 2.38 deg is confirmed: 0.8 times it decays (stays below it), 1.25 times it" in said
    )
    assert "grows past 90 deg, where it stopped at" in said and " s (heads beyond it)" in said
    assert none["speed"] == pytest.approx(100 * RPM) and none["runs"] == [] and none["confirmed"] is None
    assert "at 100 rpm" in said and "no cycle is predicted (decays from any disturbance searched)" in said


def test_a_run_below_a_threshold_that_settles_on_the_stable_cycle_under_it_stays_below_it():
    """hammond-friction-link at 212 rpm: a stable cycle of 1.11 deg under a threshold of 1.94 deg.
    The run from 0.8 times the threshold settles on the stable cycle (1.116 deg measured over
    35 s): it stays below the threshold, as a decaying run does (it was read as "did not decay"
    and the threshold as not confirmed)."""
    from groundres.assess.confirm import confirm
    from groundres.assess.limit_cycles import predict

    case = load_case("hammond-friction-link")
    found = predict(case, [212 * RPM])
    (under,), (cycle,) = ([c for c in found.cycles if c.stable is s] for s in (True, False))
    assert math.degrees(cycle.amplitude) == pytest.approx(1.94, abs=0.01)
    entry = confirm(case, cycle, 35.0, others=[under])
    below, above = entry["runs"]
    assert below["verdict"] == "settled" and below["amplitude"] == pytest.approx(
        math.degrees(under.amplitude), rel=0.02
    )
    assert not below["beyond"] and above["beyond"] and entry["confirmed"]


def test_where_a_run_heads_decides_its_side_of_a_threshold():
    """A settled run stays where it is; a growing one heads to the nearest stable cycle above it
    (or without bound), a decaying one to the nearest below (or rest)."""
    from types import SimpleNamespace

    from groundres.assess.confirm import beyond, destination

    def run(verdict, amplitude):
        return SimpleNamespace(verdict=verdict, amplitude=amplitude)

    stable = [1.0, 5.0]
    assert destination(run("settled", 1.1), stable) == 1.1
    assert destination(run("grows", 2.5), stable) == 5.0
    assert destination(run("grows", 6.0), stable) == math.inf
    assert destination(run("decays", 2.5), stable) == 1.0
    assert destination(run("decays", 0.5), stable) == 0.0
    threshold = 2.0
    assert not beyond(run("settled", 1.1), threshold, stable)
    assert beyond(run("decays", 5.5), threshold, stable)
    assert beyond(run("grows", 1.5), threshold, []) and not beyond(run("grows", 0.5), threshold, stable)


def test_a_measuring_window_over_half_the_run_is_cut_to_half():
    """Two windows of more than half a run: the earlier one was empty and read as 0, so a settled
    oscillation was said to grow."""
    from types import SimpleNamespace

    import numpy as np

    from groundres.assess.confirm import measure

    time = np.linspace(0.0, 10.0, 2001)
    lag = 0.01 * np.sin(6.0 * time)
    history = SimpleNamespace(
        time=time,
        lag=lambda k: lag,
        coordinates=[SimpleNamespace(kind="lag", short="lag1")],
        displacement=lag[:, None],
        stopped=None,
        atol=1e-10,
    )
    measured = measure(history, 8.0)
    assert measured.window == 5.0 and measured.verdict == "settled"
    assert measured.amplitude == pytest.approx(0.01, rel=1e-3)


def test_search_threshold_names_the_bracket(relief):
    cycle, bracket = search_threshold(relief, SPEED, steps=1, duration=20.0)
    assert not cycle.stable and bracket[0] < bracket[1] and bracket[0] >= 0.8 and bracket[1] <= 1.25


def test_a_stable_cycle_s_confirming_run_starts_below_a_threshold_over_it():
    """hammond-friction-link with blade 1's damper failed, at 160.6 rpm: a stable cycle of 3.82 deg
    (blade 1) with a threshold at 5.74 deg just above; 1.5 times the cycle is beyond the threshold
    (a run from there grows), so a confirming run starts halfway to it on a log scale."""
    from types import SimpleNamespace

    from groundres.assess.confirm import ABOVE, BELOW, stable_start

    cycle = SimpleNamespace(amplitude=1.0)
    assert stable_start(cycle) == ABOVE
    assert stable_start(cycle, [SimpleNamespace(amplitude=1.5)]) == pytest.approx(math.sqrt(1.5))
    assert stable_start(cycle, [SimpleNamespace(amplitude=1.05), SimpleNamespace(amplitude=0.5)]) == BELOW
    assert stable_start(
        cycle, [SimpleNamespace(amplitude=1.05), SimpleNamespace(amplitude=0.9)]
    ) == pytest.approx(math.sqrt(0.9))


def test_a_value_from_the_case_file_is_named_as_the_case_file_s_key(tmp_path):
    """--time 20 with [simulation] window = 30 from the file: the error names the file's key (it
    said --window, which was never given)."""
    path = _file(tmp_path, "\n[simulation]\nwindow = 30.0\n")
    result = _cli("simulate", path, "--speed", "264.34", "--time", "20", "--out", str(tmp_path / "out"))
    said = " ".join(result.output.split())
    assert result.exit_code == 2 and "[simulation] window = 30.0" in said and "at most 10" in said
    assert "--window" not in said and not (tmp_path / "out").exists()


def test_a_run_that_passed_90_deg_heads_without_bound_whatever_it_measured():
    """A run stopped within its first samples measures 0 over its last window: it still heads
    beyond any threshold (it once counted as settling on a stable cycle below), and a stable
    cycle's confirmation with it is 'not confirmed', not a crash on log(0)."""
    from types import SimpleNamespace

    from groundres.assess.confirm import beyond, destination

    stopped = SimpleNamespace(verdict="grows", amplitude=0.0, history=SimpleNamespace(stopped=0.03))
    assert destination(stopped, [0.02]) == math.inf and beyond(stopped, 0.05, [0.02])


def test_a_confirmation_says_where_every_run_heads_and_that_a_stopped_run_passed_90_deg():
    """Each run of a threshold's confirmation says its side, whatever its verdict; a stable
    cycle's run that stopped past 90 deg says so (it said 'grows, 0 deg at its end (-1e+02 %)')."""
    from groundres.model.schema import load_case
    from groundres.results.limit_cycles import LimitCycleResult

    found = LimitCycleResult(load_case("hammond-relief-valve"), None)
    run = {"verdict": "grows", "amplitude": 0.0, "stopped": 2.5, "factor": 1.25}
    stable = {
        "speed": 27.7,
        "stable": True,
        "predicted": 3.0,
        "confirmed": False,
        "error": -1.0,
        "runs": [run],
    }
    said = found.confirmation_words(stable)
    assert "the run grows past 90 deg, where it stopped at 2.5 s" in said and "%" not in said
    below = {"verdict": "settled", "amplitude": 1.0, "stopped": None, "factor": 0.8, "beyond": False}
    threshold = {**stable, "stable": False, "confirmed": True, "runs": [below, {**run, "beyond": True}]}
    said = found.confirmation_words(threshold)
    assert "0.8 times it settles at 1 deg (stays below it)" in said
    assert "1.25 times it grows past 90 deg, where it stopped at 2.5 s (heads beyond it)" in said


def test_a_run_too_short_for_its_motion_is_refused_naming_the_key(tmp_path):
    """--time 0.01 gave a verdict from windows holding no period of the motion: a run lasts at
    least ten periods, each window at least two, and a confirmation's [simulation] duration is
    held to the same."""

    def said(*options):
        args = (
            "simulate",
            "hammond-relief-valve",
            "--speed",
            "264.34",
            *options,
            "--out",
            str(tmp_path / "o"),
        )
        result = _cli(*args)
        assert result.exit_code == 2 and "Traceback" not in result.output
        return " ".join(result.output.split())

    text = said("--time", "0.01")
    assert "--time = 0.01" in text and "10 periods of the motion at 264.34 rpm" in text
    text = said("--time", "30", "--window", "0.2")
    assert "--window = 0.2" in text and "2 periods" in text and "--time" not in text
    path = _file(tmp_path, "confirm = [264.34]\n\n[simulation]\nduration = 1.0\n")
    result = _cli("cycles", path, "--out", str(tmp_path / "out"))
    text = " ".join(result.output.split())
    assert result.exit_code == 2 and "[simulation] duration = 1.0" in text and "Traceback" not in text
    assert not (tmp_path / "out").exists()


def test_a_confirm_speed_is_listed_once():
    text = _text("confirm = [264.34, 264.34]\n")
    with pytest.raises(
        CaseError, match=r"\[limit_cycle\] confirm = \[264.34, 264.34\]: must list each speed once"
    ):
        parse_case(tomllib.loads(text), "relief", text)


def test_a_run_that_settles_far_from_every_stable_cycle_is_undecided():
    """At 5000 rpm a 4.7 s run (120 periods of the blade's motion) from 0.8 and 1.25 times a
    threshold barely moved and read 'settles', both sides, and the threshold was 'confirmed'. A
    run that settles farther than a factor 1.25 from every predicted stable cycle changes too
    slowly to tell: undecided, and the cycle is not confirmed."""
    from types import SimpleNamespace

    from groundres.assess.confirm import run_words, undecided

    def run(level, verdict="settled"):
        return SimpleNamespace(verdict=verdict, amplitude=level)

    assert undecided(run(2.93), []) and undecided(run(1.0), [1.3])
    assert not undecided(run(1.0), [1.2]) and not undecided(run(1.0, "grows"), [])
    said = run_words({"verdict": "settled", "amplitude": 2.93, "undecided": True})
    assert said.startswith("barely changes, 2.93 deg at its end") and "lengthen [simulation] duration" in said
