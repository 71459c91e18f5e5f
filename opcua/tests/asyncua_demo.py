# SPDX-License-Identifier: MIT OR Apache-2.0
"""An independent OPC UA client (asyncua, PyPI) against procimg-opcua serving the demo.

    python asyncua_demo.py URL INSTANCE PKI_DIR WORK_DIR

The users file is the one asyncua_common.py names.

Checks, each failure naming what a user would see: the PNIO item names of the migration
guide by NodeId with their qualities, items of one Read of one cycle, unknown items refused,
the browsable tree, a subscription's notifications as the counter device counts, an anonymous
write refused, and a secure channel (Basic256Sha256, SignAndEncrypt) once the client's
certificate is trusted, over which a writer's session writes the echo device's outputs and
reads them back as its inputs, holding them against another writer's session until it ends,
a reader's write is refused and a write of the wrong type too. Prints "asyncua: all checks held" at the end.
"""

import asyncio

from asyncua import Client, ua

from asyncua_common import (
    INSTANCE, ITEMS, TREE, TYPES, URL, check, disconnect_all, event_filter, read, refused, state_word,
    trusted_connector,
)


async def items_and_tree():
    client = Client(URL)
    async with client:
        ns = await client.get_namespace_index(ITEMS)
        tns = await client.get_namespace_index(TREE)

        def item(name):
            return ua.NodeId(name, ns)

        # The migration guide's items: an input byte and the mode, with value and quality.
        eb10 = await read(client, item("PNIO:[CTRL1]EB10"))
        check(eb10.StatusCode.is_good(), f"EB10 is {eb10.StatusCode}")
        check(isinstance(eb10.Value.Value, int), f"EB10 is a byte: {eb10.Value}")
        check(eb10.SourceTimestamp is not None, "EB10 has its cycle's time stamp")
        mode = await read(client, item("PNIO:[CTRL1]mode"))
        check(mode.Value.Value == 2, f"mode is 2 (OPERATE): {mode.Value}")
        # Nobody writes the echo device's outputs: they go out invalid, and say so.
        aw0 = await read(client, item("PNIO:[CTRL1]AW0"))
        check(not aw0.StatusCode.is_good(), f"AW0 without a writer is bad: {aw0.StatusCode}")

        # One Read, one cycle: the counter as a double word and as four bytes agree.
        for _ in range(20):
            res = await client.read_values(
                [client.get_node(item("PNIO:[CTRL1]ED16")), client.get_node(item("PNIO:[CTRL1]IB16,4"))]
            )
            as_bytes = int.from_bytes(bytes(res[1]), "big")
            check(res[0] == as_bytes, f"ED16 {res[0]} and IB16,4 {res[1]} of one Read differ")
        # English and German letters name the same bytes; bits read as booleans.
        bit = await read(client, item("PNIO:[CTRL1]I20.0"))
        check(isinstance(bit.Value.Value, bool), f"I20.0 is a boolean: {bit.Value}")

        # Records by logical address: the migration guide's diagnosis record (none pending),
        # and I&M0 of the echo device's access point (its diagnostic address, I 22).
        diag = await read(client, item("PNIO:[CTRL1]EDS10,DATA61450,10"))
        check(diag.StatusCode.is_good(), f"EDS10,DATA61450,10: {diag.StatusCode}")
        im0 = await read(client, item("PNIO:[CTRL1]EDS22,DATA45040,64"))
        check(im0.StatusCode.is_good(), f"I&M0 of the echo device: {im0.StatusCode}")
        data = bytes(im0.Value.Value)
        check(data[:2] == b"\x00\x20" and data[6:8] == b"\x04\x93", f"I&M0 block, vendor 0x0493: {data.hex()}")

        # Items that name nothing are unknown.
        for name in ["PNIO:[CTRL2]EB0", "PNIO:[CTRL1]EB9999", "PNIO:[CTRL1]MB0", "PNIO:[CTRL1]EDS999,DATA1,4"]:
            dv = await read(client, item(name))
            check(dv.StatusCode.value == ua.StatusCodes.BadNodeIdUnknown, f"{name}: {dv.StatusCode}")

        # The browsable tree: Objects/procimg/<instance>/Devices/<device>/<slot>.<subslot>.
        objects = client.nodes.objects
        procimg = await objects.get_child([f"{tns}:procimg"])
        top = await procimg.get_child([f"{tns}:{INSTANCE}"])
        devices = await top.get_child([f"{tns}:Devices"])
        names = sorted([(await d.read_browse_name()).Name for d in await devices.get_children()])
        check(names == ["counter", "dio", "echo"], f"the devices browsed: {names}")
        for device, length in [("echo", 16), ("counter", 4), ("dio", 2)]:
            inputs = await devices.get_child([f"{tns}:{device}", f"{tns}:1.1", f"{tns}:Inputs"])
            dv = await inputs.read_data_value(raise_on_bad_status=False)
            check(len(dv.Value.Value) == length, f"{device}'s inputs: {dv.Value}")
        # The GSDML files (--gsdml) type the data: the counter's "Cycle number" is the
        # UInt32 its four bytes say, in the same Read; the digital inputs' bits have names.
        counter_in = await devices.get_child([f"{tns}:counter", f"{tns}:1.1", f"{tns}:Inputs"])
        cycle_number = await counter_in.get_child([f"{tns}:Cycle number"])
        check(await cycle_number.read_data_type() == ua.NodeId(ua.ObjectIds.UInt32), "Cycle number is a UInt32")
        for _ in range(10):
            raw, typed = await client.read_values([counter_in, cycle_number])
            check(int.from_bytes(bytes(raw), "big") == typed, f"Cycle number {typed} is the bytes {raw}")
        input_0 = await devices.get_child(
            [f"{tns}:dio", f"{tns}:1.1", f"{tns}:Inputs", f"{tns}:Inputs 0..7", f"{tns}:Input 0"]
        )
        check(isinstance(await input_0.read_value(), bool), "the digital input 0 is a Boolean")
        description = (await input_0.read_attribute(ua.AttributeIds.Description)).Value.Value.Text
        check(description.endswith("PNIO:[CTRL1]E20.0"), f"Input 0 names its item: {description}")
        state = await devices.get_child([f"{tns}:counter", f"{tns}:State"])
        check(await state_word(client, state) == "running", "the counter device's state")
        wakeup_p99 = await top.get_child([f"{tns}:Status", f"{tns}:WakeupLatencyP99"])
        check(await wakeup_p99.read_value() > 0.0, "the cycle's wake-up latency p99 (µs)")
        status_mode = await top.get_child([f"{tns}:Status", f"{tns}:Mode"])
        check(await status_mode.read_value() == "OPERATE", "the server's mode")

        # A subscription sees the counter count.
        seen = []

        class Handler:
            def datachange_notification(self, node, val, data):
                seen.append(val)

        sub = await client.create_subscription(20, Handler())
        params = ua.MonitoringParameters()
        params.SamplingInterval = 10
        params.QueueSize = 10
        params.Filter = ua.DataChangeFilter(Trigger=ua.DataChangeTrigger.StatusValue)
        params.ClientHandle = 1
        req = ua.MonitoredItemCreateRequest()
        req.ItemToMonitor = ua.ReadValueId(NodeId=item("PNIO:[CTRL1]ED16"), AttributeId=ua.AttributeIds.Value)
        req.MonitoringMode = ua.MonitoringMode.Reporting
        req.RequestedParameters = params
        results = await sub.create_monitored_items([req])
        check(results[0] == 1 or isinstance(results[0], int), f"monitored item created: {results}")
        for _ in range(200):
            if len(seen) >= 5:
                break
            await asyncio.sleep(0.05)
        check(len(seen) >= 5, f"5 notifications of the counter within 10 s: {seen}")
        check(all(a < b for a, b in zip(seen, seen[1:])), f"the counter counts up: {seen}")
        await sub.delete()

        # Methods of the instance: a record read by anyone; the mode changed by writers only.
        top_id = ua.NodeId(INSTANCE, tns)
        im0 = await client.get_node(top_id).call_method(
            ua.NodeId(f"{INSTANCE}/ReadRecord", tns),
            ua.Variant(22, ua.VariantType.UInt32),
            ua.Variant(0xAFF0, ua.VariantType.UInt16),
            ua.Variant(64, ua.VariantType.UInt32),
        )
        check(bytes(im0)[6:8] == b"\x04\x93", f"ReadRecord of I&M0: {bytes(im0).hex()}")
        await refused(
            client.get_node(top_id).call_method(ua.NodeId(f"{INSTANCE}/SetMode", tns), "OFFLINE"),
            "BadUserAccessDenied", "an anonymous SetMode",
        )
        await refused(
            client.get_node(top_id).call_method(ua.NodeId(f"{INSTANCE}/ActivateDevice", tns), "echo", False),
            "BadUserAccessDenied", "an anonymous ActivateDevice",
        )

        # An anonymous session does not write.
        try:
            await client.get_node(item("PNIO:[CTRL1]AB0")).write_value(ua.Variant(1, ua.VariantType.Byte))
            check(False, "an anonymous write of AB0 was taken")
        except ua.UaStatusCodeError as e:
            print(f"anonymous write refused: {e}", flush=True)


