"""User mistakes at the edges exit 2 with one clear line, quickly (docs/case-files.md, "Limits").

Each input here once ended in an internal error (exit 1: OverflowError,
MemoryError, UnicodeDecodeError, RecursionError, a ValueError of the
integrator), a misleading message or a run of hours; now each is refused
before any work with a message naming the key or option and the value.
"""

import subprocess
import sys
import time

import pytest
from click.testing import CliRunner

from conftest import HAMMOND_TOML
from groundres import Blade, Body, Case, Rotor, Sweep
from groundres.cli import main
from groundres.errors import CaseError, ParameterError, shown
from groundres.model.keys import SCHEMA
from groundres.model.params import MAX_BLADES, MAX_POINTS
from groundres.model.schema import load_case
from groundres.model.system import System

#: The Hammond case with blade 2's damper given on its own and a reference speed.
GOOD = (
    HAMMOND_TOML.lstrip("\n").replace("[body]", "[[rotor.blade]]\nindex = 2\nlag_damping = 4067.5\n[body]")
    + "reference = 16.0\n"
)
#: A pitch-roll body in case-file form, and a unit one for the library.
PITCH_ROLL = """inertia_pitch = 2.5e4
inertia_roll = 9e3
stiffness_pitch = 4e6
stiffness_roll = 2e6
hub_height = 1.8"""
PR = dict(
    mass_x=1.0,
    mass_y=1.0,
    stiffness_x=1.0,
    stiffness_y=1.0,
    inertia_pitch=1.0,
    inertia_roll=1.0,
    hub_height=1.0,
)
BIG = "9" * 400  # a 400-digit whole number
#: Wall-clock bound [s] for a refusal made in-process (imports and the
#: generated code already loaded): far below the hours the inputs once ran.
QUICK = 10.0


def run(*args):
    started = time.perf_counter()
    result = CliRunner().invoke(main, list(args))
    return result, time.perf_counter() - started


def write(tmp_path, text, name="case.toml"):
    path = tmp_path / name
    (path.write_bytes if isinstance(text, bytes) else path.write_text)(text)
    return str(path)


def edit(old, new):
    assert old in GOOD, old
    return GOOD.replace(old, new, 1)


def assert_refused(result, elapsed, *words):
    assert result.exit_code == 2, result.output
    assert isinstance(result.exception, SystemExit), result.exception
    assert "Traceback" not in result.output
    assert result.output.startswith("error: ") and len(result.output.strip().splitlines()) == 1
    for word in words:
        assert word in result.output, (word, result.output)
    assert len(result.output) < 600, result.output
    assert elapsed < QUICK, elapsed


# -- every numeric key of the case file ---------------------------------------------------------

NUMERIC = {
    k for table in SCHEMA.values() for k, kind in table.items() if kind in ("a number", "a whole number")
}
#: Lines of GOOD holding a number: every numeric key of each table it has.
NUMBER_LINES = [i for i, line in enumerate(GOOD.splitlines()) if line.split(" = ")[0] in NUMERIC]


def test_the_keys_tried_cover_every_kind_of_numeric_key():
    keys = {GOOD.splitlines()[i].split(" = ")[0] for i in NUMBER_LINES}
    assert {"blades", "points", "index", "start", "stop", "reference", "blade_mass", "damping_y"} <= keys
    assert len(NUMBER_LINES) == 19  # 7 in [rotor], 2 in [[rotor.blade]], 6 in [body], 4 in [sweep]


@pytest.mark.parametrize("line", NUMBER_LINES)
def test_a_400_digit_whole_number_in_any_numeric_key(tmp_path, line):
    lines = GOOD.splitlines()
    key = lines[line].split(" = ")[0]
    lines[line] = f"{key} = {BIG}"
    out = tmp_path / "out"
    result, elapsed = run("run", write(tmp_path, "\n".join(lines)), "--out", str(out))
    assert_refused(result, elapsed, key, "99999999...9999 (400 digits)")
    assert not out.exists()


