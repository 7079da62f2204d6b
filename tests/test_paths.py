"""Paths at the edges: output folders that cannot be made or replaced, case files that are no
regular files, keys the TOML reader would take minutes over (docs/case-files.md, "Limits" and
"Output folders").

Found by throwing some 1900 odd inputs at every command: each of these once ended in exit 1
(OSError: File name too long, PermissionError, UnicodeDecodeError), hung (a FIFO, a key of
450000 dotted parts inside an inline table), said something untrue ("no such file" for a FIFO)
or left a hidden folder no later run could remove. Now each is refused before any work with
exit status 2 and one line naming the option or file, or works and leaves nothing behind.

Tests of permissions run only where modes hold (not as root with its capabilities, which
ignores them); the FIFO tests run in a subprocess with a timeout, so that a read that waits
fails instead of hanging the suite.
"""

import os
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
from click.testing import CliRunner

from conftest import HAMMOND_TOML
from groundres.cli import main
from groundres.errors import CaseError
from groundres.model import casefile
from groundres.model.casefile import MAX_KEY_PARTS, read_file, toml_data

#: A quick case (eigen-analysis, 20 speeds).
QUICK = HAMMOND_TOML.replace("points = 60", "points = 20")
EXE = [sys.executable, "-m", "groundres.cli"]


def cli(*args):
    started = time.perf_counter()
    result = CliRunner().invoke(main, [str(a) for a in args])
    return result, time.perf_counter() - started


def refused(result, elapsed, *words):
    """Exit 2, one line naming ``words``, no traceback, quickly (before any work)."""
    assert result.exit_code == 2, result.output
    assert "Traceback" not in result.output
    assert result.output.startswith("error: ") and len(result.output.strip().splitlines()) == 1
    for word in words:
        assert word in result.output, (word, result.output)
    assert len(result.output) < 600, result.output
    assert elapsed < 10, elapsed


def bounded(*args, timeout=120):
    """The command line in a subprocess that may not wait on anything (a FIFO): (code, stderr)."""
    proc = subprocess.run([*EXE, *map(str, args)], capture_output=True, text=True, timeout=timeout)
    assert "Traceback" not in proc.stderr, proc.stderr
    return proc.returncode, proc.stderr


def write_quick(folder: Path, name="quick.toml") -> Path:
    path = folder / name
    path.write_text(QUICK)
    return path


def _modes_hold() -> bool:
    """Whether permission bits bind this process (not root with its capabilities)."""
    import tempfile

    with tempfile.TemporaryDirectory() as scratch:
        os.chmod(scratch, 0o555)
        try:
            Path(scratch, "probe").touch()
        except PermissionError:
            return True
        finally:
            os.chmod(scratch, 0o755)
    return False


modes = pytest.mark.skipif(not _modes_hold(), reason="permission bits do not bind this process (root)")


# -- 1. case files that are no regular files -------------------------------------------------------


def test_a_fifo_as_case_is_named_and_never_waited_on(tmp_path):
    os.mkfifo(tmp_path / "case.toml")
    code, err = bounded("run", tmp_path / "case.toml", "--out", tmp_path / "out", timeout=60)
    assert code == 2 and "not a regular file (a FIFO)" in err, err
    assert "no such file" not in err


@pytest.mark.parametrize(
    "kind, words",
    [
        ("character device", ["'/dev/null'", "not a regular file (a character device)"]),
        ("loop", ["a loop of symbolic links"]),
        ("dangling", ["a symbolic link to", "which does not exist"]),
        ("folder", ["a folder, not a case file"]),
        ("missing", ["no such file or shipped case"]),
        ("through a file", ["a part of it is not a folder"]),
    ],
)
def test_a_case_that_is_no_regular_file_says_what_it_is(tmp_path, kind, words):
    """All of these read "no such file or shipped case"."""
    if kind == "character device":
        case = "/dev/null"
    elif kind == "loop":
        (tmp_path / "a.toml").symlink_to(tmp_path / "b.toml")
        (tmp_path / "b.toml").symlink_to(tmp_path / "a.toml")
        case = tmp_path / "a.toml"
    elif kind == "dangling":
        (tmp_path / "a.toml").symlink_to(tmp_path / "gone.toml")
        case = tmp_path / "a.toml"
    elif kind == "folder":
        case = tmp_path
    elif kind == "missing":
        case = tmp_path / "gone.toml"
    else:
        write_quick(tmp_path)
        case = tmp_path / "quick.toml" / "x.toml"
    result, elapsed = cli("run", case, "--out", tmp_path / "out")
    refused(result, elapsed, *words)
    assert not (tmp_path / "out").exists()


def test_compare_names_the_input_that_is_no_regular_file(tmp_path):
    result, elapsed = cli("compare", "hammond-undamped", "/dev/null", "--out", tmp_path / "out")
    refused(result, elapsed, "case '/dev/null'", "a character device")


