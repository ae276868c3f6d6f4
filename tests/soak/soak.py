"""A soak of `softplc serve` with every door busy at once, for --seconds
(default 60): MC and Modbus TCP clients that connect, read, write and go
away; web-monitor event streams (SSE) opened and dropped, some mid-stream;
OPC UA sessions opened and abandoned (socket dropped without CloseSession)
or closed properly, and one subscription held throughout; a Modbus RTU line
on a socat pty pair that hangs up and comes back every 15 s.

It reports the scan-period overruns, the server's RSS and open descriptors
at the start and the end (and their peaks), and what each client did. The
exit status is 1 when the server died, a kind of client never succeeded,
or the descriptors or RSS grew without bound (more than 64 descriptors or
64 MiB over the start).

    python3 tests/soak/soak.py [--softplc target/debug/softplc] [--seconds 60]

Not part of `.ci/run` by default (`.ci/run --soak` runs it after the
checks). Needs pymcprotocol, pymodbus, asyncua (tests/python/requirements.txt)
and socat.
"""
import argparse
import asyncio
import json
import logging
import os
import pathlib
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
import urllib.request

ROOT = pathlib.Path(__file__).resolve().parents[2]
PROGRAM = ROOT / "tests" / "python" / "serve_test.il"
SCAN_MS = 10


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_port(port, proc, timeout=60.0):
    end = time.time() + timeout
    while time.time() < end:
        if proc.poll() is not None:
            raise RuntimeError("softplc serve exited")
        try:
            socket.create_connection(("127.0.0.1", port), timeout=0.2).close()
            return
        except OSError:
            time.sleep(0.05)
    raise RuntimeError(f"port {port} not open")


def rss_kib(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1])
    return 0


def open_fds(pid):
    return len(os.listdir(f"/proc/{pid}/fd"))


class Counts:
    """Successes and failures per kind of client."""

    def __init__(self):
        self.lock = threading.Lock()
        self.ok = {}
        self.failed = {}

    def add(self, kind, ok=True):
        with self.lock:
            d = self.ok if ok else self.failed
            d[kind] = d.get(kind, 0) + 1


def mc_clients(port, until, counts):
    import pymcprotocol

    while time.time() < until:
        try:
            c = pymcprotocol.Type3E(plctype="Q")
            c.soc_timeout = 2
            c.connect("127.0.0.1", port)
            for _ in range(5):
                c.batchread_wordunits(headdevice="D0", readsize=4)
            c.batchwrite_wordunits(headdevice="D100", values=[int(time.time()) % 1000])
            c.close()
            counts.add("mc")
        except Exception:
            counts.add("mc", False)
            time.sleep(0.1)


def modbus_clients(port, until, counts):
    from pymodbus.client import ModbusTcpClient

    while time.time() < until:
        try:
            c = ModbusTcpClient("127.0.0.1", port=port, timeout=2)
            if not c.connect():
                raise OSError("no connection")
            for _ in range(5):
                if c.read_holding_registers(0, count=4, device_id=1).isError():
                    raise OSError("error reply")
            c.write_register(102, 7, device_id=1)
            c.close()
            counts.add("modbus")
        except Exception:
            counts.add("modbus", False)
            time.sleep(0.1)


def sse_clients(port, until, counts, names):
    """Opens an event stream, reads one event (or drops it at once), closes."""
    n = 0
    while time.time() < until:
        n += 1
        try:
            s = socket.create_connection(("127.0.0.1", port), timeout=3)
            s.sendall(f"GET /api/v1/events?names={names[n % len(names)]} HTTP/1.1\r\n"
                      f"Host: x\r\n\r\n".encode())
            if n % 3:
                got = b""
                while b"\ndata:" not in got and len(got) < 65536:
                    chunk = s.recv(4096)
                    if not chunk:
                        break
                    got += chunk
                if b"data:" not in got:
                    raise OSError("no event")
            s.close()
            counts.add("sse")
        except Exception:
            counts.add("sse", False)
            time.sleep(0.1)


