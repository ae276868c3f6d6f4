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


@pytest.fixture
def served():
    """Yields a function starting `softplc serve serve_test.il` with extra
    options; returns (process, {name: port})."""
    binary = os.environ.get("SOFTPLC", str(ROOT / "target" / "debug" / "softplc"))
    procs = []

    def start(*servers, extra=()):
        ports = {name: free_port() for name in servers}
        cmd = [binary, "serve", str(HERE / "serve_test.il"), "--scan-time", "5ms", *extra]
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
            p.send_signal(signal.SIGTERM)
            try:
                p.wait(timeout=10)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()
