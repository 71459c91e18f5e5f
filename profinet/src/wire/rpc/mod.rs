// SPDX-License-Identifier: MIT OR Apache-2.0
//! Connectionless DCE/RPC (the PROFINET CM transport over UDP) and the NDR headers PNIO puts in
//! front of its blocks.
//!
//! A PDU is the 80-byte connectionless header, then the body (LengthOfBody bytes). For PNIO
//! requests and responses the body is a 20-byte NDR header followed by PNIO blocks:
//!
//! ```text
//! request:  RPC header(80) ArgsMaximum(4) ArgsLength(4) MaximumCount(4) Offset(4) ActualCount(4) blocks…
//! response: RPC header(80) PNIOStatus(4)  ArgsLength(4) MaximumCount(4) Offset(4) ActualCount(4) blocks…
//! ```
//!
//! Byte order: the integers and the first three fields of each UUID in the RPC header and the
//! NDR header follow the PDU's data representation (DREP, byte 4: high nibble 0x1 =
//! little-endian, 0x0 = big-endian). An S7 sends little-endian, p-net answers big-endian; both
//! parse and emit. The PNIO blocks are always big-endian and are copied through as bytes.
//!
//! Layers:
//! - [`Packet`]: a view over header + body with DREP-aware getters and setters;
//! - [`Header`]: the header as a value (`parse`, `buffer_len`, `emit` in its own DREP);
//! - [`NdrRequest`] / [`NdrResponse`] ([`Ndr`] picks one by packet type);
//! - [`Pdu`]: a whole unfragmented request or response: header + NDR + block bytes, with
//!   [`parse_pdu`], [`emit_request`] and [`emit_response`] as shortcuts;
//! - [`describe`]: a PNIOStatus in words.
//!
//! Fragmentation is not handled here: [`Pdu`] refuses PDUs with the Fragment flag. A caller
//! that reassembles fragments (FragmentNumber, LastFragment) uses [`Packet`] / [`Header`] per
//! fragment and [`parse_body`] on the reassembled body. The character and floating-point
//! formats of the DREP are ignored (PNIO carries neither in RPC fields); emission writes ASCII
//! and IEEE (0).

use super::{EmitError, EmitResult, Error, Field, PnioStatus, Rest, Result, Uuid, be16, be32};

mod ndr;
mod pdu;
mod status;
#[cfg(test)]
mod tests;

pub use ndr::{NDR_LEN, Ndr, NdrRequest, NdrResponse, parse_body};
pub use pdu::{
    MAX_FRAGMENT_BODY, Pdu, emit_request, emit_response, emit_with_body, fack, fragments, parse_pdu,
};
pub use status::{StatusText, describe};

/// The UDP port of the PNIO RPC server (0x8894), on devices and controllers alike.
pub const RPC_PORT: u16 = 34964;

/// RPCVersion of connectionless DCE/RPC.
pub const RPC_VERSION: u8 = 4;

/// InterfaceVersion of the PNIO interfaces (major 1, minor 0).
pub const PNIO_INTERFACE_VERSION: u32 = 1;

/// InterfaceHint / ActivityHint value meaning "no hint".
pub const NO_HINT: u16 = 0xffff;

/// Largest unfragmented PDU p-net sends and accepts: 80 header bytes + 1384 body bytes. Bigger
/// calls need connectionless fragmentation.
pub const MAX_PDU_LEN: usize = 1464;

/// The PNIO interface UUID `DEAxxxxx-6C97-11D1-8271-00A02442DF7D` with `data1` = 0xDEAxxxxx.
const fn pnio_interface(data1: u32) -> Uuid {
    Uuid::from_fields(
        data1,
        0x6c97,
        0x11d1,
        [0x82, 0x71, 0x00, 0xa0, 0x24, 0x42, 0xdf, 0x7d],
    )
}

