"""`softplc serve --opcua [::1]:PORT`: an IPv6 endpoint, with asyncua (its
endpoint URL is `opc.tcp://[::1]:PORT/`, brackets around the address)."""
import asyncio

import pytest

from test_opcua_sessions import connect, read_scan, served  # noqa: F401 (fixture)

pytestmark = pytest.mark.filterwarnings("ignore::DeprecationWarning")


def test_ipv6_endpoint(served):
    url = served("::1")
    assert url.startswith("opc.tcp://[::1]:")

    async def go():
        c = await connect(url)
        try:
            assert await read_scan(c) > 0
            endpoints = await c.get_endpoints()
            assert all(e.EndpointUrl.startswith("opc.tcp://[::1]:") for e in endpoints), endpoints
        finally:
            await c.disconnect()

    asyncio.run(go())