def serial_line(pty_dir, until, counts, socat_holder):
    """Polls the Modbus RTU slave; the line hangs up every 15 s for 2 s."""
    from pymodbus.client import ModbusSerialClient
    from pymodbus.framer import FramerType

    a, b = pty_dir / "plc", pty_dir / "master"
    next_hangup = time.time() + 15
    while time.time() < until:
        if time.time() >= next_hangup:
            p = socat_holder[0]
            p.terminate()
            p.wait(timeout=10)
            counts.add("serial-hangup")
            time.sleep(2)
            socat_holder[0] = start_socat(a, b)
            next_hangup = time.time() + 15
            time.sleep(1)
        try:
            c = ModbusSerialClient(port=str(b), framer=FramerType.RTU, baudrate=9600, timeout=0.5)
            if not c.connect():
                raise OSError("no port")
            r = c.read_holding_registers(0, count=2, device_id=1)
            c.close()
            if r.isError():
                raise OSError("error reply")
            counts.add("serial")
        except Exception:
            counts.add("serial", False)
            time.sleep(0.2)


def opcua_clients(url, until, counts):
    from asyncua import Client, ua

    async def one(n):
        c = Client(url, timeout=4)
        await c.connect()
        ns = await c.get_namespace_index("urn:softplc")
        await c.get_node(ua.NodeId("D0", ns)).read_value()
        if n % 2:
            # Abandoned: the socket goes, the session stays behind.
            for task in (c._monitor_server_task, c._renew_channel_task):
                if task is not None:
                    task.cancel()
            c.disconnect_socket()
            counts.add("opcua-abandoned")
        else:
            await c.disconnect()
            counts.add("opcua-closed")

    async def subscriber(changes):
        c = Client(url, timeout=4)
        await c.connect()
        ns = await c.get_namespace_index("urn:softplc")

        class Handler:
            def datachange_notification(self, node, val, data):
                changes[0] += 1

        sub = await c.create_subscription(50, Handler())
        await sub.subscribe_data_change(c.get_node(ua.NodeId("D0", ns)))
        while time.time() < until:
            await asyncio.sleep(0.5)
        await c.disconnect()

    async def main():
        changes = [0]
        sub = asyncio.create_task(subscriber(changes))
        n = 0
        while time.time() < until:
            n += 1
            try:
                await one(n)
            except Exception:
                counts.add("opcua", False)
                await asyncio.sleep(0.2)
            await asyncio.sleep(0.05)
        try:
            await sub
            counts.ok["opcua-subscription-changes"] = changes[0]
        except Exception:
            counts.add("opcua-subscription", False)

    asyncio.run(main())


