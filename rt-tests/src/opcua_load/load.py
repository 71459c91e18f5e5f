# SPDX-License-Identifier: MIT OR Apache-2.0
"""The OPC UA load of procimg-opcua-load: an asyncua (PyPI) client that monitors COUNT
PNIO items of the demo's counter device, which change every cycle.

    python load.py URL COUNT SAMPLING_MS PUBLISHING_MS SECONDS

Prints "ready" once the monitored items exist and the first notifications came, then,
after SECONDS of counting, "updates N SECONDS_MEASURED".
"""

import asyncio
import sys
import time

from asyncua import Client, ua

URL, COUNT, SAMPLING, PUBLISHING, SECONDS = (
    sys.argv[1], int(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4]), float(sys.argv[5]),
)

# Names of the counter device's inputs (I 16..19) in the served forms: bits, bytes, words,
# double words, arrays, German and English letters.
NAMES = (
    [f"{area}{byte}.{bit}" for area in "EI" for byte in (18, 19) for bit in range(8)]
    + [f"{area}B{a}" for area in "EI" for a in (18, 19)]
    + [f"{area}W18" for area in "EI"]
    + [f"{area}D16" for area in "EI"]
    + [f"{area}B16,4" for area in "EI"]
    + [f"{area}B18,2" for area in "EI"]
)

updates = 0


class Handler:
    def datachange_notification(self, node, val, data):
        global updates
        updates += 1


async def main():
    client = Client(URL, timeout=60)
    async with client:
        ns = await client.get_namespace_index("urn:procimg:pnio")
        sub = await client.create_subscription(PUBLISHING, Handler())
        requests = []
        for i in range(COUNT):
            params = ua.MonitoringParameters()
            params.SamplingInterval = SAMPLING
            params.QueueSize = 1
            params.ClientHandle = i + 1
            req = ua.MonitoredItemCreateRequest()
            req.ItemToMonitor = ua.ReadValueId(
                NodeId=ua.NodeId(f"PNIO:[CTRL1]{NAMES[i % len(NAMES)]}", ns),
                AttributeId=ua.AttributeIds.Value,
            )
            req.MonitoringMode = ua.MonitoringMode.Reporting
            req.RequestedParameters = params
            requests.append(req)
        for at in range(0, COUNT, 1000):
            results = await sub.create_monitored_items(requests[at:at + 1000])
            bad = [r for r in results if not isinstance(r, int)]
            if bad:
                print(f"monitored items refused: {bad[:3]}", flush=True)
                sys.exit(1)
        while updates < COUNT:
            await asyncio.sleep(0.05)
        print("ready", flush=True)
        start, t0 = updates, time.monotonic()
        await asyncio.sleep(SECONDS)
        n, dt = updates - start, time.monotonic() - t0
        print(f"updates {n} {dt:.3f}", flush=True)
        await sub.delete()


asyncio.run(main())
