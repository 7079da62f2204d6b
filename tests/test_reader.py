"""What a reader sees: Deutsch verdicts, neutral values, 80 columns, units, strict JSON, CF.

The reference facts are the shipped cases' own: hammond-1974-one-damper has
dissimilar blades (blade 1's damper failed, the others 4067.5 N m s/rad) and
is unstable from 22.03 to 32.16 rad/s (its case description); stiff-inplane
tunes its regressive lag mode with the body at 387.69 rpm, beyond its 340 rpm
sweep (Omega (1 - nu) = omega_b with the case's K1, K2 and omega_b = 12 rad/s).
"""

import io as _io
import json
import math

import numpy as np
import pytest
import xarray as xr
from click.testing import CliRunner
from rich.console import Console

from conftest import HAMMOND_BLADE, HAMMOND_HUB
from groundres import Blade, Body, Rotor, analyze, load_case
from groundres.assess.deutsch import deutsch, installed_lag_damping
from groundres.assess.stability import growth_threshold
from groundres.cli import main
from groundres.cli import printout as report
from groundres.results.files import MODES_CSV_HEADER

WIDTH = 80


def run(*args):
    return CliRunner().invoke(main, list(args), env={"COLUMNS": str(WIDTH)})


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    """`groundres run` of three shipped cases at 80 columns: (output, folder) by case."""
    out = {}
    for name in ("hammond-1974-one-damper", "stiff-inplane", "hammond-undamped"):
        folder = tmp_path_factory.mktemp(name)
        result = run("run", name, "--out", str(folder))
        assert result.exit_code == 0, result.output
        out[name] = (result.output, folder)
    return out


def summary_of(runs, name):
    return json.loads((runs[name][1] / "summary.json").read_text())


def no_bare_constants(text):
    def refuse(token):
        raise ValueError(f"non-standard JSON token {token}")

    return json.loads(text, parse_constant=refuse)


def nulls_have_reasons(obj, where="$"):
    """Every null value in a JSON object has a ``<key>_reason`` string beside it."""
    if isinstance(obj, dict):
        for key, value in obj.items():
            if value is None:
                assert isinstance(obj.get(f"{key}_reason"), str), f"{where}.{key} is null without a reason"
            nulls_have_reasons(value, f"{where}.{key}")
    elif isinstance(obj, list):
        for i, value in enumerate(obj):
            nulls_have_reasons(value, f"{where}[{i}]")


# -- 1. the Deutsch table tells the truth ---------------------------------------


def test_deutsch_does_not_apply_to_dissimilar_blades(runs):
    """hammond-1974-one-damper is unstable: no row may say the criterion is satisfied."""
    summary = summary_of(runs, "hammond-1974-one-damper")
    assert not summary["stable"]
    rows = summary["lag_damping"]["deutsch"]
    assert [r["body_mode"] for r in rows] == ["x", "y"]
    for row in rows:
        assert row["applies"] is False and row["limitation"] == "blades differ"
        assert row["satisfied"] is None and "does not apply" in row["satisfied_reason"]
    output = runs["hammond-1974-one-damper"][0]
    table = output[output.index("Lag damping by the Deutsch") :]
    assert table.count("does not apply") == 2
    assert "yes" not in table.split("Installed")[0]


def test_installed_damping_is_the_smallest_working_damper(runs):
    lag = summary_of(runs, "hammond-1974-one-damper")["lag_damping"]
    assert lag["installed"] == 4067.5 and lag["failed_dampers"] == 1
    assert lag["per_blade"] == [0.0, 4067.5, 4067.5, 4067.5]
    assert all(r["installed_lag_damping"] == 4067.5 for r in lag["deutsch"])
    # not the blade average (3050.6) and not the failed damper (0)
    blade = Blade(**HAMMOND_BLADE, lag_damping=4067.5)
    rotor = Rotor.uniform(4, blade)
    assert installed_lag_damping(rotor) == (4067.5, 0)
    assert installed_lag_damping(rotor.with_blade(1, lag_damping=0.0)) == (4067.5, 1)
    assert installed_lag_damping(rotor.with_blade(2, lag_damping=1000.0)) == (1000.0, 0)
    assert installed_lag_damping(Rotor.uniform(4, Blade(**HAMMOND_BLADE))) == (0.0, 0)
    body = Body(("x", "y"), **HAMMOND_HUB)
    for entry in deutsch(rotor.with_blade(2, lag_damping=1000.0), body):
        assert entry.installed_lag_damping == 1000.0 and entry.satisfied is None


