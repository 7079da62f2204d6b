"""The command line: outputs, messages and exit codes (docs/case-files.md)."""

import json
import subprocess
import sys

import pytest
import xarray as xr
from click.testing import CliRunner

from conftest import HAMMOND_TOML
from groundres.cli import main

GOOD = HAMMOND_TOML


def run(*args):
    return CliRunner().invoke(main, list(args))


def write_case(tmp_path, text):
    path = tmp_path / "case.toml"
    path.write_text(text)
    return str(path)


def edit(old, new):
    assert old in GOOD
    return GOOD.replace(old, new)


BAD = {
    "unknown key": (edit("blade_mass = 94.9", "blade_mas = 94.9"), ["blade_mas", "blade_mass"]),
    "unknown table key": (edit("[sweep]", "[sweep]\nstep = 3"), ["step", "stop"]),
    "wrong type": (edit("blade_mass = 94.9", 'blade_mass = "heavy"'), ["blade_mass", "heavy"]),
    "wrong type int": (edit("blades = 4", "blades = 4.5"), ["blades", "4.5"]),
    "missing key": (edit("blade_inertia = 1084.7", ""), ["blade_inertia", "missing"]),
    "missing body key": (edit("stiffness_y = 1240481.8", ""), ["stiffness_y", "missing"]),
    "zero mass": (edit("blade_mass = 94.9", "blade_mass = 0.0"), ["blade_mass", "0.0"]),
    "negative hub mass": (edit("mass_x = 8026.6", "mass_x = -1.0"), ["mass_x", "-1.0"]),
    "negative inertia": (edit("blade_inertia = 1084.7", "blade_inertia = -5.0"), ["blade_inertia", "-5.0"]),
    "negative lag damping": (edit("lag_damping = 4067.5", "lag_damping = -1.0"), ["lag_damping", "-1.0"]),
    "negative stiffness": (edit("stiffness_x = 1240481.8", "stiffness_x = -5.0"), ["stiffness_x", "-5.0"]),
    "negative body damping": (edit("damping_y = 25539.35", "damping_y = -2.0"), ["damping_y", "-2.0"]),
    "static moment too large": (
        edit("blade_static_moment = 289.1", "blade_static_moment = 400.0"),
        ["blade_static_moment", "400.0"],
    ),
    "one blade": (edit("blades = 4", "blades = 1"), ["blades", "1"]),
    "start above stop": (edit("start = 0.5", "start = 50.0"), ["start", "50.0", "stop"]),
    "start equal stop": (edit("start = 0.5", "start = 40.0"), ["start", "40.0"]),
    "too few points": (edit("points = 60", "points = 1"), ["points", "1"]),
    "unknown unit": (edit('unit = "rad/s"', 'unit = "rps"'), ["unit", "rps", "rpm"]),
    "unknown frame": (edit('unit = "rad/s"', 'unit = "rad/s"\nframe = "inertial"'), ["frame", "inertial"]),
    "unknown method": (edit('unit = "rad/s"', 'unit = "rad/s"\nmethod = "magic"'), ["method", "magic"]),
    "unknown dof": (edit('dofs = ["x", "y"]', 'dofs = ["x", "yaw"]'), ["dofs", "yaw"]),
    "bad toml": (edit("blades = 4", "blades = = 4"), ["TOML"]),
    "pitch without hub height": (
        edit(
            'dofs = ["x", "y"]', 'dofs = ["x", "y", "pitch"]\ninertia_pitch = 2500.0\nstiffness_pitch = 4e5'
        ),
        ["hub_height", "missing"],
    ),
    "roll without inertia": (
        edit('dofs = ["x", "y"]', 'dofs = ["x", "y", "roll"]\nstiffness_roll = 1e5\nhub_height = 1.5'),
        ["inertia_roll", "missing"],
    ),
    "zero roll inertia": (
        edit(
            'dofs = ["x", "y"]', 'dofs = ["roll"]\ninertia_roll = 0.0\nstiffness_roll = 1e5\nhub_height = 1.5'
        ),
        ["inertia_roll", "0.0"],
    ),
}


@pytest.mark.parametrize("name", BAD)
def test_bad_input_exits_2_and_names_key_and_value(tmp_path, name):
    text, words = BAD[name]
    out = tmp_path / "out"
    result = run("run", write_case(tmp_path, text), "--out", str(out))
    assert result.exit_code == 2, result.output
    assert "Traceback" not in result.output
    for word in words:
        assert word in result.output, (word, result.output)
    assert len(result.output.strip().splitlines()) == 1
    assert not out.exists()


def test_missing_case_file(tmp_path):
    result = run("run", str(tmp_path / "nope.toml"))
    assert result.exit_code == 2 and "nope.toml" in result.output


