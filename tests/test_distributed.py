"""Studies on Dask clusters as a user runs them: what the local cluster exposes, what its
processes import, what --scheduler accepts, how a study stops, and a real cluster of
Dask's own command-line processes, a worker of which is killed mid-study.

Every process a test starts is started in its own session and its whole group is
ended in a ``finally`` (no process outlives its test).
"""

from __future__ import annotations

import contextlib
import os
import signal
import socket
import struct
import subprocess
import sys
import threading
import time
import urllib.error
import urllib.request
from pathlib import Path

import numpy as np
import psutil
import pytest
from click.testing import CliRunner

from conftest import HAMMOND_TOML
from groundres.cli import main
from groundres.studies import run

BIN = Path(sys.executable).parent
GROUNDRES, DASK = BIN / "groundres", BIN / "dask"
#: The groundres under test, for every process a test starts (the console script imports it from here).
SOURCE = str(Path(__import__("groundres").__file__).parents[1])
#: The Hammond rotor on its hub, a short sweep (Floquet where a damper fails), as in test_study.py.
SMALL = HAMMOND_TOML.replace("points = 60", "points = 24").replace("start = 0.5", "start = 10.0")


def environment(**more) -> dict:
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONSAFEPATH", "GROUNDRES_DEBUG")}
    env.update(PYTHONPATH=SOURCE, MPLBACKEND="Agg", **more)
    return env


def end(proc: subprocess.Popen) -> None:
    """End ``proc`` and every process of its group (it was started in a session of its own)."""
    with contextlib.suppress(ProcessLookupError):
        os.killpg(proc.pid, signal.SIGTERM)
    try:
        proc.wait(timeout=10)
    except subprocess.TimeoutExpired:
        pass
    with contextlib.suppress(ProcessLookupError):
        os.killpg(proc.pid, signal.SIGKILL)
    proc.wait(timeout=10)


def until(condition, seconds: float, what: str):
    """Poll ``condition`` until it gives something (returned) other than None or False, for at
    most ``seconds``."""
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        got = condition()
        if got is not None and got is not False:
            return got
        time.sleep(0.02)
    raise AssertionError(f"{what}: not within {seconds} s")


# -- the local cluster: loopback only, no dashboard unless asked ----------------------------------


def listening(session_only: bool = True) -> list:
    """(pid, address) of every listening socket of this process and its children (those of this
    process's session: a test's own Dask processes run in sessions of their own)."""
    me = psutil.Process()
    out = []
    for proc in [me, *me.children(recursive=True)]:
        try:
            if session_only and os.getsid(proc.pid) != os.getsid(0):
                continue
            out += [
                (proc.pid, c.laddr) for c in proc.net_connections("inet") if c.status == psutil.CONN_LISTEN
            ]
        except (psutil.NoSuchProcess, ProcessLookupError):
            pass
    return out


def status_of(url: str) -> int:
    try:
        with urllib.request.urlopen(url, timeout=5) as response:
            return response.status
    except urllib.error.HTTPError as err:
        return err.code


@pytest.mark.slow
def test_the_local_cluster_listens_on_loopback_only_and_serves_no_dashboard_unless_asked():
    for dashboard in (False, True):
        client = run.local_client(2, dashboard=dashboard)
        try:
            sockets = listening()
            # scheduler, 2 nannies, 2 workers, and the web servers of the scheduler and workers
            assert len(sockets) >= 7, sockets
            assert all(address.ip in ("127.0.0.1", "::1") for _, address in sockets), sockets
            scheduler = f"http://127.0.0.1:{client.cluster.scheduler.http_server.port}"
            workers = client.run(lambda dask_worker: dask_worker.http_server.port)
            for port in workers.values():
                assert status_of(f"http://127.0.0.1:{port}/health") == 404  # (serves nothing)
            if dashboard:
                assert client.dashboard_link.startswith("http://127.0.0.1:")
                assert status_of(client.dashboard_link) == 200
            else:
                for page in ("/status", "/info/main/workers.html", "/health", "/metrics"):
                    assert status_of(scheduler + page) == 404, page
        finally:
            run.close(client)


