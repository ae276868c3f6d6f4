#!/usr/bin/env python3
"""Virtual-time throughput of `softplc test` (docs/performance.md,
"Virtual-time throughput").

    python3 bench/throughput.py [--rounds N] [BINARY ...]

Runs every shipped scenario (examples/**/*.toml that `softplc test` runs;
the 24 h soak only with --soak) and a generated one — a 10,000-step
program against three plant models — with each BINARY (default
target/release/softplc), one file at a time (`-j1`), in a copy of
examples/ so that no plot or trace file of the tree is rewritten. Each
scenario runs N times per binary, the binaries taking turns, and the
fastest run counts (wall time on a shared machine mostly measures the other
processes). Prints one table per binary: scenario, scans, virtual seconds,
wall seconds of the scan loop (what the report's header line gives) and
the × real-time factor, with the sample suite (examples/sim/*.toml) summed.
"""

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

HEADER = re.compile(
    r"— .*: (\d+) scans, (.+?) simulated in [\d.]+ s \((\d+)× real time\)"
)

SAMPLE = ["sim/conveyor.toml", "sim/fill_drain.toml", "sim/heated_tank.toml"]
OTHERS = [
    "process/autotune.toml",
    "process/cascade.toml",
    "process/flow_loop.toml",
    "process/fopdt_loop.toml",
    "process/ratio.toml",
    "rack/tank.toml",
    "multi_cpu/line.toml",
    "fleet/serial_line.toml",
    "aplc/barcode.toml",
    "aplc/batch_mix.toml",
    "aplc/conveyor.toml",
    "aplc/modbus_poll.toml",
    "aplc/pid_setup.toml",
    "aplc/sfc.toml",
    "aplc/subroutine.toml",
]
GENERATED = "generated/big_3_models.toml"
SOAK = "sim/soak/heated_tank_24h.toml"


def seconds(text):
    """The virtual time of a report header (`40 s`, `8 min`, `24 h`, `500 ms`)."""
    number, unit = text.split()
    scale = {"h": 3600, "min": 60, "s": 1, "ms": 1e-3, "us": 1e-6}[unit]
    return float(number) * scale


def generate(dir):
    """A 10,000-step program (the heated tank's PIDCONT loop, a motor's
    start/stop and a valve, and 472 groups of interlocks, timers,
    counters, moves, arithmetic and compares) and its scenario: a heater,
    a motor and a valve model bound to its devices, 5 min at 10 ms."""
    os.makedirs(dir, exist_ok=True)
    with open(os.path.join(ROOT, "examples/sim/heated_tank.il")) as f:
        pid = [l for l in f.read().splitlines() if l.strip() != "END"]
    lines = pid + [
        "LD X20", "OR Y10", "ANI X21", "OUT Y10",  # motor start/stop
        "LD X4", "OUT T1500 K50", "LD T1500", "OUT Y11",  # valve after 5 s running
    ]
    for g in range(472):
        m, d = 1000 + 4 * g, 2000 + 4 * g
        lines += [
            f"LD M{m}", f"OR X{g % 64:X}", f"ANI M{m + 1}", f"OUT M{m + 2}",
            f"LD M{m + 2}", f"OUT T{g} K10",
            f"LD SM400", f"MOV D{d} D{d + 1}", f"+ D{d + 1} K1 D{d + 2}",
            f"LD> D{d + 2} K100", f"OUT M{m + 3}",
        ]
    lines.append("END")
    with open(os.path.join(dir, "big_3_models.il"), "w") as f:
        f.write("\n".join(lines) + "\n")
    with open(os.path.join(dir, "big_3_models.toml"), "w") as f:
        f.write(
            """name = "10,000 steps, heater, motor and valve"
program = "big_3_models.il"
scan_time = "10ms"
duration = "5min"

[[model]]
name = "tank"
type = "heater"
params = { capacity = 12000, power = 6000, resistance = 0.02, ambient = 20 }
inputs.u = { device = "D820", raw = [0, 2000], eng = [0, 100] }
outputs.temperature = { device = "D800", eng = [0, 200], raw = [0, 2000] }

[[model]]
type = "motor"
params = { accel_time = "2s", decel_time = "2s" }
inputs.run = "Y10"
outputs.speed = "D20"
outputs.running = "X4"

[[model]]
type = "valve"
params = { travel_time = "3s" }
inputs.open = "Y11"
outputs.position = "D100:f32"

[[timeline]]
at = "1s"
set = { X0 = 1, X20 = 1 }

[[expect]]
device = "Y0"
equals = true
within = "100ms"
after = "1s"

[[expect]]
device = "D611"
never_exceeds = 780

[[expect]]
device = "D100:f32"
equals = 100
at = "1min"

[[expect]]
device = "Y1"
never = true
equals = true
"""
        )


