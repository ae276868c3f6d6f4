"""`softplc serve --mqtt` against a real broker (Debian's mosquitto, started
here) with a real client (paho-mqtt): retained values at the END they
change with their scan, `$state` online and `offline` as the last will,
writes from PREFIX/set/DEV only with --mqtt-write, bad writes logged and
ignored, and a broker that is down never stalls the scan."""
import json
import os
import shutil
import signal
import subprocess
import time
import urllib.request

import paho.mqtt.client as mqtt
import pytest

from conftest import BINARY, HERE, free_port, stop, wait_port

MOSQUITTO = shutil.which("mosquitto") or (
    "/usr/sbin/mosquitto" if shutil.os.path.exists("/usr/sbin/mosquitto") else None
)
pytestmark = pytest.mark.skipif(MOSQUITTO is None, reason="mosquitto is not installed")
TOKEN = "mqtt-test-token"


def start_broker(port, tmp_path):
    conf = tmp_path / f"mosquitto-{port}.conf"
    conf.write_text(f"listener {port} 127.0.0.1\nallow_anonymous true\npersistence false\n")
    proc = subprocess.Popen([MOSQUITTO, "-c", str(conf)], stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    wait_port(port, proc)
    return proc


@pytest.fixture
def broker(tmp_path):
    port = free_port()
    proc = start_broker(port, tmp_path)
    yield port
    proc.terminate()
    proc.wait(timeout=10)


class Subscriber:
    """Collects every message under a topic filter, retained ones included."""

    def __init__(self, port, topic):
        self.messages = []
        self.client = mqtt.Client(mqtt.CallbackAPIVersion.VERSION2)
        self.client.on_message = lambda c, u, m: self.messages.append(
            (m.topic, m.payload.decode(), m.retain))
        self.client.connect("127.0.0.1", port)
        self.client.subscribe(topic, qos=1)
        self.client.loop_start()

    def wait(self, pred, timeout=10.0):
        end = time.time() + timeout
        while time.time() < end:
            for m in list(self.messages):
                if pred(m):
                    return m
            time.sleep(0.02)
        raise AssertionError(f"no such message; got {self.messages[-20:]}")

    def close(self):
        self.client.loop_stop()
        self.client.disconnect()


def serve(mqtt_port, *extra, http=None):
    http = http or free_port()
    cmd = [BINARY, "serve", str(HERE / "serve_test.il"), "--scan-time", "10ms", "--no-realtime",
           "--http", f"127.0.0.1:{http}", "--http-token", TOKEN,
           "--mqtt", f"mqtt://127.0.0.1:{mqtt_port}", "--mqtt-topic", "plant/line1", *extra]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    wait_port(http, proc)
    return proc, http


def http(port, method, path, body=None):
    req = urllib.request.Request(f"http://127.0.0.1:{port}{path}", method=method,
                                 data=None if body is None else json.dumps(body).encode(),
                                 headers={"Authorization": f"Bearer {TOKEN}",
                                          "Content-Type": "application/json"})
    with urllib.request.urlopen(req, timeout=5) as r:
        return json.loads(r.read())


def payload(m):
    return json.loads(m[1])


def test_changes_are_published_retained_with_their_scan_and_state(broker):
    proc, hp = serve(broker, "--mqtt-publish", "D101,M11,Y0")
    sub = Subscriber(broker, "plant/line1/#")
    try:
        sub.wait(lambda m: m[0] == "plant/line1/$state" and m[1] == "online")
        first = sub.wait(lambda m: m[0] == "plant/line1/D101")
        assert payload(first)["value"] == 0
        # A write over HTTP shows up at the END it took effect.
        wrote = http(hp, "POST", "/api/v1/devices", {"D100": 1234, "M10": True})
        m = sub.wait(lambda m: m[0] == "plant/line1/D101" and payload(m)["value"] == 1234)
        assert payload(m)["scan"] >= wrote["scan"]
        assert sub.wait(lambda m: m[0] == "plant/line1/M11")[1]
        assert payload(sub.wait(lambda m: m[0] == "plant/line1/M11" and payload(m)["value"]))["value"] is True
        # Unchanged values are not sent again: D101 only at connect and at the change.
        time.sleep(0.5)
        assert len([m for m in sub.messages if m[0] == "plant/line1/D101"]) == 2
        # Without --mqtt-write the set topic is ignored.
        sub.client.publish("plant/line1/set/D100", json.dumps({"value": 5}), qos=1)
        time.sleep(0.5)
        assert http(hp, "GET", "/api/v1/devices?names=D100")["devices"]["D100"] == 1234
    finally:
        sub.close()
    # A late subscriber gets the retained latest values at once.
    late = Subscriber(broker, "plant/line1/D101")
    try:
        m = late.wait(lambda m: True)
        assert m[2] is True and payload(m)["value"] == 1234
    finally:
        late.close()
    # Killed: the broker publishes the last will.
    watch = Subscriber(broker, "plant/line1/$state")
    try:
        watch.wait(lambda m: m[1] == "online")
        proc.send_signal(signal.SIGKILL)
        proc.wait(timeout=10)
        watch.wait(lambda m: m[1] == "offline")
    finally:
        watch.close()


def test_writes_from_the_set_topic_and_bad_ones_logged_and_ignored(broker):
    proc, hp = serve(broker, "--mqtt-publish", "D101", "--mqtt-write")
    sub = Subscriber(broker, "plant/line1/#")
    try:
        sub.wait(lambda m: m[0] == "plant/line1/$state" and m[1] == "online")
        for topic, body in [("plant/line1/set/QQ9", '{"value": 1}'),
                            ("plant/line1/set/D100", "not json"),
                            ("plant/line1/set/D100", '{"value": 99999}'),
                            ("plant/line1/set/D100", '{"val": 1}')]:
            sub.client.publish(topic, body, qos=1)
        sub.client.publish("plant/line1/set/D100", json.dumps({"value": -7}), qos=1)
        sub.client.publish("plant/line1/set/M10", json.dumps({"value": True}), qos=1)
        sub.wait(lambda m: m[0] == "plant/line1/D101" and payload(m)["value"] == -7)
        got = http(hp, "GET", "/api/v1/devices?names=D100,M11")["devices"]
        assert got == {"D100": -7, "M11": True}
    finally:
        sub.close()
        stop(proc)
    err = proc.stderr.read().decode()
    assert "--mqtt-write: plant/line1/set/QQ9" in err, err


def test_a_broker_that_is_down_never_stalls_the_scan_and_is_reconnected(tmp_path):
    port = free_port()
    proc, hp = serve(port, "--mqtt-publish", "D0")
    try:
        s1 = http(hp, "GET", "/api/v1/status")["scan"]
        time.sleep(1.0)
        s2 = http(hp, "GET", "/api/v1/status")["scan"]
        # 10 ms scans: about 100 in a second, broker or not.
        assert s2 - s1 >= 50, (s1, s2)
        b = start_broker(port, tmp_path)
        try:
            sub = Subscriber(port, "plant/line1/#")
            try:
                sub.wait(lambda m: m[0] == "plant/line1/$state" and m[1] == "online", timeout=15)
                m = sub.wait(lambda m: m[0] == "plant/line1/D0", timeout=5)
                assert payload(m)["value"] > 0
            finally:
                sub.close()
        finally:
            b.terminate()
            b.wait(timeout=10)
        # The broker went away again: the CPU keeps scanning.
        s3 = http(hp, "GET", "/api/v1/status")["scan"]
        time.sleep(1.0)
        assert http(hp, "GET", "/api/v1/status")["scan"] - s3 >= 50
    finally:
        stop(proc)


def test_bad_options_are_refused_naming_them(broker):
    for extra, why in [
        (["--mqtt-publish", "QQ9"], "--mqtt-publish"),
        (["--mqtt-publish", "D0", "--mqtt-topic", "a/#"], "--mqtt-topic"),
        ([], "--mqtt-publish DEV"),
    ]:
        r = subprocess.run([BINARY, "serve", str(HERE / "serve_test.il"), "--no-realtime",
                            "--mqtt", f"mqtt://127.0.0.1:{broker}", *extra],
                           capture_output=True, text=True, timeout=30)
        assert r.returncode != 0 and why in r.stderr, (extra, r.stderr)
    r = subprocess.run([BINARY, "serve", str(HERE / "serve_test.il"), "--mqtt", "http://x"],
                       capture_output=True, text=True, timeout=30)
    assert r.returncode != 0 and "scheme `http`" in r.stderr, r.stderr


def test_the_compose_example_serves_and_publishes(broker):
    """examples/mqtt/compose.yaml's softplc command, run here against this
    test's broker (the image's /usr/share/softplc/examples is examples/)."""
    import yaml
    from conftest import ROOT

    compose = yaml.safe_load((ROOT / "examples" / "mqtt" / "compose.yaml").read_text())
    cmd = [str(a) for a in compose["services"]["plc"]["command"]]
    hp = free_port()
    args = []
    for a in cmd:
        a = a.replace("/usr/share/softplc/examples", str(ROOT / "examples"))
        a = a.replace("mqtt://broker:1883", f"mqtt://127.0.0.1:{broker}")
        a = a.replace("0.0.0.0:8080", f"127.0.0.1:{hp}")
        args.append(a)
    topic = args[args.index("--mqtt-topic") + 1]
    sub = Subscriber(broker, f"{topic}/#")
    proc = subprocess.Popen([BINARY, *args, "--no-realtime"], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE)
    try:
        wait_port(hp, proc)
        sub.wait(lambda m: m[0] == f"{topic}/$state" and m[1] == "online")
        for dev in args[args.index("--mqtt-publish") + 1].split(","):
            sub.wait(lambda m, d=dev: m[0] == f"{topic}/{d}")
    finally:
        sub.close()
        stop(proc)


def make_certs(d):
    """A CA and a certificate for localhost/127.0.0.1 signed by it (openssl)."""
    def ssl(*a):
        subprocess.run(["openssl", *a], check=True, capture_output=True)
    ssl("req", "-x509", "-newkey", "rsa:2048", "-nodes", "-keyout", d / "ca.key", "-out",
        d / "ca.pem", "-days", "2", "-subj", "/CN=softplc test CA")
    ssl("req", "-newkey", "rsa:2048", "-nodes", "-keyout", d / "server.key", "-out",
        d / "server.csr", "-subj", "/CN=localhost")
    (d / "ext.cnf").write_text("subjectAltName=DNS:localhost,IP:127.0.0.1\n")
    ssl("x509", "-req", "-in", d / "server.csr", "-CA", d / "ca.pem", "-CAkey", d / "ca.key",
        "-CAcreateserial", "-out", d / "server.pem", "-days", "2", "-extfile", d / "ext.cnf")


@pytest.mark.skipif(shutil.which("openssl") is None, reason="openssl is not installed")
def test_mqtts_with_the_brokers_ca_and_a_refused_certificate_without_it(tmp_path):
    make_certs(tmp_path)
    port = free_port()
    conf = tmp_path / "tls.conf"
    # Started as root (CI), mosquitto switches to its own user, which cannot
    # read the test's private directory: `user root` keeps it root.
    user = "user root\n" if os.geteuid() == 0 else ""
    conf.write_text(f"listener {port} 127.0.0.1\nallow_anonymous true\npersistence false\n{user}"
                    f"cafile {tmp_path / 'ca.pem'}\ncertfile {tmp_path / 'server.pem'}\n"
                    f"keyfile {tmp_path / 'server.key'}\n")
    b = subprocess.Popen([MOSQUITTO, "-c", str(conf)], stdout=subprocess.DEVNULL,
                         stderr=subprocess.DEVNULL)
    try:
        wait_port(port, b)
        seen = []
        c = mqtt.Client(mqtt.CallbackAPIVersion.VERSION2)
        c.tls_set(ca_certs=str(tmp_path / "ca.pem"))
        c.on_message = lambda c, u, m: seen.append((m.topic, m.payload.decode()))
        c.connect("localhost", port)
        c.subscribe("secure/#", qos=1)
        c.loop_start()
        hp = free_port()
        base = [BINARY, "serve", str(HERE / "serve_test.il"), "--no-realtime", "--http",
                f"127.0.0.1:{hp}", "--mqtt", f"mqtts://localhost:{port}", "--mqtt-topic",
                "secure", "--mqtt-publish", "D101"]
        proc = subprocess.Popen([*base, "--mqtt-ca", str(tmp_path / "ca.pem")],
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        try:
            wait_port(hp, proc)
            end = time.time() + 10
            while ("secure/$state", "online") not in seen and time.time() < end:
                time.sleep(0.05)
            assert ("secure/$state", "online") in seen, seen
        finally:
            stop(proc)
        c.loop_stop()
        # Without the CA the broker's certificate is refused, and said so.
        hp = free_port()
        base[base.index("--http") + 1] = f"127.0.0.1:{hp}"
        proc = subprocess.Popen(base, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        try:
            wait_port(hp, proc)
            time.sleep(1.0)
        finally:
            stop(proc)
        err = proc.stderr.read().decode()
        assert "invalid peer certificate" in err, err
    finally:
        b.terminate()
        b.wait(timeout=10)
