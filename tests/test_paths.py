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

import json
import os
import stat
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from click.testing import CliRunner

from conftest import HAMMOND_TOML
from groundres.cli import main
from groundres.cli import study as study_cli
from groundres.errors import CaseError, OutputFolderError
from groundres.model import casefile
from groundres.model.casefile import MAX_KEY_PARTS, read_file, toml_data
from groundres.results import files, folders

#: A quick case (eigen-analysis, 20 speeds).
QUICK = HAMMOND_TOML.replace("points = 60", "points = 20")
EXE = [sys.executable, "-m", "groundres.cli"]
#: Every command that writes a folder, as far as its --out (refused before any work).
COMMANDS = {
    "run": ["run", "hammond-undamped"],
    "phasors": ["phasors", "hammond-undamped", "--speed", "250", "--no-gif"],
    "simulate": ["simulate", "hammond-undamped", "--speed", "250", "--time", "3"],
    "compare": ["compare", "hammond-undamped", "hammond-1974"],
    "report": ["report", "hammond-undamped"],
    "gallery": ["gallery", "--figures", "3"],
    "study": ["study", "hammond-undamped", "--vary", "rotor.lag_damping=0:1:2", "--workers", "1"],
}


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


def leftovers(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.name.startswith(".groundres"))


def write_quick(folder: Path, name="quick.toml") -> Path:
    path = folder / name
    path.write_text(QUICK)
    return path


@pytest.fixture
def no_cluster(monkeypatch):
    """A study refused before any work starts no cluster."""

    def started(*args):
        raise AssertionError("a cluster was started")

    monkeypatch.setattr(study_cli, "_client", started)


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


@pytest.fixture
def restore_modes():
    """Paths whose mode a test takes away, given back afterwards (so that they can be removed)."""
    paths = []
    yield paths
    for path in paths:
        os.chmod(path, 0o755)


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


# -- 3. names and paths too long for the file system -----------------------------------------------