/// Interface UUID of an IO device (DEA00001-…): calls *to* a device (Connect, Read, Write,
/// Control PrmEnd, Release).
pub const DEVICE_INTERFACE: Uuid = pnio_interface(0xdea0_0001);
/// Interface UUID of an IO controller (DEA00002-…): calls *to* a controller (the device's
/// Control ApplicationReady).
pub const CONTROLLER_INTERFACE: Uuid = pnio_interface(0xdea0_0002);
/// Interface UUID of an IO supervisor (DEA00003-…).
pub const SUPERVISOR_INTERFACE: Uuid = pnio_interface(0xdea0_0003);
/// Interface UUID of a parameter server (DEA00004-…).
pub const PARAMETER_SERVER_INTERFACE: Uuid = pnio_interface(0xdea0_0004);
/// Interface UUID of the endpoint mapper, E1AF8308-5D1F-11C9-91A4-08002B14A0FA (a device must
/// answer EPM lookups).
pub const EPM_INTERFACE: Uuid = Uuid::from_fields(
    0xe1af_8308,
    0x5d1f,
    0x11c9,
    [0x91, 0xa4, 0x08, 0x00, 0x2b, 0x14, 0xa0, 0xfa],
);

/// The object UUID of a PNIO station: `DEA00000-6C97-11D1-8271-IIII-DDDD-VVVV` with the
/// instance (GSDML ObjectUUID_LocalIndex, usually 1), DeviceID and VendorID of the *addressed*
/// station.
pub const fn object_uuid(instance: u16, device_id: u16, vendor_id: u16) -> Uuid {
    let i = instance.to_be_bytes();
    let d = device_id.to_be_bytes();
    let v = vendor_id.to_be_bytes();
    Uuid::from_fields(
        0xdea0_0000,
        0x6c97,
        0x11d1,
        [0x82, 0x71, i[0], i[1], d[0], d[1], v[0], v[1]],
    )
}

/// The (instance, DeviceID, VendorID) of a PNIO object UUID, or `None` if its first 10 bytes
/// are not `DEA00000-6C97-11D1-8271`.
pub fn object_uuid_parts(uuid: &Uuid) -> Option<(u16, u16, u16)> {
    let b = &uuid.0;
    if b[..10] != object_uuid(0, 0, 0).0[..10] {
        return None;
    }
    Some((
        u16::from_be_bytes([b[10], b[11]]),
        u16::from_be_bytes([b[12], b[13]]),
        u16::from_be_bytes([b[14], b[15]]),
    ))
}

/// PNIO operation numbers (OpNum).
pub mod opnum {
    /// 0: Connect (establish an AR).
    pub const CONNECT: u16 = 0;
    /// 1: Release (end an AR).
    pub const RELEASE: u16 = 1;
    /// 2: Read a record (within an AR).
    pub const READ: u16 = 2;
    /// 3: Write a record (or WriteMultiple).
    pub const WRITE: u16 = 3;
    /// 4: Control (PrmEnd, ApplicationReady, PrmBegin…).
    pub const CONTROL: u16 = 4;
    /// 5: ReadImplicit (a record read without an AR).
    pub const READ_IMPLICIT: u16 = 5;

    /// The name of a PNIO opnum, or `None` for other values.
    pub const fn name(op: u16) -> Option<&'static str> {
        match op {
            CONNECT => Some("Connect"),
            RELEASE => Some("Release"),
            READ => Some("Read"),
            WRITE => Some("Write"),
            CONTROL => Some("Control"),
            READ_IMPLICIT => Some("ReadImplicit"),
            _ => None,
        }
    }
}

/// Flags1 bits.
pub mod flags1 {
    /// 0x02: the last fragment of a fragmented PDU (also set by some senders, e.g. the S7, on
    /// unfragmented responses).
    pub const LAST_FRAGMENT: u8 = 0x02;
    /// 0x04: this PDU is a fragment.
    pub const FRAGMENT: u8 = 0x04;
    /// 0x08: the receiver need not send a FACK for this fragment.
    pub const NO_FACK: u8 = 0x08;
    /// 0x10: "maybe" call semantics (no response).
    pub const MAYBE: u8 = 0x10;
    /// 0x20: idempotent call (no client ACK needed); PNIO requests set it.
    pub const IDEMPOTENT: u8 = 0x20;
    /// 0x40: broadcast call.
    pub const BROADCAST: u8 = 0x40;
}

/// Flags2 bits.
pub mod flags2 {
    /// 0x02: a cancel is pending.
    pub const CANCEL_PENDING: u8 = 0x02;
}

