#!/usr/bin/env python3
"""Real-time jitter of `softplc serve`: how late each scan starts against its
constant-scan deadline, at 1 ms and 10 ms, idle and under load.

Each run writes a small project (plc.toml with `[ras] constant_scan`, one
program), starts `softplc serve` on it with the web monitor, optionally starts
load (protocol clients on MC, Modbus TCP, HTTP event stream and OPC UA, and/or
a busy process per core), lets it settle, resets the server's timing figures
(`POST /api/v1/timing/reset`), waits `--seconds`, reads them
(`GET /api/v1/timing`) and stops everything. It prints one Markdown table row
per period x load x variant. It builds nothing: give the binary with
`--softplc` (a release build for figures worth keeping).

    python3 bench/jitter/run.py --softplc target/release/softplc
    python3 bench/jitter/run.py --softplc target/release/softplc --seconds 10 \\
        --periods 1ms --loads idle --variants fifo,realtime-pin

All traffic stays on 127.0.0.1 and every loop ends by itself at its deadline.
"""
import argparse
import asyncio
import http.client
import json
import multiprocessing as mp
import os
import pathlib
import signal
import socket
import subprocess
import sys
import tempfile
import time

TOKEN = "jitter"

# The server's options for each variant; {last_cpu} is the highest CPU this
# process may run on (the load's busy processes run on every CPU anyway).
VARIANTS = {
    "normal": ["--no-realtime"],
    "normal-sleep": ["--no-realtime", "--spin-us", "0"],
    "fifo": [],
    "fifo-sleep": ["--spin-us", "0"],
    "realtime": ["--realtime"],
    "realtime-pin": ["--realtime", "--cpu", "{last_cpu}"],
}
LOADS = ["idle", "clients", "cpu", "clients+cpu"]

# A small program: a scan counter, copies and compares over 100 words the
# clients read, an output.
PROGRAM = """\
LD SM400
INC D0
MOV D0 D1
BMOV D0 D2 K98
LD> D0 K1000
OUT M0
LD X0
OR M0
OUT Y0
END
"""


def plc_toml(period):
    return f"""\
[cpu]
model = "Q06HCPU"

[ras]
constant_scan = "{period}"

[[program]]
file = "main.il"
"""


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_port(port, proc, timeout=60.0):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if proc.poll() is not None:
            raise RuntimeError("softplc serve exited: " + proc.stderr.read().decode(errors="replace"))
        try:
            socket.create_connection(("127.0.0.1", port), timeout=0.2).close()
            return
        except OSError:
            time.sleep(0.05)
    raise RuntimeError(f"port {port} did not open in {timeout} s")


def request(port, method, path, token=None):
    c = http.client.HTTPConnection("127.0.0.1", port, timeout=15)
    headers = {"Authorization": f"Bearer {token}"} if token else {}
    c.request(method, path, headers=headers)
    r = c.getresponse()
    body = r.read()
    c.close()
    if r.status != 200:
        raise RuntimeError(f"{method} {path}: {r.status} {body[:200]!r}")
    return json.loads(body)


def last_cpu():
    cpus = os.sched_getaffinity(0) if hasattr(os, "sched_getaffinity") else range(os.cpu_count() or 1)
    return max(cpus)


# --- load: each client runs in its own process until `deadline` (monotonic)
# or `stop`; it puts its name on `ready` once connected (or failed) and
# (label, operations, error) on `out` at the end.

def client(name, label, session, port, deadline, stop, ready, out):
    """Runs `session(port, connected, running, tick)`: it calls `connected()`
    once it is connected, works while `running()` and calls `tick()` per
    operation. Reports as the comment above says."""
    told, n = False, 0

    def connected():
        nonlocal told
        told = True
        ready.put(name)

    def running():
        return not stop.is_set() and time.monotonic() < deadline

    def tick():
        nonlocal n
        n += 1

    err = None
    try:
        session(port, connected, running, tick)
    except Exception as e:  # reported with the run
        err = repr(e)
    if not told:
        ready.put(name)
    out.put((label, n, err))


def mc_session(port, connected, running, tick):
    import pymcprotocol
    c = pymcprotocol.Type3E(plctype="Q")
    c.connect("127.0.0.1", port)
    connected()
    while running():
        c.batchread_wordunits(headdevice="D0", readsize=100)
        tick()
    c.close()


def modbus_session(port, connected, running, tick):
    from pymodbus.client import ModbusTcpClient
    c = ModbusTcpClient("127.0.0.1", port=port)
    if not c.connect():
        raise RuntimeError("no connection")
    connected()
    while running():
        r = c.read_holding_registers(0, count=100)
        if r.isError():
            raise RuntimeError(str(r))
        tick()
    c.close()


