# SPDX-License-Identifier: MIT OR Apache-2.0
"""What the asyncua scripts of procimg-opcua's tests share: their arguments, checks that
name what a user would see, and secure sessions (Basic256Sha256, SignAndEncrypt) once the
client's certificate, first refused and kept in the PKI folder's rejected/, is trusted.

Every script is run as `python SCRIPT URL INSTANCE PKI_DIR WORK_DIR`; the server's users file
holds "operator" and "second" (writers, passwords "op-pw" and "second-pw") and "viewer" (a
reader, "viewer-pw").
"""

import shutil
import sys
from pathlib import Path

from asyncua import Client, ua
from asyncua.common.events import get_filter_from_event_type
from asyncua.crypto import security_policies
from asyncua.crypto.cert_gen import setup_self_signed_certificate
from cryptography.x509.oid import ExtendedKeyUsageOID

URL, INSTANCE, PKI, WORK = sys.argv[1], sys.argv[2], Path(sys.argv[3]), Path(sys.argv[4])
ITEMS = "urn:procimg:pnio"
TREE = f"urn:procimg:{INSTANCE}"
TYPES = "urn:procimg:types"


def check(ok, what):
    if not ok:
        print(f"asyncua: FAILED: {what}", flush=True)
        sys.exit(1)


async def read(client, node_id):
    return await client.get_node(node_id).read_data_value(raise_on_bad_status=False)


async def state_word(client, node):
    """The word of an enumeration variable's value, from its DataType's EnumStrings."""
    data_type = await node.read_data_type()
    strings = await client.get_node(data_type).get_child(["0:EnumStrings"])
    words = [t.Text for t in await strings.read_value()]
    return words[await node.read_value()]


async def refused(call, status, what):
    """`call` must fail with `status` (a name such as "BadUserAccessDenied")."""
    try:
        await call
    except ua.UaStatusCodeError as e:
        check(status in type(e).__name__, f"{what}: {e!r}")
        return
    check(False, f"{what} was taken")


async def trusted_connector():
    """Makes the client's certificate, shows it refused and kept in rejected/, trusts it,
    and returns `connect(user=None, password=None)` for secure sessions."""
    key, cert = WORK / "client-key.pem", WORK / "client-cert.der"
    await setup_self_signed_certificate(
        key, cert, "urn:procimg:test:asyncua", "localhost",
        [ExtendedKeyUsageOID.CLIENT_AUTH], {"commonName": "procimg-test"},
    )

    async def connect(user=None, password=None):
        client = Client(URL)
        client.application_uri = "urn:procimg:test:asyncua"
        if user:
            client.set_user(user)
            client.set_password(password)
        await client.set_security(
            security_policies.SecurityPolicyBasic256Sha256, str(cert), str(key),
            mode=ua.MessageSecurityMode.SignAndEncrypt,
        )
        return client

    # An unknown certificate is refused and kept in rejected/ for the administrator.
    client = await connect()
    try:
        async with client:
            check(False, "an untrusted client certificate was accepted")
    except Exception as e:  # the server closes the channel
        print(f"untrusted certificate refused: {type(e).__name__}", flush=True)
    rejected = list((PKI / "rejected").glob("*.der"))
    check(len(rejected) == 1, f"the refused certificate is in rejected/: {rejected}")
    shutil.move(str(rejected[0]), str(PKI / "trusted" / rejected[0].name))
    return connect


async def disconnect_all(clients):
    for c in clients:
        try:
            await c.disconnect()
        except Exception:
            pass


async def event_filter(event_type):
    """An event filter selecting every field of `event_type` (a Node), its events chosen by
    OfType, as UaExpert and most clients write it. (asyncua's own filter chooses them with
    InList on EventType, whose NodeIds async-opcua's filter does not compare.)"""
    evfilter = await get_filter_from_event_type([event_type])
    of_type = ua.ContentFilterElement(
        FilterOperator=ua.FilterOperator.OfType,
        FilterOperands=[ua.LiteralOperand(Value=ua.Variant(event_type.nodeid))],
    )
    evfilter.WhereClause = ua.ContentFilter(Elements=[of_type])
    return evfilter
