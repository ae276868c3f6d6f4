#!/usr/bin/env python3
"""Co-simulation of a tank with `softplc serve --lockstep` (docs/cosimulation.md).

The PLC program tank.il keeps the level between 400 and 600 mm with a pump.
This script is the plant and drives the loop; every step it

  1. advances the PLC by the step time (POST /api/v1/sim/advance: the CPU
     runs exactly those scans in virtual time and holds again),
  2. reads the pump output Y0 and the start counter D10 over Modbus TCP,
  3. integrates the tank over the step (pump in, constant draw out),
  4. writes the new level to D0 (POST /api/v1/devices), which the program
     sees from its next scan.

The PLC does not run between steps, so the run gives the same result however
slow the plant or the machine is.

    softplc serve examples/cosim/tank.il --lockstep --scan-time 10ms \\
        --http 8080 --http-token secret --modbus 5020
    python3 examples/cosim/cosim.py --http http://127.0.0.1:8080 \\
        --token secret --modbus 127.0.0.1:5020

It prints one line per step (time_ms, level_mm, pump) and, last, a JSON
summary. Needs pymodbus (tests/python/requirements.txt).
"""
import argparse
import json
import urllib.error
import urllib.request

from pymodbus.client import ModbusTcpClient

INFLOW = 150.0  # mm/s while the pump runs
OUTFLOW = 50.0  # mm/s drawn all the time


class Plc:
    """The served PLC: advance and write over HTTP, read over Modbus."""

    def __init__(self, http, token, modbus):
        self.http = http.rstrip("/")
        self.token = token
        host, port = modbus.rsplit(":", 1)
        self.modbus = ModbusTcpClient(host, port=int(port))
        if not self.modbus.connect():
            raise SystemExit(f"no Modbus server at {modbus}")

    def post(self, path, body):
        req = urllib.request.Request(
            self.http + path,
            data=json.dumps(body).encode(),
            headers={
                "Authorization": f"Bearer {self.token}",
                "Content-Type": "application/json",
            },
            method="POST",
        )
        try:
            with urllib.request.urlopen(req, timeout=60) as r:
                return json.load(r)
        except urllib.error.HTTPError as e:
            raise SystemExit(f"{path}: {e.code} {e.read().decode()}")

    def advance(self, ms):
        """Runs `ms` of virtual time; {"scan": S, "time_ms": T} of the last END."""
        return self.post("/api/v1/sim/advance", {"ms": ms})

    def outputs(self):
        """Y0 (coil 0) and D10 (holding register 10) at the held END."""
        pump = self.modbus.read_coils(0, count=1).bits[0]
        starts = self.modbus.read_holding_registers(10, count=1).registers[0]
        return pump, starts

    def write_level(self, level_mm):
        return self.post("/api/v1/devices", {"D0": level_mm})

    def close(self):
        self.modbus.close()


def tank(level_mm, pump, dt_s):
    """The plant over one step: the level after dt_s seconds."""
    return level_mm + ((INFLOW if pump else 0.0) - OUTFLOW) * dt_s


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--http", default="http://127.0.0.1:8080")
    ap.add_argument("--token", required=True)
    ap.add_argument("--modbus", default="127.0.0.1:5020")
    ap.add_argument("--steps", type=int, default=100)
    ap.add_argument("--step-ms", type=float, default=100.0)
    ap.add_argument("--level", type=float, default=500.0, help="initial level, mm")
    args = ap.parse_args()

    plc = Plc(args.http, args.token, args.modbus)
    level = args.level
    # Before scan 1: the program's first scan sees the initial level.
    plc.write_level(round(level))
    for _ in range(args.steps):
        done = plc.advance(args.step_ms)
        pump, starts = plc.outputs()
        level = tank(level, pump, args.step_ms / 1000.0)
        plc.write_level(round(level))
        print(f"{done['time_ms']:.0f} {level:.1f} {int(pump)}", flush=True)
    plc.close()
    print(json.dumps({
        "scan": done["scan"],
        "time_ms": done["time_ms"],
        "level_mm": round(level),
        "pump": pump,
        "starts": starts,
    }))


if __name__ == "__main__":
    main()