@pytest.mark.parametrize("sign", ["", "-"])
def test_a_whole_number_too_long_to_read_names_its_key(tmp_path, sign):
    result, elapsed = run(
        "run", write(tmp_path, edit("blade_mass = 94.9", f"blade_mass = {sign}{'7' * 5000}"))
    )
    assert_refused(result, elapsed, "blade_mass", "4000 digits")


@pytest.mark.parametrize(
    "old, new, words",
    [
        ("blades = 4", "blades = 9223372036854775807", ["blades", "9223372036854775807", "2 to 32"]),
        ("blades = 4", f"blades = {MAX_BLADES + 1}", ["blades", "33", "2 to 32"]),
        ("points = 60", "points = 1e12", ["points", "1000000000000.0", "whole number"]),
        ("points = 60", "points = 1000000000000", ["points", "1000000000000", "2 to 100000"]),
        ("points = 60", f"points = {MAX_POINTS + 1}", ["points", "100001"]),
        ("index = 2", f"index = {BIG}", ["index", "(400 digits)", "from 1 to blades"]),
        ("lag_damping = 4067.5\n[[", "lag_damping = nan\n[[", ["lag_damping", "nan", "finite"]),
        ("stop = 40.0", "stop = inf", ["stop", "inf", "finite"]),
        ("stop = 40.0", "stop = 1e400", ["stop", "inf", "finite"]),
        ("damping_y = 25539.35", "damping_y = -inf", ["damping_y", "-inf", "finite"]),
        ("reference = 16.0", "reference = nan", ["reference", "nan"]),
        ('dofs = ["x", "y"]', 'dofs = ["x", "y"]\ninertia_pitch = nan', ["inertia_pitch", "nan"]),
    ],
)
def test_counts_limits_and_non_finite_numbers(tmp_path, old, new, words):
    out = tmp_path / "out"
    result, elapsed = run("run", write(tmp_path, edit(old, new)), "--out", str(out))
    assert_refused(result, elapsed, *words)
    assert not out.exists()


def test_a_speed_that_overflows_in_rad_per_second(tmp_path):
    text = edit("stop = 40.0", "stop = 1.7e308").replace('unit = "rad/s"', 'unit = "Hz"')
    result, elapsed = run("run", write(tmp_path, text))
    assert_refused(result, elapsed, "stop", "1.7e+308", "rad/s")


def test_a_sweep_too_large_for_memory_says_how_many_speeds_fit(tmp_path):
    text = edit("blades = 4", "blades = 32\nflap = true").replace("points = 60", "points = 5000")
    text = text.replace('dofs = ["x", "y"]', 'dofs = ["x", "y", "pitch", "roll"]\n' + PITCH_ROLL)
    result, elapsed = run("run", write(tmp_path, text))
    # 4 body dofs + 32 lag + 32 flap = 68 coordinates: 2e7 // 136^2 = 1081 speeds
    assert_refused(result, elapsed, "[sweep] points = 5000", "at most 1081 speeds", "68 coordinates")


# -- files that are not UTF-8 TOML text ---------------------------------------------------------

NOT_TEXT = {
    "UTF-16 with byte-order mark": (GOOD.encode("utf-16"), "UTF-16"),
    "UTF-16 without byte-order mark": (GOOD.encode("utf-16-le"), "NUL"),
    "UTF-32": (GOOD.encode("utf-32"), "UTF-32"),
    "Latin-1": (GOOD.replace('"test"', '"t\xe9st"').encode("latin-1"), "byte 0xe9 on line 1"),
    "binary": (bytes(range(256)) * 40, "not UTF-8"),
    "NUL bytes": (b"\x00" * 1000, "NUL"),
}


@pytest.mark.parametrize("name", NOT_TEXT)
def test_a_file_that_is_not_utf8_text(tmp_path, name):
    data, words = NOT_TEXT[name]
    path = write(tmp_path, data)
    result, elapsed = run("run", path)
    assert_refused(result, elapsed, path, "not a UTF-8 TOML text file", words)


