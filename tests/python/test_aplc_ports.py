"""APLC PORT1 against independent peers over socat pty pairs (issue #14):
pymodbus as RTU and ASCII slave polled by the `Modbus` instruction, pymodbus
as master of the APLC slave, and a free-port exchange checked byte for byte
with pyserial. Linux ptys ignore parity, so the lines run with parity none
(contract §3.3)."""
import asyncio
import json
import shutil
import subprocess
import threading
import time

import pytest
import serial
from pymodbus.client import ModbusSerialClient
from pymodbus.datastore import (ModbusDeviceContext, ModbusSequentialDataBlock,
                                ModbusServerContext)
from pymodbus.framer import FramerType
from pymodbus.server import ModbusSerialServer

from conftest import BINARY, HERE, pty_pair, stop

pytestmark = pytest.mark.skipif(shutil.which("socat") is None, reason="socat is not installed")

AP = HERE / "aplc_ports"
MASTER = (AP / "master.apl").read_text()


def project(tmp_path, program, port1):
    (tmp_path / "main.apl").write_text(program)
    (tmp_path / "plc.toml").write_text(
        '[cpu]\nmodel = "APLC-TCP"\n[[program]]\nfile = "main.apl"\n[port1]\n' + port1)
    return tmp_path


def run(proj, pty, *opts, timeout=60):
    cmd = [BINARY, "run", str(proj), "--port1", str(pty), "--json", *opts]
    out = subprocess.run(cmd, capture_output=True, timeout=timeout, text=True)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)["devices"]


def shows(*names):
    return [a for n in names for a in ("--show", n)]


@pytest.fixture
def pair(tmp_path):
    p = pty_pair(tmp_path)
    yield next(p)
    next(p, None)


def silent_elsewhere(station):
    """pymodbus 3.16 answers a request for a station it does not have with
    exception 04 even with ignore_missing_devices; a real absent station is
    silent, so its RTU replies for other stations are dropped here."""
    def trace(sending, data):
        return b"" if sending and data[:1] != bytes([station]) else data
    return trace


def slave_thread(port, framer, station=3):
    """A pymodbus serial slave at `station` with holding registers 0-9 =
    100..109 (block at 1: pymodbus adds 1 to protocol addresses); any
    other station is silent."""
    block = ModbusSequentialDataBlock(1, [100 + k for k in range(10)])
    ctx = ModbusServerContext(devices={station: ModbusDeviceContext(hr=block)}, single=False)
    loop = asyncio.new_event_loop()
    holder = {}

    async def main():
        holder["server"] = ModbusSerialServer(ctx, framer=framer, port=str(port), baudrate=19200,
                                              parity="N", ignore_missing_devices=True,
                                              trace_packet=silent_elsewhere(station)
                                              if framer == FramerType.RTU else None)
        await holder["server"].serve_forever()

    t = threading.Thread(target=lambda: loop.run_until_complete(main()), daemon=True)
    t.start()
    time.sleep(0.5)

    def shutdown():
        asyncio.run_coroutine_threadsafe(holder["server"].shutdown(), loop).result(timeout=5)

    return shutdown


@pytest.mark.parametrize("mode", ["rtu", "ascii"])
def test_modbus_master_polls_pymodbus_slave(tmp_path, pair, mode):
    plc, peer = pair
    framer = FramerType.RTU if mode == "rtu" else FramerType.ASCII
    shutdown = slave_thread(peer, framer)
    try:
        proj = project(tmp_path, MASTER,
                       f'protocol = "modbus-master"\nmode = "{mode}"\nbaud = 19200\nparity = "none"\n'
                       'timeout_ms = 300\n')
        d = run(proj, plc, "--scans", "150", "--at", "2:X0=1", "--at", "60:X1=1",
                *shows("D100", "D101", "D102", "D103", "D104", "D105", "D106",
                       "SM135", "SM136", "SD139", "D200", "D201", "D202"))
    finally:
        shutdown()
    # 03 03 04 00 64 00 65: registers 0-1 = 100, 101 land in D, a byte a word.
    assert [d[f"D{k}"] for k in range(100, 107)] == [3, 3, 4, 0, 100, 0, 101]
    # The second request got exception 02: written to S3, code in SD139.
    assert [d["D200"], d["D201"], d["D202"]] == [3, 0x83, 2]
    assert d["SM136"] is True and d["SD139"] == 2


