"""asyncua against `softplc serve rack --opcua`: the buffer-memory words the
program uses (`U2\\G11`, ...) are nodes of the Devices folder, read and
written at END like any device (contract §3.2)."""
import asyncio
import subprocess

import pytest
from asyncua import ua

from conftest import BINARY, HERE, free_port, stop, wait_port
from test_opcua import connect, names, node, wait_value

pytestmark = pytest.mark.filterwarnings("ignore::DeprecationWarning")


@pytest.fixture
def opcua_rack(tmp_path):
    port = free_port()
    cmd = [BINARY, "serve", str(HERE / "rack"), "--scan-time", "10ms",
           "--opcua", f"127.0.0.1:{port}", "--opcua-pki", str(tmp_path / "pki")]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    wait_port(port, proc)
    yield f"opc.tcp://127.0.0.1:{port}/"
    stop(proc)


def test_buffer_memory_nodes(opcua_rack):
    async def go():
        c = await connect(opcua_rack)
        try:
            ns = await c.get_namespace_index("urn:softplc")
            root = await c.nodes.objects.get_child([f"{ns}:softplc"])
            devices = await names(await root.get_child([f"{ns}:Devices"]))
            for want in ["U2\\G10", "U2\\G11", "U2\\G12", "U2\\G13", "U4\\G0", "D0", "D1"]:
                assert want in devices, devices
            g11 = await node(c, "U2\\G11")
            assert await g11.read_data_type_as_variant_type() == ua.VariantType.Int16
            # Written at END; the program copies U2\G11 to D0 in the next scan.
            await g11.write_value(ua.DataValue(ua.Variant(-1234, ua.VariantType.Int16)))
            assert await g11.read_value() == -1234
            assert await wait_value(await node(c, "D0"), -1234) == -1234
            # D1 goes to U2\G12; U2\G13 counts scans.
            await (await node(c, "D1")).write_value(ua.DataValue(ua.Variant(55, ua.VariantType.Int16)))
            assert await wait_value(await node(c, "U2\\G12"), 55) == 55
            g13 = await node(c, "U2\\G13")
            a = await g13.read_value()
            await asyncio.sleep(0.1)
            assert await g13.read_value() != a
            # A word no program uses has no node.
            with pytest.raises(ua.uaerrors.BadNodeIdUnknown):
                await (await node(c, "U2\\G50")).read_value()
        finally:
            await c.disconnect()

    asyncio.run(go())