def test_identical_blades_are_judged_on_their_damper():
    """Identical blades: the verdict compares the blades' damper with the requirement
    (hammond-1974: 4067.5 against 605.7 and 2779.9, both satisfied)."""
    body = Body(("x", "y"), **HAMMOND_HUB)
    for damper, ok in ((4067.5, True), (2000.0, False)):
        entries = deutsch(Rotor.uniform(4, Blade(**HAMMOND_BLADE, lag_damping=damper)), body)
        assert [e.installed_lag_damping for e in entries] == [damper, damper]
        assert entries[1].applies and entries[1].satisfied is ok
        assert entries[0].satisfied is True  # 605.7 needed


def test_two_blades_do_not_meet_the_criterion_as_stated():
    body = Body(("x", "y"), **HAMMOND_HUB)
    (x, y) = deutsch(Rotor.uniform(2, Blade(**HAMMOND_BLADE, lag_damping=300.0)), body)
    assert x.limitation == y.limitation == "two blades" and x.satisfied is None


def test_tuning_beyond_the_sweep_is_said(runs):
    summary = summary_of(runs, "stiff-inplane")
    (row,) = summary["lag_damping"]["deutsch"]
    rpm = row["tuning_speed"] * 60 / (2 * math.pi)
    assert rpm == pytest.approx(387.69, abs=0.01)
    assert row["tuning_in_sweep"] is False
    assert row["required_lag_damping"] is None
    assert row["required_lag_damping_reason"] == "body undamped: no finite lag damping suffices"
    output = runs["stiff-inplane"][0]
    assert "387.7" in output and "beyond sweep" in output
    assert "outside the sweep (30 rpm to 340 rpm)" in " ".join(output.split())
    # nu is said to be at the tuning speed, and explained once
    assert " ".join(output.split()).count("nu: rotating lag frequency at that speed") == 1


def test_every_null_in_the_summary_has_a_reason(runs):
    for name in runs:
        summary = no_bare_constants((runs[name][1] / "summary.json").read_text())
        nulls_have_reasons(summary)
        for row in summary["lag_damping"]["deutsch"]:
            assert row["required_lag_damping"] is None or isinstance(row["required_lag_damping"], float)


# -- 2. round-off is not a result ------------------------------------------------


def test_neutral_case_prints_neutral_not_round_off(runs):
    output = runs["stiff-inplane"][0]
    flat = " ".join(output.split())
    assert "Largest real part: neutral (below the growth threshold" in flat
    assert "smallest damping ratio 0 (neutral)" in flat
    assert "e-15" not in output and "e-16" not in output and "e-17" not in output
    summary = summary_of(runs, "stiff-inplane")
    mr = summary["max_real_part"]
    assert mr["neutral"] and 0 < mr["value"] < mr["growth_threshold"]  # stored as computed


def test_modes_csv_never_writes_minus_zero(runs):
    for name in runs:
        text = (runs[name][1] / "modes.csv").read_text()
        cells = [c for line in text.splitlines()[1:] for c in line.split(",")]
        assert "-0" not in cells


def test_phasor_and_animation_titles_show_a_neutral_root_as_zero(tmp_path):
    """hammond-undamped at 255 rpm: body x is neutral (computed Re about -9e-16 1/s)."""
    case = load_case("hammond-undamped")
    w = 255 * 2 * math.pi / 60
    result = analyze(case, speeds=np.union1d(case.sweep.speeds, [w]))
    shape = result.mode("body x", w)
    assert abs(shape.eigenvalue.real) <= growth_threshold(w) and shape.neutral
    from groundres.plotting.animation import mode_animation
    from groundres.plotting.phasors import phasor_diagram

    title = phasor_diagram(shape, speed_text="255 rpm (1.645 ref)")._suptitle.get_text()
    assert "at 255 rpm (1.645 ref): neutral, lambda = 0 + 12.21i 1/s, damping ratio 0" in title
    anim = mode_animation(shape, frames=2, speed_text="255 rpm")
    from matplotlib.animation import PillowWriter

    anim.save(tmp_path / "mode.gif", writer=PillowWriter(fps=2), dpi=20)
    text = anim.fig._suptitle.get_text()
    assert "at 255 rpm (neutral)" in text and "rad/s" not in text