def start_socat(a, b):
    p = subprocess.Popen(["socat", f"pty,raw,echo=0,link={a}", f"pty,raw,echo=0,link={b}"],
                         stderr=subprocess.DEVNULL)
    for _ in range(100):
        if a.exists() and b.exists():
            return p
        time.sleep(0.05)
    raise RuntimeError("socat made no pty pair")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--softplc", default=os.environ.get("SOFTPLC", str(ROOT / "target" / "debug" / "softplc")))
    ap.add_argument("--seconds", type=float, default=60.0)
    args = ap.parse_args()
    # asyncua warns about every revised session timeout.
    logging.getLogger("asyncua").setLevel(logging.ERROR)
    if shutil.which("socat") is None:
        print("soak: socat is not installed", file=sys.stderr)
        return 2

    tmp = pathlib.Path(tempfile.mkdtemp(prefix="softplc-soak-"))
    socat = [start_socat(tmp / "plc", tmp / "master")]
    ports = {k: free_port() for k in ("mc", "modbus", "http", "opcua")}
    log = open(tmp / "stderr", "wb")
    cmd = [args.softplc, "serve", str(PROGRAM), "--scan-time", f"{SCAN_MS}ms",
           "--mc", f"127.0.0.1:{ports['mc']}", "--modbus", f"127.0.0.1:{ports['modbus']}",
           "--http", f"127.0.0.1:{ports['http']}", "--opcua", f"127.0.0.1:{ports['opcua']}",
           "--opcua-pki", str(tmp / "pki"), "--modbus-rtu", str(tmp / "plc"),
           "--stats-every", "10s"]
    proc = subprocess.Popen(cmd, stderr=log)
    try:
        for p in ports.values():
            wait_port(p, proc)
        # The OPC UA server makes its certificate on first start.
        time.sleep(3)
        start = (rss_kib(proc.pid), open_fds(proc.pid))
        peak = list(start)
        counts = Counts()
        until = time.time() + args.seconds
        names = ["D0", "D100", "D101", "M10", "M11", "Y0", "X0", "D0,D100"]
        workers = [
            threading.Thread(target=mc_clients, args=(ports["mc"], until, counts)),
            threading.Thread(target=mc_clients, args=(ports["mc"], until, counts)),
            threading.Thread(target=modbus_clients, args=(ports["modbus"], until, counts)),
            threading.Thread(target=modbus_clients, args=(ports["modbus"], until, counts)),
            threading.Thread(target=sse_clients, args=(ports["http"], until, counts, names)),
            threading.Thread(target=sse_clients, args=(ports["http"], until, counts, names)),
            threading.Thread(target=serial_line, args=(tmp, until, counts, socat)),
            threading.Thread(target=opcua_clients,
                             args=(f"opc.tcp://127.0.0.1:{ports['opcua']}/", until, counts)),
        ]
        for w in workers:
            w.start()
        while any(w.is_alive() for w in workers):
            time.sleep(1)
            if proc.poll() is not None:
                break
            peak[0] = max(peak[0], rss_kib(proc.pid))
            peak[1] = max(peak[1], open_fds(proc.pid))
        for w in workers:
            w.join(timeout=30)
        alive = proc.poll() is None
        end = (rss_kib(proc.pid), open_fds(proc.pid)) if alive else (0, 0)
        status = {}
        if alive:
            with urllib.request.urlopen(f"http://127.0.0.1:{ports['http']}/api/v1/status", timeout=5) as r:
                status = json.load(r)
    finally:
        if proc.poll() is None:
            proc.send_signal(signal.SIGTERM)
            try:
                proc.wait(timeout=15)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait()
        for p in socat:
            p.terminate()
        log.close()
    text = (tmp / "stderr").read_text(errors="replace")
    final = re.search(r"stopped after (\d+) scans; max scan (\d+) us, (\d+) overruns, (\d+) requests", text)
    print(f"soak: {args.seconds:.0f} s, constant scan {SCAN_MS} ms, server log {tmp / 'stderr'}")
    if final:
        scans, max_us, overruns, requests = map(int, final.groups())
        print(f"  scans {scans}, max scan {max_us} us, overruns {overruns}, requests {requests}")
    else:
        print("  no final statistics line (the server did not stop cleanly)")
    print(f"  RSS: start {start[0] / 1024:.1f} MiB, end {end[0] / 1024:.1f} MiB, peak {peak[0] / 1024:.1f} MiB")
    print(f"  descriptors: start {start[1]}, end {end[1]}, peak {peak[1]}")
    if status:
        print(f"  web monitor status: watched {status.get('watched')}, overruns {status.get('overruns')}")
    for kind in sorted(set(counts.ok) | set(counts.failed)):
        print(f"  {kind}: {counts.ok.get(kind, 0)} ok, {counts.failed.get(kind, 0)} failed")
    print(f"  serial: {text.count('hung up')} hang-ups reported, {text.count('reopened')} reopened")
    bad = []
    if not alive:
        bad.append("the server died")
    for kind in ("mc", "modbus", "sse", "serial", "opcua-abandoned", "opcua-closed"):
        if counts.ok.get(kind, 0) == 0:
            bad.append(f"no {kind} client succeeded")
    if alive and end[1] > start[1] + 64:
        bad.append(f"descriptors grew from {start[1]} to {end[1]}")
    if alive and end[0] > start[0] + 64 * 1024:
        bad.append(f"RSS grew from {start[0]} KiB to {end[0]} KiB")
    for b in bad:
        print(f"soak: FAIL: {b}", file=sys.stderr)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
