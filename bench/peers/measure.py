#!/usr/bin/env python3
"""Side-by-side scan speed of softplc and peer soft PLCs (bench/peers/README.md).

Each peer runs each workload of gen.py for LOW and HIGH cycles as a whole
process; the per-instruction time is

    (t(HIGH) - t(LOW)) / ((HIGH - LOW) * MELSEC instructions of the workload)

so loading, parsing and compiling cancel. t is the process's user + system
CPU time (so other load on the machine does not count), the minimum over
--repeat runs. A peer whose program or tool is not given is skipped with a
message; nothing is downloaded or built here except the C that matiec
generates from the workload with the driver matiec_main.cpp beside this file,
and the plain C that gen.py writes.

Example (every peer):
    python3 bench/peers/measure.py --softplc target/release/softplc \\
        --awlsim-python /opt/awlsim/bin/python --ironplc /opt/ironplc/bin \\
        --openplc /opt/OpenPLC_v3 --matiec-opt=-O0,-O2 --softplc-exec interp,jit
"""
import argparse
import os
import pathlib
import re
import shutil
import subprocess
import sys
import tempfile
import time

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parents[1]
sys.path.insert(0, str(HERE))
import gen  # noqa: E402


class Skip(Exception):
    """A peer that cannot run here; the message says why."""


def run(cmd, cwd=None, env=None):
    """Runs `cmd`; raises with its output when it fails."""
    done = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(map(str, cmd))} failed ({done.returncode}):\n{done.stdout}{done.stderr}")
    return done.stdout


def cpu_seconds(cmd, env=None):
    """User + system CPU time of one run of `cmd`: unlike wall time, it does
    not count the time other processes on the machine hold the cores."""
    with tempfile.TemporaryFile() as err:
        proc = subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL, stderr=err)
        _, status, usage = os.wait4(proc.pid, 0)
        proc.returncode = os.waitstatus_to_exitcode(status)
        if proc.returncode != 0:
            err.seek(0)
            raise RuntimeError(f"{' '.join(map(str, cmd))} failed ({proc.returncode}):\n{err.read().decode()}")
    return usage.ru_utime + usage.ru_stime


# --- peers: each returns a function cycles -> command for one workload ------


def softplc(args, work, name, exec_mode):
    binary = pathlib.Path(args.softplc)
    if not binary.is_file():
        raise Skip(f"no softplc binary at {binary} (cargo build --release -p softplc)")
    program = work / f"{name}.il"
    extra = []
    if exec_mode:
        if "--exec" not in run([binary, "run", "--help"]):
            raise Skip(f"{binary} has no --exec option (tier {exec_mode})")
        extra = ["--exec", exec_mode]
    run([binary, "check", program])
    show = [a for d in gen.CHECKS.get(name, {}) for a in ("--show", d)]
    return lambda n, check=False: [binary, "run", program, "--scans", str(n), *extra, *(show if check else [])]


def awlsim(args, work, name, cython):
    if not args.awlsim_python:
        raise Skip("no --awlsim-python (a Python with the awlsim package installed)")
    env = dict(os.environ, AWLSIM_CYTHON="2" if cython else "0")
    probe = "import awlsim_loader.core"
    done = subprocess.run([args.awlsim_python, "-c", probe], env=env, capture_output=True, text=True)
    if done.returncode != 0:
        core = "Cython core" if cython else "awlsim"
        raise Skip(f"{core} not importable with {args.awlsim_python}: {done.stderr.strip().splitlines()[-1:]}")
    program = work / f"{name}.awl"
    driver = HERE / "awlsim_run.py"
    # The Cython core keeps its memories from Python: only the pure core reports.
    shown = [] if cython else list(gen.CHECKS.get(name, {}))
    return lambda n, check=False: ([args.awlsim_python, driver, program, str(n), *(shown if check else [])], env)


def ironplc(args, work, name):
    if not args.ironplc:
        raise Skip("no --ironplc (the directory holding ironplcc and ironplcvm)")
    bindir = pathlib.Path(args.ironplc)
    compiler, vm = bindir / "ironplcc", bindir / "ironplcvm"
    for tool in (compiler, vm):
        if not tool.is_file():
            raise Skip(f"no {tool}")
    container = work / f"{name}.iplc"
    run([compiler, "compile", work / f"{name}.st", "--output", container])
    return lambda n, check=False: [vm, "run", container, "--scans", str(n), *(["--dump-vars", "-"] if check else [])]


