"""Output folders: provenance, all-or-nothing replacement, interrupts, progress (docs/case-files.md)."""

import json
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from click.testing import CliRunner

import groundres
from groundres import analyze, load_case
from groundres.cli import main
from groundres.model.casefile import shipped_cases
from groundres.solve.floquet import exponents

# A quick case (eigen-analysis, 20 speeds); CRLF line ends, a comment and a
# non-ASCII character check that case.toml keeps the text byte for byte.
QUICK = (
    '# quick case, rotor ø 11 m\r\ntitle = "{title}"\r\n'
    "[rotor]\r\nblades = 4\r\nhinge_offset = 0.3048\r\nblade_mass = 94.9\r\n"
    "blade_static_moment = 289.1\r\nblade_inertia = 1084.7\r\nlag_damping = 4067.5\r\n"
    '[body]\r\ndofs = ["x", "y"]\r\nmass_x = 8026.6\r\nmass_y = 3283.6\r\n'
    "stiffness_x = 1240481.8\r\nstiffness_y = 1240481.8\r\ndamping_x = 51078.7\r\n"
    "damping_y = 25539.35\r\n"
    '[sweep]\r\nstart = 0.5\r\nstop = 40.0\r\npoints = 20\r\nunit = "rad/s"\r\n'
)
EXE = [sys.executable, "-m", "groundres.cli"]


def write_quick(folder: Path, title="quick", name="quick.toml") -> Path:
    path = folder / name
    path.write_bytes(QUICK.format(title=title).encode("utf-8"))
    return path


def write_floquet(folder: Path) -> Path:
    """The quick case with blade 1's damper failed: a Floquet analysis."""
    path = folder / "floquet.toml"
    text = QUICK.format(title="floquet") + "[[rotor.blade]]\r\nindex = 1\r\nlag_damping = 0.0\r\n"
    path.write_bytes(text.encode("utf-8"))
    return path