def test_the_dashboard_is_asked_for_and_its_address_printed(tmp_path, monkeypatch):
    from groundres.cli import study as cli_study

    case = tmp_path / "case.toml"
    case.write_text(SMALL)
    args = ["study", str(case), "--vary", "rotor.lag_damping=2000:4000:2", "--out", str(tmp_path / "out")]
    local = CliRunner().invoke(main, [*args, "--dashboard", "--scheduler", "tcp://127.0.0.1:9"])
    assert local.exit_code == 2 and "--dashboard: only for the local cluster" in local.output
    missing = run.dashboard_missing()
    if missing is not None:  # (bokeh is not installed: refused, saying what is needed)
        result = CliRunner().invoke(main, [*args, "--dashboard", "--workers", "1"])
        assert result.exit_code == 2, result.output
        assert "--dashboard: Dask needs bokeh" in result.output and "Traceback" not in result.output
        assert not (tmp_path / "out").exists()
    started = []

    def client(scheduler, workers, dashboard=False):
        started.append(dashboard)
        return run.local_client(workers, dashboard)

    monkeypatch.setattr(run, "dashboard_missing", lambda: None)  # (Dask then serves a page saying
    monkeypatch.setattr(cli_study, "_client", client)  # what it needs: its address is printed alike)
    result = CliRunner().invoke(main, [*args, "--dashboard", "--workers", "1"])
    assert result.exit_code == 0, result.output
    assert started == [True]
    assert "Dask dashboard: http://127.0.0.1:" in result.output


# -- nothing is imported from the folder a study is started in --------------------------------------

#: Modules a ``python -c`` child imports before multiprocessing gives it its parent's sys.path.
SHADOWED = ("multiprocessing", "weakref", "runpy", "pickle", "socket", "selectors", "signal", "struct")