def test_a_utf8_byte_order_mark_is_accepted(tmp_path):
    case = load_case(write(tmp_path, b"\xef\xbb\xbf" + GOOD.encode()))
    assert case.rotor.n_blades == 4


def test_a_huge_file_is_not_read(tmp_path):
    path = write(tmp_path, GOOD + "#" * 2_000_000 + "\n")
    result, elapsed = run("run", path)
    assert_refused(result, elapsed, path, "larger than 1000000 bytes")


@pytest.mark.parametrize("depth", [1000, 100_000])
def test_deeply_nested_arrays(tmp_path, depth):
    text = edit('title = "test"', f'title = "test"\nnested = {"[" * depth}{"]" * depth}')
    result, elapsed = run("run", write(tmp_path, text))
    assert_refused(result, elapsed, "nested too deeply")


def test_nested_arrays_in_a_known_key_are_a_type_error(tmp_path):
    text = edit('dofs = ["x", "y"]', f"dofs = {'[' * 200}{']' * 200}")
    result, elapsed = run("run", write(tmp_path, text))
    assert_refused(result, elapsed, "dofs", "list of strings")


def test_a_folder_and_an_impossible_name(tmp_path):
    result, elapsed = run("run", str(tmp_path))
    assert_refused(result, elapsed, "a folder, not a case file")
    result, elapsed = run("run", "x" * 5000)
    assert_refused(result, elapsed, "xxxxxxxx")


def test_the_real_entry_point_on_nested_arrays_and_a_long_number(tmp_path):
    for text, word in (
        (f"x = {'[' * 100_000}{']' * 100_000}\n" + GOOD, "nested too deeply"),
        (edit("mass_x = 8026.6", f"mass_x = {BIG}"), "mass_x"),
    ):
        proc = subprocess.run(
            [sys.executable, "-m", "groundres.cli", "run", write(tmp_path, text)],
            capture_output=True,
            text=True,
        )
        assert proc.returncode == 2, proc.stderr
        assert "Traceback" not in proc.stderr and word in proc.stderr


# -- the library says the same without the case reader -------------------------------------------


def test_parameter_errors_from_the_library():
    blade = Blade(blade_mass=94.9, blade_static_moment=289.1, blade_inertia=1084.7, hinge_offset=0.3)
    with pytest.raises(ParameterError, match=r"blade_mass = 10000000\.\.\.0000 \(401 digits\)"):
        Blade(blade_mass=10**400, blade_static_moment=1.0, blade_inertia=1.0, hinge_offset=0.0)
    with pytest.raises(ParameterError, match="blade_static_moment"):  # S^2 = inf > m I, no OverflowError
        Blade(blade_mass=1e-200, blade_static_moment=1e200, blade_inertia=1e-200, hinge_offset=0.0)
    with pytest.raises(ParameterError, match="from 2 to 32"):
        Rotor.uniform(MAX_BLADES + 1, blade)
    with pytest.raises(ParameterError, match="2 to 32 blades"):
        Rotor((blade,) * (MAX_BLADES + 1))
    with pytest.raises(ParameterError, match="from 2 to 100000"):
        Sweep(0.0, 1.0, points=10**12)
    body = Body(mass_x=1.0, mass_y=1.0, stiffness_x=1.0, stiffness_y=1.0)
    with pytest.raises(ParameterError, match="at most 1081 speeds"):
        Case(
            Rotor.uniform(32, blade, flap=True),
            Body(dofs=("x", "y", "pitch", "roll"), **PR),
            Sweep(0, 1, 1082),
        )
    Case(Rotor.uniform(32, blade, flap=True), Body(dofs=("x", "y", "pitch", "roll"), **PR), Sweep(0, 1, 1081))
    Case(Rotor.uniform(4, blade), body, Sweep(0, 1, MAX_POINTS))  # 6 coordinates: the count limit holds


def test_shown_values_stay_short():
    assert shown(10**400) == "10000000...0000 (401 digits)"
    assert shown(-(10**30)) == "-1000000...0000 (31 digits)"
    assert "about 6021 digits" in shown(2**20000)  # beyond what str() converts
    assert shown(12345) == "12345" and shown(0) == "0" and shown(1.5) == "1.5"
    assert len(shown("x" * 1000)) < 60