def test_absent_slave_times_out_with_0x10(tmp_path, pair):
    plc, peer = pair
    shutdown = slave_thread(peer, FramerType.RTU, station=5)
    try:
        proj = project(tmp_path, MASTER,
                       'protocol = "modbus-master"\nbaud = 19200\nparity = "none"\ntimeout_ms = 200\nretries = 1\n')
        d = run(proj, plc, "--scans", "80", "--at", "2:X0=1", *shows("SM135", "SM136", "SD139", "SM124"))
    finally:
        shutdown()
    assert d["SM136"] is True and d["SM135"] is False
    assert d["SD139"] == 0x10
    assert d["SM124"] is True


def test_pymodbus_master_reads_and_writes_the_aplc_slave(tmp_path, pair):
    plc, peer = pair
    proj = project(tmp_path, "LD SM0\nMOV 1234 D0\nADD D10 1 D11\n",
                   'protocol = "modbus-slave"\naddress = 2\nbaud = 19200\nparity = "none"\n')
    srv = subprocess.Popen([BINARY, "serve", str(proj), "--port1", str(plc), "--scan-time", "5ms"],
                           stderr=subprocess.PIPE)
    try:
        time.sleep(0.5)
        assert srv.poll() is None, srv.stderr.read().decode()
        c = ModbusSerialClient(port=str(peer), framer=FramerType.RTU, baudrate=19200, timeout=1)
        assert c.connect()
        assert c.read_holding_registers(0, count=1, device_id=2).registers == [1234]
        assert not c.write_register(10, 41, device_id=2).isError()
        time.sleep(0.05)
        assert c.read_holding_registers(11, count=1, device_id=2).registers == [42]
        # Seed 002's map: M0 is coil 2000; FC 04 is exception 01.
        assert not c.write_coil(2000, True, device_id=2).isError()
        assert c.read_coils(2000, count=1, device_id=2).bits[0] is True
        assert c.read_input_registers(0, count=1, device_id=2).isError()
        c.close()
    finally:
        stop(srv)


FREE = (AP / "free.apl").read_text()


def test_free_port_exchange_byte_for_byte(tmp_path, pair):
    plc, peer = pair
    proj = project(tmp_path, FREE, 'protocol = "free"\nbaud = 9600\n')
    heard = []

    def device():
        with serial.Serial(str(peer), 9600, timeout=5) as s:
            heard.append(s.read(5))
            time.sleep(0.05)
            s.write(bytes([0x01, 0xFF, 0x02, 0x03, 0x05, 0xFE]))
            s.flush()
            time.sleep(0.5)

    t = threading.Thread(target=device)
    t.start()
    time.sleep(0.2)
    d = run(proj, plc, "--scans", "100", "--at", "5:X0=1",
            *shows(*[f"D{k}" for k in range(10, 16)], "SD125", "SD127", "D100"))
    t.join()
    assert heard == [bytes([0x01, 0xFF, 0x00, 0x01, 0x02])]
    assert [d[f"D{k}"] for k in range(10, 16)] == [0x01, 0xFF, 0x02, 0x03, 0x05, 0xFE]
    assert d["SD125"] == 4 and d["SD127"] == 6 and d["D100"] == 1


def test_the_same_programs_pass_as_scenarios():
    """master.apl and free.apl against simulated peers in virtual time."""
    out = subprocess.run([BINARY, "test", str(AP / "master.toml"), str(AP / "free.toml")],
                         capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stdout + out.stderr
    assert out.stdout.rstrip().endswith(" passed, 0 failed"), out.stdout
