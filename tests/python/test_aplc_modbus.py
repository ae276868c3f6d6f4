"""pymodbus (a real Modbus client) against `softplc serve` of an APLC-TCP
program (seed 002, spec/aplc.md §6.3-6.5, contract §3): the APLC address map
over the APLC's device memory, unit address 8, C200-C255 as true 32-bit
pairs (even address = high word), over TCP and over RTU/ASCII on a pty."""
import shutil
import subprocess
import time

import pytest
from pymodbus.client import ModbusSerialClient, ModbusTcpClient
from pymodbus.exceptions import ModbusIOException
from pymodbus.framer import FramerType
from pymodbus.pdu import ExceptionResponse

from conftest import BINARY, free_port, pty_pair, stop, wait_port

# M0 (coil 2000) drives Y10 (octal: output 8, coil 8); X10 (input 8) drives
# Y11 (coil 9); C200's 32-bit value goes to D100 (high word) and D101.
PROGRAM = """\
LD M0
OUT Y10
LD X10
OUT Y11
LD SM0
DMOV C200 D100
"""

def serve(args):
    proc = subprocess.Popen([BINARY, "serve", *args, "--scan-time", "5ms"], stderr=subprocess.PIPE)
    return proc


@pytest.fixture
def aplc_project(tmp_path):
    """An APLC-TCP project whose TCP server answers only its unit address."""
    (tmp_path / "main.apl").write_text(PROGRAM)
    (tmp_path / "plc.toml").write_text(
        '[cpu]\nmodel = "APLC-TCP"\n\n[[program]]\nfile = "main.apl"\n\n'
        "[modbus]\ntcp_any_unit = false\n"
    )
    port = free_port()
    proc = serve([str(tmp_path), "--modbus", f"127.0.0.1:{port}"])
    wait_port(port, proc)
    yield port
    stop(proc)


def test_c200_is_a_true_32_bit_pair_at_unit_8(aplc_project):
    c = ModbusTcpClient("127.0.0.1", port=aplc_project, timeout=1, retries=0)
    assert c.connect()
    # C200 = 100000 = 0x0001_86A0, high word at the even address 9700.
    assert not c.write_registers(9700, [0x0001, 0x86A0], device_id=8).isError()
    assert c.read_holding_registers(9700, count=2, device_id=8).registers == [1, 0x86A0]
    time.sleep(0.05)
    # The program saw 100000: DMOV C200 D100 → D100 = 1, D101 = 34464.
    assert c.read_holding_registers(100, count=2, device_id=8).registers == [1, 34464]
    # M0 (coil 2000) → Y10, which is output 8 (octal), coil 8.
    assert not c.write_coil(2000, True, device_id=8).isError()
    time.sleep(0.05)
    assert c.read_coils(8, count=1, device_id=8).bits[0] is True
    assert c.read_coils(7, count=1, device_id=8).bits[0] is False
    # Exceptions: FC 06 into the 32-bit counters (02, decision D24), an odd
    # start (02), an odd count (03), FC 04 (01: not an APLC function).
    r = c.write_register(9700, 1, device_id=8)
    assert isinstance(r, ExceptionResponse) and r.exception_code == 2
    r = c.read_holding_registers(9701, count=2, device_id=8)
    assert isinstance(r, ExceptionResponse) and r.exception_code == 2
    r = c.read_holding_registers(9700, count=3, device_id=8)
    assert isinstance(r, ExceptionResponse) and r.exception_code == 3
    r = c.read_input_registers(0, count=1, device_id=8)
    assert isinstance(r, ExceptionResponse) and r.exception_code == 1
    # Unit 0 and 255 are answered too (contract §3); the value is unchanged.
    assert c.read_holding_registers(9700, count=2, device_id=255).registers == [1, 0x86A0]
    c.close()


def test_other_units_get_no_answer_with_tcp_any_unit_off(aplc_project):
    c = ModbusTcpClient("127.0.0.1", port=aplc_project, timeout=0.5, retries=0)
    assert c.connect()
    with pytest.raises(ModbusIOException):
        c.read_holding_registers(0, count=1, device_id=1)
    c.close()


@pytest.fixture(params=["rtu", "ascii"])
def aplc_serial(request, tmp_path):
    if shutil.which("socat") is None:
        pytest.skip("socat is not installed")
    pair = pty_pair(tmp_path)
    a, b = next(pair)
    program = tmp_path / "main.apl"
    program.write_text(PROGRAM)
    plc = serve([str(program), f"--modbus-{request.param}", str(a)])
    time.sleep(0.5)
    assert plc.poll() is None, plc.stderr.read().decode()
    yield request.param, str(b)
    stop(plc)
    next(pair, None)


def test_serial_slave_is_station_8_with_the_aplc_map(aplc_serial):
    mode, port = aplc_serial
    framer = FramerType.RTU if mode == "rtu" else FramerType.ASCII
    c = ModbusSerialClient(port=port, framer=framer, baudrate=9600, timeout=1, retries=0)
    assert c.connect()
    # C255 is the last pair, 9810-9811: -2 is 0xFFFF_FFFE.
    assert not c.write_registers(9810, [0xFFFF, 0xFFFE], device_id=8).isError()
    assert c.read_holding_registers(9810, count=2, device_id=8).registers == [0xFFFF, 0xFFFE]
    # X0-X377 are discrete inputs 0-255; X200-X377 do not exist and read OFF.
    r = c.read_discrete_inputs(0, count=256, device_id=8)
    assert not r.isError() and not any(r.bits[:256])
    # Station 1 is not this slave: no answer (pymodbus raises on the timeout).
    with pytest.raises(ModbusIOException):
        c.read_holding_registers(0, count=1, device_id=1)
    c.close()
