#!/usr/bin/env python3
"""Scan speed of both execution tiers (docs/performance.md, "Tiers").

Per-instruction time of `softplc run` as (t(510 scans) - t(10 scans)) /
(500 x instructions), so loading and compiling cancel. t is the least CPU
time (user + system, from wait4) of RUNS runs: on a shared, loaded machine
wall time mostly measures the other processes; on a quiet one both agree.
Compile time is what `softplc check --exec jit --stats` reports (least of RUNS).
"in-process" is the scans' own wall time that `softplc run --stats` prints
(2,010 scans, least of RUNS) per instruction: no process start or load to
cancel, so steadier where the machine is noisy (END processing included,
about 0.5 us per scan).

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
    """User+system seconds of one run of args."""
    with open(os.devnull, "w") as null:
        p = subprocess.Popen(args, stdout=null, stderr=null)
        _, status, ru = os.wait4(p.pid, 0)
    if status != 0:
        sys.exit(f"{' '.join(args)}: exit status {status}")
    return ru.ru_utime + ru.ru_stime


def in_process_us(path, tier):
    """The scans' wall time per scan that one `run --stats` prints."""
    out = subprocess.run([BIN, "run", path, "--scans", "2010", "--exec", tier, "--stats"],
                         capture_output=True, text=True, check=True).stderr
    return float(re.search(r"([0-9.]+) µs per scan", out).group(1))


def compile_ms(path):
    out = subprocess.run([BIN, "check", path, "--exec", "jit", "--stats"],
                         capture_output=True, text=True, check=True).stderr
    return float(re.search(r"compiled in ([0-9.]+) ms", out).group(1))


def least(best, key, value):
    best[key] = value if key not in best else min(best[key], value)


with tempfile.TemporaryDirectory() as d:
    listing = subprocess.run([os.path.join(REL, "examples", "bench_programs"), d],
                             capture_output=True, text=True, check=True).stdout
    programs = [line.split() for line in listing.split("\n") if line]
    # Every measurement once per round, rounds RUNS times: a slow spell of
    # the machine then touches every figure alike instead of one of them.
    best = {}
    for _ in range(RUNS):
        for path, _n in programs:
            for tier in ("interp", "jit"):
                for scans in (10, 510):
                    least(best, (path, tier, scans),
                          cpu_time([BIN, "run", path, "--scans", str(scans), "--exec", tier]))
                least(best, (path, tier, "in"), in_process_us(path, tier))
            least(best, (path, "compile"), compile_ms(path))
    print(f"{'program':<12} {'tier':<7} {'ns/instr':>9} {'in-process':>11} {'jit compile':>12}")
    for path, n in programs:
        name = os.path.basename(path)[:-3]
        for tier in ("interp", "jit"):
            ns = (best[(path, tier, 510)] - best[(path, tier, 10)]) / (500 * int(n)) * 1e9
            inp = best[(path, tier, "in")] * 1e3 / int(n)
            c = f"{best[(path, 'compile')]:.1f} ms" if tier == "jit" else "-"
            print(f"{name:<12} {tier:<7} {ns:>9.3f} {inp:>11.3f} {c:>12}", flush=True)