@pytest.mark.slow
def test_the_cluster_imports_nothing_from_the_folder_the_study_is_started_in(tmp_path):
    here = tmp_path / "here"
    here.mkdir()
    for name in SHADOWED:
        (here / f"{name}.py").write_text(f"open({str(tmp_path / (name + '.imported'))!r}, 'w').close()\n")
    (here / "case.toml").write_text(SMALL)
    args = ["study", "case.toml", "--vary", "rotor.lag_damping=2000:4000:2", "--workers", "2", "--out", "out"]
    proc = subprocess.Popen(
        [str(GROUNDRES), *args],
        cwd=here,
        env=environment(),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    try:
        out, err = proc.communicate(timeout=120)
    finally:
        end(proc)
    assert proc.returncode == 0, err
    assert sorted(p.name for p in tmp_path.glob("*.imported")) == []
    assert "Study of 2 grid points" in out


# -- --scheduler: only a Dask scheduler, within a deadline --------------------------------------------


@contextlib.contextmanager
def impostor(behaviour: str):
    """A server on 127.0.0.1 that is not a Dask scheduler: its address (tcp://...)."""
    sock = socket.create_server(("127.0.0.1", 0))
    sock.settimeout(0.05)
    stop, held = threading.Event(), []

    def serve():
        while not stop.is_set():
            try:
                conn, _ = sock.accept()
            except TimeoutError:
                continue
            if behaviour == "closes":
                conn.close()
                continue
            held.append(conn)
            if behaviour == "http":  # (its first 8 bytes read as a size: 3.5e18)
                conn.sendall(b"HTTP/1.1 400 Bad Request\r\nContent-Length: 0\r\n\r\n")
            elif behaviour == "noise":  # (a plausible size, then bytes that are no Dask frames)
                conn.sendall(struct.pack("Q", 40) + bytes(range(200, 240)))

    thread = threading.Thread(target=serve, daemon=True)
    thread.start()
    try:
        yield f"tcp://127.0.0.1:{sock.getsockname()[1]}"
    finally:
        stop.set()
        thread.join(5)
        for conn in held:
            conn.close()
        sock.close()


def invoke_within(args, seconds: float):
    """The command run in this process, in a thread given ``seconds`` (a hang fails the test
    instead of stopping it); (result, seconds taken)."""
    box = {}
    thread = threading.Thread(target=lambda: box.update(result=CliRunner().invoke(main, args)), daemon=True)
    started = time.monotonic()
    thread.start()
    thread.join(seconds)
    assert not thread.is_alive(), f"groundres {' '.join(args)}: still running after {seconds} s"
    return box["result"], time.monotonic() - started


@pytest.mark.parametrize(
    "behaviour, words",
    [
        ("http", "bytes that are not Dask's greeting"),
        ("noise", "bytes that are not Dask's greeting"),
        ("closes", "closed the connection without Dask's greeting"),
        ("silent", "did not answer within 1.5 s"),
    ],
)
def test_a_scheduler_address_where_something_else_answers_is_refused_in_bounded_time(
    tmp_path, monkeypatch, behaviour, words
):
    monkeypatch.setattr(run, "CONNECT_SECONDS", 1.5)
    case = tmp_path / "case.toml"
    case.write_text(SMALL)
    with impostor(behaviour) as address:
        args = ["study", str(case), "--vary", "rotor.lag_damping=2000:4000:2", "--scheduler", address]
        result, seconds = invoke_within([*args, "--out", str(tmp_path / "out")], 30)
    assert result.exit_code == 2, result.output
    assert f"--scheduler '{address}': not a Dask scheduler" in result.output
    assert words in result.output and "Traceback" not in result.output
    assert seconds < 1.5 + 3.0
    assert not (tmp_path / "out").exists()


# -- a study stopped by Ctrl-C or SIGTERM says one line ------------------------------------------------


def start_study(tmp_path, *more) -> subprocess.Popen:
    args = ["study", "hammond-1974", "--vary", "rotor.lag_damping=1000:9000:40", "--out", "out", *more]
    return subprocess.Popen(
        [str(GROUNDRES), *args],
        cwd=tmp_path,
        env=environment(),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )


def done_points(store: Path) -> int:
    import zarr

    return int(np.asarray(zarr.open_group(str(store), mode="r")["done"][...]).sum())


@pytest.mark.slow
@pytest.mark.parametrize(
    "sig, code, word", [(signal.SIGINT, 130, "interrupted"), (signal.SIGTERM, 143, "terminated")]
)
def test_a_study_stopped_while_it_computes_says_one_line_and_resumes(tmp_path, sig, code, word):
    store = tmp_path / "out" / "study.zarr"
    proc = start_study(tmp_path, "--workers", "2")
    try:
        until(lambda: (store / "zarr.json").exists() or proc.poll() is not None, 60, "the study's store")
        time.sleep(1.0)  # (the workers at their tasks)
        assert proc.poll() is None, "the study ended before it could be stopped"
        proc.send_signal(sig)
        out, err = proc.communicate(timeout=60)
    finally:
        end(proc)
    assert proc.returncode == code, err
    assert err.splitlines() == [word] and out == ""
    # the store resumes: what was done is found done, the rest computed
    done = done_points(store)
    again = start_study(tmp_path, "--workers", "2")
    try:
        out, err = again.communicate(timeout=120)
    finally:
        end(again)
    assert again.returncode == 0, err
    assert err == "" and "Study of 40 grid points" in out
    assert done == 0 or f"{done} of them were found done in the store" in out


@pytest.mark.slow
def test_a_sigterm_while_the_cluster_starts_is_handled_once_it_has_started(tmp_path):
    """Handled at once, it left a cluster half started, which Dask's exit handler failed to
    close (a traceback); held, the cluster is closed whole. (A Ctrl-C then is ignored, as the
    workers ignore it: docs/studies.md.)"""
    proc = start_study(tmp_path, "--workers", "2")
    try:

        def a_worker_starting():
            if proc.poll() is not None:
                return True
            return any("spawn_main" in " ".join(c.cmdline()) for c in psutil.Process(proc.pid).children())

        until(a_worker_starting, 60, "a worker process")
        proc.send_signal(signal.SIGTERM)
        out, err = proc.communicate(timeout=60)
    finally:
        end(proc)
    assert proc.returncode == 143, (out, err)
    assert err.splitlines() == ["terminated"] and out == ""