def test_case_errors_name_the_table(tmp_path):
    with pytest.raises(CaseError, match=r"^\[rotor\] blades = 33: "):
        load_case(write(tmp_path, edit("blades = 4", "blades = 33")))


# -- command-line options -----------------------------------------------------------------------


@pytest.fixture(scope="module")
def warm():
    """Derive or load the generated equations once, so that the timings below are of the refusals."""
    from groundres.solve.simulate import fastest_rate

    case = load_case("hammond-1974-one-damper")
    fastest_rate(System(case.rotor, case.body), 26.7)


SIMULATE = {
    # option values, words of the message
    "time 1e-9": (
        ["--speed", "255", "--time", "1e-9"],
        ["--time = 1e-09", "at least 6 revolutions", "1.412 s"],
    ),
    "time 0": (["--speed", "255", "--time", "0"], ["--time = 0.0", "finite number > 0"]),
    "time -1": (["--speed", "255", "--time", "-1"], ["--time = -1.0", "finite number > 0"]),
    "time inf": (["--speed", "255", "--time", "inf"], ["--time = inf", "finite number > 0"]),
    "time nan": (["--speed", "255", "--time", "nan"], ["--time = nan", "finite number > 0"]),
    "time too long": (
        ["--speed", "255", "--time", "1e5"],
        ["--time = 100000.0", "at 255 rpm", "limit of 100000", "at most 470"],
    ),
    "speed inf": (["--speed", "inf"], ["--speed = inf", "finite number > 0", "rpm"]),
    "speed nan": (["--speed", "nan"], ["--speed = nan", "finite number > 0"]),
    "speed 0": (["--speed", "0"], ["--speed = 0.0", "> 0"]),
    "speed -5": (["--speed", "-5"], ["--speed = -5.0", "> 0"]),
    "speed 0.01 rpm": (
        ["--speed", "0.01"],
        [
            "--speed = 0.01 rpm",
            "the default run of 40 revolutions (2.4e+05 s)",
            "1.8e+07 integration steps",
        ],
    ),
    "speed 0.01 rpm, time 3 h": (["--speed", "0.01", "--time", "10800"], ["--time = 10800", "6 revolutions"]),
    "speed 1e-300": (
        ["--speed", "1e-300"],
        ["--speed = 1e-300 rpm", "at 1e-300 rpm", "integration steps", "higher speed"],
    ),
    "speed 1e-320": (["--speed", "1e-320"], ["--speed = 1e-320", "too slow"]),
    "speed 1e80": (["--speed", "1e80"], ["--speed = 1e+80 rpm", "too fast", "1e+150"]),
    "speed 1e100": (["--speed", "1e100"], ["--speed = 1e+100 rpm", "too fast"]),
    "initial nan": (["--speed", "255", "--initial", "x=nan"], ["--initial 'x=nan'", "finite"]),
    "initial inf": (["--speed", "255", "--initial", "lag1=-inf"], ["--initial 'lag1=-inf'", "finite"]),
    "initial unknown": (
        ["--speed", "255", "--initial", "flap1=0.1"],
        ["--initial flap1=0.1", "x, y, lag1, lag2, lag3, lag4", "NAME_rate"],
    ),
    "initial not a number": (["--speed", "255", "--initial", "x=big"], ["--initial 'x=big'", "NAME=NUMBER"]),
    "initial no name": (["--speed", "255", "--initial", "=1"], ["--initial '=1'", "NAME=NUMBER"]),
    "initial all zero": (["--speed", "255", "--initial", "x=0", "--initial", "y=0"], ["every value is zero"]),
}


@pytest.mark.parametrize("name", SIMULATE)
def test_simulate_options(tmp_path, warm, name):
    options, words = SIMULATE[name]
    out = tmp_path / "out"
    result, elapsed = run("simulate", "hammond-1974-one-damper", *options, "--out", str(out))
    assert_refused(result, elapsed, *words)
    assert not out.exists()


