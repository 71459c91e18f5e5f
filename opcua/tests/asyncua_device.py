# SPDX-License-Identifier: MIT OR Apache-2.0
"""An independent OPC UA client (asyncua, PyPI) against procimg-opcua serving the device
demo (`procimgd --demo-device`: procimgd is the PROFINET station "procimg-device", the demo's
PLC connects it and sends back each byte of submodule 1.1's I data plus one as its Q data).

    python asyncua_device.py URL INSTANCE PKI_DIR WORK_DIR

Checks, each failure naming what a user would see: the station's items and tree (its AR's
state as an enumeration, the PLC and its RUN, the I and Q data with their qualities); an
anonymous write refused; a client that vanishes while subscribed touching nothing; a
writer's session writing the station's I data and reading back the PLC's answer; a write of
the wrong length or type refused with the I data untouched; the AR's end and new start as
events as the station goes OFFLINE and back, and the new AR answering the I data written
anew (OFFLINE forgets outputs, as IO-Base does). Prints "asyncua: all checks held" at the end.
"""

import asyncio
import subprocess
import sys

from asyncua import Client, ua

from asyncua_common import (
    INSTANCE, ITEMS, TREE, TYPES, URL, check, disconnect_all, event_filter, read, refused, state_word, trusted_connector,
)

STATION = f"{INSTANCE}/Devices/procimg-device"
PATTERN = list(range(0x10, 0x18))


async def items_and_tree():
    client = Client(URL)
    async with client:
        ns = await client.get_namespace_index(ITEMS)
        tns = await client.get_namespace_index(TREE)

        def item(name):
            return ua.NodeId(f"PNIO:[CTRL1]{name}", ns)

        def node(path):
            return client.get_node(ua.NodeId(f"{STATION}/{path}", tns))

        # Q data (what the PLC wrote) reads as inputs, good; nobody writes the I data yet,
        # so it goes out invalid, and says so.
        q = await read(client, item("EB0,8"))
        check(q.StatusCode.is_good() and len(q.Value.Value) == 8, f"EB0,8 (Q data): {q}")
        i = await read(client, item("AB0,8"))
        check(i.StatusCode.name == "BadOutOfService", f"AB0,8 without a writer: {i.StatusCode}")
        # The station's tree: its AR as an enumeration, the PLC, RUN, the data's names.
        check(await state_word(client, node("State")) == "data", "the AR is in data exchange")
        check("demo-plc" in await node("Plc").read_value(), "the PLC's name")
        check(await node("PlcRunning").read_value() is True, "the PLC is in RUN")
        names = sorted([(await c.read_browse_name()).Name for c in await node("1.1").get_children()])
        check(names == ["IData", "IDataIOCS", "IDataIOPS", "QData", "QDataIOCS", "QDataIOPS"], f"1.1: {names}")
        description = (await node("1.1/IData").read_attribute(ua.AttributeIds.Description)).Value.Value
        check(description.Text.endswith("PNIO:[CTRL1]AB0,8"), f"IData names its item: {description}")
        await refused(
            client.get_node(item("AB0")).write_value(ua.Variant(1, ua.VariantType.Byte)),
            "BadUserAccessDenied", "an anonymous write of the I data",
        )


VANISHING = """
import asyncio, sys
from asyncua import Client, ua
async def main():
    c = Client(sys.argv[1])
    await c.connect()
    ns = await c.get_namespace_index("urn:procimg:pnio")
    class H:
        def datachange_notification(self, node, val, data):
            pass
    sub = await c.create_subscription(10, H())
    await sub.subscribe_data_change([c.get_node(ua.NodeId(f"PNIO:[CTRL1]EB{a}", ns)) for a in range(8)])
    print("subscribed", flush=True)
    await asyncio.sleep(3600)
asyncio.run(main())
"""


def vanish():
    """A client that subscribes and is killed: no goodbye, its session left to time out."""
    child = subprocess.Popen([sys.executable, "-c", VANISHING, URL], stdout=subprocess.PIPE, text=True)
    line = child.stdout.readline()
    check("subscribed" in line, f"the vanishing client subscribed: {line!r}")
    child.kill()
    child.wait()