def run(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


@pytest.fixture(scope="module", autouse=True)
def derived(tmp_path_factory):
    """Derive the equations once in this process, so subprocesses start from the cache."""
    analyze(load_case(write_quick(tmp_path_factory.mktemp("warm"))))


def provenance(folder: Path) -> dict:
    return json.loads((folder / "provenance.json").read_text())


def staging(parent: Path) -> list[str]:
    """Hidden folders and lock files a run leaves beside its output folder."""
    return sorted(p.name for p in parent.iterdir() if p.name.startswith(".groundres"))


def assert_complete(folder: Path) -> dict:
    """A complete run folder: the listed files, one title throughout, no temporary files."""
    record = provenance(folder)
    assert record["generator"] == "groundres"
    assert sorted(os.listdir(folder)) == record["files"]
    assert set(record["files"]) >= {"summary.json", "modes.csv", "modes.nc", "coleman.png", "case.toml"}
    title = json.loads((folder / "summary.json").read_text())["title"]
    with xr.open_dataset(folder / "modes.nc") as ds:
        assert ds.attrs["title"] == title
    assert f'title = "{title}"' in (folder / "case.toml").read_text()
    assert record["case"]["title"] == title
    assert (folder / "coleman.png").read_bytes()[:4] == b"\x89PNG"
    return record


def test_run_folder_holds_the_exact_case_text_and_provenance(tmp_path):
    case = write_quick(tmp_path)
    out = tmp_path / "out"
    result = run("run", case, "--out", out)
    assert result.exit_code == 0, result.output
    assert (out / "case.toml").read_bytes() == case.read_bytes()  # CRLF and UTF-8 kept
    record = assert_complete(out)
    summary = json.loads((out / "summary.json").read_text())
    assert record["groundres_version"] == groundres.__version__
    assert record["command"] == "run" and record["argv"][:2] == ["groundres", "run"]
    assert str(case) in record["command_line"] and record["case"]["source"] == str(case)
    assert record["method"] == summary["method"] == "multiblade-eigen"
    assert record["frame"] == "nonrotating" and record["started"] <= record["finished"]
    assert record["accuracy"]["growth_threshold"]["per_radian"] == summary["growth_threshold_per_radian"]
    assert "LAPACK" in record["accuracy"]["roots"]
    assert {"python", "numpy", "scipy"} <= set(record["software"])
    assert record["software"]["numpy"] == np.__version__
    assert "Sweep over" not in result.output  # progress only on a terminal


def test_floquet_provenance_records_the_integration(tmp_path):
    result = run("run", write_floquet(tmp_path), "--out", tmp_path / "out")
    assert result.exit_code == 0, result.output
    accuracy = provenance(tmp_path / "out")["accuracy"]
    assert accuracy["transition_tolerance"] == exponents.TOLERANCE
    steps = accuracy["steps_per_interval"]
    assert 32 <= steps["min"] <= steps["max"]


def test_simulate_and_phasors_have_their_own_default_folders(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    sim = run("simulate", "hammond-undamped", "--speed", "250", "--time", "3")
    assert sim.exit_code == 0, sim.output
    folder = Path("groundres-out/hammond-undamped-simulate")
    record = provenance(folder)
    assert record["command"] == "simulate" and record["accuracy"]["rtol"] == 1e-10
    assert sorted(os.listdir(folder)) == record["files"]
    assert (folder / "case.toml").read_text(encoding="utf-8") == shipped_cases()["hammond-undamped"]
    write_quick(tmp_path)
    ph = run("phasors", "quick.toml", "--speed", "20", "--no-gif")
    assert ph.exit_code == 0, ph.output
    record = provenance(Path("groundres-out/quick-phasors"))
    assert record["command"] == "phasors" and "phasors.json" in record["files"]
    assert sorted(os.listdir("groundres-out")) == ["hammond-undamped-simulate", "quick-phasors"]


def test_a_folder_groundres_did_not_write_is_refused(tmp_path):
    case = write_quick(tmp_path)
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("my notes")
    result = run("run", case, "--out", out)
    assert result.exit_code == 2
    assert str(out) in result.output and "notes.txt" in result.output and "did not write" in result.output
    assert os.listdir(out) == ["notes.txt"] and staging(tmp_path) == []
    # a groundres folder with a file of the user's in it is refused as well
    good = tmp_path / "good"
    assert run("run", case, "--out", good).exit_code == 0
    (good / "notes.txt").write_text("my notes")
    again = run("run", case, "--out", good)
    assert again.exit_code == 2 and "notes.txt" in again.output
    assert (good / "notes.txt").exists()


def test_the_current_folder_is_refused(tmp_path, monkeypatch):
    here = tmp_path / "here"
    here.mkdir()
    monkeypatch.chdir(here)
    result = run("run", write_quick(tmp_path), "--out", ".")
    assert result.exit_code == 2 and "current folder" in result.output
    assert os.listdir(here) == [] and staging(tmp_path) == []


def test_empty_and_older_groundres_folders_are_replaced(tmp_path):
    case = write_quick(tmp_path)
    empty = tmp_path / "empty"
    empty.mkdir()
    assert run("run", case, "--out", empty).exit_code == 0
    assert_complete(empty)
    older = tmp_path / "older"  # what a version without provenance.json wrote
    older.mkdir()
    for name in ("summary.json", "modes.csv", "modes.nc", "coleman.png", ".modes.csv.x1.part.csv"):
        (older / name).write_text("old")
    assert run("run", case, "--out", older).exit_code == 0
    assert_complete(older)


def test_a_folder_is_replaced_whole(tmp_path):
    case = write_quick(tmp_path)
    out = tmp_path / "out"
    assert run("run", case, "--out", out).exit_code == 0
    sim = run("simulate", case, "--speed", "20", "--time", "3", "--out", out)
    assert sim.exit_code == 0, sim.output
    assert sorted(os.listdir(out)) == ["case.toml", "provenance.json", "simulation.csv", "simulation.png"]
    assert staging(tmp_path) == []


def test_stale_folders_of_dead_runs_are_removed(tmp_path):
    case = write_quick(tmp_path)
    dead = tmp_path / ".groundres-new-999999999-abcd1234-out"  # pids stay below 2**22
    live = tmp_path / f".groundres-new-{os.getpid()}-abcd1234-other"
    for folder in (dead, live):
        folder.mkdir()
        (folder / "summary.json").write_text("partial")
    assert run("run", case, "--out", tmp_path / "out").exit_code == 0
    assert not dead.exists() and live.exists()


def _session_processes(sid: int) -> list[int]:
    """Processes still alive in the session ``sid`` (a /proc scan)."""
    found = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                stat = (entry / "stat").read_text()
            except OSError:
                continue
            fields = stat.rsplit(")", 1)[1].split()
            if int(fields[3]) == sid and fields[0] != "Z":
                found.append(int(entry.name))
    return found


def _default_sigint():
    """In the child: Ctrl-C as a terminal delivers it, whatever the test runner
    inherited (a shell's background job ignores SIGINT, and so would the run)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _start(case: Path, out: Path) -> subprocess.Popen:
    return subprocess.Popen(
        [*EXE, "run", str(case), "--out", str(out)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
        preexec_fn=_default_sigint,
    )


def _interrupted_run(case: Path, out: Path, parent: Path, sig: int, prepare=lambda: None):
    """A run sent ``sig`` while it writes: (process, stderr, seconds to exit, what
    ``prepare()`` returned just before that run).

    On a loaded machine the test can be descheduled between seeing the fresh
    folder and signalling, and the run may finish first: such a run must have
    written a complete folder (exit 0), which is removed, and the run is tried
    again (at most five times).
    """
    for _ in range(5):
        state = prepare()
        proc = _start(case, out)
        took = _interrupt_while_writing(proc, parent, sig)
        _, err = proc.communicate()
        if proc.returncode != 0:
            return proc, err, took, state
        assert {"summary.json", "modes.nc", "coleman.png"} <= set(os.listdir(out)), err
        shutil.rmtree(out)
    raise AssertionError("five runs finished before the signal reached them")


def _interrupt_while_writing(proc: subprocess.Popen, parent: Path, sig: int) -> float:
    """Send ``sig`` to the run's process group as soon as its fresh folder appears; seconds to exit."""
    prefix = f".groundres-new-{proc.pid}-"
    deadline = time.monotonic() + 300
    while not any(p.name.startswith(prefix) for p in parent.iterdir()):
        assert proc.poll() is None, proc.communicate()
        assert time.monotonic() < deadline, "the run never started writing"
        time.sleep(0.002)
    os.killpg(proc.pid, sig)
    sent = time.monotonic()
    proc.wait(timeout=60)
    return time.monotonic() - sent


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="scans /proc")
def test_sigterm_while_writing_leaves_the_old_folder_whole(tmp_path):
    old_case = write_quick(tmp_path, title="old", name="old.toml")
    out = tmp_path / "out"
    assert run("run", old_case, "--out", out).exit_code == 0

    def old_folder():
        if not out.exists():
            assert run("run", old_case, "--out", out).exit_code == 0
        return {name: (out / name).read_bytes() for name in os.listdir(out)}

    new_case = write_quick(tmp_path, title="new", name="new.toml")
    proc, err, took, before = _interrupted_run(new_case, out, tmp_path, signal.SIGTERM, old_folder)
    assert proc.returncode == 143 and "terminated" in err and "Traceback" not in err, err
    assert took < 10
    assert {name: (out / name).read_bytes() for name in os.listdir(out)} == before
    assert staging(tmp_path) == [] and not list(out.glob("*.part*"))
    assert _session_processes(proc.pid) == []


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="scans /proc")
def test_ctrl_c_exits_130_and_leaves_nothing(tmp_path):
    proc, err, took, _ = _interrupted_run(write_quick(tmp_path), tmp_path / "out", tmp_path, signal.SIGINT)
    assert proc.returncode == 130 and err.strip() == "interrupted", err
    assert took < 10
    assert not (tmp_path / "out").exists() and staging(tmp_path) == []
    assert _session_processes(proc.pid) == []


