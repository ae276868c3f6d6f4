"""Buffer memory of the rack's intelligent function modules over the MC
protocol, against `softplc serve` of the rack project in rack/ (a generic
module of 100 words at X/Y20, unit 2; another of 4096 words at X/Y40,
unit 4; the program copies U2\\G11 to D0, D1 to U2\\G12, counts scans in
U2\\G13).

- U\\G in the device extension specification (0401/1401 with subcommand
  0080) through plc-comm-slmp, an independent SLMP client (its Q profile
  with an Ethernet module speaks 4E binary).
- 0601/1601 (intelligent function module buffer memory batch read/write,
  SLMP Reference Manual SH-080956ENG section 10.2), which no Python client
  offers: frames built by hand from the manual, 3E/4E, binary and ASCII.
"""
import socket
import struct
import subprocess
import time

import pytest
import slmp

from conftest import BINARY, HERE, free_port, stop, wait_port


@pytest.fixture
def mc():
    """`softplc serve rack --mc`; yields the port."""
    port = free_port()
    cmd = [BINARY, "serve", str(HERE / "rack"), "--scan-time", "5ms",
           "--mc", f"127.0.0.1:{port}"]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    wait_port(port, proc)
    yield port
    stop(proc)


def slmp_client(port):
    target = slmp.SlmpTarget(network=0, station=0xFF, module_io=0x3FF, multidrop=0)
    return slmp.SlmpClient("127.0.0.1", port, transport="tcp",
                           plc_profile="melsec:qcpu:qj71e71-100", default_target=target)


def length_at(frame):
    """Where a response's data length field is, and whether it is ASCII."""
    if frame[:1] == b"D":
        return (22 if frame[:4] == b"D400" else 14), True
    return (11 if frame[0] == 0xD4 else 7), False


def exchange(port, frame):
    """Sends one request frame; returns the whole response frame."""
    with socket.create_connection(("127.0.0.1", port), timeout=5) as s:
        s.sendall(frame)
        buf = b""
        while True:
            chunk = s.recv(4096)
            assert chunk, f"connection closed after {buf!r}"
            buf += chunk
            at, ascii_ = length_at(buf)
            width = 4 if ascii_ else 2
            if len(buf) >= at + width:
                field = buf[at:at + width]
                n = int(field, 16) if ascii_ else struct.unpack("<H", field)[0]
                if len(buf) >= at + width + n:
                    return buf


def bin3e(body):
    """3E binary: network 00, PC FF, I/O 03FF, station 00, timer 0010."""
    return (b"\x50\x00\x00\xFF\xFF\x03\x00" + struct.pack("<H", 2 + len(body))
            + b"\x10\x00" + body)


def bin4e(body, serial=0x1234):
    return b"\x54\x00" + struct.pack("<H", serial) + b"\x00\x00" + bin3e(body)[2:]


def ascii3e(body):
    return f"500000FF03FF00{4 + len(body):04X}0010{body}".encode()


def ascii4e(body, serial=0x1234):
    return f"5400{serial:04X}0000".encode() + ascii3e(body)[4:]


def bin_reply(frame):
    """(end code, data) of a binary response."""
    at, _ = length_at(frame)
    n = struct.unpack_from("<H", frame, at)[0]
    return struct.unpack_from("<H", frame, at + 2)[0], frame[at + 4:at + 2 + n]


def ascii_reply(frame):
    at, _ = length_at(frame)
    n = int(frame[at:at + 4], 16)
    return int(frame[at + 4:at + 8], 16), frame[at + 8:at + 4 + n].decode()