def matiec(args, work, name, opt):
    """iec2c as OpenPLC's compile_program.sh calls it, then g++ on the
    generated Config0.c and Res0.c (which includes POUS.c) with OpenPLC's
    runtime headers and the driver matiec_main.cpp."""
    if not args.openplc:
        raise Skip("no --openplc (an OpenPLC_v3 tree with utils/matiec_src built)")
    tree = pathlib.Path(args.openplc)
    iec2c = next((p for p in (tree / "webserver" / "iec2c", tree / "utils" / "matiec_src" / "iec2c") if p.is_file()),
                 None)
    lib, include = tree / "utils" / "matiec_src" / "lib", tree / "webserver" / "core" / "lib"
    if iec2c is None or not (lib / "ieclib.txt").is_file() or not (include / "iec_std_lib.h").is_file():
        raise Skip(f"{tree} lacks webserver/iec2c or utils/matiec_src/iec2c, utils/matiec_src/lib/ieclib.txt "
                   "or webserver/core/lib/iec_std_lib.h")
    cxx = shutil.which("g++")
    if not cxx:
        raise Skip("no g++")
    out = work / f"matiec_{name}{opt}"
    out.mkdir(exist_ok=True)
    source, driver, binary = work / f"{name}_matiec.st", HERE / "matiec_main.cpp", out / "plc"
    # g++ -O2 takes minutes on the bits program: a build newer than its
    # inputs (--keep) is reused.
    command = lambda n, check=False: [binary, str(n), *(["show"] if check else [])]  # noqa: E731
    if binary.is_file() and binary.stat().st_mtime > max(source.stat().st_mtime, driver.stat().st_mtime):
        return command
    run([iec2c, "-f", "-l", "-p", "-r", "-R", "-a", "-I", lib, "-T", out, source])
    # OpenPLC passes no -O (so -O0); the row's flag is the one difference.
    (out / "show.h").write_text(matiec_show(name))
    run([cxx, "-std=gnu++11", opt, "-w", "-I", include, "-I", out,
         out / "Config0.c", out / "Res0.c", driver, "-o", binary])
    return command


def matiec_show(name):
    """show.h for matiec_main.cpp: show_values() prints the checked devices
    from the program instance (a variable's value is its `.value`)."""
    checks = gen.CHECKS.get(name, {})
    if not checks:
        return "static void show_values(void) {}\n"
    lines = ['#include "POUS.h"', f"extern {name.upper()}_PROG RES0__INSTANCE0;", "static void show_values(void) {"]
    for device in checks:
        lines.append(f'    printf("{device} = %d\\n", (int)RES0__INSTANCE0.{gen.st_name(device)}.value);')
    return "\n".join(lines + ["}", ""])


def plainc(args, work, name, opt):
    """gen.py's plain C of the workload, compiled with gcc and `opt`."""
    cc = shutil.which(args.cc)
    if not cc:
        raise Skip(f"no {args.cc}")
    source, binary = work / f"{name}.c", work / f"plainc_{name}{opt}"
    if not (binary.is_file() and binary.stat().st_mtime > source.stat().st_mtime):
        run([cc, opt, "-o", binary, source])
    checks = list(gen.CHECKS.get(name, {}))
    return lambda n, check=False: [binary, str(n), *(checks if check else [])]


def peers(args):
    """(label, prepare(work, name) -> cycles -> command)"""
    rows = []
    for mode in args.softplc_exec:
        label = f"softplc ({mode})" if mode else "softplc"
        rows.append((label, lambda w, n, m=mode: softplc(args, w, n, m)))
    rows.append(("awlsim 0.77 Cython core", lambda w, n: awlsim(args, w, n, True)))
    rows.append(("awlsim 0.77 pure Python", lambda w, n: awlsim(args, w, n, False)))
    rows.append(("IronPLC VM", lambda w, n: ironplc(args, w, n)))
    for opt in args.matiec_opt:
        rows.append((f"matiec + g++ {opt}", lambda w, n, o=opt: matiec(args, w, n, o)))
    for opt in args.plainc_opt:
        rows.append((f"plain C + {args.cc} {opt}", lambda w, n, o=opt: plainc(args, w, n, o)))
    return rows


def check(command, name):
    """'ok' when the peer holds gen.CHECKS[name] after gen.CHECK_CYCLES
    cycles; None for a workload without checks. Peers print `NAME = value`
    or `NAME: value` (IronPLC), in MELSEC names or their ST names (C0.CV for
    CN0); a bit is TRUE/true/1."""
    expected = gen.CHECKS.get(name)
    if not expected:
        return None
    cmd = command(gen.CHECK_CYCLES, check=True)
    cmd, env = cmd if isinstance(cmd, tuple) else (cmd, None)
    out = run(cmd, env=env)
    melsec = {gen.st_name(d): d for d in expected} | {d: d for d in expected}
    bits = {"true": 1, "false": 0}
    got = {}
    for key, value in re.findall(r"^(\S+?)\s*[:=]\s*(\S+)\s*$", out, re.M):
        if key in melsec:
            value = value.lower()
            got[melsec[key]] = bits[value] if value in bits else int(value) if re.fullmatch(r"-?\d+", value) else value
    if not got:
        return "not shown"
    if any(got[d] != v for d, v in expected.items() if d in got):
        return f"wrong: {got}"
    # IronPLC's dump shows no function block's fields (a counter's CV).
    missing = [d for d in expected if d not in got]
    return f"ok ({', '.join(missing)} not shown)" if missing else "ok"