@pytest.mark.parametrize("speed", ["inf", "-inf", "nan", "0", "-1"])
def test_phasors_speed(tmp_path, speed):
    out = tmp_path / "out"
    result, elapsed = run("phasors", "hammond-undamped", "--speed", speed, "--no-gif", "--out", str(out))
    assert_refused(result, elapsed, f"--speed = {float(speed)!r}", "finite number > 0", "rpm")
    assert not out.exists()


def test_simulate_estimate_is_of_the_right_size(warm):
    """The estimate before integrating bounds the steps DOP853 takes (within a factor of two).

    Measured on hammond-1974-one-damper at rtol 1e-10: 3511 steps for 30 s at
    255 rpm and 2290 at 50 rpm; the estimate (25 steps per period of the
    fastest rate) gives 6375 and 2249.
    """
    from groundres.solve import simulate

    case = load_case("hammond-1974-one-damper")
    system = System(case.rotor, case.body)
    rpm = 2 * 3.141592653589793 / 60
    for speed, measured in ((255.0, 3511), (50.0, 2290)):
        estimate = simulate.estimate_steps(system, speed * rpm, 30.0)
        assert 0.9 * measured < estimate < 2 * measured, (speed, estimate)


def test_the_order_of_body_dofs_does_not_matter(tmp_path):
    """dofs is a subset: ["y", "x"] once crashed in the mode identification
    ("block of 4 coordinates has labels ['body y', 'body x', 'body y', ...]")."""
    from groundres.analysis import analyze

    text = edit('dofs = ["x", "y"]', 'dofs = ["roll", "y", "x", "pitch"]\n' + PITCH_ROLL)
    in_order = text.replace('["roll", "y", "x", "pitch"]', '["x", "y", "pitch", "roll"]')
    ordered = load_case(write(tmp_path, in_order))
    shuffled = load_case(write(tmp_path, text, "shuffled.toml"))
    assert shuffled.body.dofs == ("x", "y", "pitch", "roll") and shuffled.body == ordered.body
    a, b = analyze(shuffled), analyze(ordered)
    assert a.labels == b.labels
    assert (a.real_part == b.real_part).all() and a.summary()["stable"] == b.summary()["stable"]


@pytest.mark.parametrize(
    "line", ["a" + ".b" * 100_000 + " = 1", "[" + ".".join(["c"] * 100_000) + "]", '"q".' * 40 + "z = 1"]
)
def test_keys_of_many_dotted_parts_are_refused_before_reading(tmp_path, line):
    """The TOML reader takes a time quadratic in a key's parts (100000 parts: minutes)."""
    result, elapsed = run("run", write(tmp_path, GOOD + line + "\n"))
    assert_refused(result, elapsed, f"line {GOOD.count(chr(10)) + 1}", "over 32 dotted parts")


# -- found by throwing some 600 odd inputs at the command line (issue 9 review) ----------------


@pytest.mark.parametrize(
    "old, new",
    [
        ("blade_mass = 94.9", "blade_mass = 1.3e308"),  # (its mass unit was 2^1024: no float)
        ("blade_inertia = 1084.7", "blade_inertia = 1.797e308"),
        (
            "lag_damping = 4067.5\n[[",
            "lag_damping = 4067.5\nflap_stiffness = 1e308\nflap_damping = 1.797e308\n[[",
        ),
        ("start = 0.5\nstop = 40.0", "start = 0.0\nstop = 1e-200"),  # (Omega^2 underflowed)
    ],
)
def test_magnitudes_near_the_ends_of_floating_point_run(tmp_path, old, new):
    """Each once ended in OverflowError or ZeroDivisionError (exit 1); they are
    inside the documented ranges, so they run (masses are computed in a mass
    unit, blade averages divided before they are summed)."""
    out = tmp_path / "out"
    result, _ = run(
        "run", write(tmp_path, edit(old, new).replace("points = 60", "points = 8")), "--out", str(out)
    )
    assert result.exit_code == 0, result.output
    assert (out / "summary.json").exists()