def run(binary, examples, rel):
    """(scans, virtual s, wall s) of one run, or an error text."""
    path = os.path.join(examples, rel)
    p = subprocess.run(
        [binary, "test", "-q", "--no-progress", "-j1", path],
        capture_output=True,
        text=True,
        cwd=os.path.dirname(path),
    )
    m = HEADER.search(p.stdout)
    if not m or " 0 failed" not in (p.stdout + p.stderr):
        return f"failed: {(p.stdout + p.stderr).strip().splitlines()[-3:]}"
    scans, virtual, factor = int(m[1]), seconds(m[2]), int(m[3])
    return scans, virtual, virtual / max(factor, 1)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("binaries", nargs="*", default=[os.path.join(ROOT, "target/release/softplc")])
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--soak", action="store_true", help="also the 24 h soak (8.64 M scans)")
    ap.add_argument("--only", help="only scenarios whose path contains this")
    args = ap.parse_args()
    args.binaries = [os.path.abspath(b) for b in args.binaries]
    scenarios = SAMPLE + OTHERS + [GENERATED] + ([SOAK] if args.soak else [])
    if args.only:
        scenarios = [s for s in scenarios if args.only in s]
    with tempfile.TemporaryDirectory() as tmp:
        examples = os.path.join(tmp, "examples")
        shutil.copytree(os.path.join(ROOT, "examples"), examples)
        generate(os.path.join(examples, "generated"))
        best = {}
        for _ in range(args.rounds):
            for rel in scenarios:
                for b in args.binaries:
                    r = run(b, examples, rel)
                    old = best.get((b, rel))
                    if isinstance(r, str):
                        best[(b, rel)] = r
                    elif not isinstance(old, tuple) or r[2] < old[2]:
                        if not isinstance(old, str):
                            best[(b, rel)] = r
    load = os.getloadavg()[0]
    for b in args.binaries:
        print(f"\n{b} (least of {args.rounds} runs, load average {load:.1f})\n")
        print("| scenario | scans | virtual s | wall s | × real time | µs/scan |")
        print("|---|---:|---:|---:|---:|---:|")
        suite = [0, 0.0, 0.0]
        for rel in scenarios:
            r = best[(b, rel)]
            if isinstance(r, str):
                print(f"| {rel} | {r} | | | | |")
                continue
            scans, virtual, wall = r
            print(
                f"| {rel} | {scans} | {virtual:g} | {wall:.4f} | {virtual / wall:,.0f} | {wall / scans * 1e6:.2f} |"
            )
            if rel in SAMPLE:
                suite = [suite[0] + scans, suite[1] + virtual, suite[2] + wall]
        if suite[2] > 0:
            print(
                f"| **sample suite** (examples/sim/*.toml) | {suite[0]} | {suite[1]:g} | {suite[2]:.4f} | **{suite[1] / suite[2]:,.0f}** | {suite[2] / suite[0] * 1e6:.2f} |"
            )


if __name__ == "__main__":
    sys.exit(main())