/// Flags1 of the responses [`Header::reply`] builds: LastFragment | NoFack (0x0A), as the S7
/// answers p-net's calls (p-net itself answers with NoFack | Idempotent, 0x28; both peers
/// accept either).
pub const REPLY_FLAGS1: u8 = flags1::LAST_FRAGMENT | flags1::NO_FACK;

coded_enum! {
    /// The PacketType of a connectionless PDU.
    pub enum PacketType(u8) display "type {:#04x}" {
        /// 0: request (a call).
        Request = 0 => "request",
        /// 1: ping (client asks whether a call is still running).
        Ping = 1 => "ping",
        /// 2: response (the result of a call).
        Response = 2 => "response",
        /// 3: fault (the call failed in the server; the body holds a status).
        Fault = 3 => "fault",
        /// 4: working (answer to a ping: still running).
        Working = 4 => "working",
        /// 5: no-call (answer to a ping: no such call).
        NoCall = 5 => "no-call",
        /// 6: reject (the call was refused, e.g. unknown interface; the body holds a status).
        Reject = 6 => "reject",
        /// 7: ack (client acknowledges a response of a non-idempotent call).
        Ack = 7 => "ack",
        /// 8: cancel (client cancels a call).
        ClCancel = 8 => "cancel",
        /// 9: fragment ack.
        Fack = 9 => "fack",
        /// 10: cancel ack.
        CancelAck = 10 => "cancel-ack",
    }
}

mod field {
    use super::{Field, Rest};
    pub const VERSION: usize = 0;
    pub const PACKET_TYPE: usize = 1;
    pub const FLAGS1: usize = 2;
    pub const FLAGS2: usize = 3;
    pub const DREP: Field = 4..7;
    pub const SERIAL_HIGH: usize = 7;
    pub const OBJECT: Field = 8..24;
    pub const INTERFACE: Field = 24..40;
    pub const ACTIVITY: Field = 40..56;
    pub const SERVER_BOOT_TIME: Field = 56..60;
    pub const INTERFACE_VERSION: Field = 60..64;
    pub const SEQUENCE_NUMBER: Field = 64..68;
    pub const OPNUM: Field = 68..70;
    pub const INTERFACE_HINT: Field = 70..72;
    pub const ACTIVITY_HINT: Field = 72..74;
    pub const BODY_LEN: Field = 74..76;
    pub const FRAGMENT_NUMBER: Field = 76..78;
    pub const AUTH_PROTOCOL: usize = 78;
    pub const SERIAL_LOW: usize = 79;
    pub const BODY: Rest = 80..;
}

/// Bytes of the connectionless RPC header.
pub const HEADER_LEN: usize = field::BODY.start;

/// DREP byte 0 of a little-endian PDU (integers LE, characters ASCII).
pub const DREP_LITTLE_ENDIAN: u8 = 0x10;
/// DREP byte 0 of a big-endian PDU (integers BE, characters ASCII).
pub const DREP_BIG_ENDIAN: u8 = 0x00;

/// Reads a u16 in DREP order from a 2-byte slice.
fn rd16(b: &[u8], little_endian: bool) -> u16 {
    let v = be16(b);
    if little_endian { v.swap_bytes() } else { v }
}

/// Reads a u32 in DREP order from a 4-byte slice.
fn rd32(b: &[u8], little_endian: bool) -> u32 {
    let v = be32(b);
    if little_endian { v.swap_bytes() } else { v }
}

/// Writes a u16 in DREP order into a 2-byte slice.
fn wr16(b: &mut [u8], v: u16, little_endian: bool) {
    let bytes = if little_endian {
        v.to_le_bytes()
    } else {
        v.to_be_bytes()
    };
    b.copy_from_slice(&bytes);
}

/// Writes a u32 in DREP order into a 4-byte slice.
fn wr32(b: &mut [u8], v: u32, little_endian: bool) {
    let bytes = if little_endian {
        v.to_le_bytes()
    } else {
        v.to_be_bytes()
    };
    b.copy_from_slice(&bytes);
}

/// Reads a UUID in DREP order from a 16-byte slice.
fn rd_uuid(b: &[u8], little_endian: bool) -> Uuid {
    let mut a = [0u8; 16];
    a.copy_from_slice(b);
    Uuid::from_drep(&a, little_endian)
}

