"""pymcprotocol (a real MC protocol client) against `softplc serve --mc`."""
import signal
import time

import pymcprotocol
import pytest


def client(port, commtype="binary"):
    c = pymcprotocol.Type3E(plctype="Q")
    if commtype != "binary":
        c.setaccessopt(commtype=commtype)
    c.connect("127.0.0.1", port)
    return c


@pytest.mark.parametrize("commtype", ["binary", "ascii"])
def test_read_write_while_running(served, commtype):
    proc, ports = served("mc")
    c = client(ports["mc"], commtype)
    assert c.read_cputype()[0].strip() == "Q06HCPU"
    # X0 written by the client drives Y0 through the program.
    c.batchwrite_bitunits(headdevice="X0", values=[1])
    time.sleep(0.05)
    assert c.batchread_bitunits(headdevice="Y0", readsize=1) == [1]
    c.batchwrite_bitunits(headdevice="X0", values=[0])
    time.sleep(0.05)
    assert c.batchread_bitunits(headdevice="Y0", readsize=1) == [0]
    # D100 → D101 by MOV, D0 counts scans.
    c.batchwrite_wordunits(headdevice="D100", values=[1234])
    time.sleep(0.05)
    assert c.batchread_wordunits(headdevice="D101", readsize=1) == [1234]
    d0 = c.batchread_wordunits(headdevice="D0", readsize=1)[0]
    time.sleep(0.1)
    assert c.batchread_wordunits(headdevice="D0", readsize=1)[0] > d0
    # M10 → M11, word-unit read of bit devices.
    c.batchwrite_bitunits(headdevice="M10", values=[1])
    time.sleep(0.05)
    assert c.batchread_bitunits(headdevice="M11", readsize=1) == [1]
    c.close()
    proc.send_signal(signal.SIGTERM)
    assert proc.wait(timeout=10) == 0


def test_remote_stop_and_run(served):
    proc, ports = served("mc")
    c = client(ports["mc"])
    c.remote_stop()
    time.sleep(0.05)
    d0 = c.batchread_wordunits(headdevice="D0", readsize=1)[0]
    time.sleep(0.1)
    assert c.batchread_wordunits(headdevice="D0", readsize=1)[0] == d0, "STOP stops the program"
    # Devices stay writable in STOP.
    c.batchwrite_wordunits(headdevice="D200", values=[7])
    assert c.batchread_wordunits(headdevice="D200", readsize=1) == [7]
    c.remote_run(clear_mode=0)
    time.sleep(0.1)
    assert c.batchread_wordunits(headdevice="D0", readsize=1)[0] > d0, "RUN resumes"
    c.close()


def test_bad_address_gets_an_end_code_and_the_server_keeps_serving(served):
    proc, ports = served("mc")
    c = client(ports["mc"])
    with pytest.raises(Exception):
        c.batchread_wordunits(headdevice="D12280", readsize=100)
    assert c.batchread_wordunits(headdevice="D0", readsize=1)[0] >= 0
    other = client(ports["mc"])
    assert other.read_cputype()[0].strip() == "Q06HCPU"
    c.close()
    other.close()


def test_remote_password(served):
    proc, ports = served("mc", extra=("--password", "ab12"))
    c = client(ports["mc"])
    with pytest.raises(Exception):
        c.batchwrite_wordunits(headdevice="D100", values=[1])
    c.remote_unlock(password="ab12")
    c.batchwrite_wordunits(headdevice="D100", values=[5])
    assert c.batchread_wordunits(headdevice="D100", readsize=1) == [5]
    c.close()
