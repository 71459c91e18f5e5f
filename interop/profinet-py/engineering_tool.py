#!/usr/bin/env python3
# SPDX-License-Identifier: MIT OR Apache-2.0
"""An engineering tool's visit to a PROFINET IO device, played by profinet-py (PyPI,
GPL-3.0, used here as an independent peer, not copied): a device access AR (profinet-py's
default connect), the physical device's records, ARData, I&M0 read and I&M1 written, and
the Release. Prints what profinet-py decoded as one JSON object on standard output.

    engineering_tool.py --ip 10.47.0.50 --mac 02:00:00:00:00:01 --name py-device \
        --vendor 0x0493 --device 0x0100 --src-mac 02:00:00:00:00:02

The device is described by hand (no DCP, so no raw socket needed for the lookup).
"""

import argparse
import ipaddress
import json
import sys

from profinet import dcp, rpc


def text(v):
    """A field profinet-py gives as bytes or as str, as str without its blank padding."""
    if isinstance(v, (bytes, bytearray)):
        v = v.decode("latin-1")
    return v.rstrip(" \x00")


def mac_bytes(text):
    return bytes(int(b, 16) for b in text.split(":"))


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--ip", required=True)
    p.add_argument("--mac", required=True)
    p.add_argument("--name", required=True)
    p.add_argument("--vendor", type=lambda v: int(v, 0), required=True)
    p.add_argument("--device", type=lambda v: int(v, 0), required=True)
    p.add_argument("--src-mac", required=True)
    p.add_argument("--location", default="hall-3 line-2")
    a = p.parse_args()

    ip = ipaddress.IPv4Address(a.ip).packed
    info = dcp.DCPDeviceDescription(
        mac_bytes(a.mac),
        {
            (2, 2): a.name.encode(),
            (1, 2): ip + bytes([255, 255, 255, 0]) + bytes(4),
            (2, 3): bytes([a.vendor >> 8, a.vendor & 0xFF, a.device >> 8, a.device & 0xFF]),
        },
    )
    conn = rpc.RPCCon(info, timeout=10.0)
    out = {}
    conn.connect(mac_bytes(a.src_mac))

    pd = conn.read_pd_real_data()
    out["slots"] = [[s.api, s.slot, s.subslot, s.blocks] for s in pd.slots]
    i = pd.interface
    out["interface"] = None if i is None else {
        "chassis_id": i.chassis_id, "mac": i.mac_str, "ip": i.ip_str, "netmask": i.subnet_str}
    # profinet-py reads a port's slot, subslot, name and number of peers right; the fields
    # after the name it reads two bytes off (see the README's interop notes).
    out["ports"] = [{"slot": q.slot, "subslot": q.subslot, "port_id": q.port_id,
                     "peers": len(q.peers)} for q in pd.ports]
    _, ports = conn.read_topology()
    out["topology_ports"] = [[q.slot, q.subslot, q.port_id] for q in ports]
    port = conn.read_port_info(slot=0, subslot=0x8001)
    out["port_info"] = [port.slot, port.subslot, port.port_id]
    ar = conn.read_ar_info()
    # profinet-py takes ARData for its version 1.0 layout, where ARType follows the ARUUID;
    # devices send version 1.1 (p-net, procimgd), where the CMInitiatorObjectUUID does: only
    # the first AR's ARUUID is read right.
    out["ar_info"] = None if ar is None else {"ar_uuid": ar.ar_uuid}

    im0 = conn.read_im0(slot=0, subslot=1)
    out["im0"] = {"vendor_id": im0.vendor_id, "order_id": text(im0.order_id),
                  "im_version": im0.im_version}
    tag = a.location.encode().ljust(22, b" ")
    im1 = bytes([0x00, 0x21, 0x00, 0x38, 0x01, 0x00]) + b" " * 32 + tag
    conn.write(api=0, slot=0, subslot=1, idx=0xAFF1, data=im1)
    out["im1_location"] = text(conn.read_im1(slot=0, subslot=1).im_tag_location)
    conn.disconnect()
    # Raw bytes (profinet-py gives some identifiers so) as hex.
    json.dump(out, sys.stdout, default=lambda o: o.hex() if isinstance(o, (bytes, bytearray)) else str(o))


if __name__ == "__main__":
    main()