buffer_view! {
    /// A view of a connectionless DCE/RPC PDU: the 80-byte header and the body.
    pub struct Packet;
}

impl<T: AsRef<[u8]>> Packet<T> {
    /// Checks the buffer holds the header, RPCVersion is 4, the DREP integer representation
    /// is big- (0) or little-endian (1), and the buffer holds the LengthOfBody bytes the header
    /// announces. Bytes after the body are allowed and ignored.
    pub fn check_len(&self) -> Result<()> {
        let b = self.buffer.as_ref();
        if b.len() < HEADER_LEN
            || b[field::VERSION] != RPC_VERSION
            || b[field::DREP.start] >> 4 > 1
            || b.len() < HEADER_LEN + usize::from(self.body_len())
        {
            Err(Error)
        } else {
            Ok(())
        }
    }

    /// RPCVersion (4).
    pub fn version(&self) -> u8 {
        self.buffer.as_ref()[field::VERSION]
    }

    /// PacketType.
    pub fn packet_type(&self) -> PacketType {
        PacketType::from(self.buffer.as_ref()[field::PACKET_TYPE])
    }

    /// Flags1 ([`flags1`] bits).
    pub fn flags1(&self) -> u8 {
        self.buffer.as_ref()[field::FLAGS1]
    }

    /// Flags2 ([`flags2`] bits).
    pub fn flags2(&self) -> u8 {
        self.buffer.as_ref()[field::FLAGS2]
    }

    /// The three DREP bytes.
    pub fn drep(&self) -> [u8; 3] {
        let b = &self.buffer.as_ref()[field::DREP];
        [b[0], b[1], b[2]]
    }

    /// Whether integers and UUIDs are little-endian (DREP byte 0 high nibble 1).
    pub fn little_endian(&self) -> bool {
        self.buffer.as_ref()[field::DREP.start] >> 4 == 1
    }

    /// SerialHigh (byte 7).
    pub fn serial_high(&self) -> u8 {
        self.buffer.as_ref()[field::SERIAL_HIGH]
    }

    /// SerialLow (byte 79).
    pub fn serial_low(&self) -> u8 {
        self.buffer.as_ref()[field::SERIAL_LOW]
    }

    /// The serial number, SerialHigh << 8 | SerialLow.
    pub fn serial(&self) -> u16 {
        u16::from_be_bytes([self.serial_high(), self.serial_low()])
    }

    /// ObjectUUID.
    pub fn object_uuid(&self) -> Uuid {
        rd_uuid(&self.buffer.as_ref()[field::OBJECT], self.little_endian())
    }

    /// InterfaceUUID.
    pub fn interface_uuid(&self) -> Uuid {
        rd_uuid(
            &self.buffer.as_ref()[field::INTERFACE],
            self.little_endian(),
        )
    }

    /// ActivityUUID.
    pub fn activity_uuid(&self) -> Uuid {
        rd_uuid(&self.buffer.as_ref()[field::ACTIVITY], self.little_endian())
    }

    /// ServerBootTime (0 in requests).
    pub fn server_boot_time(&self) -> u32 {
        rd32(
            &self.buffer.as_ref()[field::SERVER_BOOT_TIME],
            self.little_endian(),
        )
    }

    /// InterfaceVersion (1 for PNIO).
    pub fn interface_version(&self) -> u32 {
        rd32(
            &self.buffer.as_ref()[field::INTERFACE_VERSION],
            self.little_endian(),
        )
    }

    /// SequenceNumber (per activity, +1 per call; echoed in the response).
    pub fn sequence_number(&self) -> u32 {
        rd32(
            &self.buffer.as_ref()[field::SEQUENCE_NUMBER],
            self.little_endian(),
        )
    }

    /// OpNum ([`opnum`]).
    pub fn opnum(&self) -> u16 {
        rd16(&self.buffer.as_ref()[field::OPNUM], self.little_endian())
    }

    /// InterfaceHint ([`NO_HINT`] usually).
    pub fn interface_hint(&self) -> u16 {
        rd16(
            &self.buffer.as_ref()[field::INTERFACE_HINT],
            self.little_endian(),
        )
    }

