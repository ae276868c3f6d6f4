"""The web monitor's door under hostile clients (issue #31): more half-sent
HTTP requests than the server has descriptors must not lock out new HTTP, MC
or Modbus clients, and a request head dribbled a byte at a time is closed
after the header timeout. `softplc serve` runs with RLIMIT_NOFILE = 256."""
import json
import resource
import socket
import time
import urllib.request

import pymcprotocol
from pymodbus.client import ModbusTcpClient

from conftest import BINARY, HERE, free_port, stop, wait_port
import subprocess

import pytest

NOFILE = 256


def serve(*extra):
    ports = {name: free_port() for name in ("http", "mc", "modbus")}
    cmd = [BINARY, "serve", str(HERE / "serve_test.il"), "--scan-time", "5ms", "--no-realtime", *extra]
    for name, port in ports.items():
        cmd += [f"--{name}", f"127.0.0.1:{port}"]

    def few_descriptors():
        resource.setrlimit(resource.RLIMIT_NOFILE, (NOFILE, NOFILE))

    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            preexec_fn=few_descriptors)
    for port in ports.values():
        wait_port(port, proc)
    return proc, ports


@pytest.fixture
def server():
    procs = []

    def start(*extra):
        proc, ports = serve(*extra)
        procs.append(proc)
        return ports

    yield start
    for p in procs:
        stop(p)


def status(port):
    with urllib.request.urlopen(f"http://127.0.0.1:{port}/api/v1/status", timeout=5) as r:
        return r.status, json.loads(r.read())


def test_half_sent_requests_beyond_the_descriptors_lock_no_one_out(server):
    ports = server()
    # This process needs more descriptors than the server has.
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    if soft < 4 * NOFILE:
        resource.setrlimit(resource.RLIMIT_NOFILE, (min(hard, 4 * NOFILE), hard))
    held = []
    try:
        for _ in range(2 * NOFILE):
            s = socket.create_connection(("127.0.0.1", ports["http"]), timeout=5)
            s.sendall(b"GET /api/v1/status HTTP/1.1\r\nHost: x\r\n")
            held.append(s)
        time.sleep(0.3)
        t0 = time.time()
        code, j = status(ports["http"])
        assert code == 200 and j["state"] == "RUN"
        mc = pymcprotocol.Type3E(plctype="Q")
        mc.soc_timeout = 3
        mc.connect("127.0.0.1", ports["mc"])
        assert mc.batchread_wordunits(headdevice="D0", readsize=1)[0] > 0
        mc.close()
        mb = ModbusTcpClient("127.0.0.1", port=ports["modbus"], timeout=3, retries=0)
        assert mb.connect()
        assert not mb.read_holding_registers(0, count=1).isError()
        mb.close()
        assert time.time() - t0 < 5, "served, but slowly"
    finally:
        for s in held:
            s.close()


def test_a_dribbled_request_head_is_closed_after_the_header_timeout(server):
    ports = server("--http-header-timeout", "1s")
    s = socket.create_connection(("127.0.0.1", ports["http"]), timeout=5)
    s.settimeout(0.2)
    head = b"GET /api/v1/status HTTP/1.1\r\nHost: localhost\r\nX-Slow: " + b"a" * 100
    t0 = time.time()
    closed = False
    for b in head:
        try:
            s.sendall(bytes([b]))
            if s.recv(1024) == b"":
                closed = True
                break
        except socket.timeout:
            continue
        except OSError:
            closed = True
            break
    took = time.time() - t0
    s.close()
    assert closed, f"a head dribbled over {took:.1f} s was never closed"
    assert 0.8 < took < 3, f"closed after {took:.1f} s"
    assert status(ports["http"])[0] == 200
