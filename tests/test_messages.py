"""Messages that name what the user wrote, and a terminal free of noise (docs/case-files.md, "Errors").

Each input here once gave a message naming the wrong thing (a derived quantity, another
option, nothing at all), echoed a value whole, printed the identical-blade equations of a
rotor whose blades differ without saying so, or put warnings, matplotlib's notices or a
title's escape sequences on the terminal.
"""

import os
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest
from click.testing import CliRunner

import groundres
from conftest import HAMMOND_TOML
from groundres.cli import main
from groundres.errors import CaseError, ParameterError, shown

CASES = Path(groundres.__file__).parent / "cases"
#: The light helicopter on skids (a rigid body on four legs), at 20 speeds.
SKIDS = (CASES / "light-helicopter-skids.toml").read_text().replace("points = 400", "points = 20")
#: The Hammond rotor on its hub (modal body) in rad/s, 60 speeds.
GOOD = HAMMOND_TOML.lstrip("\n")
#: Control characters a title or a file name may smuggle to a terminal: OSC (set the
#: window title, ended by BEL), CSI "clear the screen", and the one-byte C1 CSI.
ESCAPES = "\x1b]0;pwned\x07\x1b[2J\x9b31m"
RAW = ("\x1b", "\x07", "\x9b")


def run(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


def write(tmp_path, text, name="case.toml"):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def leg(text, n, old, new):
    """``text`` with ``old`` replaced by ``new`` in its ``n``-th [[body.gear]] table (1-based)."""
    head, *legs = text.split("[[body.gear]]")
    assert old in legs[n - 1], old
    legs[n - 1] = legs[n - 1].replace(old, new, 1)
    return "[[body.gear]]".join([head, *legs])


def refused(result, *words):
    """Exit 2 with one line holding every word."""
    assert result.exit_code == 2, result.output
    assert isinstance(result.exception, SystemExit), result.exception
    assert result.output.startswith("error: ") and len(result.output.strip().splitlines()) == 1, result.output
    for word in words:
        assert word in result.output, (word, result.output)
    return result.output


# -- 1, 2, 5: a rigid body's keys named as the file writes them ------------------------------------------


def test_a_gear_leg_far_stiffer_than_the_others_is_named_with_its_number_and_key(tmp_path):
    """Was "[body] dofs: the gear legs hold no stiffness against 'y'": the legs do hold y, but
    leg 1's 1e20 N/m leaves the others' 1e5 N/m below round-off of the stiffness matrix."""
    text = leg(SKIDS, 1, "stiffness_x = 1.0e5", "stiffness_x = 1e20")
    message = refused(
        run("run", write(tmp_path, text), "--out", tmp_path / "o"),
        "[[body.gear]] 1: stiffness_x = 1e+20",
        "so large against the legs' other stiffness values",
        "cannot be resolved in double precision",
        "here up to about",
    )
    assert "dofs" not in message
    # the same leg named by its number wherever it stands (here the third), and a value so
    # small that the others drown it
    text = leg(SKIDS, 3, "stiffness_z = 2.5e5", "stiffness_z = 1e30")
    refused(
        run("run", write(tmp_path, text), "--out", tmp_path / "o"), "[[body.gear]] 3: stiffness_z = 1e+30"
    )
    text = SKIDS.replace("stiffness_y = 0.5e5", "stiffness_y = 1e-12")
    refused(
        run("run", write(tmp_path, text), "--out", tmp_path / "o"),
        "[[body.gear]] 1: stiffness_y = 1e-12",
        "so small",
        "at least about",
    )


def test_legs_that_hold_no_stiffness_in_a_direction_still_name_dofs(tmp_path):
    text = SKIDS.replace("stiffness_y = 0.5e5", "stiffness_y = 0.0")
    refused(
        run("run", write(tmp_path, text), "--out", tmp_path / "o"), "[body] dofs", "no stiffness against 'y'"
    )


def test_the_library_names_the_leg_of_a_body(tmp_path):
    from groundres.model.schema import load_case

    body = load_case(write(tmp_path, SKIDS)).body
    legs = list(body.gear)
    legs[1] = type(legs[1])(**{**legs[1].__dict__, "stiffness_x": 1e20})
    with pytest.raises(ParameterError) as err:
        type(body)(**{**body.__dict__, "gear": tuple(legs)})
    assert err.value.key == "gear[2].stiffness_x" and err.value.value == 1e20


def test_a_leg_damper_beyond_resolution_is_named_with_its_leg_and_key(tmp_path):
    """Was "[[body.gear]] damping (in roll) = 1.21e+300 N m s/rad", a sum no file holds."""
    text = leg(SKIDS, 1, "damping_z = 2500.0", "damping_z = 1e300")
    message = refused(
        run("run", write(tmp_path, text), "--out", tmp_path / "o"),
        "[[body.gear]] 1: damping_z = 1e+300 N s/m",
        "allowed here: leg 1's damping_z up to about",
    )
    assert "(in roll) =" not in message
    text = leg(SKIDS, 4, "stiffness_y = 0.5e5", "stiffness_y = 1e40")
    refused(
        run("run", write(tmp_path, text), "--out", tmp_path / "o"), "[[body.gear]] 4: stiffness_y = 1e+40"
    )


@pytest.mark.parametrize("mass", ["1e300", "1e20"])
def test_a_rigid_body_mass_that_makes_the_mass_matrix_singular_is_named(tmp_path, mass):
    """Was "the mass matrix of this case is singular to working precision", no key nor value."""
    text = SKIDS.replace("mass = 1100.0", f"mass = {mass}")
    refused(
        run("run", write(tmp_path, text), "--out", tmp_path / "o"),
        f"[body] mass = {float(mass):g} kg",
        "inertia_xx = 700, inertia_yy = 2500",
        "allowed here: mass up to about",
    )


def test_a_large_rigid_mass_the_model_resolves_runs(tmp_path):
    text = SKIDS.replace("mass = 1100.0", "mass = 1e300").replace("centre_z = 1.0", "centre_z = 0.0")
    result = run("run", write(tmp_path, text), "--out", tmp_path / "o")
    assert result.exit_code == 0, result.output


# -- 3: simulate --initial ----------------------------------------------------------------------------


@pytest.mark.parametrize("value", ["1e308", "1e300", "-1e151"])
def test_an_initial_displacement_beyond_the_bound_names_initial(tmp_path, value):
    """1e308 was blamed on the speed ("choose a lower speed") after an overflow warning."""
    message = refused(
        run(
            "simulate",
            write(tmp_path, GOOD),
            "--speed",
            "20",
            "--initial",
            f"x={value}",
            "--out",
            tmp_path / "o",
        ),
        f"--initial x={float(value)!r}",
        "|value| <= 1e+150",
        "linear",
    )
    assert "--speed" not in message and "lower speed" not in message


def test_an_initial_rate_beyond_the_bound_names_it(tmp_path):
    refused(
        run(
            "simulate",
            write(tmp_path, GOOD),
            "--speed",
            "20",
            "--initial",
            "lag1_rate=1e200",
            "--out",
            tmp_path / "o",
        ),
        "--initial lag1_rate=1e+200",
    )


def test_a_run_whose_growth_would_overflow_names_the_time(tmp_path):
    """x = 1e140 growing at 0.355 1/s for 100 s overflowed (RuntimeWarnings, then exit 1)."""
    args = ("simulate", write(tmp_path, SKIDS), "--speed", "150", "--initial", "x=1e140", "--time", "100")
    refused(run(*args, "--out", tmp_path / "o"), "--time = 100.0", "e^35.", "at most 64.8", "1e+150")
    assert not (tmp_path / "o").exists()


def test_the_growth_bound():
    from groundres.solve.simulate import LARGEST_MOTION, MIN_REVOLUTIONS, fit_growth

    speed = 15.7  # [rad/s]: a revolution of 0.4 s
    assert fit_growth(100.0, 0.0, {"x": 1e140}, True, speed) == 100.0  # neutral: no bound
    assert fit_growth(100.0, -1.0, {"x": 1e150}, True, speed) == 100.0  # decaying
    longest = fit_growth(100.0, 0.5, {"x": 1e140, "y": 1.0}, False, speed)  # the default, shortened
    assert longest == pytest.approx(__import__("math").log(LARGEST_MOTION / 1e140) / 0.5)
    with pytest.raises(ParameterError) as err:
        fit_growth(100.0, 0.5, {"x": 1e140}, True, speed)
    assert err.value.key == "duration" and "at most 46.05 s" in err.value.allowed
    with pytest.raises(ParameterError) as err:  # too large even for the shortest run
        fit_growth(100.0, 50.0, {"x": 1.0, "lag1": -1e100}, False, speed)
    assert err.value.key == "initial" and err.value.value == {"lag1": -1e100}
    assert f"{MIN_REVOLUTIONS} revolutions" in err.value.allowed


# -- 4: --method named as given ---------------------------------------------------------------------


def test_eigen_from_the_command_line_names_the_option(tmp_path):
    """Was "[sweep] method = 'eigen'" though the case asks for auto."""
    message = refused(
        run("run", "hammond-1974-one-damper", "--method", "eigen", "--out", tmp_path / "o"),
        "--method eigen: this case has periodic coefficients in every frame",
        "use 'floquet' or 'auto'",
    )
    assert "[sweep]" not in message
    text = (
        (CASES / "hammond-1974-one-damper.toml")
        .read_text()
        .replace('unit = "rpm"', 'unit = "rpm"\nmethod = "eigen"')
    )
    message = refused(run("run", write(tmp_path, text), "--out", tmp_path / "o"), "[sweep] method = 'eigen':")
    assert "--method" not in message
    refused(
        run(
            "compare", "hammond-1974", "hammond-1974-one-damper", "--method", "eigen", "--out", tmp_path / "o"
        ),
        "entry 2 (hammond-1974-one-damper by method 'eigen'): --method eigen: ",
    )


def test_method_errors_keep_their_parts_through_pickling():
    """(A study's points are analysed in other processes.)"""
    import pickle

    from groundres.errors import MethodError

    err = MethodError("method", "eigen", "no eigenvalues", "entry 2")
    back = pickle.loads(pickle.dumps(err))
    assert (back.key, back.value, back.entry, str(back)) == ("method", "eigen", "entry 2", str(err))
    assert back.named("--method eigen") == "entry 2: --method eigen: no eigenvalues"


# -- 6: values shortened ----------------------------------------------------------------------------

LONG = "r" * 20000


@pytest.mark.parametrize(
    "old, new, key",
    [
        ('unit = "rad/s"', f'unit = "{LONG}"', "[sweep] unit"),
        ('dofs = ["x", "y"]', f'dofs = ["x", "{LONG}"]', "[body] dofs"),
        ('dofs = ["x", "y"]', f'dofs = ["x", "y", "x", "{LONG}"]', "[body] dofs"),
    ],
)
def test_a_long_value_is_shown_shortened(tmp_path, old, new, key):
    """unit and dofs echoed 20000 characters (twice for dofs)."""
    message = refused(
        run("run", write(tmp_path, GOOD.replace(old, new)), "--out", tmp_path / "o"), key, "..."
    )
    assert len(message) < 300, len(message)


@pytest.mark.parametrize(
    "args",
    [
        ["simulate", "--speed", "20", "--initial", LONG],
        ["simulate", "--speed", "20", "--initial", f"x={LONG}"],
        ["run", " " * 20000],
        ["run", "--out", " " * 20000],
        ["phasors", "--speed", "200", "--mode", LONG],
        ["gallery", "--figures", LONG],
    ],
)
def test_a_long_option_value_is_shown_shortened(tmp_path, args):
    result = run(*args)
    assert result.exit_code == 2, result.output
    error = result.output.strip().splitlines()[-1]
    assert error.startswith("error: ") and "..." in error and len(error) < 300, error


def test_shown_and_printable():
    from groundres.errors import printable

    assert shown("a\x1bb") == "'a\\x1bb'"
    assert shown(["x" * 500]).endswith("...xxxxxxxxxx']") and len(shown(["x" * 500])) == 55
    assert printable("line 1\nline\x1b[2J 2\x9b\t") == "line 1\nline\\x1b[2J 2\\x9b\\t"
    assert printable("a\nb", keep="") == "a\\nb"
    assert (
        str(CaseError(f"{ESCAPES}.toml: no such file"))
        == "\\x1b]0;pwned\\x07\\x1b[2J\\x9b31m.toml: no such file"
    )


# -- 7: equations in multiblade form of dissimilar blades -----------------------------------------


def test_multiblade_equations_of_dissimilar_blades_say_what_they_show():
    """They were printed as if the blades were identical."""
    result = run("equations", "hammond-1974-one-damper", "--form", "multiblade")
    assert result.exit_code == 0, result.output
    head = result.output.split("mass matrix")[0]
    for words in (
        "NOTE: this rotor does not look the same from every blade",
        "blade 1's lag_damping is 0, the others' 4067.5",
        "its multiblade equations are periodic",
        "those of identical",
        "--form blade prints each blade's equations exactly",
        "by Floquet theory",
    ):
        assert words in head, (words, head)
    rods = run("equations", "hammond-interblade-one-failed", "--form", "multiblade").output
    assert "damper rods do not repeat from blade to blade" in rods
    isotropic = run("equations", "hammond-one-damper-isotropic", "--form", "multiblade").output
    assert "in rotating axes (its body is isotropic)" in isotropic
    # no note where the form is exact, nor for the blade form
    assert "NOTE" not in run("equations", "hammond-1974", "--form", "multiblade").output
    assert "NOTE" not in run("equations", "hammond-1974-one-damper").output


# -- 8: characters the font cannot draw -------------------------------------------------------------


def test_a_title_character_no_font_draws_is_replaced():
    from groundres.plotting.titles import REPLACEMENT, figure_title, literal

    assert figure_title("Rotor \U0001f681 ü é 中") == f"Rotor {REPLACEMENT} ü é {REPLACEMENT}"
    assert literal("heli\U0001f681copter $1") == f"heli{REPLACEMENT}copter \\$1"
    assert figure_title("Hammond (1974) rotor") == "Hammond (1974) rotor"


EMOJI = GOOD.replace('title = "test"', 'title = "Rotor \U0001f681 on its hub"').replace(
    "points = 60", "points = 30"
)


@pytest.mark.parametrize(
    "command",
    [
        ["run"],
        ["simulate", "--speed", "20"],
        ["phasors", "--speed", "20"],
        ["report"],
        ["compare", "{other}"],
        ["run", "--format", "pdf"],
        ["run", "--format", "svg"],
    ],
)
def test_an_emoji_in_a_title_draws_without_a_warning(tmp_path, command):
    """matplotlib warned "Glyph 128641 (HELICOPTER) missing from font(s) DejaVu Sans" (an error here,
    where warnings are errors: exit 1)."""
    case = write(tmp_path, EMOJI)
    other = write(tmp_path, EMOJI.replace("lag_damping = 4067.5", "lag_damping = 3000.0"), "other.toml")
    args = [a.replace("{other}", str(other)) for a in command]
    result = run(args[0], case, *args[1:], "--out", tmp_path / "o")
    assert result.exit_code == 0, result.output
    assert "Warning" not in result.output


# -- 9, 8: a HOME that cannot be written, in a process of its own -----------------------------------


def _env(**extra):
    env = {
        k: v for k, v in os.environ.items() if k not in ("MPLCONFIGDIR", "XDG_CACHE_HOME", "XDG_CONFIG_HOME")
    }
    env["PYTHONPATH"] = os.pathsep.join(
        filter(None, [str(Path(groundres.__file__).parents[1]), env.get("PYTHONPATH")])
    )
    return {**env, **extra}


def test_nothing_but_the_results_where_home_cannot_be_written(tmp_path):
    """matplotlib said "Matplotlib created a temporary cache directory ..." on every command
    that draws, and warned of the missing glyph. /dev/null as HOME is not writable even by
    root. The case is periodic: the numba cache (off without a safe folder) says nothing either."""
    text = (CASES / "hammond-1974-one-damper.toml").read_text().replace("points = 400", "points = 8")
    text = text.replace('title = "Hammond', 'title = "\U0001f681 Hammond')
    case = write(tmp_path, text)
    result = subprocess.run(
        [
            sys.executable,
            "-W",
            "default",
            "-m",
            "groundres.cli",
            "run",
            str(case),
            "--out",
            str(tmp_path / "o"),
        ],
        capture_output=True,
        text=True,
        env=_env(HOME="/dev/null"),
        timeout=300,
    )
    assert result.returncode == 0, result.stderr
    assert result.stderr == "", result.stderr
    assert (tmp_path / "o" / "coleman.png").exists()


def test_matplotlib_gets_a_private_folder_only_where_its_own_cannot_be_written():
    code = (
        "import os, stat; from groundres.cli.common import matplotlib_folder; matplotlib_folder(); "
        "p = os.environ.get('MPLCONFIGDIR'); "
        "print(p, p and oct(stat.S_IMODE(os.stat(p).st_mode)), p and os.stat(p).st_uid == os.getuid())"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=_env(HOME="/dev/null"), timeout=60
    )
    assert out.stderr == ""
    folder, mode, own = out.stdout.split()
    assert mode == "0o700" and own == "True"  # (no other account can put a matplotlibrc there)
    assert Path(folder).parent == Path(tempfile.gettempdir()) and "groundres-matplotlib-" in folder
    assert not Path(folder).exists()  # (removed at exit)
    # a writable HOME: matplotlib's own folder, untouched
    with tempfile.TemporaryDirectory() as home:
        out = subprocess.run(
            [sys.executable, "-c", code], capture_output=True, text=True, env=_env(HOME=home), timeout=60
        )
        assert out.stdout.split()[0] == "None"


def test_the_numba_cache_is_off_and_silent_where_home_cannot_be_written(monkeypatch, capfd):
    from groundres.solve.floquet.compiled import cache_folder

    monkeypatch.setenv("HOME", "/dev/null")
    monkeypatch.delenv("XDG_CACHE_HOME", raising=False)
    assert cache_folder() is None
    assert capfd.readouterr() == ("", "")


# -- 10: control characters never reach the terminal ------------------------------------------------


def assert_clean(output):
    assert not any(ch in output for ch in RAW), repr(output)


def test_a_case_file_name_with_escape_sequences_is_escaped_in_messages(tmp_path):
    """Printed raw: "error: x^[]0;pwned^G.toml: not valid TOML" set the terminal's title."""
    path = write(tmp_path, "title = \x1b", name=f"x{ESCAPES}.toml")
    output = refused(run("run", path), "not valid TOML", "x\\x1b]0;pwned\\x07\\x1b[2J\\x9b31m.toml")
    assert_clean(output)
    missing = tmp_path / f"gone{ESCAPES}.toml"
    assert_clean(refused(run("run", missing), "no such file", "x9b31m.toml"))
    assert_clean(refused(run("run", "--frame", f"r{ESCAPES}"), "--frame"))


def test_a_title_with_escape_sequences_is_printed_escaped(tmp_path):
    """Control characters were dropped from the run's headers (so the title read differently
    from the file) and printed raw by equations."""
    text = GOOD.replace('title = "test"', 'title = "\\u001b]0;pwned\\u0007\\u001b[2J\\u009b31m [red]rotor"')
    case = write(tmp_path, text)
    result = run("run", case, "--out", tmp_path / "o")
    assert result.exit_code == 0, result.output
    assert_clean(result.output)
    assert "\\x1b]0;pwned\\x07\\x1b[2J\\x9b31m [red]rotor" in result.output  # (markup literal too)
    result = run("equations", case)
    assert result.exit_code == 0
    assert_clean(result.output)
    assert result.output.startswith("# \\x1b]0;pwned\\x07\\x1b[2J\\x9b31m [red]rotor\n")


def test_case_names_with_escape_sequences_in_a_comparison_are_escaped(tmp_path):
    first = write(tmp_path, GOOD, name=f"a{ESCAPES}.toml")
    second = write(
        tmp_path, GOOD.replace("lag_damping = 4067.5", "lag_damping = 3000.0"), name="b\x1b[2J.toml"
    )
    result = run("compare", first, second, "--out", tmp_path / "o")
    assert result.exit_code == 0, result.output
    assert_clean(result.output)
    assert "b\\x1b[2J" in result.output


def test_the_console_escapes_whatever_is_printed_through_it():
    """What a command prints without escaping it first (a path, a reason) is escaped too;
    rich's own styles still reach a terminal."""
    import io

    from groundres.cli.common import make_console
    from groundres.errors import printable

    console = make_console(file=io.StringIO())
    console.print(f"Wrote {ESCAPES}/study.zarr", markup=False)
    console.print("[bold]bold[/bold]")
    # (rich drops BEL itself)
    assert console.file.getvalue() == "Wrote \\x1b]0;pwned\\x1b[2J\\x9b31m/study.zarr\nbold\n"
    terminal = make_console(file=io.StringIO(), force_terminal=True)
    terminal.print(f"[bold]{printable(ESCAPES)}[/bold]{ESCAPES}")
    text = terminal.file.getvalue()
    assert "\x1b[1m" in text and text.count("\\x1b]0;pwned") == 2
    assert "\x07" not in text and "\x9b" not in text and "\x1b]" not in text


def test_equations_of_a_huge_rigid_mass_print_it_without_overflow(tmp_path):
    """equations rounded the body matrices by scaling them by 1e10: [body] mass = 1e300 printed an
    overflow warning (and would have shown inf); the value is shown as it is."""
    import subprocess
    import sys

    from groundres import load_case

    text = load_case("light-helicopter-skids").text
    case = tmp_path / "m.toml"
    case.write_text(
        "\n".join("mass = 1e300" if line.startswith("mass =") else line for line in text.splitlines())
    )
    run = subprocess.run(
        [sys.executable, "-W", "error", "-m", "groundres.cli", "equations", str(case)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert run.returncode == 0 and run.stderr == "", run.stderr
    assert "1.0e+300" in run.stdout


def _run_strict(tmp_path, text: str):
    """``groundres run`` of the case ``text`` with every warning an error (subprocess)."""
    import subprocess
    import sys

    case = tmp_path / "case.toml"
    case.write_text(text)
    return subprocess.run(
        [
            sys.executable,
            "-W",
            "error",
            "-m",
            "groundres.cli",
            "run",
            str(case),
            "--out",
            str(tmp_path / "o"),
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )


def test_a_leg_stiffness_at_the_largest_float_is_named_without_overflow(tmp_path):
    """A gear leg's stiffness_z = 1.797e308 overflowed in the legs' matrix (two warnings on the
    terminal before the message); the leg is named with no warning."""
    from groundres import load_case

    text = load_case("light-helicopter-skids").text
    run = _run_strict(tmp_path, text.replace("stiffness_z =", "stiffness_z = 1.7976931348623157e+308 #", 1))
    assert run.returncode == 2, run.stderr
    assert run.stderr.startswith("error: [[body.gear]] 1: stiffness_z = 1.797"), run.stderr
    assert "Warning" not in run.stderr


def test_a_leg_damping_near_the_largest_float_is_named_without_overflow(tmp_path):
    """A gear leg's damping_z = 1e308 overflowed in the body's isotropy test (a warning before
    the message); the leg is named with no warning."""
    from groundres import load_case

    text = load_case("light-helicopter-skids").text
    at = text.rindex("damping_z =")
    run = _run_strict(tmp_path, text[:at] + "damping_z = 1e308 #" + text[at + len("damping_z =") :])
    assert run.returncode == 2, run.stderr
    assert run.stderr.startswith("error: [[body.gear]] 4: damping_z = 1e+308"), run.stderr
    assert "Warning" not in run.stderr