def test_u_g_with_plc_comm_slmp(mc):
    """An independent client's device extension frames (4E binary, 0080)."""
    with slmp_client(mc) as c:
        c.write_devices_extended("U2\\G11", [4321], bit_unit=False)
        assert c.read_devices_extended("U2\\G11", 1, bit_unit=False) == [4321]
        # The program copies it to D0 at its next scan.
        for _ in range(100):
            if c.read_devices("D0", 1, bit_unit=False) == [4321]:
                break
            time.sleep(0.01)
        assert c.read_devices("D0", 1, bit_unit=False) == [4321]
        # D1 goes to U2\G12; U2\G13 counts scans.
        c.write_devices("D1", [-5 & 0xFFFF], bit_unit=False)
        time.sleep(0.05)
        assert c.read_devices_extended("U2\\G12", 1, bit_unit=False) == [0xFFFB]
        a = c.read_devices_extended("U2\\G13", 1, bit_unit=False)[0]
        time.sleep(0.05)
        assert c.read_devices_extended("U2\\G13", 1, bit_unit=False)[0] != a
        # The last word of the 4096-word module at X/Y40.
        c.write_devices_extended("U4\\G4095", [7], bit_unit=False)
        assert c.read_devices_extended("U4\\G4094", 2, bit_unit=False) == [0, 7]
        # No module at X/Y30: end code 4043; past the 100 words of U2: 4041.
        with pytest.raises(slmp.SlmpError) as e:
            c.read_devices_extended("U3\\G0", 1, bit_unit=False)
        assert e.value.end_code == 0x4043
        with pytest.raises(slmp.SlmpError) as e:
            c.read_devices_extended("U2\\G99", 2, bit_unit=False)
        assert e.value.end_code == 0x4041


@pytest.mark.parametrize("frame", ["3e", "4e"])
def test_buffer_memory_commands_binary(mc, frame):
    wrap = bin3e if frame == "3e" else bin4e
    # 1601: start address 2 x 20 = 28H, 4 bytes, module 0002 (X/Y20): U2\G20-21.
    body = bytes.fromhex("0116 0000 28000000 0400 0200") + struct.pack("<HH", 0x1234, 0xABCD)
    end, data = bin_reply(exchange(mc, wrap(body)))
    assert (end, data) == (0, b"")
    # 0601 reads them back, and U2\G11 (start 16H) too.
    end, data = bin_reply(exchange(mc, wrap(bytes.fromhex("0106 0000 28000000 0400 0200"))))
    assert end == 0 and struct.unpack("<HH", data) == (0x1234, 0xABCD)
    # The program sees 1601's write: U2\G11 → D0.
    exchange(mc, wrap(bytes.fromhex("0116 0000 16000000 0200 0200") + struct.pack("<H", 99)))
    time.sleep(0.05)
    end, data = bin_reply(exchange(mc, wrap(bytes.fromhex("0104 0000 000000 A8 0100"))))
    assert (end, struct.unpack("<H", data)[0]) == (0, 99)
    # Errors: module 0003 has none (4043), words 99-100 of U2 (4041).
    end, _ = bin_reply(exchange(mc, wrap(bytes.fromhex("0106 0000 00000000 0200 0300"))))
    assert end == 0x4043
    end, _ = bin_reply(exchange(mc, wrap(bytes.fromhex("0106 0000 C6000000 0400 0200"))))
    assert end == 0x4041


@pytest.mark.parametrize("frame", ["3e", "4e"])
def test_buffer_memory_commands_ascii(mc, frame):
    wrap = ascii3e if frame == "3e" else ascii4e
    # 1601 "0000" start "00000028" bytes "0004" module "0002", data 4 digits a word.
    end, data = ascii_reply(exchange(mc, wrap("1601000000000028000400020BB80FA0")))
    assert (end, data) == (0, "")
    end, data = ascii_reply(exchange(mc, wrap("060100000000002800040002")))
    assert (end, data) == (0, "0BB80FA0")
    # U2\G20 in the device extension specification, ASCII: "00", "U002",
    # "000", "G*", "000020", "000".
    end, data = ascii_reply(exchange(mc, wrap("0401008000U002000G*0000200000002")))
    assert (end, data) == (0, "0BB80FA0")
    end, _ = ascii_reply(exchange(mc, wrap("060100000000000000020003")))
    assert end == 0x4043