def test_run_writes_the_four_outputs(tmp_path):
    out = tmp_path / "out"
    result = run("run", write_case(tmp_path, GOOD), "--out", str(out))
    assert result.exit_code == 0, result.output
    summary = json.loads((out / "summary.json").read_text())
    for key in (
        "title",
        "groundres_version",
        "method",
        "frame",
        "speed_unit",
        "stable",
        "unstable_ranges",
        "max_real_part",
        "min_damping_ratio",
    ):
        assert key in summary
    assert summary["method"] == "multiblade-eigen" and summary["speed_unit"] == "rad/s"
    assert set(summary["max_real_part"]) >= {"value", "speed"}
    header = (out / "modes.csv").read_text().splitlines()[0]
    assert header == "speed [rad/s],mode,frequency [rad/s],real_part [1/s],damping_ratio [-]"
    assert len((out / "modes.csv").read_text().splitlines()) == 1 + 60 * 6
    ds = xr.open_dataset(out / "modes.nc")
    assert ds["frequency"].dims == ("speed", "mode") and ds.sizes["speed"] == 60
    ds.close()
    assert (out / "coleman.png").read_bytes()[:4] == b"\x89PNG"
    assert not list(out.glob("*.part"))


def test_run_without_case_says_which_default(tmp_path):
    result = run("run", "--out", str(tmp_path / "d"))
    assert result.exit_code == 0, result.output
    assert "hammond-undamped" in result.output
    summary = json.loads((tmp_path / "d" / "summary.json").read_text())
    assert len(summary["unstable_ranges"]) == 2


def test_cases_lists_shipped_cases():
    result = run("cases")
    assert result.exit_code == 0
    assert "hammond-1974" in result.output and "hammond-undamped" in result.output
    shown = run("cases", "hammond-1974")
    assert "[rotor]" in shown.output


def test_equations_prints_matrices(tmp_path):
    result = run("equations", write_case(tmp_path, GOOD))
    assert result.exit_code == 0, result.output
    assert "mass matrix" in result.output and "lag_1c" in result.output
    latex = run("equations", write_case(tmp_path, GOOD), "--latex", "--form", "blade")
    assert latex.exit_code == 0 and "\\left[" in latex.output


def test_blade_overrides_run_with_floquet(tmp_path):
    text = GOOD + "\n[[rotor.blade]]\nindex = 1\nlag_damping = 0.0\n"
    out = tmp_path / "o"
    result = run("run", write_case(tmp_path, text), "--out", str(out))
    assert result.exit_code == 0, result.output
    assert json.loads((out / "summary.json").read_text())["method"] == "floquet"


def test_eigen_on_a_periodic_case_is_a_clear_error(tmp_path):
    text = GOOD.replace('unit = "rad/s"', 'unit = "rad/s"\nmethod = "eigen"')
    text += "\n[[rotor.blade]]\nindex = 1\nlag_damping = 0.0\n"
    result = run("run", write_case(tmp_path, text), "--out", str(tmp_path / "o"))
    assert result.exit_code == 2 and "method = 'eigen'" in result.output and "floquet" in result.output


def test_bad_blade_override_names_the_blade(tmp_path):
    text = GOOD + "\n[[rotor.blade]]\nindex = 5\nlag_damping = 0.0\n"
    result = run("run", write_case(tmp_path, text), "--out", str(tmp_path / "o"))
    assert result.exit_code == 2 and "index" in result.output and "5" in result.output
    text = GOOD + "\n[[rotor.blade]]\nindex = 2\nlag_damping = -3.0\n"
    result = run("run", write_case(tmp_path, text), "--out", str(tmp_path / "o"))
    assert result.exit_code == 2 and "lag_damping" in result.output and "-3.0" in result.output


def test_simulate_writes_a_picture_and_reports_growth(tmp_path):
    out = tmp_path / "s"
    result = run("simulate", "hammond-undamped", "--speed", "250", "--time", "6", "--out", str(out))
    assert result.exit_code == 0, result.output
    assert "Measured growth rate" in result.output
    assert (out / "simulation.png").exists() and (out / "simulation.csv").exists()
    bad = run("simulate", "hammond-undamped", "--speed", "250", "--initial", "z=1")
    assert bad.exit_code == 2 and "--initial z=1" in bad.output


def test_real_entry_point_exit_code(tmp_path):
    bad = write_case(tmp_path, edit("blades = 4", "blades = 1"))
    proc = subprocess.run([sys.executable, "-m", "groundres.cli", "run", bad], capture_output=True, text=True)
    assert proc.returncode == 2
    assert "Traceback" not in proc.stderr and "blades" in proc.stderr


def test_import_stays_light():
    heavy = "('matplotlib', 'sympy', 'click')"
    code = f"import sys, groundres; print(sorted(m for m in {heavy} if m in sys.modules))"
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert proc.stdout.strip() == "[]"


def test_a_sigterm_swallowed_where_it_landed_still_ends_the_command():
    """Python swallows an exception raised in a weak-reference callback or a destructor; a SIGTERM
    whose Terminated landed there must still end the command (it did not: a study ran on and
    exited 0)."""
    from groundres.cli import common

    with pytest.raises(common.Terminated):
        with common.interrupts():
            try:
                common._terminate(15, None)  # (as if raised inside a callback that swallows it)
            except common.Terminated:
                pass
    with common.interrupts():  # (a later command starts afresh)
        pass