    /// ActivityHint ([`NO_HINT`] usually).
    pub fn activity_hint(&self) -> u16 {
        rd16(
            &self.buffer.as_ref()[field::ACTIVITY_HINT],
            self.little_endian(),
        )
    }

    /// LengthOfBody: bytes of body in this PDU (fragment).
    pub fn body_len(&self) -> u16 {
        rd16(&self.buffer.as_ref()[field::BODY_LEN], self.little_endian())
    }

    /// FragmentNumber.
    pub fn fragment_number(&self) -> u16 {
        rd16(
            &self.buffer.as_ref()[field::FRAGMENT_NUMBER],
            self.little_endian(),
        )
    }

    /// AuthProtocol (0).
    pub fn auth_protocol(&self) -> u8 {
        self.buffer.as_ref()[field::AUTH_PROTOCOL]
    }

    /// The body: exactly LengthOfBody bytes, trailing bytes excluded. Empty if the buffer is
    /// too short (never the case after `check_len`).
    pub fn body(&self) -> &[u8] {
        let b = self.buffer.as_ref();
        let end = HEADER_LEN + usize::from(self.body_len());
        b.get(field::BODY.start..end).unwrap_or(&[])
    }
}

impl<T: AsRef<[u8]> + AsMut<[u8]>> Packet<T> {
    /// Sets RPCVersion.
    pub fn set_version(&mut self, v: u8) {
        self.buffer.as_mut()[field::VERSION] = v;
    }

    /// Sets PacketType.
    pub fn set_packet_type(&mut self, v: PacketType) {
        self.buffer.as_mut()[field::PACKET_TYPE] = v.into();
    }

    /// Sets Flags1.
    pub fn set_flags1(&mut self, v: u8) {
        self.buffer.as_mut()[field::FLAGS1] = v;
    }

    /// Sets Flags2.
    pub fn set_flags2(&mut self, v: u8) {
        self.buffer.as_mut()[field::FLAGS2] = v;
    }

    /// Sets the DREP (ASCII characters, IEEE floats, integers as asked). Set it before the
    /// integer and UUID fields: their setters write in the buffer's current DREP.
    pub fn set_drep(&mut self, little_endian: bool) {
        let byte0 = if little_endian {
            DREP_LITTLE_ENDIAN
        } else {
            DREP_BIG_ENDIAN
        };
        self.buffer.as_mut()[field::DREP].copy_from_slice(&[byte0, 0, 0]);
    }

    /// Sets SerialHigh and SerialLow.
    pub fn set_serial(&mut self, v: u16) {
        let [high, low] = v.to_be_bytes();
        let b = self.buffer.as_mut();
        b[field::SERIAL_HIGH] = high;
        b[field::SERIAL_LOW] = low;
    }

    /// Sets ObjectUUID (in the buffer's DREP).
    pub fn set_object_uuid(&mut self, v: &Uuid) {
        let le = self.little_endian();
        self.buffer.as_mut()[field::OBJECT].copy_from_slice(&v.to_drep(le));
    }

    /// Sets InterfaceUUID (in the buffer's DREP).
    pub fn set_interface_uuid(&mut self, v: &Uuid) {
        let le = self.little_endian();
        self.buffer.as_mut()[field::INTERFACE].copy_from_slice(&v.to_drep(le));
    }

    /// Sets ActivityUUID (in the buffer's DREP).
    pub fn set_activity_uuid(&mut self, v: &Uuid) {
        let le = self.little_endian();
        self.buffer.as_mut()[field::ACTIVITY].copy_from_slice(&v.to_drep(le));
    }

    /// Sets ServerBootTime.
    pub fn set_server_boot_time(&mut self, v: u32) {
        let le = self.little_endian();
        wr32(&mut self.buffer.as_mut()[field::SERVER_BOOT_TIME], v, le);
    }

    /// Sets InterfaceVersion.
    pub fn set_interface_version(&mut self, v: u32) {
        let le = self.little_endian();
        wr32(&mut self.buffer.as_mut()[field::INTERFACE_VERSION], v, le);
    }

    /// Sets SequenceNumber.
    pub fn set_sequence_number(&mut self, v: u32) {
        let le = self.little_endian();
        wr32(&mut self.buffer.as_mut()[field::SEQUENCE_NUMBER], v, le);
    }

