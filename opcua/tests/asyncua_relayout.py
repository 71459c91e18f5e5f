# SPDX-License-Identifier: MIT OR Apache-2.0
"""An independent OPC UA client (asyncua, PyPI) subscribed to procimg-opcua while procimgd
starts anew with another layout: first the device demo (the station "procimg-device"),
then the controller demo (devices echo, counter, dio) under the same instance.

    python asyncua_relayout.py URL INSTANCE PKI_DIR WORK_DIR

It subscribes to a variable of the station and prints "subscribed"; the test then restarts
procimgd. Checks: the subscription hears that the station's variable went
(BadNodeIdUnknown), a Read of it says so too, and the new layout's tree and items serve, in
the same session. Prints "asyncua: all checks held" at the end.
"""

import asyncio

from asyncua import Client, ua

from asyncua_common import INSTANCE, ITEMS, TREE, URL, check, read, state_word


async def main():
    client = Client(URL)
    async with client:
        ns = await client.get_namespace_index(ITEMS)
        tns = await client.get_namespace_index(TREE)
        q_data = ua.NodeId(f"{INSTANCE}/Devices/procimg-device/1.1/QData", tns)
        statuses = []

        class Handler:
            def datachange_notification(self, node, val, data):
                statuses.append(data.monitored_item.Value.StatusCode.name)

        sub = await client.create_subscription(20, Handler())
        await sub.subscribe_data_change([client.get_node(q_data)])
        print("subscribed", flush=True)
        devices = client.get_node(ua.NodeId(f"{INSTANCE}/Devices", tns))
        names = []
        for _ in range(1200):
            try:
                children = await devices.get_children()
                names = sorted([(await d.read_browse_name()).Name for d in children])
            except ua.UaStatusCodeError:
                # Browsed while the tree was being made anew: a child may be gone by the
                # time it is read. Look again.
                names = []
            if names == ["counter", "dio", "echo"]:
                break
            await asyncio.sleep(0.1)
        check(names == ["counter", "dio", "echo"], f"the new layout's devices: {names}")
        for _ in range(100):
            if "BadNodeIdUnknown" in statuses:
                break
            await asyncio.sleep(0.05)
        check("BadNodeIdUnknown" in statuses, f"the subscription heard the station go: {statuses}")
        gone = await read(client, q_data)
        check(gone.StatusCode.name == "BadNodeIdUnknown", f"a Read of the station's QData: {gone.StatusCode}")
        counter = client.get_node(ua.NodeId(f"{INSTANCE}/Devices/counter/State", tns))
        word = None
        for _ in range(600):
            word = await state_word(client, counter)
            if word == "running":
                break
            await asyncio.sleep(0.1)
        check(word == "running", f"the counter device's state: {word}")
        eb10 = await read(client, ua.NodeId("PNIO:[CTRL1]EB10", ns))
        check(eb10.StatusCode.is_good(), f"EB10 of the new layout: {eb10.StatusCode}")
        await sub.delete()
    print("asyncua: all checks held", flush=True)


asyncio.run(main())