async def writes_and_events():
    connect = await trusted_connector()
    operator = await connect("operator", "op-pw")
    viewer = await connect("viewer", "viewer-pw")
    await operator.connect()
    await viewer.connect()
    try:
        ns = await operator.get_namespace_index(ITEMS)
        tns = await operator.get_namespace_index(TREE)

        def item(name):
            return operator.get_node(ua.NodeId(f"PNIO:[CTRL1]{name}", ns))

        # The writer writes the station's I data; the PLC's Q data answers each byte plus one.
        await item("AB0,8").write_value(ua.Variant(PATTERN, ua.VariantType.Byte))
        answer = None
        for _ in range(200):
            answer = await item("EB0,8").read_value()
            if list(answer) == [b + 1 for b in PATTERN]:
                break
            await asyncio.sleep(0.05)
        check(list(answer) == [b + 1 for b in PATTERN], f"the PLC's answer to the I data: {answer}")
        sent = await read(operator, ua.NodeId("PNIO:[CTRL1]AB0,8", ns))
        check(sent.StatusCode.is_good() and list(sent.Value.Value) == PATTERN, f"AB0,8 as sent: {sent}")
        # The wrong length and the wrong type are refused; the I data stays.
        await refused(
            item("AB0,8").write_value(ua.Variant(PATTERN[:7], ua.VariantType.Byte)),
            "BadTypeMismatch", "7 bytes written to AB0,8",
        )
        await refused(
            item("AW0").write_value(ua.Variant(1, ua.VariantType.Byte)),
            "BadTypeMismatch", "a Byte written to AW0",
        )
        await refused(
            item("EB0").write_value(ua.Variant(1, ua.VariantType.Byte)),
            "BadNotWritable", "a write of the Q data",
        )
        check(list(await item("AB0,8").read_value()) == PATTERN, "the I data after the refused writes")

        # The station goes OFFLINE and back: the AR's end and its new start come as events
        # of procimg's ArEventType, with their fields.
        events = []

        class Events:
            def event_notification(self, event):
                events.append((event.Station, event.ArState, event.Plc, event.Reason, event.SourceName))

        types = await viewer.get_namespace_index(TYPES)
        ar_event = viewer.get_node(ua.NodeId("ArEventType", types))
        sub = await viewer.create_subscription(50, Events())
        await sub.subscribe_events(
            viewer.nodes.server, ar_event, evfilter=await event_filter(ar_event), queuesize=100
        )
        top = operator.get_node(ua.NodeId(INSTANCE, tns))
        await top.call_method(ua.NodeId(f"{INSTANCE}/SetMode", tns), "OFFLINE")
        await top.call_method(ua.NodeId(f"{INSTANCE}/SetMode", tns), "OPERATE")

        def seen(state):
            return [e for e in events if e[0] == e[4] == "procimg-device" and e[1] == state]

        for _ in range(300):
            if seen("ended") and seen("data"):
                break
            await asyncio.sleep(0.1)
        check(seen("ended") and seen("data"), f"the AR's end and new start as events: {events}")
        check(seen("ended")[0][3], f"the AR's end says why: {seen('ended')}")
        check(seen("data")[0][2] == "demo-plc", f"the new AR names its PLC: {seen('data')}")
        # OFFLINE forgot the I data (as IO-Base does); written again, the new AR answers.
        again = [b ^ 0x40 for b in PATTERN]
        answer = None
        for _ in range(200):
            try:
                await item("AB0,8").write_value(ua.Variant(again, ua.VariantType.Byte))
            except ua.UaStatusCodeError as e:
                print(f"write during the AR's start: {e!r}", flush=True)
            answer = await read(operator, ua.NodeId("PNIO:[CTRL1]EB0,8", ns))
            if answer.StatusCode.is_good() and list(answer.Value.Value) == [b + 1 for b in again]:
                break
            await asyncio.sleep(0.05)
        check(list(answer.Value.Value) == [b + 1 for b in again], f"the new AR's answer: {answer}")
    finally:
        await disconnect_all([operator, viewer])


async def main():
    await items_and_tree()
    vanish()
    await writes_and_events()
    print("asyncua: all checks held", flush=True)


asyncio.run(main())
