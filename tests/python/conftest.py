"""Starts `softplc serve` for the Python client tests; the binary is
target/debug/softplc (built by `cargo test`), or $SOFTPLC."""
import os
import pathlib
import signal
import socket
import subprocess
import time

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
HERE = pathlib.Path(__file__).resolve().parent
BINARY = os.environ.get("SOFTPLC", str(ROOT / "target" / "debug" / "softplc"))


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_port(port, proc, timeout=20.0):
    end = time.time() + timeout
    while time.time() < end:
        if proc.poll() is not None:
            raise RuntimeError("softplc serve exited: " + proc.stderr.read().decode())
        try:
            socket.create_connection(("127.0.0.1", port), timeout=0.2).close()
            return
        except OSError:
            time.sleep(0.05)
    raise RuntimeError(f"port {port} not open")


def stop(proc):
    """SIGTERM (softplc commits latched data and exits), kill after 10 s."""
    proc.send_signal(signal.SIGTERM)
    try:
        proc.wait(timeout=10)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()


def pty_pair(tmp_path):
    """A generator for fixtures: a socat pty pair `(plc, master)` in
    tmp_path, closed when the fixture ends."""
    a, b = tmp_path / "plc", tmp_path / "master"
    socat = subprocess.Popen(
        ["socat", f"pty,raw,echo=0,link={a}", f"pty,raw,echo=0,link={b}"],
        stderr=subprocess.DEVNULL,
    )
    for _ in range(100):
        if a.exists() and b.exists():
            break
        time.sleep(0.05)
    yield a, b
    socat.terminate()
    socat.wait(timeout=10)


@pytest.fixture
def served():
    """Yields a function starting `softplc serve serve_test.il` with extra
    options; returns (process, {name: port})."""
    procs = []

    def start(*servers, extra=()):
        ports = {name: free_port() for name in servers}
        cmd = [BINARY, "serve", str(HERE / "serve_test.il"), "--scan-time", "5ms", *extra]
        for name, port in ports.items():
            cmd += [f"--{name}", f"127.0.0.1:{port}"]
        proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        procs.append(proc)
        for port in ports.values():
            wait_port(port, proc)
        return proc, ports

    yield start
    for p in procs:
        if p.poll() is None:
            stop(p)