@pytest.mark.parametrize("stop", ["1e160", "1.7e308"])
def test_a_stop_whose_square_overflows_says_how_fast_the_case_can_go(tmp_path, stop):
    result, elapsed = run(
        "run", write(tmp_path, edit("stop = 40.0", f"stop = {stop}")), "--out", str(tmp_path / "o")
    )
    assert_refused(result, elapsed, "[sweep] stop = ", "overflow", "represented up to about")
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("command", ["phasors", "simulate"])
def test_a_speed_beyond_what_the_equations_represent(tmp_path, command):
    """phasors --speed 1e300 ended in OverflowError; both commands now say how fast
    the case can go, in its unit."""
    out = tmp_path / "out"
    result, elapsed = run(command, "hammond-1974", "--speed", "1e300", "--out", str(out))
    assert_refused(result, elapsed, "--speed = 1e+300 rpm", "represented up to about", "rpm (")
    assert not out.exists()


def test_a_simulation_that_cannot_take_large_steps_is_stopped():
    """soft-inplane-pitch-roll at 1e50 rpm ran for hours inside the integrator:
    the steps are counted and a run that needs far more than estimated stops
    with a model-range error (exit 2 on the command line)."""
    from groundres.errors import ModelRangeError
    from groundres.solve import simulate

    case = load_case("hammond-1974")
    system = System(case.rotor, case.body)
    q0, v0 = simulate.initial_state(system, {"x": 0.01})
    with pytest.raises(ModelRangeError, match="took more than 50 steps"):
        simulate.integrate(system, 27.0, 10.0, (q0, v0), max_steps=50, speed_text="258 rpm")


@pytest.mark.parametrize("out", ["", "  ", "/proc/groundres-nope"])
def test_an_output_folder_that_cannot_be_written(tmp_path, out):
    """--out '' was taken as the default silently; --out /proc/... failed with
    FileNotFoundError after the whole analysis. Both are refused first."""
    import os

    if out.startswith("/proc") and not os.path.isdir("/proc"):
        pytest.skip("no /proc here")
    result, elapsed = run("run", "soft-inplane", "--out", out)
    assert_refused(result, elapsed, "--out" if not out.strip() else "cannot write in")


@pytest.mark.parametrize(
    "args, words",
    [
        (
            ["simulate", "hammond-1974", "--speed", "abc"],
            ["'--speed'", "not a valid float", "simulate --help"],
        ),
        (["run", "--bogus"], ["--bogus", "run --help"]),
        (["frob"], ["frob", "--help)"]),
    ],
)
def test_option_mistakes_are_one_line(args, words):
    """click printed three lines (usage, a hint, the error) for these."""
    result, elapsed = run(*args)
    assert_refused(result, elapsed, *words)


def test_the_largest_number_is_written_as_a_float(tmp_path):
    """|value| <= 1.798e+308 was the rounded largest float, itself no float."""
    from groundres.model.casefile import LARGEST_NUMBER, LARGEST_NUMBER_TEXT

    assert float(LARGEST_NUMBER_TEXT) <= LARGEST_NUMBER
    result, elapsed = run("run", write(tmp_path, edit("blade_mass = 94.9", "blade_mass = nan")))
    assert_refused(result, elapsed, "blade_mass", f"|value| <= {LARGEST_NUMBER_TEXT}")


def test_picture_titles_drop_control_characters_and_stay_short():
    """A title with an escape character warned that no font has the glyph, and one
    of 100000 characters took minutes to lay out."""
    from groundres.plotting.titles import TITLE_LENGTH, TITLE_LINE, figure_title

    assert figure_title("rotor \x1b[31mred\x07") == "rotor [31mred"
    long = figure_title("W" * 100000)
    assert len(long.replace("\n", "")) == TITLE_LENGTH and long.endswith("\u2026")
    assert max(len(line) for line in long.split("\n")) <= TITLE_LINE  # (broken into lines that fit)
    assert figure_title("Hammond (1974) rotor") == "Hammond (1974) rotor"
