"""Messages that name what the user wrote, and a terminal free of noise (docs/case-files.md, "Errors").

Each input here once gave a message naming the wrong thing (a derived quantity, another
option, nothing at all), echoed a value whole, printed the identical-blade equations of a
rotor whose blades differ without saying so, or put warnings, matplotlib's notices or a
title's escape sequences on the terminal.
"""

from pathlib import Path

import pytest
from click.testing import CliRunner

import groundres
from conftest import HAMMOND_TOML
from groundres.cli import main
from groundres.errors import CaseError, shown

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