@pytest.mark.parametrize("too_long", ["name", "path"])
@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_an_out_too_long_for_the_file_system_is_refused_first(tmp_path, command, too_long, no_cluster):
    """A last name over NAME_MAX or a path over PATH_MAX gave OSError [Errno 36] (exit 1)."""
    name_max = os.pathconf(tmp_path, "PC_NAME_MAX")
    path_max = os.pathconf(tmp_path, "PC_PATH_MAX")
    if too_long == "name":
        out, words = tmp_path / ("a" * (name_max + 45)), [f"over the {name_max}", "NAME_MAX"]
    else:
        out = tmp_path.joinpath(*["b" * 200] * (path_max // 200 + 1))
        words = [f"over the {path_max - folders.ROOM}", f"PATH_MAX {path_max}"]
    result, elapsed = cli(*COMMANDS[command], "--out", out)
    refused(result, elapsed, "--out '", "bytes", *words)
    assert list(tmp_path.iterdir()) == []


def test_the_path_limit_keeps_room_for_the_files_inside(tmp_path):
    """A path just within PATH_MAX less the room passes the check; one byte more does not."""
    path_max = os.pathconf(tmp_path, "PC_PATH_MAX")
    base, limit = Path(os.path.realpath(tmp_path)), path_max - folders.ROOM
    parts, length = [], len(str(base))
    while limit - length > 250:
        parts.append("d" * 200)
        length += 201
    fits = base.joinpath(*parts, "e" * (limit - length - 1))
    assert len(str(fits)) == limit
    assert folders.check_folder(fits, "--out") is False  # (missing, and may be made)
    with pytest.raises(OutputFolderError, match=f"over the {path_max - folders.ROOM} a folder"):
        folders.check_folder(str(fits) + "e", "--out")


def test_a_default_folder_whose_name_grows_too_long_says_to_choose_one(tmp_path, monkeypatch):
    """groundres-out/<case name>-phasors from a case name near NAME_MAX: OSError (exit 1)."""
    monkeypatch.chdir(tmp_path)
    name_max = os.pathconf(tmp_path, "PC_NAME_MAX")
    case = write_quick(tmp_path, "q" * (name_max - 6) + ".toml")
    result, elapsed = cli("phasors", case.name, "--speed", "20", "--no-gif")
    refused(result, elapsed, "the default output folder (choose one with --out)", "NAME_MAX")
    assert sorted(os.listdir(tmp_path)) == [case.name]


def test_a_long_name_within_the_limit_is_written_and_replaced_leaving_nothing(tmp_path):
    """The hidden folders beside it took '-<its name>' after 30 characters of their own: a name
    of 230 to 255 bytes failed after the analysis (exit 2 on the first run, exit 1 on the next,
    which could not name the old folder's hidden copy)."""
    case = write_quick(tmp_path)
    out = tmp_path / ("c" * (os.pathconf(tmp_path, "PC_NAME_MAX") - 5))
    for _ in range(2):
        result, _ = cli("run", case, "--out", out)
        assert result.exit_code == 0, result.output
        assert leftovers(tmp_path) == []
    record = json.loads((out / "provenance.json").read_text())
    assert sorted(os.listdir(out)) == record["files"]


# -- 4. folders a command cannot write -------------------------------------------------------------


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_an_out_under_a_file_is_refused_first(tmp_path, command, no_cluster):
    (tmp_path / "file").write_text("mine")
    result, elapsed = cli(*COMMANDS[command], "--out", tmp_path / "file" / "out")
    refused(result, elapsed, "--out '", "cannot be made", "is not a folder (a regular file)")
    assert sorted(os.listdir(tmp_path)) == ["file"]


def test_an_out_through_a_loop_of_symbolic_links_is_named(tmp_path):
    (tmp_path / "a").symlink_to(tmp_path / "b")
    (tmp_path / "b").symlink_to(tmp_path / "a")
    result, elapsed = cli("run", "hammond-undamped", "--out", tmp_path / "a" / "out")
    refused(result, elapsed, "--out '", "is a loop of symbolic links")


@modes
@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_a_read_only_out_is_refused_first(tmp_path, command, no_cluster, restore_modes):
    """A study wrote into it after starting its cluster (PermissionError, exit 1); the others
    replaced a folder the user had made read-only."""
    out = tmp_path / "ro"
    out.mkdir()
    os.chmod(out, 0o555)
    restore_modes.append(out)
    result, elapsed = cli(*COMMANDS[command], "--out", out)
    refused(result, elapsed, "--out '", "not writable")
    assert os.listdir(out) == [] and leftovers(tmp_path) == []


@modes
def test_an_out_under_a_folder_that_cannot_be_searched(tmp_path, restore_modes):
    """Path.exists() raised PermissionError (exit 1)."""
    locked = tmp_path / "locked"
    (locked / "in").mkdir(parents=True)
    os.chmod(locked, 0)
    restore_modes.append(locked)
    result, elapsed = cli("run", "hammond-undamped", "--out", locked / "in" / "out")
    refused(result, elapsed, "--out '", f"{str(locked)!r} cannot be searched")


@modes
def test_a_study_folder_with_an_unreadable_case_copy_is_refused_first(tmp_path, no_cluster):
    out = tmp_path / "out"
    out.mkdir()
    (out / "case.toml").write_text(QUICK)
    os.chmod(out / "case.toml", 0)
    result, elapsed = cli(*COMMANDS["study"], "--out", out)
    refused(result, elapsed, "--out '", "case.toml", "cannot be read (permission denied)")


@modes
def test_a_study_store_that_is_not_writable_is_refused_first(tmp_path, no_cluster, restore_modes):
    out = tmp_path / "out"
    (out / "study.zarr" / "growth_margin").mkdir(parents=True)
    os.chmod(out / "study.zarr" / "growth_margin", 0o555)
    restore_modes.append(out / "study.zarr" / "growth_margin")
    result, elapsed = cli(*COMMANDS["study"], "--out", out)
    refused(result, elapsed, "--out '", "study.zarr/growth_margin there is not writable")


def test_a_study_folder_holding_a_fifo_for_its_case_copy_is_refused(tmp_path):
    """Its case.toml was read to compare with the case: a FIFO there made the study wait forever."""
    out = tmp_path / "out"
    out.mkdir()
    os.mkfifo(out / "case.toml")
    code, err = bounded(*COMMANDS["study"], "--out", out, timeout=60)
    assert code == 2, err
    assert "--out '" in err and "case.toml: not a regular file (a FIFO)" in err
    assert sorted(os.listdir(out)) == ["case.toml"]


def test_a_mount_point_is_refused_first(tmp_path, monkeypatch):
    """It cannot be moved aside: the run found out only after all its work."""
    out = tmp_path / "mnt"
    out.mkdir()
    real = os.path.ismount
    monkeypatch.setattr(os.path, "ismount", lambda p: os.fspath(p) == str(out) or real(p))
    result, elapsed = cli("run", "hammond-undamped", "--out", out)
    refused(result, elapsed, "--out '", "cannot be replaced: a mount point", "mnt/results")


# -- 5. nothing left beside a folder ---------------------------------------------------------------


@modes
def test_an_earlier_output_folder_made_read_only_is_not_replaced(tmp_path, restore_modes):
    """It was replaced (exit 0), and its old copy, which could not be emptied, stayed beside it as
    .groundres-old-*, which no later run could remove."""
    case = write_quick(tmp_path)
    out = tmp_path / "out"
    assert cli("run", case, "--out", out)[0].exit_code == 0
    before = {name: (out / name).read_bytes() for name in os.listdir(out)}
    os.chmod(out, 0o555)
    restore_modes.append(out)
    result, elapsed = cli("run", case, "--out", out)
    refused(result, elapsed, "--out '", "cannot be replaced: not writable")
    assert {name: (out / name).read_bytes() for name in os.listdir(out)} == before
    assert leftovers(tmp_path) == []


@modes
def test_hidden_folders_left_read_only_are_removed_by_the_next_run(tmp_path):
    case = write_quick(tmp_path)
    stale = tmp_path / ".groundres-old-999999999-abcd1234-out"  # (pids stay below 2**22)
    stale.mkdir()
    (stale / "summary.json").write_text("old")
    os.chmod(stale, 0o555)
    result, _ = cli("run", case, "--out", tmp_path / "out")
    assert result.exit_code == 0, result.output
    assert leftovers(tmp_path) == []


@modes
def test_a_folder_made_read_only_during_the_run_is_left_whole(tmp_path, restore_modes):
    """The check is made again under the lock, before the swap: the run is refused then, the
    folder left as it was and the fresh one removed."""
    out = tmp_path / "out"
    out.mkdir()
    (out / "summary.json").write_text("older")  # (what an older version wrote: replaceable)
    with pytest.raises(OutputFolderError, match="not writable"):
        with folders.output_folder(out, "--out") as fresh:
            (fresh / "summary.json").write_text("new")
            os.chmod(out, 0o555)
            restore_modes.append(out)
    assert (out / "summary.json").read_text() == "older" and leftovers(tmp_path) == []


@modes
def test_a_umask_that_takes_the_owners_write_leaves_nothing(tmp_path, restore_modes):
    """Under umask 0222 the fresh folder and each temporary file were made read-only before
    they were written: every run failed (PermissionError, exit 1) after all its work. Now a run
    writes its folder (read-only, as the umask asks), a second run is refused before any work,
    and a run refused at the swap leaves no read-only fresh folder behind."""
    case = write_quick(tmp_path)
    out, other = tmp_path / "out", tmp_path / "other"
    other.mkdir()
    previous = os.umask(0o222)
    try:
        result, _ = cli("run", case, "--out", out)
        assert result.exit_code == 0, result.output
        restore_modes.append(out)
        assert stat.S_IMODE(os.stat(out).st_mode) == 0o555
        refused(*cli("run", case, "--out", out), "--out '", "cannot be replaced: not writable")
        with pytest.raises(OutputFolderError, match="did not write"):
            with folders.output_folder(other, "--out") as fresh:
                files.write_bytes(fresh / "summary.json", b"new")
                os.umask(0o022)
                (other / "notes.txt").write_text("mine")
                os.umask(0o222)
    finally:
        os.umask(previous)
    assert os.listdir(other) == ["notes.txt"] and leftovers(tmp_path) == []


def test_a_failed_run_removes_the_parent_folders_it_made(tmp_path):
    """--out a/b/out: a and b were made for the hidden folder and stayed when the run failed."""
    with pytest.raises(RuntimeError):
        with folders.output_folder(tmp_path / "a" / "b" / "out", "--out") as fresh:
            (fresh / "summary.json").write_text("half")
            raise RuntimeError("the run failed while writing")
    assert list(tmp_path.iterdir()) == []


@modes
def test_a_parent_one_may_write_in_but_not_list(tmp_path, restore_modes):
    """Listing it for the stale hidden folders of killed runs raised PermissionError (exit 1)
    once the results were written."""
    drop = tmp_path / "drop"
    drop.mkdir()
    os.chmod(drop, 0o333)
    restore_modes.append(drop)
    result, _ = cli("run", write_quick(tmp_path), "--out", drop / "out")
    assert result.exit_code == 0, result.output
    assert (drop / "out" / "provenance.json").is_file()
    os.chmod(drop, 0o755)
    assert leftovers(drop) == []


def test_stale_probe_folders_are_removed_like_other_hidden_folders(tmp_path):
    probe = tmp_path / ".groundres-probe-999999999-abcd1234"
    probe.mkdir()
    assert folders._STAGING.fullmatch(probe.name)
    result, _ = cli("run", write_quick(tmp_path), "--out", tmp_path / "out")
    assert result.exit_code == 0, result.output
    assert leftovers(tmp_path) == []


# -- 6. the study folder report --study reads ------------------------------------------------------


def test_report_study_too_long_is_named(tmp_path):
    result, elapsed = cli("report", "--study", tmp_path / ("s" * 300), "--out", tmp_path / "r")
    refused(result, elapsed, "--study '", "File name too long", "sss' (")


def _study_folder(folder: Path) -> Path:
    """The files a study's --out holds that the report reads."""
    folder.mkdir()
    ds = xr.Dataset(
        {"stable": (("rotor.lag_damping",), np.array([0, 1]))}, coords={"rotor.lag_damping": [1.0, 2.0]}
    )
    ds.to_netcdf(folder / "study.nc")
    (folder / "case.toml").write_text(QUICK)
    (folder / "provenance.json").write_text('{"generator": "groundres", "command": "study"}')
    (folder / "map.png").write_bytes(b"\x89PNG\r\n\x1a\n")
    return folder


@pytest.mark.parametrize("name", ["provenance.json", "map.png", "case.toml"])
def test_report_study_with_a_fifo_is_refused_never_waited_on(tmp_path, name):
    """provenance.json was read as soon as the folder was checked, map.png and case.toml after
    the analysis: a FIFO in the study folder made the report wait forever."""
    study = _study_folder(tmp_path / "study")
    (study / name).unlink()
    os.mkfifo(study / name)
    code, err = bounded("report", "--study", study, "--out", tmp_path / "r", timeout=120)
    assert code == 2 and f"--study {str(study)!r}: {name}: not a regular file (a FIFO)" in err, err
    assert not (tmp_path / "r").exists()


def test_report_study_with_a_case_copy_that_is_not_utf8(tmp_path):
    """It was compared with the case as text: UnicodeDecodeError (exit 1)."""
    study = _study_folder(tmp_path / "study")
    (study / "case.toml").write_bytes(b"\xff\xfe t i t l e")
    result, elapsed = cli("report", "hammond-undamped", "--study", study, "--out", tmp_path / "r")
    refused(result, elapsed, "--study '", "case.toml is not UTF-8 text")
    assert not (tmp_path / "r").exists()


@modes
@pytest.mark.parametrize("name", ["case.toml", "map.png"])
def test_report_study_with_an_unreadable_file(tmp_path, name):
    """PermissionError (exit 1), the map's only after the analysis."""
    study = _study_folder(tmp_path / "study")
    os.chmod(study / name, 0)
    result, elapsed = cli("report", "hammond-undamped", "--study", study, "--out", tmp_path / "r")
    refused(result, elapsed, "--study '", f"{name}: cannot be read (permission denied)")


def test_report_study_that_is_a_file_or_not_a_study(tmp_path):
    (tmp_path / "file").write_text("x")
    result, elapsed = cli("report", "--study", tmp_path / "file", "--out", tmp_path / "r")
    refused(result, elapsed, "--study '", "not a folder (a regular file)")
    study = _study_folder(tmp_path / "study")
    (study / "provenance.json").unlink()
    result, elapsed = cli("report", "--study", study, "--out", tmp_path / "r")
    refused(result, elapsed, "not the --out folder of a groundres study (it has no provenance.json)")


def test_a_case_file_whose_name_is_no_utf8_runs_and_is_recorded_escaped(tmp_path):
    """A file name the file system gives as bytes that are no UTF-8 (c\\xff\\xfe.toml) made
    run and compare fail (exit 1) writing NetCDF attributes; its name is recorded with the
    bytes escaped."""
    if sys.platform == "darwin":
        pytest.skip("the file system takes UTF-8 names only")
    name = os.fsdecode(b"c\xff\xfe.toml")
    case = tmp_path / name
    case.write_text(HAMMOND_TOML)
    result = CliRunner().invoke(main, ["run", str(case), "--out", str(tmp_path / "r")])
    assert result.exit_code == 0, result.output
    provenance = json.loads((tmp_path / "r" / "provenance.json").read_text())
    assert provenance["case"]["source"].endswith("c\\xff\\xfe.toml")


def test_an_empty_shipped_case_name_is_refused():
    result = CliRunner().invoke(main, ["cases", ""])
    assert result.exit_code == 2 and "no such shipped case" in result.output


@pytest.mark.parametrize("port", ["-1", "0", "70000"])
def test_a_scheduler_port_out_of_range_is_named(tmp_path, port):
    args = ["study", "hammond-1974", "--vary", "rotor.lag_damping=1000:3000:2"]
    result = CliRunner().invoke(
        main, [*args, "--scheduler", f"tcp://127.0.0.1:{port}", "--out", str(tmp_path / "o")]
    )
    assert result.exit_code == 2
    assert f"port {port}: a port is a whole number from 1 to 65535" in " ".join(result.output.split())


def test_an_out_path_far_over_path_max_is_refused_at_once(tmp_path):
    """An --out of 100,000 bytes ('o/' x 50,000) took 8 GiB while its parents were listed; it is
    refused from its length before it is resolved."""
    started = time.perf_counter()
    result = CliRunner().invoke(main, ["run", "hammond-1974", "--out", "o/" * 50000])
    assert result.exit_code == 2 and "far over the 4096" in " ".join(result.output.split())
    assert time.perf_counter() - started < 5


def test_an_out_that_is_no_utf8_is_recorded_escaped(tmp_path):
    """gallery --out with bytes that are no UTF-8 failed (exit 1) writing the command line into
    its page; the command line is recorded with those bytes escaped."""
    if sys.platform == "darwin":
        pytest.skip("the file system takes UTF-8 names only")
    out = tmp_path / os.fsdecode(b"g\xff\x9b")
    result = CliRunner().invoke(main, ["gallery", "--figures", "3", "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert "g\\xff\\x9b" in (out / "index.html").read_text(encoding="utf-8")


def test_a_lock_file_that_is_a_folder_is_refused_before_any_work(tmp_path, monkeypatch):
    """The lock file runs share beside their output folders, made a folder, failed the run after
    its work (exit 1, IsADirectoryError); it is refused first, naming it."""
    (tmp_path / ".groundres.lock").mkdir()
    monkeypatch.chdir(tmp_path)
    result = CliRunner().invoke(main, ["run", "hammond-1974", "--out", "out"])
    assert result.exit_code == 2
    assert "lock file" in result.output and "not a regular file" in result.output
    assert not (tmp_path / "out").exists()