def summary(results):
    """The table's values cell: 'ok' when every checked workload was right."""
    shown = {n: r for n, r in results.items() if r is not None}
    if not shown:
        return ""
    if all(r == "not shown" for r in shown.values()):
        return "not shown"
    if all(r.startswith("ok") for r in shown.values()):
        # "ok (CN0, CN999 not shown)" of a workload becomes "tcc: CN0, ...".
        notes = [f"{n}: {r[len('ok ('):-1]}" for n, r in shown.items() if r != "ok"]
        return f"ok ({'; '.join(notes)})" if notes else "ok"
    return "; ".join(f"{n} {r}" for n, r in shown.items())


def measure(command, low, high, repeat):
    """CPU seconds per cycle: min-of-repeat time of HIGH minus that of LOW."""
    def best(n):
        cmd = command(n)
        cmd, env = cmd if isinstance(cmd, tuple) else (cmd, None)
        return min(cpu_seconds(cmd, env) for _ in range(repeat))

    return (best(high) - best(low)) / (high - low)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    default_bin = pathlib.Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target")) / "release" / "softplc"
    p.add_argument("--softplc", default=str(default_bin), help="softplc binary (default: %(default)s)")
    p.add_argument("--softplc-exec", default="", help="comma list of --exec tiers to measure, e.g. interp,jit "
                   "(default: the CLI's default tier)")
    p.add_argument("--awlsim-python", help="Python interpreter with awlsim 0.77 installed")
    p.add_argument("--ironplc", help="directory holding ironplcc and ironplcvm")
    p.add_argument("--openplc", help="OpenPLC_v3 tree with its matiec (utils/matiec_src) built")
    p.add_argument("--matiec-opt", default="-O2", help="comma list of g++ optimisation flags (default: %(default)s; "
                   "OpenPLC itself passes none, i.e. -O0)")
    p.add_argument("--cc", default="gcc", help="C compiler of the plain-C peer (default: %(default)s)")
    p.add_argument("--plainc-opt", default="-O2", help="comma list of its optimisation flags, one row each "
                   "(default: %(default)s; empty: no plain-C row)")
    p.add_argument("--workloads", default=",".join(gen.WORKLOADS), help="comma list (default: %(default)s)")
    p.add_argument("--only", default="", help="comma list of label prefixes to run, e.g. softplc,matiec")
    p.add_argument("--scans", default="10,510", help="LOW,HIGH cycles (default: %(default)s)")
    p.add_argument("--slow-scans", default="10,60", help="LOW,HIGH for awlsim (default: %(default)s)")
    p.add_argument("--repeat", type=int, default=5, help="runs per count; the minimum is kept (default: %(default)s)")
    p.add_argument("--keep", help="write the generated programs and peer builds here (default: a temporary dir)")
    args = p.parse_args()
    args.softplc_exec = args.softplc_exec.split(",") if args.softplc_exec else [""]
    args.matiec_opt = [o for o in args.matiec_opt.split(",") if o]
    args.plainc_opt = [o for o in args.plainc_opt.split(",") if o]
    names = [n for n in args.workloads.split(",") if n]
    for n in names:
        if n not in gen.WORKLOADS:
            p.error(f"unknown workload {n!r} (known: {', '.join(gen.WORKLOADS)})")
    only = [o for o in args.only.split(",") if o]

    work = pathlib.Path(args.keep or tempfile.mkdtemp(prefix="softplc-peers-"))
    gen.write_all(work)
    counts = {n: gen.instructions(n) for n in names}
    table, checks = [], {}
    for label, prepare in peers(args):
        if only and not any(label.startswith(o) for o in only):
            continue
        low, high = map(int, (args.slow_scans if label.startswith("awlsim") else args.scans).split(","))
        cells = []
        for n in names:
            try:
                command = prepare(work, n)
                ns = measure(command, low, high, args.repeat) * 1e9 / counts[n]
                result = check(command, n)
                checks.setdefault(label, {})[n] = result
                if result is not None:
                    print(f"{label} {n} values after {gen.CHECK_CYCLES} cycles: {result}", file=sys.stderr)
                cells.append(f"{ns:,.2f}" if ns < 100 else f"{ns:,.0f}")
                print(f"{label} {n}: {ns:.3f} ns/instruction ({low} vs {high} cycles)", file=sys.stderr)
            except Skip as e:
                print(f"skipped {label}: {e}", file=sys.stderr)
                break
            except RuntimeError as e:
                print(f"{label} {n} failed: {e}", file=sys.stderr)
                cells.append("fails")
        else:
            table.append((label, cells))
    print(f"| peer | {' | '.join(f'{n} ({counts[n]:,})' for n in names)} | values |")
    print(f"|---|{'---:|' * len(names)}---|")
    for label, cells in table:
        print(f"| {label} | {' | '.join(cells)} | {summary(checks.get(label, {}))} |")
    print(f"\nns per MELSEC instruction; programs in {work}")


if __name__ == "__main__":
    main()