def test_two_runs_into_one_folder_do_not_mix(tmp_path):
    out = tmp_path / "out"
    first = _start(write_quick(tmp_path, title="first", name="a.toml"), out)
    time.sleep(0.05)
    second = _start(write_quick(tmp_path, title="second", name="b.toml"), out)
    for proc in (first, second):
        _, err = proc.communicate(timeout=300)
        assert proc.returncode == 0, err
    record = assert_complete(out)
    assert record["case"]["title"] in ("first", "second")
    assert staging(tmp_path) == []


def test_analysis_reports_progress_by_stage(tmp_path):
    calls = []
    case = load_case(write_floquet(tmp_path))  # Floquet: the sweep reports batches of speeds
    analyze(case, progress=lambda stage, done, total: calls.append((stage, done, total)))
    stages = list(dict.fromkeys(stage for stage, _, _ in calls))
    assert stages == ["sweep", "range ends", "lag damping", "margins"]
    sweep = [(done, total) for stage, done, total in calls if stage == "sweep"]
    assert sweep[0] == (0, case.sweep.points) and sweep[-1] == (case.sweep.points,) * 2
    assert all(a[0] <= b[0] for a, b in zip(sweep, sweep[1:]))
    assert calls[-1] == ("margins", 1, 1)


def test_simulation_reports_progress_in_simulated_seconds():
    from groundres.model.system import System
    from groundres.solve import simulate

    case = load_case("hammond-1974")
    system = System(case.rotor, case.body)
    calls = []
    initial = simulate.initial_state(system, {"x": 0.01})
    simulate.integrate(system, 26.0, 2.0, initial, progress=lambda done, total: calls.append((done, total)))
    done = [d for d, _ in calls]
    assert 50 <= len(calls) <= 101 and all(total == 2.0 for _, total in calls)
    assert done == sorted(done) and 0 < done[0] and done[-1] <= 2.0


