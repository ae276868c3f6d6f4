"""OPC UA sessions under abuse, with asyncua: clients that connect and go
away without closing their session do not lock the others out; one client
address cannot take every session."""
import asyncio
import socket
import subprocess
import time

import pytest
from asyncua import Client, ua

from conftest import BINARY, HERE, stop

pytestmark = pytest.mark.filterwarnings("ignore::DeprecationWarning")

# The server's default limits (docs/opcua.md, Limits).
SESSIONS_PER_CLIENT = 8


def free_port(host):
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    with socket.socket(family) as s:
        s.bind((host, 0))
        return s.getsockname()[1]


def serve(tmp_path, host):
    """`softplc serve opcua_test.il --opcua HOST:PORT`; returns (process, url)."""
    port = free_port(host)
    bracketed = f"[{host}]" if ":" in host else host
    cmd = [BINARY, "serve", str(HERE / "opcua_test.il"), "--scan-time", "10ms",
           "--opcua", f"{bracketed}:{port}", "--opcua-pki", str(tmp_path / "pki")]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    end = time.time() + 20
    while True:
        if proc.poll() is not None:
            raise RuntimeError("softplc serve exited: " + proc.stderr.read().decode())
        try:
            socket.create_connection((host, port), timeout=0.2).close()
            break
        except OSError:
            if time.time() > end:
                stop(proc)
                raise RuntimeError(f"port {port} not open")
            time.sleep(0.05)
    return proc, f"opc.tcp://{bracketed}:{port}/"


@pytest.fixture
def served(tmp_path):
    procs = []

    def start(host="127.0.0.1"):
        proc, url = serve(tmp_path, host)
        procs.append(proc)
        return url

    yield start
    for p in procs:
        stop(p)


async def connect(url, within=20.0):
    """A connected client; the server may still be making its certificate
    (tried for `within` seconds)."""
    end = time.monotonic() + within
    while True:
        c = Client(url, timeout=2)
        try:
            await c.connect()
            return c
        except (OSError, asyncio.TimeoutError, ua.UaError) as e:
            if time.monotonic() > end:
                raise RuntimeError(f"no session on {url}: {e!r}") from e
            await asyncio.sleep(0.2)


async def abandon(c):
    """Drops the client's socket without closing its session, as a client
    that crashes or loses its network does."""
    for task in (c._monitor_server_task, c._renew_channel_task):
        if task is not None:
            task.cancel()
    c.disconnect_socket()
    await asyncio.sleep(0)


async def read_scan(c):
    ns = await c.get_namespace_index("urn:softplc")
    return await c.get_node(ua.NodeId("/softplc/Diagnostics/Scan", ns)).read_value()


def test_abandoned_sessions_do_not_lock_others_out(served):
    url = served()

    async def go():
        await abandon(await connect(url))
        for _ in range(24):
            await abandon(await connect(url, within=0))
        # A new client gets a session at once (it got BadTooManySessions
        # for the session timeout, 60 s, before).
        t0 = time.monotonic()
        c = Client(url, timeout=4)
        await c.connect()
        try:
            assert time.monotonic() - t0 < 3
            assert await read_scan(c) > 0
        finally:
            await c.disconnect()

    asyncio.run(go())


def test_one_client_address_cannot_take_every_session(served):
    url = served()

    async def go():
        live = [await connect(url)]
        for _ in range(SESSIONS_PER_CLIENT - 1):
            live.append(await connect(url, within=0))
        # Every session of this address is in use: the next is refused…
        extra = Client(url, timeout=4)
        with pytest.raises(ua.UaStatusCodeError) as e:
            await extra.connect()
        assert e.value.code == ua.StatusCodes.BadTooManySessions
        # …and the sessions in use keep working.
        for c in live:
            assert await read_scan(c) > 0
        # A session closed properly makes room.
        await live.pop().disconnect()
        c = Client(url, timeout=4)
        await c.connect()
        live.append(c)
        assert await read_scan(c) > 0
        for c in live:
            await c.disconnect()

    asyncio.run(go())

