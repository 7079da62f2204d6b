"""Whether an address is a Dask scheduler's, found out within one deadline before a client connects.

distributed's own connect (``distributed.comm.core.connect``, 2026.8) bounds only the
opening of the TCP connection by its timeout. It then writes its greeting and reads
the peer's with no deadline and no limit: the first 8 bytes are taken as the size of
what follows. A server that is not a Dask scheduler either never answers (the client
waits forever) or answers with bytes read as a size of exabytes (``MemoryError``).

Here, for ``tcp://`` (Dask's default), the peer's greeting is read first: within the
deadline, at most :data:`GREETING_BYTES`, and it must be Dask's (a msgpack map with
``compression``, ``python`` and ``pickle-protocol``). Then the peer is asked who it is
through distributed's comm (a worker's address is not a scheduler's). Every step shares
the one deadline; a refused connection is tried again within it (a scheduler may be
starting), as distributed does.
"""

from __future__ import annotations

import asyncio
import contextlib
import struct
import time

#: Longest greeting a Dask server sends [bytes] (its own is about 60).
GREETING_BYTES = 64 * 1024
#: The keys of a Dask greeting (``Comm.handshake_info``).
GREETING_KEYS = {"compression", "python", "pickle-protocol"}
#: The frame header of Dask's TCP comm: the size of the frames that follow (``distributed.comm.tcp``).
_SIZE = struct.Struct("Q")


def check_scheduler(address: str, seconds: float) -> float:
    """Return the seconds left of ``seconds`` once a Dask scheduler has answered at ``address``.

    Raises
    ------
    ConnectionError
        Nothing accepts a connection there, or what answers is not a Dask
        scheduler (the message says what it did).
    TimeoutError
        Connected, but no answer within ``seconds``.
    ValueError
        ``address`` is not an address (no port, say).
    """
    from distributed.comm.addressing import parse_address, parse_host_port

    try:
        scheme, where = parse_address(address)
        target = parse_host_port(where) if scheme == "tcp" else None
    except ValueError as err:
        raise ValueError(f"not an address such as tcp://host:8786 ({err})") from None
    if target is not None and not 0 < target[1] < 65536:
        raise ValueError(f"port {target[1]}: a port is a whole number from 1 to 65535")
    started = time.monotonic()
    state = {"step": "connect", "last": None}
    loop = asyncio.new_event_loop()
    try:
        loop.run_until_complete(asyncio.wait_for(_check(address, target, seconds, state), seconds))
    except TimeoutError:
        if state["step"] == "connect":
            raise ConnectionError(
                f"nothing accepted a connection there within {seconds:g} s ({state['last']})"
            ) from None
        raise TimeoutError(f"not a Dask scheduler, or one that did not answer within {seconds:g} s") from None
    finally:
        loop.close()  # (a name lookup still running is not waited for)
    return max(seconds - (time.monotonic() - started), 0.0)


async def _check(address: str, target, seconds: float, state: dict) -> None:
    """The steps of :func:`check_scheduler`, ``state['step']`` saying which one runs."""
    if target is not None:
        reader, writer = await _connect(*target, state)
        state["step"] = "greeting"
        try:
            greeting = await _greeting(reader)
        finally:
            writer.close()
            with contextlib.suppress(OSError):
                await writer.wait_closed()
        if not (isinstance(greeting, dict) and GREETING_KEYS <= set(greeting)):
            raise ConnectionError(
                "not a Dask scheduler (it answered with bytes that are not Dask's greeting)"
            )
    state["step"] = "identity"
    kind = await _identity(address, seconds)
    if kind != "Scheduler":
        raise ConnectionError(
            f"a Dask {kind.lower()}, not a scheduler: give the scheduler's address "
            "(its log says 'Scheduler at: ...')"
        )


async def _connect(host: str, port: int, state: dict):
    """A TCP connection to ``host:port``, tried again while it is refused (until the caller's deadline)."""
    pause = 0.01
    while True:
        try:
            return await asyncio.open_connection(host, port)
        except OSError as err:  # (refused, unreachable, no such host: tried again within the deadline)
            state["last"] = f"{type(err).__name__}: {err}"
            await asyncio.sleep(pause)
            pause = min(2 * pause, 0.5)


async def _greeting(reader):
    """The peer's first message, decoded without unpickling anything; None where it is not
    one of Dask's (too long, cut short or not decodable)."""
    from distributed.protocol.core import loads
    from distributed.protocol.utils import unpack_frames

    try:
        (size,) = _SIZE.unpack(await reader.readexactly(_SIZE.size))
        if size > GREETING_BYTES:
            return None
        body = await reader.readexactly(size)
    except asyncio.IncompleteReadError:
        raise ConnectionError(
            "not a Dask scheduler (it closed the connection without Dask's greeting)"
        ) from None
    try:
        frames, more = unpack_frames(memoryview(body), partial=True)
        return None if more else loads(frames, deserialize=False)
    except Exception:  # noqa: BLE001 - any bytes at all came from the peer: undecodable is the answer
        return None


async def _identity(address: str, seconds: float) -> str:
    """What the Dask server at ``address`` says it is ("Scheduler", "Worker", "Nanny"), through
    distributed's own comm (nothing it sends is unpickled)."""
    from distributed import Security
    from distributed.comm import connect

    try:
        # (TLS and the like as Dask's client takes them: from Dask's configuration)
        arguments = Security().get_connection_args("client")
        comm = await connect(address, timeout=seconds, deserialize=False, **arguments)
        try:
            await comm.write({"op": "identity", "reply": True})
            who = await comm.read()
            await comm.write({"op": "close", "reply": False})
        finally:
            await comm.close()
    except TimeoutError:
        raise
    except Exception as err:  # noqa: BLE001 - a peer that breaks distributed's protocol, in any way
        raise ConnectionError(f"not a Dask scheduler ({type(err).__name__}: {err})") from None
    if not (isinstance(who, dict) and isinstance(who.get("type"), str)):
        raise ConnectionError("not a Dask scheduler (it did not say what it is)")
    return who["type"]