# -- 3. readable at 80 columns ---------------------------------------------------


def row_heights(rendered: str) -> list[int]:
    """Lines per row of a table rendered by report.simple_table (rows start in column 0)."""
    lines = rendered.rstrip("\n").splitlines()
    body = lines[next(i for i, line in enumerate(lines) if set(line.strip()) == {"─"}) + 1 :]
    starts = [i for i, line in enumerate(body) if line[:1].strip()]
    return [b - a for a, b in zip(starts, starts[1:] + [len(body)])]


def render(table) -> str:
    console = Console(width=WIDTH, file=_io.StringIO(), highlight=False, color_system=None)
    console.print(table)
    return console.file.getvalue()


def test_run_output_fits_80_columns(runs):
    for name, (output, _) in runs.items():
        for line in output.splitlines():
            assert len(line) <= WIDTH, (name, line)


@pytest.mark.parametrize("name", ["hammond-1974-one-damper", "stiff-inplane", "hammond-undamped"])
def test_no_table_cell_wraps_over_three_lines(runs, name):
    summary = summary_of(runs, name)
    sweep = load_case(name).sweep
    tables = [report.deutsch_table(summary, sweep)]
    if summary["unstable_ranges"]:
        tables.append(report.unstable_table(summary, sweep))
    for table in tables:
        heights = row_heights(render(table))
        assert len(heights) == len(table.rows) and max(heights) <= 3, (name, heights)


def test_every_column_header_has_its_unit(runs):
    summary = summary_of(runs, "stiff-inplane")
    sweep = load_case("stiff-inplane").sweep
    table = report.deutsch_table(summary, sweep)
    for column in table.columns:
        header = str(column.header)
        if header not in ("body mode", "verdict"):
            assert "[" in header and "]" in header, header
    text = render(table)
    for unit in ("[cycles/min]", "[rpm]", "[/rev]", "[N m s/rad]"):
        assert unit in text  # printed, not taken as markup
    output = " ".join(runs["stiff-inplane"][0].split())
    for explained in ("omega_b: body frequency", "ref: rotor speed / the case's reference speed, 155 rpm"):
        assert output.count(explained) == 1


def test_cases_list_fits_80_columns():
    result = run("cases")
    assert result.exit_code == 0
    assert max(len(line) for line in result.output.splitlines()) <= WIDTH
    assert max(row_heights(result.output)) <= 3


# -- 4 and 10. units and self-describing files -----------------------------------


def test_units_in_every_csv_header(runs, tmp_path):
    header = (runs["hammond-undamped"][1] / "modes.csv").read_text().splitlines()[0]
    assert header.split(",") == MODES_CSV_HEADER
    assert header == "speed [rad/s],mode,frequency [rad/s],real_part [1/s],damping_ratio [-]"
    sim = run("simulate", "hammond-undamped", "--speed", "250", "--time", "3", "--out", str(tmp_path / "s"))
    assert sim.exit_code == 0, sim.output
    columns = (tmp_path / "s" / "simulation.csv").read_text().splitlines()[0].split(",")
    assert columns[0] == "time [s]" and "x [m]" in columns and "lag1 [rad]" in columns
    assert all(c.endswith("]") for c in columns)


def test_phasors_files_are_strict_and_speak_units(tmp_path):
    """The README's example: phasors hammond-undamped --speed 255 (rpm)."""
    out = tmp_path / "p"
    result = run("phasors", "hammond-undamped", "--speed", "255", "--no-gif", "--out", str(out))
    assert result.exit_code == 0, result.output
    assert max(len(line) for line in result.output.splitlines()) <= WIDTH
    assert "cycles/min" in result.output  # the whirl in the case's unit
    assert "ref: rotor speed / the case's reference speed" in " ".join(result.output.split())
    report_ = no_bare_constants((out / "phasors.json").read_text())
    nulls_have_reasons(report_)
    entry = report_["body x"]
    assert entry["neutral"] and entry["case_unit"] == "rpm"
    assert entry["rotor_speed_in_case_unit"] == pytest.approx(255)
    assert entry["whirl"]["centre_of_mass"]["frequency_unit"] == "rad/s"
    header = (out / "phasors.csv").read_text().splitlines()[0].split(",")
    numeric = [h for h in header if h not in ("mode", "frame", "coordinate", "kind", "unit")]
    assert numeric and all(h.endswith("]") for h in numeric), header


