"""The co-simulation example (docs/cosimulation.md) against `softplc serve
--lockstep`: examples/cosim/cosim.py advances the PLC over HTTP, reads it
over Modbus TCP and writes the plant's level back, step by step. In lockstep
the run is exact, so its result is the one worked out by hand."""
import json
import subprocess
import sys
import urllib.request

from conftest import BINARY, ROOT, free_port, stop, wait_port

EXAMPLE = ROOT / "examples" / "cosim"
TOKEN = "cosim-token"


def serve(*extra):
    http, modbus = free_port(), free_port()
    proc = subprocess.Popen(
        [BINARY, "serve", str(EXAMPLE / "tank.il"), "--lockstep", "--scan-time", "10ms",
         "--http", f"127.0.0.1:{http}", "--http-token", TOKEN,
         "--modbus", f"127.0.0.1:{modbus}", *extra],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE,
    )
    wait_port(http, proc)
    wait_port(modbus, proc)
    return proc, http, modbus


def status(http):
    with urllib.request.urlopen(f"http://127.0.0.1:{http}/api/v1/status", timeout=30) as r:
        return json.load(r)


def cosim(http, modbus, steps):
    out = subprocess.run(
        [sys.executable, str(EXAMPLE / "cosim.py"), "--http", f"http://127.0.0.1:{http}",
         "--token", TOKEN, "--modbus", f"127.0.0.1:{modbus}", "--steps", str(steps)],
        capture_output=True, text=True, timeout=300,
    )
    assert out.returncode == 0, out.stderr
    lines = out.stdout.strip().splitlines()
    return lines[:-1], json.loads(lines[-1])


def test_the_tank_cosimulation_gives_the_hand_worked_result():
    proc, http, modbus = serve()
    try:
        # Held at power-on: no scan before the first advance.
        st = status(http)
        assert (st["scan"], st["time_ms"]) == (0, 0.0)
        trace, summary = cosim(http, modbus, 100)
        # From 500 mm the level falls 5 mm a step (100 ms at 50 mm/s). After
        # step 21 it is 395: the program sees it in step 22 and starts the
        # pump (+10 mm a step); 605 after step 42 stops it in step 43 (600);
        # 395 after step 84 starts it again in step 85 (405); 15 steps later,
        # after step 100, the level is 555 mm with the pump running.
        assert summary == {"scan": 1000, "time_ms": 10000.0, "level_mm": 555,
                           "pump": True, "starts": 2}
        assert trace[20] == "2100 395.0 0"
        assert trace[21] == "2200 405.0 1"
        assert trace[42] == "4300 600.0 0"
        assert trace[84] == "8500 405.0 1"
        # The server holds after the last advance.
        st = status(http)
        assert (st["scan"], st["time_ms"]) == (1000, 10000.0)
    finally:
        stop(proc)


def test_the_same_run_paced_at_real_time_scale_gives_the_same_result():
    # --time-scale paces an advance's scans; lockstep keeps the result exact.
    proc, http, modbus = serve("--time-scale", "1000")
    try:
        _, summary = cosim(http, modbus, 30)
        # 30 steps from 500 mm: 395 after step 21, pump ON from step 22,
        # 405 + 8 × 10 = 485 after step 30.
        assert summary == {"scan": 300, "time_ms": 3000.0, "level_mm": 485,
                           "pump": True, "starts": 1}
    finally:
        stop(proc)