    /// Sets OpNum.
    pub fn set_opnum(&mut self, v: u16) {
        let le = self.little_endian();
        wr16(&mut self.buffer.as_mut()[field::OPNUM], v, le);
    }

    /// Sets InterfaceHint.
    pub fn set_interface_hint(&mut self, v: u16) {
        let le = self.little_endian();
        wr16(&mut self.buffer.as_mut()[field::INTERFACE_HINT], v, le);
    }

    /// Sets ActivityHint.
    pub fn set_activity_hint(&mut self, v: u16) {
        let le = self.little_endian();
        wr16(&mut self.buffer.as_mut()[field::ACTIVITY_HINT], v, le);
    }

    /// Sets LengthOfBody.
    pub fn set_body_len(&mut self, v: u16) {
        let le = self.little_endian();
        wr16(&mut self.buffer.as_mut()[field::BODY_LEN], v, le);
    }

    /// Sets FragmentNumber.
    pub fn set_fragment_number(&mut self, v: u16) {
        let le = self.little_endian();
        wr16(&mut self.buffer.as_mut()[field::FRAGMENT_NUMBER], v, le);
    }

    /// Sets AuthProtocol.
    pub fn set_auth_protocol(&mut self, v: u8) {
        self.buffer.as_mut()[field::AUTH_PROTOCOL] = v;
    }

    /// The body, mutable: LengthOfBody bytes (empty if the buffer is too short).
    pub fn body_mut(&mut self) -> &mut [u8] {
        let end = HEADER_LEN + usize::from(self.body_len());
        self.buffer
            .as_mut()
            .get_mut(field::BODY.start..end)
            .unwrap_or(&mut [])
    }
}

impl<T: AsRef<[u8]>> core::fmt::Display for Packet<T> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match Header::parse(self) {
            Ok(h) => write!(f, "{h}"),
            Err(_) => f.write_str("DCE/RPC (malformed)"),
        }
    }
}

/// The 80-byte connectionless RPC header as a value.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Header {
    /// PacketType.
    pub packet_type: PacketType,
    /// Flags1 ([`flags1`] bits).
    pub flags1: u8,
    /// Flags2 ([`flags2`] bits).
    pub flags2: u8,
    /// DREP: integers and UUID fields little-endian (DREP 0x10) or big-endian (0x00).
    pub little_endian: bool,
    /// Serial number (SerialHigh << 8 | SerialLow).
    pub serial: u16,
    /// ObjectUUID: the addressed station ([`object_uuid`]).
    pub object: Uuid,
    /// InterfaceUUID ([`DEVICE_INTERFACE`], [`CONTROLLER_INTERFACE`]…).
    pub interface: Uuid,
    /// ActivityUUID: the client's activity (one per AR for an S7).
    pub activity: Uuid,
    /// ServerBootTime (0 in requests).
    pub server_boot_time: u32,
    /// InterfaceVersion ([`PNIO_INTERFACE_VERSION`]).
    pub interface_version: u32,
    /// SequenceNumber (per activity, +1 per call).
    pub sequence_number: u32,
    /// OpNum ([`opnum`]).
    pub opnum: u16,
    /// InterfaceHint.
    pub interface_hint: u16,
    /// ActivityHint.
    pub activity_hint: u16,
    /// LengthOfBody. [`Pdu::emit`] computes it; [`Header::emit`] writes it as is.
    pub body_len: u16,
    /// FragmentNumber.
    pub fragment_number: u16,
    /// AuthProtocol (0).
    pub auth_protocol: u8,
}

impl Header {
    /// A PNIO request header: Idempotent, big-endian, no hints, interface version 1,
    /// ServerBootTime 0, body length 0 (set by [`Pdu::emit`]).
    pub const fn request(
        object: Uuid,
        interface: Uuid,
        activity: Uuid,
        sequence_number: u32,
        opnum: u16,
    ) -> Header {
        Header {
            packet_type: PacketType::Request,
            flags1: flags1::IDEMPOTENT,
            flags2: 0,
            little_endian: false,
            serial: 0,
            object,
            interface,
            activity,
            server_boot_time: 0,
            interface_version: PNIO_INTERFACE_VERSION,
            sequence_number,
            opnum,
            interface_hint: NO_HINT,
            activity_hint: NO_HINT,
            body_len: 0,
            fragment_number: 0,
            auth_protocol: 0,
        }
    }

