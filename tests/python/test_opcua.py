"""asyncua (an independent OPC UA client) against `softplc serve --opcua`
(contract §3.2): browse, read, write at END, subscriptions to a device and
to a loop field, and the status codes of bad requests."""
import asyncio
import subprocess

import pytest
from asyncua import Client, ua

from conftest import BINARY, HERE, free_port, stop, wait_port

pytestmark = pytest.mark.filterwarnings("ignore::DeprecationWarning")


@pytest.fixture
def opcua(tmp_path):
    """`softplc serve opcua_test.il --opcua` on a free loopback port; yields
    its endpoint URL."""
    port = free_port()
    cmd = [BINARY, "serve", str(HERE / "opcua_test.il"), "--scan-time", "10ms",
           "--opcua", f"127.0.0.1:{port}", "--opcua-pki", str(tmp_path / "pki")]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    wait_port(port, proc)
    yield f"opc.tcp://127.0.0.1:{port}/"
    stop(proc)


async def connect(url):
    """A connected client; the server may still be making its certificate."""
    for _ in range(100):
        c = Client(url, timeout=4)
        try:
            await c.connect()
            return c
        except (OSError, asyncio.TimeoutError, ua.UaError):
            await asyncio.sleep(0.2)
    raise RuntimeError(f"no session on {url}")


async def node(c, name):
    ns = await c.get_namespace_index("urn:softplc")
    return c.get_node(ua.NodeId(name, ns))


async def names(n):
    """The browse names of `n`'s children, sorted."""
    return sorted([(await k.read_browse_name()).Name for k in await n.get_children()])


async def wait_value(n, want, timeout=5.0):
    end = asyncio.get_running_loop().time() + timeout
    while True:
        v = await n.read_value()
        if v == want or asyncio.get_running_loop().time() > end:
            return v
        await asyncio.sleep(0.02)


def test_browse_and_read(opcua):
    async def go():
        c = await connect(opcua)
        try:
            ns = await c.get_namespace_index("urn:softplc")
            root = await c.nodes.objects.get_child([f"{ns}:softplc"])
            assert await names(root) == ["Devices", "Diagnostics", "Loops"]
            devices = await names(await root.get_child([f"{ns}:Devices"]))
            for want in ["D0", "D100", "D101", "D200:i32", "D300:f32", "X0", "Y0"]:
                assert want in devices, devices
            loop = await root.get_child([f"{ns}:Loops", f"{ns}:PIDCONT D600 loop 1"])
            assert await names(loop) == ["ALARM", "MODE", "MV", "MVMAN", "PV", "SV"]
            # Types of contract §3.2.
            assert await (await node(c, "D0")).read_data_type_as_variant_type() == ua.VariantType.Int16
            assert await (await node(c, "Y0")).read_data_type_as_variant_type() == ua.VariantType.Boolean
            assert await (await node(c, "D200:i32")).read_data_type_as_variant_type() == ua.VariantType.Int32
            assert await (await node(c, "D300:f32")).read_data_type_as_variant_type() == ua.VariantType.Float
            diag = await root.get_child([f"{ns}:Diagnostics"])
            state = await (await diag.get_child([f"{ns}:State"])).read_value()
            assert state == "RUN"
            scan1 = await (await diag.get_child([f"{ns}:Scan"])).read_value()
            await asyncio.sleep(0.2)
            # D0 counts executed scans (Int16, wraps at 32767).
            d0 = await (await node(c, "D0")).read_value()
            scan2 = await (await diag.get_child([f"{ns}:Scan"])).read_value()
            # 10 ms scans: about 20 more in 0.2 s.
            assert scan2 > scan1 + 5, (scan1, scan2)
            assert scan1 < d0 <= scan2, (scan1, d0, scan2)
            with pytest.raises(ua.uaerrors.BadNodeIdUnknown):
                await (await node(c, "D9999")).read_value()
        finally:
            await c.disconnect()

    asyncio.run(go())


def test_write_at_end(opcua):
    async def go():
        c = await connect(opcua)
        try:
            d100 = await node(c, "D100")
            await d100.write_value(ua.DataValue(ua.Variant(4321, ua.VariantType.Int16)))
            # The reply comes after the END that wrote it.
            assert await d100.read_value() == 4321
            # The program copies D100 to D101 in the next scan.
            assert await wait_value(await node(c, "D101"), 4321) == 4321
            await (await node(c, "X0")).write_value(ua.DataValue(ua.Variant(True, ua.VariantType.Boolean)))
            assert await wait_value(await node(c, "Y0"), True) is True
            # -2 as a 32-bit value: D200 = 0xFFFE, D201 = 0xFFFF (low word first).
            await (await node(c, "D200:i32")).write_value(ua.DataValue(ua.Variant(-2, ua.VariantType.Int32)))
            assert await wait_value(await node(c, "D202:i32"), -2) == -2
            await (await node(c, "D300:f32")).write_value(ua.DataValue(ua.Variant(2.5, ua.VariantType.Float)))
            assert await wait_value(await node(c, "D302:f32"), 2.5) == 2.5
            # A Double on a Float node, an Int32 on an Int16 node.
            with pytest.raises(ua.uaerrors.BadTypeMismatch):
                await (await node(c, "D300:f32")).write_value(ua.DataValue(ua.Variant(1.0, ua.VariantType.Double)))
            with pytest.raises(ua.uaerrors.BadTypeMismatch):
                await d100.write_value(ua.DataValue(ua.Variant(5, ua.VariantType.Int32)))
            assert await d100.read_value() == 4321
        finally:
            await c.disconnect()

    asyncio.run(go())


class Collect:
    def __init__(self):
        self.values = {}

    def datachange_notification(self, n, val, data):
        self.values.setdefault(n.nodeid.Identifier, []).append(val)


def test_subscribe_to_a_device_and_a_loop_field(opcua):
    async def go():
        c = await connect(opcua)
        try:
            handler = Collect()
            sub = await c.create_subscription(50, handler)
            d0 = await node(c, "D0")
            loop = "/softplc/Loops/PIDCONT D600 loop 1/"
            mv = await node(c, loop + "MV")
            await sub.subscribe_data_change([d0, mv], queuesize=100, sampling_interval=0)
            await asyncio.sleep(0.3)
            # Automatic (MODE 1; in manual SV tracks PV), then SV 1000 with
            # PV 0: Kp 1.00 makes MV the error, 1000 (the integral time of
            # 3276.7 s adds < 1 in 1 s).
            await (await node(c, loop + "MODE")).write_value(ua.DataValue(ua.Variant(1, ua.VariantType.Int16)))
            await (await node(c, loop + "SV")).write_value(ua.DataValue(ua.Variant(1000, ua.VariantType.Int16)))
            await asyncio.sleep(0.7)
            await sub.delete()
            counts = handler.values.get("D0", [])
            # D0 changes every 10 ms scan; 50 ms publishing with a queue
            # keeps every sampled value: far more than one per publish.
            assert len(counts) >= 20, counts
            assert all(a < b for a, b in zip(counts, counts[1:])), counts
            mvs = handler.values.get(loop + "MV", [])
            # The initial value (manual, 0), then the computed one.
            assert mvs[0] == 0 and mvs[-1] in (1000, 1001), mvs
        finally:
            await c.disconnect()

    asyncio.run(go())
