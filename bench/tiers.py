#!/usr/bin/env python3
"""Scan speed of both execution tiers (docs/performance.md, "Tiers").

Per-instruction time of `softplc run` as (t(510 scans) - t(10 scans)) /
(500 x instructions), so loading and compiling cancel. t is the least CPU
time (user + system, from wait4) of RUNS runs: on a shared, loaded machine
wall time mostly measures the other processes; on a quiet one both agree.
Compile time is what `softplc check --exec jit --stats` reports (least of RUNS).

    cargo build --release -p softplc
    cargo build --release -p softplc-core --example bench_programs
    python3 bench/tiers.py [RUNS]
"""
import os
import re
import subprocess
import sys
import tempfile

RUNS = int(sys.argv[1]) if len(sys.argv) > 1 else 7
REL = os.path.join(os.environ.get("CARGO_TARGET_DIR", "target"), "release")
BIN = os.path.join(REL, "softplc")


def cpu_time(args):
    """Least user+system seconds of RUNS runs of args."""
    best = None
    for _ in range(RUNS):
        with open(os.devnull, "w") as null:
            p = subprocess.Popen(args, stdout=null, stderr=null)
            _, status, ru = os.wait4(p.pid, 0)
        if status != 0:
            sys.exit(f"{' '.join(args)}: exit status {status}")
        t = ru.ru_utime + ru.ru_stime
        best = t if best is None else min(best, t)
    return best


def compile_ms(path):
    best = None
    for _ in range(RUNS):
        out = subprocess.run([BIN, "check", path, "--exec", "jit", "--stats"],
                             capture_output=True, text=True, check=True).stderr
        ms = float(re.search(r"compiled in ([0-9.]+) ms", out).group(1))
        best = ms if best is None else min(best, ms)
    return best


with tempfile.TemporaryDirectory() as d:
    listing = subprocess.run([os.path.join(REL, "examples", "bench_programs"), d],
                             capture_output=True, text=True, check=True).stdout
    print(f"{'program':<12} {'tier':<7} {'ns/instr':>9} {'jit compile':>12}")
    for line in listing.split("\n"):
        if not line:
            continue
        path, n = line.split()
        name = os.path.basename(path)[:-3]
        for tier in ("interp", "jit"):
            t = {s: cpu_time([BIN, "run", path, "--scans", str(s), "--exec", tier])
                 for s in (10, 510)}
            ns = (t[510] - t[10]) / (500 * int(n)) * 1e9
            c = f"{compile_ms(path):.1f} ms" if tier == "jit" else "-"
            print(f"{name:<12} {tier:<7} {ns:>9.3f} {c:>12}", flush=True)