def test_envelope_of_a_growing_oscillation_grows_at_its_rate():
    """The simulation picture's log panel: growth sigma is a line of slope sigma."""
    from groundres.plotting.timehistory import envelope

    t = np.linspace(0.0, 30.0, 4000)
    sigma = 0.3258  # the README's simulate example
    signal_ = np.exp(sigma * t) * (np.cos(12.2 * t) + 0.3 * np.sin(18.1 * t + 1.0))
    env = envelope(t, signal_)
    assert np.all(env >= 0.5 * np.abs(signal_))
    slope = np.polyfit(t[t > 5], np.log(env[t > 5]), 1)[0]
    assert abs(slope - sigma) < 2e-3  # peaks sit within a period of the fit: a few 1e-3 of sigma


def test_an_output_folder_that_cannot_be_moved_aside_is_a_clear_error(tmp_path, monkeypatch):
    """A mount point or an immutable folder cannot be renamed: exit-2 error naming the folder,
    the folder as it was, and no hidden folder left beside it."""
    import errno
    import os

    from groundres.results import folders

    target = tmp_path / "out"
    target.mkdir()
    real = os.rename

    def rename(src, dst):
        if ".groundres-old-" in str(dst):
            raise OSError(errno.EBUSY, "Device or resource busy")
        return real(src, dst)

    monkeypatch.setattr(folders.os, "rename", rename)
    with pytest.raises(folders.OutputFolderError, match="cannot be replaced.*give a folder inside it"):
        with folders.output_folder(target) as fresh:
            (fresh / "a.txt").write_text("x")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]
    assert list(target.iterdir()) == []
