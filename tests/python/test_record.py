"""A 60 s session of `softplc serve --record` with real clients — pymodbus,
pymcprotocol and the JSON API — writing, forcing and stopping the CPU, then
`softplc replay`: the replay ends with the device values the live CPU had at
its last END (docs/recording.md)."""
import json
import random
import subprocess
import time
import urllib.request

import pymcprotocol
from pymodbus.client import ModbusTcpClient

from conftest import BINARY, free_port, stop, wait_port

# 60 s of traffic; with the start and the replay the test takes a little
# over a minute.
SECONDS = 60

PROGRAM = """\
LD SM400
INC D3
MOV D0 D2
LD M0
OUT T0 K20
LD M1
OUT T1 K7
LD X1
OUT Y1
LD X2
OUT C0 K5
LD M5
MOV D10 D41
LD SM400
MOV D20 D42
+ D30 D43
END
"""

TOKEN = "t"


def http(port, method, path, body=None):
    data = None if body is None else json.dumps(body).encode()
    req = urllib.request.Request(f"http://127.0.0.1:{port}{path}", data=data, method=method)
    req.add_header("Authorization", f"Bearer {TOKEN}")
    req.add_header("Content-Type", "application/json")
    with urllib.request.urlopen(req, timeout=10) as r:
        return json.loads(r.read())


def wide():
    names = []
    for n in range(100):
        names += [f"D{n}", f"M{n}"]
    for n in range(32):
        names += [f"X{n:X}", f"Y{n:X}"]
    for n in range(10):
        names += [f"T{n}", f"TN{n}", f"C{n}", f"CN{n}"]
    return names


def test_a_60_s_session_replays_to_the_devices_of_its_last_end(tmp_path):
    program = tmp_path / "p.il"
    program.write_text(PROGRAM)
    rec = tmp_path / "session.rec"
    ports = {name: free_port() for name in ("modbus", "mc", "http")}
    cmd = [BINARY, "serve", str(program), "--scan-time", "5ms", "--no-realtime",
           "--record", str(rec), "--http-token", TOKEN]
    for name, port in ports.items():
        cmd += [f"--{name}", f"127.0.0.1:{port}"]
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    try:
        for port in ports.values():
            wait_port(port, proc)
        mb = ModbusTcpClient("127.0.0.1", port=ports["modbus"])
        assert mb.connect()
        mc = pymcprotocol.Type3E(plctype="Q")
        mc.connect("127.0.0.1", ports["mc"])
        rnd = random.Random(29)
        end = time.time() + SECONDS
        written = {}
        while time.time() < end:
            k = rnd.randrange(8)
            v = rnd.randrange(1, 30000)
            if k == 0:
                assert not mb.write_register(10 + rnd.randrange(3), v).isError()
            elif k == 1:
                m = rnd.choice([0, 1, 5])
                assert not mb.write_coil(8192 + m, rnd.random() < 0.7).isError()
            elif k == 2:
                mc.batchwrite_wordunits(headdevice="D20", values=[v, v + 1])
            elif k == 3:
                mc.batchwrite_bitunits(headdevice="X2", values=[rnd.randrange(2)])
            elif k == 4:
                http(ports["http"], "POST", "/api/v1/devices", {"D0": v, "D30": rnd.randrange(5)})
                written["D0"] = v
            elif k == 5:
                http(ports["http"], "POST", "/api/v1/force", {"X1": rnd.random() < 0.5})
            elif k == 6 and rnd.random() < 0.3:
                # A short remote STOP by MC, then RUN again.
                mc.remote_stop()
                time.sleep(rnd.uniform(0.01, 0.2))
                mc.remote_run(clear_mode=0)
            elif k == 7 and rnd.random() < 0.3:
                http(ports["http"], "POST", "/api/v1/cpu/pause")
                time.sleep(rnd.uniform(0.01, 0.1))
                http(ports["http"], "POST", "/api/v1/cpu/run")
            time.sleep(rnd.uniform(0.0, 0.25))
        # STOP: the devices hold still to be read.
        http(ports["http"], "POST", "/api/v1/cpu/stop")
        names = wide()
        live = http(ports["http"], "GET", "/api/v1/devices?names=" + ",".join(names))
        mb.close()
        mc.close()
    finally:
        stop(proc)
    assert proc.returncode == 0, proc.stderr.read().decode()
    args = [BINARY, "replay", str(rec), "--json"]
    for n in names:
        args += ["--show", n]
    out = subprocess.run(args, capture_output=True, timeout=60)
    assert out.returncode == 0, out.stderr.decode()
    again = json.loads(out.stdout)
    assert again["recording"]["ending"] == "shutdown"
    assert again["scans"] == live["scan"]
    assert again["state"] == "STOP"
    assert again["devices"] == live["devices"]
    # D3 counts the scans since power-on (about 10,000 of 5 ms: no wrap);
    # D2 holds the last D0 written.
    assert again["devices"]["D3"] == again["scans"]
    assert again["devices"]["D2"] == written["D0"]
