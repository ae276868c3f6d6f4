"""One MC server for a multi-CPU system: `softplc serve SYSTEM_DIR --mc`
against real clients. The request destination module I/O number of a
frame picks the CPU: 03E0-03E3 are CPU 1-4, 03FF (own station) CPU 1; a
CPU the system does not have answers end code 4B00.

- plc-comm-slmp (its `SlmpTarget.module_io`, 4E binary) and pymcprotocol
  (`setaccessopt(dest_moduleio=...)`, 3E binary and ASCII), both of which
  let a client choose the destination module I/O number.
- A 3E ASCII frame built by hand for the absent CPU's exact reply.
"""
import socket
import subprocess
import time

import pymcprotocol
import pytest
import slmp

from conftest import BINARY, free_port, stop, wait_port

# CPU 1 (Q06HCPU) puts 11 in D1; CPU 2 (Q12HCPU) puts 22 in D1 and copies
# D10 to D11.
PROGRAMS = {
    "cpu1": ("Q06HCPU", "LD SM400\nMOV K11 D1\nEND\n"),
    "cpu2": ("Q12HCPU", "LD SM400\nMOV K22 D1\nMOV D10 D11\nEND\n"),
}


@pytest.fixture
def system(tmp_path):
    """`softplc serve` of a two-CPU system built in tmp_path; yields the
    MC port."""
    manifest = ""
    for name, (model, il) in PROGRAMS.items():
        d = tmp_path / name
        d.mkdir()
        (d / "plc.toml").write_text(
            f'[cpu]\nmodel = "{model}"\n[[program]]\nfile = "main.il"\n'
            "[multi_cpu]\ncpus = 2\n[ras]\nremote_reset = true\n")
        (d / "main.il").write_text(il)
        manifest += f'[[cpu]]\nproject = "{name}"\n'
    (tmp_path / "system.toml").write_text(manifest)
    port = free_port()
    cmd = [BINARY, "serve", str(tmp_path), "--scan-time", "5ms", "--mc", f"127.0.0.1:{port}"]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    wait_port(port, proc)
    yield port
    stop(proc)
    err = proc.stderr.read().decode()
    # The start message names every CPU.
    assert "CPU 1:" in err and "CPU 2:" in err, err


def slmp_client(port, module_io):
    target = slmp.SlmpTarget(network=0, station=0xFF, module_io=module_io, multidrop=0)
    return slmp.SlmpClient("127.0.0.1", port, transport="tcp",
                           plc_profile="melsec:qcpu:qj71e71-100", default_target=target)


def eventually(read, want):
    for _ in range(200):
        if read() == want:
            return
        time.sleep(0.01)
    assert read() == want


def test_the_destination_picks_the_cpu_plc_comm_slmp(system):
    with slmp_client(system, 0x3FF) as own, slmp_client(system, 0x3E0) as one, \
            slmp_client(system, 0x3E1) as two:
        eventually(lambda: own.read_devices("D1", 1, bit_unit=False), [11])
        assert one.read_devices("D1", 1, bit_unit=False) == [11]
        eventually(lambda: two.read_devices("D1", 1, bit_unit=False), [22])
        # Read CPU model answers per CPU.
        assert own.read_type_name().model.strip() == "Q06HCPU"
        assert two.read_type_name().model.strip() == "Q12HCPU"
        # A write reaches its CPU only; CPU 2's program copies D10 to D11.
        two.write_devices("D10", [777], bit_unit=False)
        eventually(lambda: two.read_devices("D11", 1, bit_unit=False), [777])
        assert own.read_devices("D10", 2, bit_unit=False) == [0, 0]


def test_an_absent_cpu_answers_4b00(system):
    for io in (0x3E2, 0x3E3):
        with slmp_client(system, io) as c:
            with pytest.raises(slmp.SlmpError) as e:
                c.read_devices("D1", 1, bit_unit=False)
            assert e.value.end_code == 0x4B00
    # The same as a hand-built 3E ASCII frame: batch read D1 of CPU 3, the
    # error information echoes the station and the command.
    frame = b"500000FF03E200" + b"0018" + b"0010" + b"04010000D*0000010001"
    with socket.create_connection(("127.0.0.1", system), timeout=5) as s:
        s.sendall(frame)
        reply = b""
        while len(reply) < 40:
            chunk = s.recv(4096)
            assert chunk, reply
            reply += chunk
    assert reply == b"D00000FF03E20000164B0000FF03E20004010000"


@pytest.mark.parametrize("commtype", ["binary", "ascii"])
def test_remote_operations_reach_their_cpu_pymcprotocol(system, commtype):
    def client(io):
        c = pymcprotocol.Type3E(plctype="Q")
        c.setaccessopt(commtype=commtype, dest_moduleio=io)
        c.connect("127.0.0.1", system)
        return c

    one, two = client(0x3E0), client(0x3E1)
    assert two.read_cputype()[0].strip() == "Q12HCPU"
    eventually(lambda: two.batchread_wordunits(headdevice="D1", readsize=1), [22])
    two.remote_stop()
    # CPU 2 stopped: its D10 → D11 copy no longer runs; CPU 1 still scans.
    two.batchwrite_wordunits(headdevice="D10", values=[5])
    time.sleep(0.05)
    assert two.batchread_wordunits(headdevice="D11", readsize=1) == [0]
    one.batchwrite_wordunits(headdevice="D1", values=[0])
    eventually(lambda: one.batchread_wordunits(headdevice="D1", readsize=1), [11])
    # RESET of CPU 2 alone brings CPU 1 down with MULTI CPU DOWN (SD0 = 7000).
    two.remote_reset()
    eventually(lambda: one.batchread_wordunits(headdevice="SD0", readsize=1), [7000])
    one.close()
    two.close()
