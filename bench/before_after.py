#!/usr/bin/env python3
"""Scan speed of two softplc builds compared in one sitting (docs/performance.md).

For ROUNDS rounds, every program of `bench_programs` runs on each tier with
the old and then the new binary, one right after the other, so that a slow
spell of the machine touches both alike. The figure is the least
in-process time of `run --stats` (2,010 scans) per instruction, in ns.

    python3 bench/before_after.py OLD_SOFTPLC NEW_SOFTPLC BENCH_PROGRAMS [ROUNDS]

(build each with `cargo build --release -p softplc` and the generator with
`cargo build --release -p softplc-core --example bench_programs`; copy the
old binary aside before building the new one). For exact counts where wall
time drifts, run one program under `valgrind --tool=callgrind` on each.
"""
import os
import re
import subprocess
import sys
import tempfile

if len(sys.argv) < 4:
    sys.exit(__doc__)
OLD, NEW, GEN = sys.argv[1:4]
ROUNDS = int(sys.argv[4]) if len(sys.argv) > 4 else 8
BINS = {"before": OLD, "after": NEW}


def in_process_ns(binary, path, tier, n):
    out = subprocess.run([binary, "run", path, "--scans", "2010", "--exec", tier, "--stats"],
                         capture_output=True, text=True, check=True).stderr
    return float(re.search(r"([0-9.]+) µs per scan", out).group(1)) * 1e3 / n


with tempfile.TemporaryDirectory() as d:
    listing = subprocess.run([GEN, d], capture_output=True, text=True, check=True).stdout
    programs = [line.split() for line in listing.split("\n") if line]
    best = {}
    for _ in range(ROUNDS):
        for path, n in programs:
            for tier in ("interp", "jit"):
                for name, binary in BINS.items():
                    v = in_process_ns(binary, path, tier, int(n))
                    key = (path, tier, name)
                    best[key] = min(best.get(key, v), v)
    print(f"{'program':<10} {'tier':<7} {'before ns':>10} {'after ns':>10} {'after/before':>13}")
    for path, _ in programs:
        for tier in ("interp", "jit"):
            a, b = best[(path, tier, "before")], best[(path, tier, "after")]
            name = os.path.basename(path)[:-3]
            print(f"{name:<10} {tier:<7} {a:>10.3f} {b:>10.3f} {b / a:>13.3f}", flush=True)