def test_modes_nc_follows_cf(runs):
    folder = runs["hammond-1974-one-damper"][1]
    with xr.open_dataset(folder / "modes.nc") as ds:
        assert ds.attrs["Conventions"] == "CF-1.10"
        for name, var in ds.variables.items():
            assert var.attrs.get("long_name"), name
            if var.dtype.kind in "fiu":
                assert var.attrs.get("units"), name
        assert ds["shape_real"].attrs["units"] == "1"
        assert set(ds["coordinate_units"].values) == {"m", "rad"}
        ranges = ds["unstable_range"]
        assert ranges.dims == ("range", "end") and list(ds["end"].values) == ["start", "stop"]
        summary = summary_of(runs, "hammond-1974-one-damper")
        expected = [[r["start"], r["end"]] for r in summary["unstable_ranges"]]
        np.testing.assert_allclose(ranges.values, expected, rtol=1e-12)
        assert ds["unstable_range"].attrs["units"] == "rad/s"
        assert list(ds["unstable_range_modes"].values) == [
            ", ".join(r["modes"]) for r in summary["unstable_ranges"]
        ]
        assert "unstable_ranges_rad_per_s" not in ds.attrs
        # the case, flattened, with units
        assert list(ds.attrs["rotor_lag_damping"]) == [0.0, 4067.5, 4067.5, 4067.5]
        assert ds.attrs["rotor_lag_damping_units"] == "N m s/rad"
        assert ds.attrs["sweep_reference"] == pytest.approx(155 * 2 * math.pi / 60)
        assert ds.attrs["sweep_reference_units"] == "rad/s" and ds.attrs["sweep_unit"] == "rpm"
        assert ds.attrs["body_damping_y"] == 25539.35 and ds.attrs["body_damping_y_units"] == "N s/m"
        for key, value in ds.attrs.items():
            if isinstance(value, (float, np.floating, np.ndarray)) and not key.startswith(
                "growth_threshold_per"
            ):
                assert f"{key}_units" in ds.attrs, key


def test_stable_case_has_an_empty_range_variable(runs):
    with xr.open_dataset(runs["stiff-inplane"][1] / "modes.nc") as ds:
        assert ds.sizes["range"] == 0 and ds["unstable_range"].shape == (0, 2)


def test_to_xarray_is_the_file(runs):
    result = analyze(load_case("hammond-undamped"))
    ds = result.to_xarray()
    with xr.open_dataset(runs["hammond-undamped"][1] / "modes.nc") as disk:
        assert set(ds.variables) == set(disk.variables)
        assert ds.attrs["Conventions"] == disk.attrs["Conventions"]
        for name in ds.variables:
            assert ds[name].attrs.get("units") == disk[name].attrs.get("units"), name
        np.testing.assert_array_equal(ds["unstable_range"].values, disk["unstable_range"].values)


# -- 14. user text is printed literally -------------------------------------------


MARKUP_CASE = """
title = "[/bold] rotor [red]x"
[rotor]
blades = 4
hinge_offset = 0.3048
blade_mass = 94.9
blade_static_moment = 289.1
blade_inertia = 1084.7
lag_damping = 4067.5
[body]
dofs = ["x"]
mass_x = 8026.6
stiffness_x = 1240481.8
damping_x = 51078.7
[sweep]
start = 5.0
stop = 40.0
points = 30
"""


def test_rich_markup_in_a_title_is_printed_literally(tmp_path):
    path = tmp_path / "case.toml"
    path.write_text(MARKUP_CASE)
    result = run("run", str(path), "--out", str(tmp_path / "o"))
    assert result.exit_code == 0, result.output
    assert "[/bold] rotor [red]x" in result.output
    # the spinner shown on a terminal takes the title as plain text too
    from groundres.cli.common import status

    console = Console(file=_io.StringIO(), force_terminal=True)
    with status(console, "Analysing [/bold] rotor..."):
        pass
