"""Studies on Dask clusters as a user runs them: what the local cluster exposes, what its
processes import, what --scheduler accepts, how a study stops, and a real cluster of
Dask's own command-line processes, a worker of which is killed mid-study.

Every process a test starts is started in its own session and its whole group is
ended in a ``finally`` (no process outlives its test).
"""

from __future__ import annotations

import contextlib
import json
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
import xarray as xr
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
    proc = start_groundres(args, here)
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
    return start_groundres(args, tmp_path)


def start_groundres(args, cwd) -> subprocess.Popen:
    """The groundres console script with ``args`` in ``cwd``, in a session of its own, its output piped."""
    return subprocess.Popen(
        [str(GROUNDRES), *args],
        cwd=cwd,
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
    assert err.splitlines() == [word]
    assert [line.split(":")[0] for line in out.splitlines()] == ["Estimated"]  # (the study's own first line)
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


# -- a cluster of Dask's own processes ------------------------------------------------------------------

GRID = ["--vary", "rotor.lag_damping=1500:6000:20", "--failures", "single"]


@pytest.fixture(scope="module")
def dask_cluster(tmp_path_factory):
    """`dask scheduler` and two `dask worker` processes (one thread each, no nanny's second
    worker) on 127.0.0.1, separate from this process: (scheduler address, worker processes)."""
    from groundres.solve.floquet import compiled

    compiled.kernel(wait=True)  # (ready before any study: every process then takes the compiled kernel)
    folder = tmp_path_factory.mktemp("dask")
    spec = folder / "scheduler.json"
    env = environment(PYTHONSAFEPATH="1")
    procs = []

    def start(*args, name):
        log = open(folder / f"{name}.log", "w")
        procs.append(
            subprocess.Popen(
                [str(DASK), *args],
                cwd=folder,
                env=env,
                stdout=log,
                stderr=subprocess.STDOUT,
                start_new_session=True,
            )
        )
        log.close()
        return procs[-1]

    try:
        start(
            "scheduler",
            *("--host", "127.0.0.1", "--port", "0", "--no-dashboard", "--scheduler-file", str(spec)),
            name="scheduler",
        )
        until(lambda: spec.exists() and spec.stat().st_size > 0, 60, "dask scheduler")
        address = json.loads(spec.read_text())["address"]
        worker = ("--scheduler-file", str(spec), "--host", "127.0.0.1", "--nthreads", "1", "--no-dashboard")
        workers = [start("worker", *worker, "--name", f"w{k}", name=f"worker{k}") for k in (1, 2)]
        with remote(address) as client:
            client.wait_for_workers(2, timeout=60)
            found = client.run(lambda: __import__("groundres").__file__)  # (the groundres under test)
        assert set(found.values()) == {str(Path(SOURCE) / "groundres" / "__init__.py")}, found
        yield address, workers
    finally:
        for proc in procs:
            end(proc)


@contextlib.contextmanager
def remote(address):
    from distributed import Client

    client = Client(address, timeout="20s")
    try:
        yield client
    finally:
        client.close()


def run_study(tmp_path, name, *more) -> tuple[subprocess.Popen, Path]:
    (tmp_path / "case.toml").write_text(SMALL)
    out = tmp_path / name
    proc = subprocess.Popen(
        [str(GROUNDRES), "study", "case.toml", *GRID, "--out", str(out), *more],
        cwd=tmp_path,
        env=environment(),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    return proc, out


def finish(proc, seconds=120) -> str:
    try:
        out, err = proc.communicate(timeout=seconds)
    finally:
        end(proc)
    assert proc.returncode == 0, err
    assert err == ""
    return out


@pytest.fixture(scope="module")
def on_the_local_cluster(tmp_path_factory):
    """The study of GRID on a local cluster of 2 workers (the reference)."""
    tmp_path = tmp_path_factory.mktemp("local")
    proc, out = run_study(tmp_path, "local", "--workers", "2")
    finish(proc)
    return xr.open_dataset(out / "study.nc").load()


@pytest.mark.slow
def test_a_study_on_a_cluster_of_dask_processes_equals_the_study_on_the_local_cluster(
    tmp_path, dask_cluster, on_the_local_cluster
):
    """Equal exactly: each point is computed in one process on one thread (BLAS held to one),
    by the same code and the same compiled kernel on the same machine, so the same operations
    in the same order whichever process runs it."""
    address, _ = dask_cluster
    proc, out = run_study(tmp_path, "remote", "--scheduler", address)
    text = finish(proc)
    assert "Study of 100 grid points" in text
    remote_ds = xr.open_dataset(out / "study.nc").load()
    assert (remote_ds.error.values == "").all()
    xr.testing.assert_identical(remote_ds, on_the_local_cluster)


@pytest.mark.slow
def test_a_worker_address_is_not_taken_for_the_scheduler(tmp_path, dask_cluster):
    address, _ = dask_cluster
    with remote(address) as client:
        worker = next(iter(client.scheduler_info()["workers"]))
    (tmp_path / "case.toml").write_text(SMALL)
    args = ["study", str(tmp_path / "case.toml"), "--vary", "rotor.lag_damping=2000:4000:2"]
    result, seconds = invoke_within([*args, "--scheduler", worker, "--out", str(tmp_path / "out")], 30)
    assert result.exit_code == 2, result.output
    assert f"--scheduler '{worker}': a Dask worker, not a scheduler" in result.output
    assert seconds < 10


def chunk_of(key: str) -> int | None:
    """The index of a study task's chunk, from its key (``compute_points-<token>-<index>``)."""
    prefix, _, index = str(key).rpartition("-")
    return int(index) if prefix.startswith("compute_points-") else None


@pytest.mark.slow
def test_a_worker_killed_mid_study_loses_nothing_and_computes_no_finished_chunk_again(
    tmp_path, dask_cluster, on_the_local_cluster
):
    """SIGKILL to a worker process that has computed chunks already written to the store: Dask
    computes the task it held again elsewhere and the study completes; no chunk written
    before the kill is computed again (its result was let go once written: the scheduler's
    task stream holds each of their keys once), and the store equals the local study."""
    import tomllib

    import zarr

    from groundres.model.schema import parse_case
    from groundres.studies import store
    from groundres.studies.grid import make_grid
    from groundres.studies.run import study_chunk

    address, workers = dask_cluster
    with remote(address) as client:
        client.get_task_stream()  # (the scheduler records every task from here on)
        first = len(client.get_task_stream())
        proc, out = run_study(tmp_path, "killed", "--scheduler", address)
        try:
            zstore = out / "study.zarr"

            def done_chunks():
                try:
                    done = np.asarray(zarr.open_group(str(zstore), mode="r")["done"][...])
                except Exception:  # noqa: BLE001 - (not yet there, or being written: read again)
                    return None
                return done if done.any(axis=-1).sum() >= 4 else None

            done = until(done_chunks, 60, "four chunks written")
            written = client.get_task_stream()[first:]
            time.sleep(0.3)  # (their results let go: the scheduler has forgotten them)
            by_worker = {}
            for record in written:
                by_worker.setdefault(record["worker"], []).append(chunk_of(record["key"]))
            # the worker that computed most of them; its process (the nanny's child) killed
            host = max(by_worker, key=lambda w: len(by_worker[w]))
            names = {a: w["name"] for a, w in client.scheduler_info()["workers"].items()}
            nanny = workers[int(names[host][1:]) - 1]
            child = next(
                c for c in psutil.Process(nanny.pid).children() if "spawn_main" in " ".join(c.cmdline())
            )
            assert proc.poll() is None, "the study ended before the kill"
            child.send_signal(signal.SIGKILL)
            text = finish(proc)
        finally:
            end(proc)
        records = client.get_task_stream()[first:]
    assert "Study of 100 grid points" in text
    grid = make_grid(
        parse_case(tomllib.loads(SMALL), "small", SMALL), {"rotor.lag_damping": "1500:6000:20"}, "single"
    )
    where = store.chunks(grid.shape, study_chunk(grid))
    before = {i for i, w in enumerate(where) if done[w].all()}
    counts = {}
    for record in records:
        if chunk_of(record["key"]) is not None:
            counts[chunk_of(record["key"])] = counts.get(chunk_of(record["key"]), 0) + 1
    assert set(counts) == set(range(len(where)))  # every chunk computed
    assert before and len(before) < len(where)  # (killed mid-study)
    assert all(counts[i] == 1 for i in before), (before, counts)
    assert set(by_worker[host]) & before  # (the killed worker held some of them)
    result = xr.open_dataset(out / "study.nc").load()
    xr.testing.assert_identical(result, on_the_local_cluster)
