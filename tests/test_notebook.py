"""The results in a notebook: short repr, HTML repr, plot into the caller's axes or subfigure,
tidy rows in the case's unit."""

import math
import tomllib

import matplotlib
import numpy as np
import pandas as pd
import pytest
from matplotlib.figure import Figure

import groundres
from conftest import HAMMOND_TOML
from groundres import analyze, load_case, parse_case, simulate

#: A 4-blade Hammond rotor with 1000 N m s/rad of lag damping (unstable over a middle range),
#: in rpm, a title with markup in it (the HTML must escape it).
CASE = (
    HAMMOND_TOML.replace('title = "test"', 'title = "Notebook <b>case</b> & co"')
    .replace("lag_damping = 4067.5", "lag_damping = 1000.0")
    .replace(
        'start = 0.5\nstop = 40.0\npoints = 60\nunit = "rad/s"',
        'start = 10.0\nstop = 400.0\npoints = 80\nunit = "rpm"',
    )
    + "operating_start = 200.0\noperating_stop = 400.0\nrequired_damping_ratio = 0.01\n"
)
assert "lag_damping = 1000.0" in CASE and 'unit = "rpm"' in CASE and "<b>case</b>" in CASE


@pytest.fixture(scope="module")
def result():
    return analyze(parse_case(tomllib.loads(CASE), "notebook", CASE))


def test_repr_is_a_few_lines_with_the_verdict_ranges_margins_and_method(result):
    text = repr(result)
    assert len(text) < 1200 and text.count("\n") < 12, text  # (not the arrays: 38,766 characters before)
    assert "[[" not in text and "array(" not in text
    assert "multiblade-eigen, nonrotating frame" in text
    assert "verdict: unstable" in text
    start, end = result.stability.unstable_ranges[0]
    assert f"{start / (2 * math.pi / 60):.4g} rpm to {end / (2 * math.pi / 60):.4g} rpm" in text
    assert "least damping ratio over the operating range" in text and "required 1 %" in text
    assert "growth margin" in text


def test_html_repr_holds_a_table_per_mode_with_its_verdict_and_escapes_the_title(result):
    html = result._repr_html_()
    assert "<table>" in html and html.count("<tr>") >= len(result.labels) + 4
    assert "Notebook &lt;b&gt;case&lt;/b&gt; &amp; co" in html and "<b>case</b>" not in html
    for label in result.labels:
        assert f">{label}<" in html
    assert "unstable</span>" in html
    assert "run-up" in html  # (the operating range starts above the sweep's start)


def test_plot_draws_into_one_axes_of_the_callers_figure_and_nowhere_else():
    import matplotlib.pyplot as plt

    case = parse_case(tomllib.loads(CASE), "notebook", CASE)
    result = analyze(case, lag_damping_search=False)
    fig, (left, right) = plt.subplots(1, 2, layout="constrained")
    right.plot([0, 1], [0, 1])
    try:
        got = result.plot(ax=left)
        assert got is fig and fig.axes == [left, right]  # (no axes added)
        assert len(left.lines) > len(result.labels) and len(right.lines) == 1
        assert left.get_legend() is not None
        pair = plt.subplots(2, 1, layout="constrained")
        result.plot(ax=pair[1], show_damping_ratio=True)
        assert pair[1][1].get_ylabel() == "damping ratio [-]" and len(pair[0].axes) == 2
    finally:
        plt.close("all")


def test_plot_into_a_subfigure_leaves_the_other_alone_and_refuses_a_figure_with_axes(result):
    fig = Figure(layout="constrained")
    mine, theirs = fig.subfigures(1, 2)
    other = theirs.subplots()
    result.plot(fig=mine)
    assert len(mine.axes) >= 2 and theirs.axes == [other]
    busy = Figure()
    busy.subplots(1, 2)
    with pytest.raises(ValueError, match="fig holds 2 axes already"):
        result.plot(fig=busy)
    with pytest.raises(ValueError, match="pass one of them"):
        result.plot(fig=Figure(), ax=other)
    with pytest.raises(ValueError, match="must be 1 or 2 matplotlib Axes"):
        result.plot(ax=[other, other, other])


def test_to_dataframe_gives_tidy_rows_in_the_cases_unit(result):
    df = result.to_dataframe()
    assert isinstance(df, pd.DataFrame)
    assert list(df.columns) == ["speed", "mode", "frequency", "real_part", "damping_ratio", "vibrating"]
    n_s, n_m = result.frequency.shape
    assert len(df) == n_s * n_m
    rpm = 2 * math.pi / 60
    np.testing.assert_allclose(df["speed"].unique(), result.rotor_speed / rpm, rtol=1e-12)
    assert df["speed"].iloc[0] == pytest.approx(10.0) and df["speed"].iloc[-1] == pytest.approx(400.0)
    j = result.labels.index("regressive lag")
    rows = df[df["mode"] == "regressive lag"]
    np.testing.assert_allclose(rows["frequency"], result.frequency[:, j] / rpm)  # (cycles/min)
    np.testing.assert_allclose(rows["real_part"], result.real_part[:, j])
    np.testing.assert_allclose(rows["damping_ratio"], result.damping_ratio[:, j])
    assert df.attrs["units"] == {
        "speed": "rpm",
        "frequency": "cycles/min",
        "real_part": "1/s",
        "damping_ratio": "1",
    }
    assert df.attrs["frame"] == "nonrotating"


def test_simulation_and_comparison_read_short_and_plot_where_asked():
    case = load_case("hammond-1974-one-damper")
    sim = simulate(case, 26.7, duration=5.0)
    text = repr(sim)
    assert len(text) < 800 and "linear" in text and "x = 0.01 m" in text and "lag1 = 0.01 rad" in text
    assert "<table>" in sim._repr_html_()
    fig = Figure()
    ax = fig.subplots()
    assert sim.plot(ax=ax) is fig and ax.get_ylabel() == "amplitude / d [-]" and fig.axes == [ax]
    comparison = groundres.compare([load_case("hammond-1974"), case])
    text = repr(comparison)
    assert len(text) < 1500 and "entry 1" in text and "entry 2" in text and "beyond round-off" in text
    assert "<table>" in comparison._repr_html_()
    fig = Figure()
    ax = fig.subplots()
    comparison.plot(ax=ax)
    assert fig.axes == [ax] and ax.get_legend() is not None


def test_the_compare_picture_gives_each_mode_its_coleman_colour_and_each_entry_a_line_style():
    from groundres.plotting.coleman import label_colour
    from groundres.plotting.overlay import entry_style

    comparison = groundres.compare([load_case("hammond-1974"), load_case("hammond-1974")])
    fig = comparison.plot()
    ax_f = fig.axes[0]
    by_colour = {}
    for line in ax_f.lines[:-2]:  # (the 1/rev and 2/rev lines last)
        by_colour.setdefault(matplotlib.colors.to_hex(line.get_color()), set()).add(str(line.get_linestyle()))
    for label in comparison.labels:
        assert label_colour(label) in by_colour, label
    styles = {k: v for k, v in by_colour.items() if k in {label_colour(x) for x in comparison.labels}}
    assert all(len(v) == 2 for v in styles.values())  # (two entries: solid and dashed for every mode)
    assert entry_style(1)["linestyle"] == "-" and entry_style(2)["linestyle"] != "-"