def sse_session(port, connected, running, tick):
    c = http.client.HTTPConnection("127.0.0.1", port, timeout=5)
    c.request("GET", "/api/v1/events?names=" + ",".join(f"D{i}" for i in range(20)))
    r = c.getresponse()
    if r.status != 200:
        raise RuntimeError(f"events: {r.status}")
    connected()
    while running():
        line = r.fp.readline()
        if not line:
            break
        if line.startswith(b"data:"):
            tick()
    c.close()


def opcua_session(port, connected, running, tick):
    class Count:
        def datachange_notification(self, node, val, data):
            tick()

    async def go():
        from asyncua import Client, ua
        c = None
        while running():
            c = Client(f"opc.tcp://127.0.0.1:{port}/", timeout=4)
            try:
                await c.connect()
                break
            except Exception:
                c = None
                await asyncio.sleep(0.2)
        if c is None:
            raise RuntimeError("no OPC UA session")
        try:
            ns = await c.get_namespace_index("urn:softplc")
            nodes = [c.get_node(ua.NodeId(f"D{i}", ns)) for i in range(10)]
            sub = await c.create_subscription(50, Count())
            await sub.subscribe_data_change(nodes, queuesize=100, sampling_interval=0)
            connected()
            while running():
                await asyncio.sleep(0.1)
            await sub.delete()
        finally:
            await c.disconnect()

    asyncio.run(go())


# (name on `ready`, label in the report, session, the port it uses)
CLIENTS = [
    ("MC", "MC", mc_session, "mc"),
    ("Modbus", "Modbus", modbus_session, "modbus"),
    ("SSE", "SSE events", sse_session, "http"),
    ("OPC UA", "OPC UA notifications", opcua_session, "opcua"),
]


def busy_worker(deadline, stop, ready, out):
    n = 0
    ready.put("busy")
    while not stop.is_set() and time.monotonic() < deadline:
        for _ in range(10000):
            n += 1
    out.put(("busy", n, None))


class Load:
    """The load of one run: started before the warm-up, stopped after."""

    def __init__(self, kind, ports, deadline):
        ctx = mp.get_context("spawn")
        self.stop = ctx.Event()
        self.ready = ctx.Queue()
        self.out = ctx.Queue()
        self.procs = []
        parts = set(kind.split("+")) - {"idle"}
        if "clients" in parts:
            for name, label, session, port in CLIENTS:
                args = (name, label, session, ports[port], deadline, self.stop, self.ready, self.out)
                self.procs.append(ctx.Process(target=client, args=args))
        if "cpu" in parts:
            for _ in range(os.cpu_count() or 1):
                self.procs.append(ctx.Process(target=busy_worker, args=(deadline, self.stop, self.ready, self.out)))
        for p in self.procs:
            p.start()

    def wait_ready(self, timeout=120):
        """Waits until every worker is connected (or has failed)."""
        end = time.monotonic() + timeout
        for _ in self.procs:
            self.ready.get(timeout=max(0.1, end - time.monotonic()))

    def finish(self, seconds):
        """Stops the workers; returns {name: operations per second} and errors."""
        self.stop.set()
        rates, errors = {}, []
        for _ in self.procs:
            try:
                name, n, err = self.out.get(timeout=20)
            except Exception:
                errors.append("a load process did not report")
                continue
            if name != "busy":
                rates[name] = round(n / seconds)
            if err:
                errors.append(f"{name}: {err}")
        for p in self.procs:
            p.join(timeout=10)
            if p.is_alive():
                p.kill()
        return rates, errors


def stop_serve(proc):
    proc.send_signal(signal.SIGTERM)
    try:
        proc.wait(timeout=15)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()


