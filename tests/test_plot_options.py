"""Picture formats and the Coleman diagram's options (docs/case-files.md, command line)."""

import json
import tomllib

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402
from click.testing import CliRunner  # noqa: E402
from matplotlib import cbook  # noqa: E402

import groundres  # noqa: E402
from conftest import HAMMOND_TOML  # noqa: E402
from groundres.cli import main  # noqa: E402
from groundres.cli.plotoptions import SPEED_AXES  # noqa: E402
from groundres.model.casefile import shipped_cases  # noqa: E402
from groundres.plotting import axes, coleman  # noqa: E402
from groundres.plotting.titles import figure_title  # noqa: E402

#: Figure 3's case (two unstable ranges, a reference speed) on 40 speeds: fast.
UNDAMPED = shipped_cases()["hammond-undamped"].replace("points = 400", "points = 40")
#: A damped case in rad/s without a reference speed.
NO_REFERENCE = HAMMOND_TOML.replace("points = 60", "points = 40")
#: The first bytes of each format.
MAGIC = {"png": (b"\x89PNG",), "svg": (b"<?xml", b"<svg"), "pdf": (b"%PDF",)}


def run(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


def case_file(tmp_path, text=UNDAMPED, name="case.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.fixture(scope="module")
def undamped():
    return groundres.analyze(parse(UNDAMPED), lag_damping_search=False)


def parse(text):
    return groundres.parse_case(tomllib.loads(text), "case.toml", text)


def legend_texts(fig):
    return [t.get_text() for leg in fig.legends for t in leg.get_texts()]


@pytest.mark.parametrize("fmt", ["svg", "pdf"])
def test_run_writes_the_diagram_in_the_format_asked(tmp_path, fmt):
    out = tmp_path / "out"
    result = run("run", case_file(tmp_path), "--out", out, "--format", fmt)
    assert result.exit_code == 0, result.output
    picture = out / f"coleman.{fmt}"
    assert picture.read_bytes().startswith(MAGIC[fmt])
    assert not (out / "coleman.png").exists()
    assert f"coleman.{fmt}" in result.output
    assert f"coleman.{fmt}" in json.loads((out / "provenance.json").read_text())["files"]


def test_compare_simulate_and_phasors_follow_format(tmp_path):
    case = case_file(tmp_path)
    result = run("compare", case, case, "--out", tmp_path / "c", "--format", "pdf")
    assert result.exit_code == 0, result.output
    assert (tmp_path / "c" / "compare.pdf").read_bytes().startswith(MAGIC["pdf"])
    assert "compare.pdf" in result.output
    result = run("simulate", case, "--speed", 250, "--time", 3, "--out", tmp_path / "s", "--format", "svg")
    assert result.exit_code == 0, result.output
    assert (tmp_path / "s" / "simulation.svg").read_bytes().startswith(MAGIC["svg"])
    assert "simulation.svg" in result.output
    phasors = ["phasors", case, "--speed", 250, "--mode", "regressive lag", "--out", tmp_path / "p"]
    result = run(*phasors, "--format", "svg", "--no-gif")  # (the GIFs take seconds: GIF whatever --format)
    assert result.exit_code == 0, result.output
    assert (tmp_path / "p" / "phasors_regressive-lag.svg").read_bytes().startswith(MAGIC["svg"])
    assert "phasors_*.svg" in result.output


def test_a_study_folder_may_hold_its_map_in_any_format():
    from groundres.cli.study import STUDY_FILES

    assert {"map.png", "map.svg", "map.pdf"} <= STUDY_FILES


@pytest.mark.parametrize(
    "option, value, words",
    [
        ("--frequency-limits", "3:1", ["LOW must be below HIGH"]),
        ("--frequency-limits", "2:2", ["LOW must be below HIGH"]),
        ("--frequency-limits", "1", ["not two numbers"]),
        ("--frequency-limits", "a:b", ["not two numbers"]),
        ("--frequency-limits", "1:2:3", ["not two numbers"]),
        ("--real-limits", "nan:1", ["finite"]),
        ("--real-limits", "-1:inf", ["finite"]),
        ("--real-limits", "", ["not two numbers"]),
        ("--modes", "body z", ["not a mode", "regressive lag", "body x"]),
        ("--speed-axis", "normalised", ["no [sweep] reference", "auto", "unit"]),
    ],
)
@pytest.mark.parametrize("command", ["run", "compare"])
def test_bad_plot_options_exit_2_with_one_line(tmp_path, command, option, value, words):
    case = case_file(tmp_path, NO_REFERENCE)
    out = tmp_path / "out"
    cases = [case] if command == "run" else [case, case]
    result = run(command, *cases, "--out", out, option, value)
    assert result.exit_code == 2, result.output
    assert "Traceback" not in result.output
    assert len(result.output.strip().splitlines()) == 1, result.output
    assert option in result.output and value in result.output
    for word in words:
        assert word in result.output, (word, result.output)
    assert not out.exists()


def test_good_plot_options_run(tmp_path):
    out = tmp_path / "out"
    result = run(
        "run",
        case_file(tmp_path),
        "--out",
        out,
        "--speed-axis",
        "unit",
        "--frequency-limits",
        "0:300",
        "--real-limits",
        "-0.5:2",  # (a value that starts with a minus sign is a value, not an option)
        "--modes",
        "regressive lag",
        "--modes",
        "body x",
    )
    assert result.exit_code == 0, result.output
    assert (out / "coleman.png").read_bytes()[:4] == b"\x89PNG"


def test_modes_restrict_the_legend_and_the_lines(undamped):
    every = coleman.coleman_diagram(undamped)
    fig = coleman.coleman_diagram(undamped, modes=["regressive lag", "body x"])
    texts = legend_texts(fig)
    assert "regressive lag" in texts and "body x" in texts
    assert not {"body y", "progressive lag", "collective lag", "differential lag"} & set(texts)
    assert {"body y", "progressive lag"} <= set(legend_texts(every))
    grey = coleman.label_colour("body y")
    assert not any(line.get_color() == grey for ax in fig.axes for line in ax.get_lines())
    assert any(line.get_color() == grey for ax in every.axes for line in ax.get_lines())
    assert "unstable range" in texts  # the bands show whichever modes are drawn
    with pytest.raises(ValueError, match="body z"):
        undamped.plot(modes=["body z"])


def test_speed_axis_and_limits(undamped):
    auto = undamped.plot()
    assert auto.axes[-1].get_xlabel().startswith("rotor speed / reference")
    unit = undamped.plot(speed_axis="unit")
    assert unit.axes[-1].get_xlabel() == "rotor speed [rpm]"
    assert "[cycles/min]" in unit.axes[0].get_ylabel()
    assert unit.axes[0].get_xlim()[1] == pytest.approx(400.0)
    fig = undamped.plot(frequency_limits=(0.5, 1.5), real_limits=(-0.25, 0.5))
    assert fig.axes[0].get_ylim() == (0.5, 1.5) and fig.axes[1].get_ylim() == (-0.25, 0.5)
    ratio = undamped.plot(show_damping_ratio=True, real_limits=(-0.01, 0.02))
    assert ratio.axes[1].get_ylim() == (-0.01, 0.02) and ratio.axes[1].get_ylabel() == "damping ratio [-]"
    for bad in ((2, 1), (0, np.nan), (1,), "0:1"):
        with pytest.raises(ValueError, match="frequency_limits"):
            undamped.plot(frequency_limits=bad)
    with pytest.raises(ValueError, match="speed_axis"):
        undamped.plot(speed_axis="rpm")


def test_normalised_needs_a_reference():
    result = groundres.analyze(parse(NO_REFERENCE), lag_damping_search=False)
    assert result.plot().axes[-1].get_xlabel() == "rotor speed [rad/s]"
    with pytest.raises(ValueError, match="no \\[sweep\\] reference"):
        result.plot(speed_axis="normalised")


def test_the_overlay_takes_the_same_options(undamped):
    comparison = groundres.compare([undamped.case, undamped.case])
    fig = comparison.plot(modes=["regressive lag"], frequency_limits=(0, 2), speed_axis="normalised")
    texts = legend_texts(fig)
    assert "regressive lag" in texts and "body x" not in texts
    assert fig.axes[0].get_ylim() == (0, 2)
    assert comparison.plot(speed_axis="unit").axes[-1].get_xlabel() == "rotor speed [rpm]"


def test_the_command_line_offers_the_plot_module_s_speed_axes():
    assert SPEED_AXES == axes.SPEED_AXES


#: A title matplotlib would read as mathtext between its dollars, and fail on
#: (an unknown command, a lone superscript): shown as typed instead.
DOLLAR_TITLE = r"Rotor $\frac{1}{2}$ test at $\foo$, cost $5 and $^$"


def test_a_title_or_name_with_dollar_signs_shows_as_typed(tmp_path):
    text = run("cases", "hammond-1974").output
    assert text.startswith("title = ") and "points = 400\n" in text
    text = f"title = '{DOLLAR_TITLE}'" + text[text.index("\n") :]
    text = text.replace("points = 400", "points = 20")
    assert tomllib.loads(text)["title"] == DOLLAR_TITLE and tomllib.loads(text)["sweep"]["points"] == 20
    path = case_file(tmp_path, text, name=r"rotor $x$ $\foo$.toml")
    out = tmp_path / "out"
    result = run("run", path, "--out", out)
    assert result.exit_code == 0, result.output
    assert (out / "coleman.png").read_bytes().startswith(MAGIC["png"][0])
    shown = figure_title(DOLLAR_TITLE)
    assert not cbook.is_math_text(shown) and shown.replace(r"\$", "$") == DOLLAR_TITLE
    # the overlay: the case's title, and its file's stem in the legend
    result = run("compare", path, path, "--out", tmp_path / "compare")
    assert result.exit_code == 0, result.output
    fig = groundres.compare([str(path), str(path)]).plot()
    assert not any(cbook.is_math_text(t) for t in legend_texts(fig))
    assert any(t.replace(r"\$", "$").endswith(r"rotor $x$ $\foo$") for t in legend_texts(fig))
