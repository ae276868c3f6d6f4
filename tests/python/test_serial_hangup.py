"""A serial line that hangs up and comes back: `serve --modbus-rtu` on one
end of a socat pty pair; socat is stopped (the line hangs up), the server
stays idle and says so once, socat starts again (the line comes back) and
the server serves again on it."""
import os
import shutil
import subprocess
import time

import pytest
from pymodbus.client import ModbusSerialClient
from pymodbus.framer import FramerType

from conftest import BINARY, HERE, stop

pytestmark = pytest.mark.skipif(shutil.which("socat") is None, reason="socat is not installed")


def socat(a, b):
    """A pty pair linked at `a` and `b`, once both links exist."""
    p = subprocess.Popen(
        ["socat", f"pty,raw,echo=0,link={a}", f"pty,raw,echo=0,link={b}"],
        stderr=subprocess.DEVNULL,
    )
    for _ in range(100):
        if a.exists() and b.exists():
            return p
        time.sleep(0.05)
    raise RuntimeError("socat made no pty pair")


def cpu_seconds(pid):
    """User and system CPU time of process `pid` so far (/proc/PID/stat)."""
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def wait_for(predicate, timeout):
    end = time.time() + timeout
    while time.time() < end:
        if predicate():
            return True
        time.sleep(0.05)
    return False


def reads_d101(port):
    c = ModbusSerialClient(port=port, framer=FramerType.RTU, baudrate=9600, timeout=1)
    try:
        if not c.connect():
            return None
        r = c.read_holding_registers(101, count=1, device_id=1)
        return None if r.isError() else r.registers[0]
    finally:
        c.close()


def test_line_hangs_up_and_comes_back(tmp_path):
    a, b = tmp_path / "plc", tmp_path / "master"
    line = socat(a, b)
    log = tmp_path / "stderr"
    with open(log, "wb") as err:
        plc = subprocess.Popen(
            [BINARY, "serve", str(HERE / "serve_test.il"), "--scan-time", "5ms", "--modbus-rtu", str(a)],
            stderr=err,
        )
    try:
        time.sleep(0.5)
        assert plc.poll() is None, log.read_text()
        c = ModbusSerialClient(port=str(b), framer=FramerType.RTU, baudrate=9600, timeout=1)
        assert c.connect()
        assert not c.write_register(100, 4321, device_id=1).isError()
        c.close()

        # The line hangs up.
        line.terminate()
        line.wait(timeout=10)
        time.sleep(0.5)
        before = cpu_seconds(plc.pid)
        time.sleep(2.0)
        used = cpu_seconds(plc.pid) - before
        # It busy-looped on zero-length reads (2 s of CPU in 2 s) before.
        assert used < 0.2, f"{used:.2f} s of CPU in 2 s after the hang-up"
        assert plc.poll() is None, log.read_text()
        text = log.read_text()
        assert text.count("hung up") == 1, text

        # The line comes back: the server reopens it and serves again.
        line = socat(a, b)
        assert wait_for(lambda: "reopened" in log.read_text(), 10), log.read_text()
        assert reads_d101(str(b)) == 4321
        assert log.read_text().count("hung up") == 1, log.read_text()
    finally:
        stop(plc)
        line.terminate()
        line.wait(timeout=10)