async def secure():
    connect = await trusted_connector()
    client = await connect()
    async with client:
        ns = await client.get_namespace_index(ITEMS)
        dv = await read(client, ua.NodeId("PNIO:[CTRL1]EB10", ns))
        check(dv.StatusCode.is_good(), f"EB10 over Basic256Sha256: {dv.StatusCode}")

    # A wrong password is no session.
    try:
        async with await connect("operator", "wrong"):
            check(False, "a wrong password opened a session")
    except ua.UaStatusCodeError as e:
        print(f"wrong password refused: {e}", flush=True)

    def item(ns, name):
        return ua.NodeId(name, ns)

    pattern = list(range(0xA0, 0xB0))
    operator = await connect("operator", "op-pw")
    second = await connect("second", "second-pw")
    viewer = await connect("viewer", "viewer-pw")
    await operator.connect()
    await second.connect()
    await viewer.connect()
    try:
        ns = await operator.get_namespace_index(ITEMS)
        # The writer writes the echo device's 16 outputs; they come back as its inputs.
        await operator.get_node(item(ns, "PNIO:[CTRL1]AB0,16")).write_value(
            ua.Variant(pattern, ua.VariantType.Byte)
        )
        echoed = None
        for _ in range(200):
            echoed = await operator.get_node(item(ns, "PNIO:[CTRL1]EB0,16")).read_value()
            if list(echoed) == pattern:
                break
            await asyncio.sleep(0.05)
        check(list(echoed) == pattern, f"the echo device's inputs after the write: {echoed}")
        aw0 = await read(operator, item(ns, "PNIO:[CTRL1]AW0"))
        check(aw0.StatusCode.is_good() and aw0.Value.Value == 0xA0A1, f"AW0 as sent: {aw0}")
        # The wrong type is refused, the outputs untouched.
        try:
            await operator.get_node(item(ns, "PNIO:[CTRL1]AW0")).write_value(ua.Variant(1, ua.VariantType.Byte))
            check(False, "a Byte written to a word was taken")
        except ua.UaStatusCodeError as e:
            check("BadTypeMismatch" in type(e).__name__, f"a Byte written to AW0: {e!r}")
        # Another writer's session finds the outputs held.
        try:
            await second.get_node(item(ns, "PNIO:[CTRL1]AB0")).write_value(ua.Variant(1, ua.VariantType.Byte))
            check(False, "a second session wrote outputs the first holds")
        except ua.UaStatusCodeError as e:
            check("BadResourceUnavailable" in type(e).__name__, f"the second writer: {e!r}")
        # A reader does not write.
        try:
            await viewer.get_node(item(ns, "PNIO:[CTRL1]AB16")).write_value(ua.Variant(1, ua.VariantType.Byte))
            check(False, "a reader's write was taken")
        except ua.UaStatusCodeError as e:
            check("BadUserAccessDenied" in type(e).__name__, f"the reader's write: {e!r}")
        # Once the first session ends, the second writes.
        await operator.disconnect()
        written = False
        for _ in range(100):
            try:
                await second.get_node(item(ns, "PNIO:[CTRL1]AB0")).write_value(ua.Variant(7, ua.VariantType.Byte))
                written = True
                break
            except ua.UaStatusCodeError:
                await asyncio.sleep(0.1)
        check(written, "the second writer wrote once the first session had ended")

        # A writer takes the controller OFFLINE and back to OPERATE: every device's failure
        # and return come as events of procimg's DeviceEventType, to a subscriber of the
        # Server object that selects the type's fields.
        events = []

        class Events:
            def event_notification(self, event):
                events.append((event.Device, event.InDataExchange, event.Reason, event.SourceName))

        types = await viewer.get_namespace_index(TYPES)
        device_event = viewer.get_node(ua.NodeId("DeviceEventType", types))
        sub = await viewer.create_subscription(50, Events())
        await sub.subscribe_events(
            viewer.nodes.server, device_event, evfilter=await event_filter(device_event), queuesize=100
        )
        tns = await second.get_namespace_index(TREE)
        top = second.get_node(ua.NodeId(INSTANCE, tns))
        await top.call_method(ua.NodeId(f"{INSTANCE}/SetMode", tns), "OFFLINE")
        await top.call_method(ua.NodeId(f"{INSTANCE}/SetMode", tns), "OPERATE")
        all_three = {"echo", "counter", "dio"}
        for _ in range(300):
            if {d for d, up, _, _ in events if up} == all_three:
                break
            await asyncio.sleep(0.1)
        failed = {d for d, up, why, source in events if not up and why and source == d}
        returned = {d for d, up, _, source in events if up and source == d}
        check(failed == returned == all_three, f"the devices' events: {events}")

        # A writer deactivates the echo device (IO-Base's PNIO_device_activate) and
        # activates it again: its failure and return come as events.
        events.clear()
        activate = ua.NodeId(f"{INSTANCE}/ActivateDevice", tns)
        await top.call_method(activate, "echo", False)
        for _ in range(300):
            if any(d == "echo" and not up for d, up, _, _ in events):
                break
            await asyncio.sleep(0.1)
        check(any(d == "echo" and not up for d, up, _, _ in events), f"echo deactivated: {events}")
        await top.call_method(activate, "echo", True)
        for _ in range(300):
            if any(d == "echo" and up for d, up, _, _ in events):
                break
            await asyncio.sleep(0.1)
        check(any(d == "echo" and up for d, up, _, _ in events), f"echo activated again: {events}")
        check({d for d, _, _, _ in events} == {"echo"}, f"only echo's events: {events}")
    finally:
        await disconnect_all([second, viewer])


async def main():
    await items_and_tree()
    await secure()
    print("asyncua: all checks held", flush=True)


asyncio.run(main())