def one_run(args, period, load, variant, work):
    project = work / f"{period}-{load}-{variant}"
    project.mkdir(parents=True)
    (project / "plc.toml").write_text(plc_toml(period))
    (project / "main.il").write_text(PROGRAM)
    ports = {"http": free_port()}
    extra = [a.format(last_cpu=last_cpu()) for a in VARIANTS[variant]]
    cmd = [args.softplc, "serve", str(project), "--http", f"127.0.0.1:{ports['http']}",
           "--http-token", TOKEN, *extra]
    if "clients" in load:
        ports.update(mc=free_port(), modbus=free_port(), opcua=free_port())
        cmd += ["--mc", f"127.0.0.1:{ports['mc']}", "--modbus", f"127.0.0.1:{ports['modbus']}",
                "--opcua", f"127.0.0.1:{ports['opcua']}", "--opcua-pki", str(project / "pki")]
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    loadrun = None
    try:
        for port in ports.values():
            wait_port(port, proc)
        loadrun = Load(load, ports, time.monotonic() + args.warmup + args.seconds + 180)
        loadrun.wait_ready()
        time.sleep(args.warmup)
        request(ports["http"], "POST", "/api/v1/timing/reset", TOKEN)
        time.sleep(args.seconds)
        t = request(ports["http"], "GET", "/api/v1/timing")
        rates, errors = loadrun.finish(args.seconds)
        loadrun = None
    finally:
        if loadrun is not None:
            loadrun.finish(args.seconds)
        stop_serve(proc)
    return {"period": period, "load": load, "variant": variant, "options": " ".join(extra),
            "timing": t, "load_rates": rates, "errors": errors}


def row(r):
    t = r["timing"]
    late, pj, ex = t["lateness_us"], t["period_jitter_us"], t["scan_time_us"]
    rt = t["realtime"]
    got = ", ".join(x for x in [
        "FIFO" if rt["sched_fifo"] else "normal",
        "locked" if rt["memory_locked"] else None,
        f"CPU {rt['cpu']}" if rt["cpu"] is not None else None,
        f"spin {rt['spin_us']}",
    ] if x)
    rates = ", ".join(f"{k} {v}/s" for k, v in r["load_rates"].items())
    return (f"| {r['period']} | {r['load']}{' (' + rates + ')' if rates else ''} | {r['variant']} ({got}) "
            f"| {t['count']} | {t['overruns']} | {late['p50']} | {late['p99']} | {late['p999']} | {late['max']} "
            f"| {pj['p99']} | {pj['max']} | {ex['p50']} / {ex['max']} |")


HEADER = ("| period | load | variant (got) | scans | overruns | lateness p50 µs | p99 | p99.9 | max "
          "| period jitter p99 µs | max | scan time p50 / max µs |\n"
          "|---|---|---|---|---|---|---|---|---|---|---|---|")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--softplc", required=True, help="the softplc binary (e.g. target/release/softplc)")
    ap.add_argument("--seconds", type=float, default=60, help="measured time per run (default 60)")
    ap.add_argument("--warmup", type=float, default=2, help="time before the figures are reset (default 2)")
    ap.add_argument("--periods", default="1ms,10ms", help="constant scans (default 1ms,10ms)")
    ap.add_argument("--loads", default="idle,clients,cpu",
                    help=f"comma-separated, of {', '.join(LOADS)} (default idle,clients,cpu)")
    ap.add_argument("--variants", default="normal,fifo,realtime-pin",
                    help=f"comma-separated, of {', '.join(VARIANTS)} (default normal,fifo,realtime-pin)")
    ap.add_argument("--json", help="also write every run's figures to this file")
    args = ap.parse_args()
    periods = [p.strip() for p in args.periods.split(",") if p.strip()]
    loads = [x.strip() for x in args.loads.split(",") if x.strip()]
    variants = [v.strip() for v in args.variants.split(",") if v.strip()]
    for x in loads:
        if x not in LOADS:
            ap.error(f"--loads: {x!r} is not one of {', '.join(LOADS)}")
    for v in variants:
        if v not in VARIANTS:
            ap.error(f"--variants: {v!r} is not one of {', '.join(VARIANTS)}")
    if not os.access(args.softplc, os.X_OK):
        ap.error(f"--softplc {args.softplc}: not an executable file (build it: cargo build --release -p softplc)")
    runs = [(p, x, v) for p in periods for x in loads for v in variants]
    print(f"{len(runs)} runs of {args.seconds:g} s (+{args.warmup:g} s warm-up each); "
          f"{os.cpu_count()} CPUs; {os.uname().release}", file=sys.stderr)
    results = []
    with tempfile.TemporaryDirectory(prefix="softplc-jitter-") as work:
        for i, (p, x, v) in enumerate(runs, 1):
            print(f"[{i}/{len(runs)}] {p} {x} {v}", file=sys.stderr, flush=True)
            r = one_run(args, p, x, v, pathlib.Path(work))
            results.append(r)
            for e in r["errors"]:
                print(f"  load error: {e}", file=sys.stderr)
    print(HEADER)
    for r in results:
        print(row(r))
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps(results, indent=1) + "\n")


if __name__ == "__main__":
    main()