@modes
def test_an_unreadable_case_file(tmp_path):
    case = write_quick(tmp_path)
    os.chmod(case, 0)
    result, elapsed = cli("run", case, "--out", tmp_path / "out")
    refused(result, elapsed, str(case), "cannot be read (permission denied)")


def test_a_fifo_put_in_place_after_the_check_is_not_waited_on(tmp_path, monkeypatch):
    """read_file opens without blocking: a FIFO swapped in between the check and the open
    (here: the check told it is a regular file) is refused at once."""
    fifo = tmp_path / "case.toml"
    os.mkfifo(fifo)
    regular = os.stat(__file__)
    real = os.stat
    monkeypatch.setattr(casefile.os, "stat", lambda p, *a, **k: regular if p == fifo else real(p, *a, **k))
    outcome = []

    def read():
        try:
            read_file(fifo, "case", 100)
        except CaseError as err:
            outcome.append(str(err))

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    reader.join(10)
    assert not reader.is_alive(), "the read waited on the FIFO"
    assert outcome == ["case: not a regular file (a FIFO)"]


# -- 2. keys of many dotted parts, wherever they stand ---------------------------------------------

GOOD = QUICK.lstrip("\n")
#: A key of n dotted parts.
key = ".".join


@pytest.mark.parametrize(
    "where",
    [
        "z = { " + key(["a"] * 40) + " = 1 }",
        "z = [ { x = 1 }, { " + key(["a"] * 40) + " = 1 } ]",
        "[" + key(["c"] * 40) + "]",
        "[[" + key(["c"] * 40) + "]]",
        "[ " + " . ".join(["c"] * 40) + " ]",
        "[[ " + key(['"c"', "'d'"] * 20) + " ]]",
        key(['"q"'] * 40) + " = 1",
        "z = { x = 1, y = { " + key(["'p'"] * 40) + " = 2 } }",
        "z = 1 # a comment\n" + key(["a"] * 40) + ' = "value"',
    ],
)
def test_every_key_of_over_32_parts_is_refused(tmp_path, where):
    """Only keys at the start of a line were checked: one inside an inline table, an array of
    them or a spaced header reached the TOML reader."""
    text = GOOD + where + "\n"
    line = GOOD.count("\n") + 1 + where.count("\n")
    with pytest.raises(CaseError, match=f"on line {line} has over {MAX_KEY_PARTS} dotted parts"):
        toml_data(text, "case.toml")


def test_an_inline_table_key_of_450000_parts_is_refused_at_once(tmp_path):
    """It reached the TOML reader, whose time grows as the square of the parts (minutes)."""
    path = tmp_path / "case.toml"
    path.write_text(GOOD + "z = { " + "a." * 450_000 + "b = 1 }\n")
    started = time.perf_counter()
    with pytest.raises(CaseError, match="over 32 dotted parts .450001."):
        toml_data(path.read_text(), str(path))
    assert time.perf_counter() - started < 0.5
    result, elapsed = cli("run", path, "--out", tmp_path / "out")
    refused(result, elapsed, str(path), "the key 'a.a.a.a", "a.a.b' on line", "over 32 dotted parts")


@pytest.mark.parametrize(
    "value",
    [
        '"' + "a." * 100_000 + 'b"',
        "'" + "a." * 100_000 + "b'",
        '"""\n' + "a.b." * 50_000 + '\nc\\"""d.e."""',
        "'''\n" + "a.b." * 50_000 + "\n'''",
        '"""x.y""""',
        '[ "' + key(["s"] * 40) + '", { k = "' + key(["t"] * 40) + '" } ]',
        '{ w = "' + key(["u"] * 40) + '" } # ' + key(["v"] * 40),
        "1979-05-27T07:32:00.999999-07:00",
        "1.5e10",
    ],
)
def test_dots_in_strings_comments_and_values_are_not_keys(value):
    text = f'{GOOD}description = {value}\n["{key(["h"] * 40)}"]\n'
    started = time.perf_counter()
    data = toml_data(text, "case.toml")
    assert time.perf_counter() - started < 1
    assert "description" in data["sweep"]


@pytest.mark.parametrize(
    "form",
    ["{} = 1", "[{}]", "[[{}]]", "z = {{ {} = 1 }}", "z = [{{ {} = 1 }}]"],
)
@pytest.mark.parametrize("part", ["k", "'k'", '"k"'])
def test_keys_of_32_parts_are_read_and_of_33_refused(form, part):
    toml_data(GOOD + form.format(key([part] * MAX_KEY_PARTS)) + "\n", "case.toml")
    with pytest.raises(CaseError, match=f"has over {MAX_KEY_PARTS} dotted parts .{MAX_KEY_PARTS + 1}."):
        toml_data(GOOD + form.format(key([part] * (MAX_KEY_PARTS + 1))) + "\n", "case.toml")
