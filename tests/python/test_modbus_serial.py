"""Modbus RTU and ASCII over a pty pair (socat) with pymodbus's serial client."""
import shutil
import subprocess
import time

import pytest
from pymodbus.client import ModbusSerialClient
from pymodbus.framer import FramerType

from conftest import BINARY, HERE, pty_pair, stop

pytestmark = pytest.mark.skipif(shutil.which("socat") is None, reason="socat is not installed")


@pytest.fixture(params=["rtu", "ascii"])
def serial_pair(request, tmp_path):
    pair = pty_pair(tmp_path)
    a, b = next(pair)
    plc = subprocess.Popen(
        [BINARY, "serve", str(HERE / "serve_test.il"), "--scan-time", "5ms", f"--modbus-{request.param}", str(a)],
        stderr=subprocess.PIPE,
    )
    time.sleep(0.5)
    assert plc.poll() is None, plc.stderr.read().decode()
    yield request.param, str(b)
    stop(plc)
    next(pair, None)


def test_read_write_over_serial(serial_pair):
    mode, port = serial_pair
    framer = FramerType.RTU if mode == "rtu" else FramerType.ASCII
    c = ModbusSerialClient(port=port, framer=framer, baudrate=9600, timeout=1)
    assert c.connect()
    assert not c.write_register(100, 777, device_id=1).isError()
    time.sleep(0.05)
    assert c.read_holding_registers(101, count=1, device_id=1).registers == [777]
    d0 = c.read_holding_registers(0, count=1, device_id=1).registers[0]
    time.sleep(0.1)
    assert c.read_holding_registers(0, count=1, device_id=1).registers[0] > d0
    assert not c.write_coil(8192 + 10, True, device_id=1).isError()
    time.sleep(0.05)
    assert c.read_coils(8192 + 11, count=1, device_id=1).bits[0] is True
    # Exception 02 for an unmapped address; the slave keeps answering.
    r = c.read_holding_registers(53248, count=1, device_id=1)
    assert r.isError()
    assert c.read_holding_registers(101, count=1, device_id=1).registers == [777]
    c.close()