    /// The header of the response to this request: echoes the object, interface and activity
    /// UUIDs, the interface version, sequence number, opnum and DREP; flags [`REPLY_FLAGS1`],
    /// no hints, serial and fragment number 0, body length 0 (set by [`Pdu::emit`]).
    pub const fn reply(&self, server_boot_time: u32) -> Header {
        Header {
            packet_type: PacketType::Response,
            flags1: REPLY_FLAGS1,
            flags2: 0,
            little_endian: self.little_endian,
            serial: 0,
            object: self.object,
            interface: self.interface,
            activity: self.activity,
            server_boot_time,
            interface_version: self.interface_version,
            sequence_number: self.sequence_number,
            opnum: self.opnum,
            interface_hint: NO_HINT,
            activity_hint: NO_HINT,
            body_len: 0,
            fragment_number: 0,
            auth_protocol: 0,
        }
    }

    /// Parses the header of a packet (checking its length first: see
    /// [`Packet::check_len`]).
    pub fn parse<T: AsRef<[u8]>>(packet: &Packet<T>) -> Result<Header> {
        packet.check_len()?;
        Ok(Header {
            packet_type: packet.packet_type(),
            flags1: packet.flags1(),
            flags2: packet.flags2(),
            little_endian: packet.little_endian(),
            serial: packet.serial(),
            object: packet.object_uuid(),
            interface: packet.interface_uuid(),
            activity: packet.activity_uuid(),
            server_boot_time: packet.server_boot_time(),
            interface_version: packet.interface_version(),
            sequence_number: packet.sequence_number(),
            opnum: packet.opnum(),
            interface_hint: packet.interface_hint(),
            activity_hint: packet.activity_hint(),
            body_len: packet.body_len(),
            fragment_number: packet.fragment_number(),
            auth_protocol: packet.auth_protocol(),
        })
    }

    /// Bytes of the header (80).
    pub const fn buffer_len(&self) -> usize {
        HEADER_LEN
    }

    /// Writes the 80 header bytes, in this header's DREP, into the start of `buf`; the body
    /// is left alone. A buffer shorter than 80 bytes gives [`EmitError::BufferTooShort`].
    pub fn emit(&self, buf: &mut [u8]) -> EmitResult<()> {
        let len = buf.len();
        let header = buf.get_mut(..HEADER_LEN).ok_or(EmitError::BufferTooShort {
            what: "RPC header",
            needed: HEADER_LEN,
            len,
        })?;
        let mut p = Packet::new_unchecked(header);
        p.set_version(RPC_VERSION);
        p.set_packet_type(self.packet_type);
        p.set_flags1(self.flags1);
        p.set_flags2(self.flags2);
        p.set_drep(self.little_endian);
        p.set_serial(self.serial);
        p.set_object_uuid(&self.object);
        p.set_interface_uuid(&self.interface);
        p.set_activity_uuid(&self.activity);
        p.set_server_boot_time(self.server_boot_time);
        p.set_interface_version(self.interface_version);
        p.set_sequence_number(self.sequence_number);
        p.set_opnum(self.opnum);
        p.set_interface_hint(self.interface_hint);
        p.set_activity_hint(self.activity_hint);
        p.set_body_len(self.body_len);
        p.set_fragment_number(self.fragment_number);
        p.set_auth_protocol(self.auth_protocol);
        Ok(())
    }

    /// Whether the Fragment flag is set.
    pub const fn is_fragment(&self) -> bool {
        self.flags1 & flags1::FRAGMENT != 0
    }
}

impl core::fmt::Display for Header {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "DCE/RPC {} ", self.packet_type)?;
        match opnum::name(self.opnum) {
            Some(name) => write!(f, "{name}")?,
            None => write!(f, "opnum {}", self.opnum)?,
        }
        write!(
            f,
            " seq {} act {} {} body {}",
            self.sequence_number,
            self.activity,
            if self.little_endian { "LE" } else { "BE" },
            self.body_len
        )
    }
}
