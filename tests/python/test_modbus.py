"""pymodbus (a real Modbus TCP client) against `softplc serve --modbus`, with the
MELSEC-Q default map of the contract: coils 0-8191 = Y, 8192- = M; discrete
inputs = X; holding registers 0-12287 = D; input registers = SD."""
import time

from pymodbus.client import ModbusTcpClient
from pymodbus.pdu import ExceptionResponse

M0 = 8192  # coil address of M0


def client(port):
    c = ModbusTcpClient("127.0.0.1", port=port)
    assert c.connect()
    return c


def test_read_write_while_running(served):
    proc, ports = served("modbus", "mc")
    c = client(ports["modbus"])
    # D100 (holding register 100) is copied to D101 by the program.
    assert not c.write_register(100, 4321).isError()
    time.sleep(0.05)
    assert c.read_holding_registers(101, count=1).registers == [4321]
    # D0 counts scans.
    d0 = c.read_holding_registers(0, count=1).registers[0]
    time.sleep(0.1)
    assert c.read_holding_registers(0, count=1).registers[0] > d0
    # M10 → M11 through the program (coils 8202 → 8203).
    assert not c.write_coil(M0 + 10, True).isError()
    time.sleep(0.05)
    assert c.read_coils(M0 + 11, count=1).bits[0] is True
    # Y0 follows X0; X is written by the MC protocol (Modbus discrete inputs are read-only).
    import pymcprotocol

    mc = pymcprotocol.Type3E(plctype="Q")
    mc.connect("127.0.0.1", ports["mc"])
    mc.batchwrite_bitunits(headdevice="X0", values=[1])
    time.sleep(0.05)
    assert c.read_discrete_inputs(0, count=1).bits[0] is True
    assert c.read_coils(0, count=1).bits[0] is True
    # Several registers at once (FC 16 / FC 3) and SD registers (FC 4): SD203 = 0 (RUN).
    assert not c.write_registers(200, [1, 2, 3]).isError()
    assert c.read_holding_registers(200, count=3).registers == [1, 2, 3]
    assert c.read_input_registers(203, count=1).registers == [0]
    mc.close()
    c.close()


def test_exceptions_and_the_server_keeps_serving(served):
    proc, ports = served("modbus")
    c = client(ports["modbus"])
    # Holding register 53248 is past R32767: exception 02 (illegal data address).
    r = c.read_holding_registers(53248, count=1)
    assert isinstance(r, ExceptionResponse) and r.exception_code == 2
    # 126 registers is more than FC 3 allows: exception 03 (pymodbus refuses to
    # send it, so the frame is written by hand: MBAP, unit 1, FC 3, 0000, 007E).
    import socket

    with socket.create_connection(("127.0.0.1", ports["modbus"])) as s:
        s.sendall(bytes.fromhex("0001 0000 0006 01 03 0000 007E".replace(" ", "")))
        assert s.recv(64) == bytes.fromhex("000100000003018303")
    # Still serving, also for a new client.
    assert c.read_holding_registers(0, count=2).registers is not None
    other = client(ports["modbus"])
    assert not other.read_coils(0, count=16).isError()
    other.close()
    c.close()


def test_remote_stop_leaves_devices_writable(served):
    import pymcprotocol

    proc, ports = served("modbus", "mc")
    mc = pymcprotocol.Type3E(plctype="Q")
    mc.connect("127.0.0.1", ports["mc"])
    c = client(ports["modbus"])
    mc.remote_stop()
    time.sleep(0.05)
    d0 = c.read_holding_registers(0, count=1).registers[0]
    time.sleep(0.1)
    assert c.read_holding_registers(0, count=1).registers[0] == d0
    assert c.read_input_registers(203, count=1).registers[0] & 0xF == 1  # SD203: STOP
    assert not c.write_register(300, 99).isError()
    assert c.read_holding_registers(300, count=1).registers == [99]
    mc.remote_run(clear_mode=0)
    time.sleep(0.1)
    assert c.read_holding_registers(0, count=1).registers[0] > d0
    mc.close()
    c.close()
