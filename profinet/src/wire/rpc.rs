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

use super::{Error, Field, PnioStatus, Rest, Result, Uuid, be16, be32};

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

/// The PacketType of a connectionless PDU.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PacketType {
    /// 0: request (a call).
    Request,
    /// 1: ping (client asks whether a call is still running).
    Ping,
    /// 2: response (the result of a call).
    Response,
    /// 3: fault (the call failed in the server; the body holds a status).
    Fault,
    /// 4: working (answer to a ping: still running).
    Working,
    /// 5: no-call (answer to a ping: no such call).
    NoCall,
    /// 6: reject (the call was refused, e.g. unknown interface; the body holds a status).
    Reject,
    /// 7: ack (client acknowledges a response of a non-idempotent call).
    Ack,
    /// 8: cancel (client cancels a call).
    ClCancel,
    /// 9: fragment ack.
    Fack,
    /// 10: cancel ack.
    CancelAck,
    /// Any other value (never 0..=10).
    Unknown(u8),
}

impl From<u8> for PacketType {
    fn from(v: u8) -> PacketType {
        match v {
            0 => PacketType::Request,
            1 => PacketType::Ping,
            2 => PacketType::Response,
            3 => PacketType::Fault,
            4 => PacketType::Working,
            5 => PacketType::NoCall,
            6 => PacketType::Reject,
            7 => PacketType::Ack,
            8 => PacketType::ClCancel,
            9 => PacketType::Fack,
            10 => PacketType::CancelAck,
            other => PacketType::Unknown(other),
        }
    }
}

impl From<PacketType> for u8 {
    fn from(v: PacketType) -> u8 {
        match v {
            PacketType::Request => 0,
            PacketType::Ping => 1,
            PacketType::Response => 2,
            PacketType::Fault => 3,
            PacketType::Working => 4,
            PacketType::NoCall => 5,
            PacketType::Reject => 6,
            PacketType::Ack => 7,
            PacketType::ClCancel => 8,
            PacketType::Fack => 9,
            PacketType::CancelAck => 10,
            PacketType::Unknown(other) => other,
        }
    }
}

impl core::fmt::Display for PacketType {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let name = match self {
            PacketType::Request => "request",
            PacketType::Ping => "ping",
            PacketType::Response => "response",
            PacketType::Fault => "fault",
            PacketType::Working => "working",
            PacketType::NoCall => "no-call",
            PacketType::Reject => "reject",
            PacketType::Ack => "ack",
            PacketType::ClCancel => "cancel",
            PacketType::Fack => "fack",
            PacketType::CancelAck => "cancel-ack",
            PacketType::Unknown(v) => return write!(f, "type {v:#04x}"),
        };
        f.write_str(name)
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

/// A view of a connectionless DCE/RPC PDU: the 80-byte header and the body.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Packet<T: AsRef<[u8]>> {
    buffer: T,
}

impl<T: AsRef<[u8]>> Packet<T> {
    /// Wraps a buffer without checking it.
    pub const fn new_unchecked(buffer: T) -> Packet<T> {
        Packet { buffer }
    }

    /// Wraps a buffer after [`check_len`](Self::check_len).
    pub fn new_checked(buffer: T) -> Result<Packet<T>> {
        let p = Packet::new_unchecked(buffer);
        p.check_len()?;
        Ok(p)
    }

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

    /// The buffer.
    pub fn into_inner(self) -> T {
        self.buffer
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
    /// is left alone. A buffer shorter than 80 bytes gives [`Error`].
    pub fn emit(&self, buf: &mut [u8]) -> Result<()> {
        let header = buf.get_mut(..HEADER_LEN).ok_or(Error)?;
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

mod ndr_field {
    use super::Field;
    /// ArgsMaximum (request) or PNIOStatus (response).
    pub const FIRST: Field = 0..4;
    pub const ARGS_LENGTH: Field = 4..8;
    pub const MAXIMUM_COUNT: Field = 8..12;
    pub const OFFSET: Field = 12..16;
    pub const ACTUAL_COUNT: Field = 16..20;
}

/// Bytes of an NDR request or response header.
pub const NDR_LEN: usize = ndr_field::ACTUAL_COUNT.end;

/// The five u32 of an NDR header, in DREP order, from the first 20 bytes of `b`.
fn parse_ndr_words(b: &[u8], little_endian: bool) -> Result<[u32; 5]> {
    let b = b.get(..NDR_LEN).ok_or(Error)?;
    Ok([
        rd32(&b[ndr_field::FIRST], little_endian),
        rd32(&b[ndr_field::ARGS_LENGTH], little_endian),
        rd32(&b[ndr_field::MAXIMUM_COUNT], little_endian),
        rd32(&b[ndr_field::OFFSET], little_endian),
        rd32(&b[ndr_field::ACTUAL_COUNT], little_endian),
    ])
}

/// Writes the five u32 of an NDR header, in DREP order, into the first 20 bytes of `b`.
fn emit_ndr_words(w: [u32; 5], b: &mut [u8], little_endian: bool) -> Result<()> {
    let b = b.get_mut(..NDR_LEN).ok_or(Error)?;
    wr32(&mut b[ndr_field::FIRST], w[0], little_endian);
    wr32(&mut b[ndr_field::ARGS_LENGTH], w[1], little_endian);
    wr32(&mut b[ndr_field::MAXIMUM_COUNT], w[2], little_endian);
    wr32(&mut b[ndr_field::OFFSET], w[3], little_endian);
    wr32(&mut b[ndr_field::ACTUAL_COUNT], w[4], little_endian);
    Ok(())
}

/// A length as an NDR u32, saturating (such a length never fits a PDU anyway).
fn len32(len: usize) -> u32 {
    u32::try_from(len).unwrap_or(u32::MAX)
}

/// The NDR header of a PNIO request (20 bytes, DREP order).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct NdrRequest {
    /// ArgsMaximum: the response size the client accepts.
    pub args_maximum: u32,
    /// ArgsLength: bytes of PNIO blocks.
    pub args_length: u32,
    /// MaximumCount (= ArgsMaximum).
    pub maximum_count: u32,
    /// Offset (0).
    pub offset: u32,
    /// ActualCount (= ArgsLength).
    pub actual_count: u32,
}

impl NdrRequest {
    /// The header of a request carrying `blocks_len` bytes of blocks and accepting responses
    /// of up to `args_maximum` bytes: MaximumCount = ArgsMaximum, Offset 0, ArgsLength =
    /// ActualCount = `blocks_len` (saturated to `u32::MAX`).
    pub const fn for_blocks(args_maximum: u32, blocks_len: usize) -> NdrRequest {
        let len = if blocks_len > u32::MAX as usize {
            u32::MAX
        } else {
            blocks_len as u32
        };
        NdrRequest {
            args_maximum,
            args_length: len,
            maximum_count: args_maximum,
            offset: 0,
            actual_count: len,
        }
    }

    /// Parses the first 20 bytes of `b` in the given DREP; a shorter `b` gives [`Error`].
    pub fn parse(b: &[u8], little_endian: bool) -> Result<NdrRequest> {
        let [
            args_maximum,
            args_length,
            maximum_count,
            offset,
            actual_count,
        ] = parse_ndr_words(b, little_endian)?;
        Ok(NdrRequest {
            args_maximum,
            args_length,
            maximum_count,
            offset,
            actual_count,
        })
    }

    /// Bytes of the header (20).
    pub const fn buffer_len(&self) -> usize {
        NDR_LEN
    }

    /// Writes the 20 bytes into the start of `b` in the given DREP; a shorter `b` gives
    /// [`Error`].
    pub fn emit(&self, b: &mut [u8], little_endian: bool) -> Result<()> {
        let w = [
            self.args_maximum,
            self.args_length,
            self.maximum_count,
            self.offset,
            self.actual_count,
        ];
        emit_ndr_words(w, b, little_endian)
    }

    /// Whether the header is what [`for_blocks`](Self::for_blocks) would build for
    /// `blocks_len` bytes of blocks (the shape p-net and the S7 send and check).
    pub fn is_consistent(&self, blocks_len: usize) -> bool {
        *self == NdrRequest::for_blocks(self.args_maximum, blocks_len)
    }
}

/// The NDR header of a PNIO response (20 bytes, DREP order).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct NdrResponse {
    /// PNIOStatus: a u32 in DREP order with ErrorCode most significant (a little-endian
    /// response stores ErrorCode2 first).
    pub status: PnioStatus,
    /// ArgsLength: bytes of PNIO blocks.
    pub args_length: u32,
    /// MaximumCount: echoes the request's ArgsMaximum.
    pub maximum_count: u32,
    /// Offset (0).
    pub offset: u32,
    /// ActualCount (= ArgsLength).
    pub actual_count: u32,
}

impl NdrResponse {
    /// The header of a response carrying `blocks_len` bytes of blocks to a request whose
    /// ArgsMaximum was `args_maximum`: MaximumCount = that ArgsMaximum, Offset 0, ArgsLength =
    /// ActualCount = `blocks_len` (saturated to `u32::MAX`).
    pub const fn for_blocks(
        status: PnioStatus,
        args_maximum: u32,
        blocks_len: usize,
    ) -> NdrResponse {
        let r = NdrRequest::for_blocks(args_maximum, blocks_len);
        NdrResponse {
            status,
            args_length: r.args_length,
            maximum_count: args_maximum,
            offset: 0,
            actual_count: r.actual_count,
        }
    }

    /// Parses the first 20 bytes of `b` in the given DREP; a shorter `b` gives [`Error`].
    pub fn parse(b: &[u8], little_endian: bool) -> Result<NdrResponse> {
        let [status, args_length, maximum_count, offset, actual_count] =
            parse_ndr_words(b, little_endian)?;
        Ok(NdrResponse {
            status: PnioStatus::from_u32(status),
            args_length,
            maximum_count,
            offset,
            actual_count,
        })
    }

    /// Bytes of the header (20).
    pub const fn buffer_len(&self) -> usize {
        NDR_LEN
    }

    /// Writes the 20 bytes into the start of `b` in the given DREP; a shorter `b` gives
    /// [`Error`].
    pub fn emit(&self, b: &mut [u8], little_endian: bool) -> Result<()> {
        let w = [
            self.status.to_u32(),
            self.args_length,
            self.maximum_count,
            self.offset,
            self.actual_count,
        ];
        emit_ndr_words(w, b, little_endian)
    }

    /// Whether ArgsLength = ActualCount = `blocks_len`, Offset is 0 and ArgsLength does not
    /// exceed MaximumCount (the shape p-net and the S7 send and check).
    pub fn is_consistent(&self, blocks_len: usize) -> bool {
        let len = len32(blocks_len);
        self.args_length == len
            && self.actual_count == len
            && self.offset == 0
            && self.args_length <= self.maximum_count
    }
}

/// The NDR header of a PNIO call, by packet type: a request or a response.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Ndr {
    /// The header of a request (PacketType 0).
    Request(NdrRequest),
    /// The header of a response (PacketType 2).
    Response(NdrResponse),
}

impl Ndr {
    /// Parses the NDR header at the start of a body of this packet type: requests and
    /// responses only; other packet types or fewer than 20 bytes give [`Error`].
    pub fn parse(packet_type: PacketType, b: &[u8], little_endian: bool) -> Result<Ndr> {
        match packet_type {
            PacketType::Request => NdrRequest::parse(b, little_endian).map(Ndr::Request),
            PacketType::Response => NdrResponse::parse(b, little_endian).map(Ndr::Response),
            _ => Err(Error),
        }
    }

    /// The packet type that carries this header.
    pub const fn packet_type(&self) -> PacketType {
        match self {
            Ndr::Request(_) => PacketType::Request,
            Ndr::Response(_) => PacketType::Response,
        }
    }

    /// ArgsLength.
    pub const fn args_length(&self) -> u32 {
        match self {
            Ndr::Request(r) => r.args_length,
            Ndr::Response(r) => r.args_length,
        }
    }

    /// ActualCount.
    pub const fn actual_count(&self) -> u32 {
        match self {
            Ndr::Request(r) => r.actual_count,
            Ndr::Response(r) => r.actual_count,
        }
    }

    /// MaximumCount.
    pub const fn maximum_count(&self) -> u32 {
        match self {
            Ndr::Request(r) => r.maximum_count,
            Ndr::Response(r) => r.maximum_count,
        }
    }

    /// The PNIOStatus of a response; `None` for a request.
    pub const fn status(&self) -> Option<PnioStatus> {
        match self {
            Ndr::Request(_) => None,
            Ndr::Response(r) => Some(r.status),
        }
    }

    /// Bytes of the header (20).
    pub const fn buffer_len(&self) -> usize {
        NDR_LEN
    }

    /// Writes the 20 bytes into the start of `b` in the given DREP; a shorter `b` gives
    /// [`Error`].
    pub fn emit(&self, b: &mut [u8], little_endian: bool) -> Result<()> {
        match self {
            Ndr::Request(r) => r.emit(b, little_endian),
            Ndr::Response(r) => r.emit(b, little_endian),
        }
    }

    /// Whether the header has the shape p-net and the S7 send for `blocks_len` bytes of
    /// blocks (see [`NdrRequest::is_consistent`], [`NdrResponse::is_consistent`]).
    pub fn is_consistent(&self, blocks_len: usize) -> bool {
        match self {
            Ndr::Request(r) => r.is_consistent(blocks_len),
            Ndr::Response(r) => r.is_consistent(blocks_len),
        }
    }
}

/// Splits a whole (unfragmented or reassembled) request or response body into its NDR header
/// and the block bytes after it. The blocks are everything after the 20 NDR bytes; whether
/// ArgsLength agrees is left to the caller ([`Ndr::is_consistent`]).
pub fn parse_body(
    packet_type: PacketType,
    little_endian: bool,
    body: &[u8],
) -> Result<(Ndr, &[u8])> {
    let (ndr, blocks) = body.split_at_checked(NDR_LEN).ok_or(Error)?;
    Ok((Ndr::parse(packet_type, ndr, little_endian)?, blocks))
}

/// A whole unfragmented PNIO request or response: RPC header, NDR header and PNIO block bytes
/// (big-endian, not interpreted here).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pdu<'a> {
    /// The RPC header. Its `packet_type` matches `ndr`; its `body_len` is 20 + the blocks
    /// after parsing and is ignored (recomputed) on emission.
    pub header: Header,
    /// The NDR header.
    pub ndr: Ndr,
    /// The PNIO blocks: the body after the NDR header.
    pub blocks: &'a [u8],
}

impl<'a> Pdu<'a> {
    /// Parses a request or response PDU (the UDP payload). Other packet types, PDUs with the
    /// Fragment flag (reassemble them and use [`parse_body`]), a body shorter than the NDR
    /// header or a malformed header give [`Error`]. Bytes after LengthOfBody are ignored.
    pub fn parse(bytes: &'a [u8]) -> Result<Pdu<'a>> {
        let header = Header::parse(&Packet::new_unchecked(bytes))?;
        if header.is_fragment() {
            return Err(Error);
        }
        let body = bytes
            .get(HEADER_LEN..HEADER_LEN + usize::from(header.body_len))
            .ok_or(Error)?;
        let (ndr, blocks) = parse_body(header.packet_type, header.little_endian, body)?;
        Ok(Pdu {
            header,
            ndr,
            blocks,
        })
    }

    /// Bytes of the body: 20 + the blocks.
    pub fn body_len(&self) -> usize {
        NDR_LEN.saturating_add(self.blocks.len())
    }

    /// Bytes of the PDU: 80 + 20 + the blocks.
    pub fn buffer_len(&self) -> usize {
        HEADER_LEN.saturating_add(self.body_len())
    }

    /// Writes the PDU into the first [`buffer_len`](Self::buffer_len) bytes of `buf`, header
    /// and NDR header in the header's DREP, LengthOfBody computed from the blocks. Never
    /// panics: a short buffer, a body above 65535 bytes, the Fragment flag, or a packet type
    /// that does not match the NDR header give [`Error`].
    pub fn emit(&self, buf: &mut [u8]) -> Result<()> {
        if self.header.packet_type != self.ndr.packet_type() || self.header.is_fragment() {
            return Err(Error);
        }
        let body_len = u16::try_from(self.body_len()).map_err(|_| Error)?;
        let pdu = buf.get_mut(..self.buffer_len()).ok_or(Error)?;
        let (header, body) = pdu.split_at_mut(HEADER_LEN);
        Header {
            body_len,
            ..self.header
        }
        .emit(header)?;
        let (ndr, blocks) = body.split_at_mut(NDR_LEN);
        self.ndr.emit(ndr, self.header.little_endian)?;
        blocks.copy_from_slice(self.blocks);
        Ok(())
    }

    /// The PDU as a new vector of [`buffer_len`](Self::buffer_len) bytes.
    pub fn to_vec(&self) -> Result<Vec<u8>> {
        let mut v = vec![0u8; self.buffer_len()];
        self.emit(&mut v)?;
        Ok(v)
    }
}

/// Parses a request or response PDU into its header, NDR header and block bytes (see
/// [`Pdu::parse`]).
pub fn parse_pdu(bytes: &[u8]) -> Result<(Header, Ndr, &[u8])> {
    Pdu::parse(bytes).map(|p| (p.header, p.ndr, p.blocks))
}

/// A request PDU: `header` (its packet type forced to request, its body length computed), an
/// NDR header from [`NdrRequest::for_blocks`] and the blocks. A body above 65535 bytes or the
/// Fragment flag give [`Error`].
pub fn emit_request(header: &Header, args_maximum: u32, blocks: &[u8]) -> Result<Vec<u8>> {
    Pdu {
        header: Header {
            packet_type: PacketType::Request,
            ..*header
        },
        ndr: Ndr::Request(NdrRequest::for_blocks(args_maximum, blocks.len())),
        blocks,
    }
    .to_vec()
}

/// Body bytes of one fragment: [`MAX_PDU_LEN`] − 80, the fragment size p-net and the S7 use.
pub const MAX_FRAGMENT_BODY: usize = MAX_PDU_LEN - HEADER_LEN;

/// The PDU `header` describes with `body` after it: LengthOfBody set, the header in its
/// DREP. A body above 65535 bytes gives [`Error`].
pub fn emit_with_body(header: &Header, body: &[u8]) -> Result<Vec<u8>> {
    let body_len = u16::try_from(body.len()).map_err(|_| Error)?;
    let mut v = vec![0u8; HEADER_LEN + body.len()];
    Header {
        body_len,
        ..*header
    }
    .emit(&mut v)?;
    v[HEADER_LEN..].copy_from_slice(body);
    Ok(v)
}

/// The PDUs that carry `body` under `header`: one when it fits [`MAX_FRAGMENT_BODY`], else
/// fragments numbered from 0 with the Fragment flag, LastFragment on the last, and NoFack
/// when `no_fack` (the receiver need not acknowledge them).
pub fn fragments(header: &Header, body: &[u8], no_fack: bool) -> Result<Vec<Vec<u8>>> {
    if body.len() <= MAX_FRAGMENT_BODY {
        return Ok(vec![emit_with_body(header, body)?]);
    }
    let count = body.len().div_ceil(MAX_FRAGMENT_BODY);
    body.chunks(MAX_FRAGMENT_BODY)
        .enumerate()
        .map(|(i, chunk)| {
            // LastFragment belongs to the last fragment only and NoFack is the caller's
            // choice, whatever the header (a reply header carries both).
            let base = header.flags1 & !(flags1::LAST_FRAGMENT | flags1::NO_FACK);
            let mut f = base | flags1::FRAGMENT;
            if i + 1 == count {
                f |= flags1::LAST_FRAGMENT;
            }
            if no_fack {
                f |= flags1::NO_FACK;
            }
            let h = Header {
                flags1: f,
                fragment_number: u16::try_from(i).map_err(|_| Error)?,
                ..*header
            };
            emit_with_body(&h, chunk)
        })
        .collect()
}

/// A FACK for the fragment whose header is `fragment`: its fragment number and serial, the
/// given boot time, and the body (in the fragment's DREP) version 0, pad, `window` (fragments
/// the sender may send ahead), `max_tsdu` (largest whole body taken), `max_frag` (largest
/// fragment PDU taken), serial number and an empty selective-ack list.
pub fn fack(
    fragment: &Header,
    boot_time: u32,
    window: u16,
    max_tsdu: u32,
    max_frag: u32,
) -> Result<Vec<u8>> {
    let h = Header {
        packet_type: PacketType::Fack,
        flags1: 0,
        fragment_number: fragment.fragment_number,
        ..fragment.reply(boot_time)
    };
    let le = fragment.little_endian;
    let u16b = |v: u16| if le { v.to_le_bytes() } else { v.to_be_bytes() };
    let u32b = |v: u32| if le { v.to_le_bytes() } else { v.to_be_bytes() };
    let mut body = vec![0u8, 0];
    body.extend_from_slice(&u16b(window));
    body.extend_from_slice(&u32b(max_tsdu));
    body.extend_from_slice(&u32b(max_frag));
    body.extend_from_slice(&u16b(fragment.serial));
    body.extend_from_slice(&u16b(0));
    emit_with_body(&h, &body)
}

/// A response PDU: `header` (its packet type forced to response, its body length computed;
/// see [`Header::reply`]), an NDR header from [`NdrResponse::for_blocks`] with the request's
/// ArgsMaximum, and the blocks. A body above 65535 bytes or the Fragment flag give [`Error`].
pub fn emit_response(
    header: &Header,
    status: PnioStatus,
    request_args_maximum: u32,
    blocks: &[u8],
) -> Result<Vec<u8>> {
    Pdu {
        header: Header {
            packet_type: PacketType::Response,
            ..*header
        },
        ndr: Ndr::Response(NdrResponse::for_blocks(
            status,
            request_args_maximum,
            blocks.len(),
        )),
        blocks,
    }
    .to_vec()
}

/// A PNIOStatus in words, e.g. "Connect refused: IOCRBlockReq field 9 (FrameID)" or
/// "Read failed: access: invalid index"; values this module does not know print in hex.
pub fn describe(status: PnioStatus) -> String {
    StatusText(status).to_string()
}

/// Displays a PNIOStatus in words (see [`describe`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct StatusText(pub PnioStatus);

impl core::fmt::Display for StatusText {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let s = self.0;
        if s.is_ok() {
            return f.write_str("OK");
        }
        match service_name(s.error_code) {
            Some(name) => f.write_str(name)?,
            None => write!(f, "ErrorCode {:#04x}", s.error_code)?,
        }
        f.write_str(": ")?;
        let (c1, c2) = (s.error_code1, s.error_code2);
        match s.error_decode {
            0x80 => describe_pniorw(f, c1, c2),
            0x81 => describe_pnio(f, c1, c2),
            0x82 => write!(f, "manufacturer specific {c1:#04x} {c2:#04x}"),
            d => write!(
                f,
                "ErrorDecode {d:#04x}, ErrorCode1 {c1:#04x}, ErrorCode2 {c2:#04x}"
            ),
        }
    }
}

/// The service an ErrorCode belongs to, as the start of a sentence.
const fn service_name(error_code: u8) -> Option<&'static str> {
    Some(match error_code {
        0x81 => "PNIO error",
        0xcf => "RTA error",
        0xda => "AlarmAck failed",
        0xdb => "Connect refused",
        0xdc => "Release refused",
        0xdd => "Control refused",
        0xde => "Read failed",
        0xdf => "Write failed",
        _ => return None,
    })
}

/// ErrorDecode 0x80 (PNIORW): ErrorCode1 = class (high nibble) and code (low nibble),
/// ErrorCode2 user specific.
fn describe_pniorw(f: &mut core::fmt::Formatter<'_>, c1: u8, c2: u8) -> core::fmt::Result {
    let code = c1 & 0x0f;
    let (class, what) = match c1 >> 4 {
        0xa => (
            "application",
            match code {
                0x0 => Some("read error"),
                0x1 => Some("write error"),
                0x2 => Some("module failure"),
                0x7 => Some("busy"),
                0x8 => Some("version conflict"),
                0x9 => Some("feature not supported"),
                _ => None,
            },
        ),
        0xb => (
            "access",
            match code {
                0x0 => Some("invalid index"),
                0x1 => Some("write length error"),
                0x2 => Some("invalid slot/subslot"),
                0x3 => Some("type conflict"),
                0x4 => Some("invalid area/API"),
                0x5 => Some("state conflict"),
                0x6 => Some("access denied"),
                0x7 => Some("invalid range"),
                0x8 => Some("invalid parameter"),
                0x9 => Some("invalid type"),
                0xa => Some("backup"),
                _ => None,
            },
        ),
        0xc => (
            "resource",
            match code {
                0x0 => Some("read constrain conflict"),
                0x1 => Some("write constrain conflict"),
                0x2 => Some("resource busy"),
                0x3 => Some("resource unavailable"),
                _ => None,
            },
        ),
        _ => ("", None),
    };
    match (class, what) {
        ("", _) => write!(f, "ErrorCode1 {c1:#04x}")?,
        (class, Some(what)) => write!(f, "{class}: {what}")?,
        (class, None) => write!(f, "{class} error {c1:#04x}")?,
    }
    if c2 != 0 {
        write!(f, ", user code {c2:#04x}")?;
    }
    Ok(())
}

/// The fields every block starts with, numbered 0..=3 in PNIO field indices.
const BLOCK_HEADER_FIELDS: [&str; 4] = [
    "BlockType",
    "BlockLength",
    "BlockVersionHigh",
    "BlockVersionLow",
];

/// ARBlockReq fields from index 4 on.
const AR_FIELDS: &[&str] = &[
    "ARType",
    "ARUUID",
    "SessionKey",
    "CMInitiatorMacAdd",
    "CMInitiatorObjectUUID",
    "ARProperties",
    "CMInitiatorActivityTimeoutFactor",
    "CMInitiatorUDPRTPort",
    "StationNameLength",
    "CMInitiatorStationName",
];

/// IOCRBlockReq fields from index 4 on.
const IOCR_FIELDS: &[&str] = &[
    "IOCRType",
    "IOCRReference",
    "LT",
    "IOCRProperties",
    "DataLength",
    "FrameID",
    "SendClockFactor",
    "ReductionRatio",
    "Phase",
    "Sequence",
    "FrameSendOffset",
    "WatchdogFactor",
    "DataHoldFactor",
    "IOCRTagHeader",
    "IOCRMulticastMACAdd",
    "NumberOfAPIs",
    "API",
    "NumberOfIODataObjects",
    "SlotNumber",
    "SubslotNumber",
    "IODataObjectFrameOffset",
    "NumberOfIOCS",
    "SlotNumber",
    "SubslotNumber",
    "IOCSFrameOffset",
];

/// ExpectedSubmoduleBlockReq fields from index 4 on.
const EXPECTED_SUBMODULE_FIELDS: &[&str] = &[
    "NumberOfAPIs",
    "API",
    "SlotNumber",
    "ModuleIdentNumber",
    "ModuleProperties",
    "NumberOfSubmodules",
    "SubslotNumber",
    "SubmoduleIdentNumber",
    "SubmoduleProperties",
    "DataDescription",
    "SubmoduleDataLength",
    "LengthIOCS",
    "LengthIOPS",
];

/// AlarmCRBlockReq fields from index 4 on.
const ALARM_CR_FIELDS: &[&str] = &[
    "AlarmCRType",
    "LT",
    "AlarmCRProperties",
    "RTATimeoutFactor",
    "RTARetries",
    "LocalAlarmReference",
    "MaxAlarmDataLength",
    "AlarmCRTagHeaderHigh",
    "AlarmCRTagHeaderLow",
];

/// The name of a Connect request block (ErrorCode1 with ErrorDecode PNIO) and its fields
/// after the block header, in layout order.
const fn connect_block(c1: u8) -> Option<(&'static str, &'static [&'static str])> {
    Some(match c1 {
        0x01 => ("ARBlockReq", AR_FIELDS),
        0x02 => ("IOCRBlockReq", IOCR_FIELDS),
        0x03 => ("ExpectedSubmoduleBlockReq", EXPECTED_SUBMODULE_FIELDS),
        0x04 => ("AlarmCRBlockReq", ALARM_CR_FIELDS),
        0x05 => ("PrmServerBlockReq", &[]),
        0x06 => ("MCRBlockReq", &[]),
        0x07 => ("ARRPCBlockReq", &[]),
        0x0c => ("ARVendorBlockReq", &[]),
        _ => return None,
    })
}

/// ErrorCode2 of CMRPC (ErrorCode1 0x40).
const fn cmrpc_reason(c2: u8) -> Option<&'static str> {
    Some(match c2 {
        0 => "invalid NDR ArgsLength",
        1 => "unknown blocks",
        2 => "IOCR missing",
        3 => "wrong block count",
        4 => "out of AR resources",
        5 => "AR UUID unknown",
        6 => "state conflict",
        9 => "PDev already owned",
        _ => return None,
    })
}

/// ErrorCode2 of an AR abort (ErrorCode1 0xFD, e.g. in an ERR-RTA PDU `CF 81 FD xx`).
const fn abort_reason(c2: u8) -> Option<&'static str> {
    Some(match c2 {
        0x01 => "alarm sequence number error",
        0x02 => "instance closed",
        0x03 => "out of memory",
        0x05 => "consumer data hold timer expired",
        0x06 => "CM initiator activity timeout",
        0x0b => "alarm indication with error",
        0x0c => "RPC client call failed",
        0x0d => "abort requested",
        0x0e => "re-run aborts the existing AR",
        0x0f => "release indication received",
        0x12 => "protocol violation",
        0x1b => "link down",
        0x1f => "station name changed by DCP",
        0x20 => "reset to factory by DCP",
        0x24 => "PDEV check failed",
        0x25 => "IP address changed by DCP",
        _ => return None,
    })
}

/// ErrorDecode 0x81 (PNIO): ErrorCode1 = faulty block or protocol machine, ErrorCode2 =
/// field index or reason.
fn describe_pnio(f: &mut core::fmt::Formatter<'_>, c1: u8, c2: u8) -> core::fmt::Result {
    if let Some((block, fields)) = connect_block(c1) {
        write!(f, "{block} field {c2}")?;
        let i = usize::from(c2);
        let name = match i.checked_sub(BLOCK_HEADER_FIELDS.len()) {
            None => BLOCK_HEADER_FIELDS.get(i),
            Some(j) => fields.get(j),
        };
        if let Some(name) = name {
            write!(f, " ({name})")?;
        }
        return Ok(());
    }
    match c1 {
        0x08 => write!(f, "faulty record, field {c2}"),
        0x3d => write!(f, "device CM state machine (CMDEV), code {c2:#04x}"),
        0x40 => match cmrpc_reason(c2) {
            Some(r) => write!(f, "CMRPC: {r}"),
            None => write!(f, "CMRPC code {c2:#04x}"),
        },
        0xfd => match abort_reason(c2) {
            Some(r) => write!(f, "AR abort: {r}"),
            None => write!(f, "AR abort, code {c2:#04x}"),
        },
        _ => write!(f, "ErrorCode1 {c1:#04x}, ErrorCode2 {c2:#04x}"),
    }
}

#[cfg(test)]
mod tests {
    use super::super::BlockHeader;
    use super::*;
    use proptest::prelude::*;

    // The captures below come from the test data of the `pnio` crate 0.1.0
    // (core-engineering/pnio-rs, MIT OR Apache-2.0): an S7-1515 talking to the p-net sample
    // device. Each is the UDP payload (the RPC PDU), i.e. bytes 42.. of the Ethernet frame in
    // /work/shared/captures (14 Ethernet + 20 IPv4 + 8 UDP), as hex text.

    /// captures/cm/connect_req.hex, bytes 42.. (657 bytes): frame 50: CPU Connect request, DREP LE, 699 bytes (RPC PDU at offset 42)
    const CONNECT_REQ: &str = "\
        04 00 20 00 10 00 00 00 00 00 a0 de 97 6c d1 11 \
        82 71 00 01 00 02 04 93 01 00 a0 de 97 6c d1 11 \
        82 71 00 a0 24 42 df 7d ae a1 ac d2 32 00 10 10 \
        b0 58 ec 1c 5d 61 e7 3f 00 00 00 00 01 00 00 00 \
        00 00 00 00 00 00 ff ff ff ff 41 02 00 00 00 00 \
        2d 02 00 00 2d 02 00 00 2d 02 00 00 00 00 00 00 \
        2d 02 00 00 01 01 00 5b 01 00 00 01 e5 e1 ae cc \
        b1 33 4b 4d b1 87 cc 68 b0 21 1e d2 00 02 ec 1c \
        5d 61 e7 3f de a0 00 00 6c 97 11 d1 82 71 10 64 \
        01 0e 00 2a 40 00 00 11 00 c8 88 92 00 25 70 6c \
        63 78 62 62 65 6e 63 68 2e 70 72 6f 66 69 6e 65 \
        74 78 61 69 6e 74 65 72 66 61 63 65 78 62 32 35 \
        66 62 64 01 02 00 68 01 00 00 01 00 01 88 92 00 \
        00 00 02 00 28 80 00 00 20 00 20 00 01 00 00 ff \
        ff ff ff 00 03 00 03 c0 00 00 00 00 00 00 00 00 \
        01 00 00 00 00 00 06 00 00 00 01 00 00 00 00 80 \
        00 00 01 00 00 80 01 00 02 00 01 00 01 00 03 00 \
        03 00 01 00 06 00 04 00 01 00 09 00 03 00 02 00 \
        01 00 05 00 03 00 01 00 08 00 04 00 01 00 12 01 \
        02 00 68 01 00 00 02 00 02 88 92 00 00 00 02 00 \
        28 80 01 00 20 00 20 00 01 00 00 ff ff ff ff 00 \
        03 00 03 c0 00 00 00 00 00 00 00 00 01 00 00 00 \
        00 00 03 00 02 00 01 00 04 00 03 00 01 00 07 00 \
        04 00 01 00 0a 00 06 00 00 00 01 00 00 00 00 80 \
        00 00 01 00 00 80 01 00 02 00 01 00 01 00 03 00 \
        03 00 01 00 06 00 04 00 01 00 09 01 04 00 3c 01 \
        00 00 01 00 00 00 00 00 00 00 00 00 01 00 00 00 \
        03 00 01 00 00 00 01 00 00 00 01 00 00 01 01 80 \
        00 00 00 80 00 00 00 00 01 00 00 01 01 80 01 00 \
        00 80 01 00 00 00 01 00 00 01 01 01 04 00 20 01 \
        00 00 01 00 00 00 00 00 01 00 00 00 30 00 00 00 \
        01 00 01 00 00 01 30 00 01 00 01 00 01 01 01 01 \
        04 00 20 01 00 00 01 00 00 00 00 00 02 00 00 00 \
        31 00 00 00 01 00 01 00 00 01 31 00 02 00 02 00 \
        01 01 01 01 04 00 26 01 00 00 01 00 00 00 00 00 \
        03 00 00 00 32 00 00 00 01 00 01 00 00 01 32 00 \
        03 00 01 00 01 01 01 00 02 00 01 01 01 01 04 00 \
        26 01 00 00 01 00 00 00 00 00 04 00 00 00 40 00 \
        00 00 01 00 01 00 00 01 40 00 03 00 01 00 08 01 \
        01 00 02 00 08 01 01 01 03 00 16 01 00 00 01 88 \
        92 00 00 00 00 00 01 00 03 00 00 01 00 c0 00 a0 \
        00";

    /// captures/cm/connect_res.hex, bytes 42.. (190 bytes): frame 53: p-net Connect response, DREP BE, 232 bytes (RPC PDU at offset 42)
    const CONNECT_RES: &str = "\
        04 02 28 00 00 00 00 00 de a0 00 00 6c 97 11 d1 \
        82 71 00 01 00 02 04 93 de a0 00 01 6c 97 11 d1 \
        82 71 00 a0 24 42 df 7d d2 ac a1 ae 00 32 10 10 \
        b0 58 ec 1c 5d 61 e7 3f 00 00 00 00 00 00 00 01 \
        00 00 00 00 00 00 ff ff ff ff 00 6e 00 00 00 00 \
        00 00 00 00 00 00 00 5a 00 00 02 2d 00 00 00 00 \
        00 00 00 5a 81 01 00 1e 01 00 00 01 e5 e1 ae cc \
        b1 33 4b 4d b1 87 cc 68 b0 21 1e d2 00 02 8c f3 \
        19 cd 19 f8 88 92 81 02 00 08 01 00 00 01 00 01 \
        80 00 81 02 00 08 01 00 00 02 00 02 80 01 81 03 \
        00 08 01 00 00 01 00 00 00 c8 81 06 00 10 01 00 \
        00 0b 72 74 2d 6c 61 62 73 2d 64 65 76 00";

    /// captures/cm/write_req.hex, bytes 42.. (444 bytes): frame 54: CPU Write MultipleWrite, DREP LE, 486 bytes
    const WRITE_REQ: &str = "\
        04 00 20 00 10 00 00 00 00 00 a0 de 97 6c d1 11 \
        82 71 00 01 00 02 04 93 01 00 a0 de 97 6c d1 11 \
        82 71 00 a0 24 42 df 7d ae a1 ac d2 32 00 10 10 \
        b0 58 ec 1c 5d 61 e7 3f 00 00 00 00 01 00 00 00 \
        01 00 00 00 03 00 ff ff ff ff 6c 01 00 00 00 00 \
        58 01 00 00 58 01 00 00 58 01 00 00 00 00 00 00 \
        58 01 00 00 00 08 00 3c 01 00 00 00 e5 e1 ae cc \
        b1 33 4b 4d b1 87 cc 68 b0 21 1e d2 ff ff ff ff \
        ff ff ff ff 00 00 e0 40 00 00 01 18 00 00 00 00 \
        00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 \
        00 00 00 00 00 08 00 3c 01 00 00 01 e5 e1 ae cc \
        b1 33 4b 4d b1 87 cc 68 b0 21 1e d2 00 00 00 00 \
        00 00 80 00 00 00 80 71 00 00 00 0c 00 00 00 00 \
        00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 \
        00 00 00 00 02 50 00 08 01 00 00 00 00 00 00 01 \
        00 08 00 3c 01 00 00 02 e5 e1 ae cc b1 33 4b 4d \
        b1 87 cc 68 b0 21 1e d2 00 00 00 00 00 03 00 01 \
        00 00 00 7b 00 00 00 04 00 00 00 00 00 00 00 00 \
        00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 \
        00 00 00 01 00 08 00 3c 01 00 00 03 e5 e1 ae cc \
        b1 33 4b 4d b1 87 cc 68 b0 21 1e d2 00 00 00 00 \
        00 03 00 01 00 00 00 7c 00 00 00 04 00 00 00 00 \
        00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 \
        00 00 00 00 00 00 00 02 00 08 00 3c 01 00 00 04 \
        e5 e1 ae cc b1 33 4b 4d b1 87 cc 68 b0 21 1e d2 \
        00 00 00 00 00 04 00 01 00 00 00 7d 00 00 00 04 \
        00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 \
        00 00 00 00 00 00 00 00 00 00 00 02";

    /// captures/cm/write_res.hex, bytes 42.. (420 bytes): frame 56: p-net Write response, DREP BE, 462 bytes
    const WRITE_RES: &str = "\
        04 02 28 00 00 00 00 00 de a0 00 00 6c 97 11 d1 \
        82 71 00 01 00 02 04 93 de a0 00 01 6c 97 11 d1 \
        82 71 00 a0 24 42 df 7d d2 ac a1 ae 00 32 10 10 \
        b0 58 ec 1c 5d 61 e7 3f 00 00 00 00 00 00 00 01 \
        00 00 00 01 00 03 ff ff ff ff 01 54 00 00 00 00 \
        00 00 00 00 00 00 01 40 00 00 01 58 00 00 00 00 \
        00 00 01 40 80 08 00 3c 01 00 00 00 e5 e1 ae cc \
        b1 33 4b 4d b1 87 cc 68 b0 21 1e d2 ff ff ff ff \
        ff ff ff ff 00 00 e0 40 00 00 00 00 00 00 00 00 \
        00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 \
        00 00 00 00 80 08 00 3c 01 00 00 01 e5 e1 ae cc \
        b1 33 4b 4d b1 87 cc 68 b0 21 1e d2 00 00 00 00 \
        00 00 80 00 00 00 80 71 00 00 00 00 00 00 00 00 \
        00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 \
        00 00 00 00 80 08 00 3c 01 00 00 02 e5 e1 ae cc \
        b1 33 4b 4d b1 87 cc 68 b0 21 1e d2 00 00 00 00 \
        00 03 00 01 00 00 00 7b 00 00 00 00 00 00 00 00 \
        00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 \
        00 00 00 00 80 08 00 3c 01 00 00 03 e5 e1 ae cc \
        b1 33 4b 4d b1 87 cc 68 b0 21 1e d2 00 00 00 00 \
        00 03 00 01 00 00 00 7c 00 00 00 00 00 00 00 00 \
        00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 \
        00 00 00 00 80 08 00 3c 01 00 00 04 e5 e1 ae cc \
        b1 33 4b 4d b1 87 cc 68 b0 21 1e d2 00 00 00 00 \
        00 04 00 01 00 00 00 7d 00 00 00 00 00 00 00 00 \
        00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 \
        00 00 00 00";

    /// captures/cm/prmend_req.hex, bytes 42.. (132 bytes): frame 57: CPU Control PrmEnd, DREP LE, 174 bytes
    const PRMEND_REQ: &str = "\
        04 00 20 00 10 00 00 00 00 00 a0 de 97 6c d1 11 \
        82 71 00 01 00 02 04 93 01 00 a0 de 97 6c d1 11 \
        82 71 00 a0 24 42 df 7d ae a1 ac d2 32 00 10 10 \
        b0 58 ec 1c 5d 61 e7 3f 00 00 00 00 01 00 00 00 \
        02 00 00 00 04 00 ff ff ff ff 34 00 00 00 00 00 \
        20 00 00 00 20 00 00 00 20 00 00 00 00 00 00 00 \
        20 00 00 00 01 10 00 1c 01 00 00 00 e5 e1 ae cc \
        b1 33 4b 4d b1 87 cc 68 b0 21 1e d2 00 02 00 00 \
        00 01 00 00";

    /// captures/cm/prmend_res.hex, bytes 42.. (132 bytes): frame 58: p-net Control PrmEnd Done, DREP BE, 174 bytes
    const PRMEND_RES: &str = "\
        04 02 28 00 00 00 00 00 de a0 00 00 6c 97 11 d1 \
        82 71 00 01 00 02 04 93 de a0 00 01 6c 97 11 d1 \
        82 71 00 a0 24 42 df 7d d2 ac a1 ae 00 32 10 10 \
        b0 58 ec 1c 5d 61 e7 3f 00 00 00 00 00 00 00 01 \
        00 00 00 02 00 04 ff ff ff ff 00 34 00 00 00 00 \
        00 00 00 00 00 00 00 20 00 00 00 20 00 00 00 00 \
        00 00 00 20 81 10 00 1c 01 00 00 00 e5 e1 ae cc \
        b1 33 4b 4d b1 87 cc 68 b0 21 1e d2 00 02 00 00 \
        00 08 00 00";

    /// captures/cm/appready_req.hex, bytes 42.. (132 bytes): frame 59: p-net -> CPU Control ApplicationReady, DREP BE, 174 bytes (src port 49153)
    const APPREADY_REQ: &str = "\
        04 00 20 00 00 00 00 00 de a0 00 00 6c 97 11 d1 \
        82 71 10 64 01 0e 00 2a de a0 00 02 6c 97 11 d1 \
        82 71 00 a0 24 42 df 7d 14 af 19 8a 12 34 10 56 \
        80 79 8c f3 19 cd 19 f8 00 00 00 00 00 00 00 01 \
        00 00 00 00 00 04 ff ff ff ff 00 34 00 00 00 00 \
        00 00 05 3c 00 00 00 20 00 00 05 3c 00 00 00 00 \
        00 00 00 20 01 12 00 1c 01 00 00 00 e5 e1 ae cc \
        b1 33 4b 4d b1 87 cc 68 b0 21 1e d2 00 02 00 00 \
        00 02 00 00";

    /// captures/cm/appready_res.hex, bytes 42.. (132 bytes): frame 60: CPU -> p-net ApplicationReady Done, DREP LE, flags1 0x0a, 174 bytes
    const APPREADY_RES: &str = "\
        04 02 0a 00 10 00 00 00 00 00 a0 de 97 6c d1 11 \
        82 71 10 64 01 0e 00 2a 02 00 a0 de 97 6c d1 11 \
        82 71 00 a0 24 42 df 7d 8a 19 af 14 34 12 56 10 \
        80 79 8c f3 19 cd 19 f8 56 51 00 00 01 00 00 00 \
        00 00 00 00 04 00 ff ff ff ff 34 00 00 00 00 00 \
        00 00 00 00 20 00 00 00 3c 05 00 00 00 00 00 00 \
        20 00 00 00 81 12 00 1c 01 00 00 00 e5 e1 ae cc \
        b1 33 4b 4d b1 87 cc 68 b0 21 1e d2 00 02 00 00 \
        00 08 00 00";

    /// captures/alarm/im0_read_req.hex, bytes 42.. (164 bytes): frame 24414 of plan5-alarm.pcapng (2026-08-30): CPU -> p-net, DCE-RPC Read request (opnum 2), IODReadReqHeader slot 0 subslot 1, index 0xAFF0 I&M0, RecordDataLength 0x8000, 206 bytes
    const IM0_READ_REQ: &str = "\
        04 00 20 00 10 00 00 00 00 00 a0 de 97 6c d1 11 \
        82 71 00 01 00 02 04 93 01 00 a0 de 97 6c d1 11 \
        82 71 00 a0 24 42 df 7d 6b d7 6d 8d 13 00 10 10 \
        94 79 ec 1c 5d 61 e7 3c 00 00 00 00 01 00 00 00 \
        04 00 00 00 02 00 ff ff ff ff 54 00 00 00 00 00 \
        40 80 00 00 40 00 00 00 40 80 00 00 00 00 00 00 \
        40 00 00 00 00 09 00 3c 01 00 00 06 ef 79 6d 60 \
        ef 2b 99 46 b3 9e 85 31 f5 b7 f9 66 00 00 00 00 \
        00 00 00 01 00 00 af f0 00 00 80 00 00 00 00 00 \
        00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 \
        00 00 00 00";

    /// captures/alarm/im0_read_req_if.hex, bytes 42.. (164 bytes): frame 24410 of plan5-alarm.pcapng (2026-08-30): CPU -> p-net, Read request I&M0 on the interface submodule slot 0 subslot 0x8000, 206 bytes
    const IM0_READ_REQ_IF: &str = "\
        04 00 20 00 10 00 00 00 00 00 a0 de 97 6c d1 11 \
        82 71 00 01 00 02 04 93 01 00 a0 de 97 6c d1 11 \
        82 71 00 a0 24 42 df 7d 6b d7 6d 8d 13 00 10 10 \
        94 79 ec 1c 5d 61 e7 3c 00 00 00 00 01 00 00 00 \
        03 00 00 00 02 00 ff ff ff ff 54 00 00 00 00 00 \
        40 80 00 00 40 00 00 00 40 80 00 00 00 00 00 00 \
        40 00 00 00 00 09 00 3c 01 00 00 05 ef 79 6d 60 \
        ef 2b 99 46 b3 9e 85 31 f5 b7 f9 66 00 00 00 00 \
        00 00 80 00 00 00 af f0 00 00 80 00 00 00 00 00 \
        00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 \
        00 00 00 00";

    /// captures/alarm/im0_read_res.hex, bytes 42.. (224 bytes): frame 24415 of plan5-alarm.pcapng (2026-08-30): p-net -> CPU, DCE-RPC Read response, IODReadResHeader + I&M0 block (60 bytes), p-net identity VendorID 0x0493 OrderID '12345 Abcdefghijk', 266 bytes
    const IM0_READ_RES: &str = "\
        04 02 28 00 00 00 00 00 de a0 00 00 6c 97 11 d1 \
        82 71 00 01 00 02 04 93 de a0 00 01 6c 97 11 d1 \
        82 71 00 a0 24 42 df 7d 8d 6d d7 6b 00 13 10 10 \
        94 79 ec 1c 5d 61 e7 3c 00 00 00 00 00 00 00 01 \
        00 00 00 04 00 02 ff ff ff ff 00 90 00 00 00 00 \
        00 00 00 00 00 00 00 7c 00 00 80 40 00 00 00 00 \
        00 00 00 7c 80 09 00 3c 01 00 00 06 ef 79 6d 60 \
        ef 2b 99 46 b3 9e 85 31 f5 b7 f9 66 00 00 00 00 \
        00 00 00 01 00 00 af f0 00 00 00 3c 00 00 00 00 \
        00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 \
        00 00 00 00 00 20 00 38 01 00 04 93 31 32 33 34 \
        35 20 41 62 63 64 65 66 67 68 69 6a 6b 20 20 20 \
        30 30 37 20 20 20 20 20 20 20 20 20 20 20 20 20 \
        00 03 56 00 02 00 00 00 12 34 56 78 01 01 00 0e";

    /// captures/alarm/im0_read_res_if.hex, bytes 42.. (224 bytes): frame 24411 of plan5-alarm.pcapng (2026-08-30): p-net -> CPU, Read response I&M0 on the interface submodule, 266 bytes
    const IM0_READ_RES_IF: &str = "\
        04 02 28 00 00 00 00 00 de a0 00 00 6c 97 11 d1 \
        82 71 00 01 00 02 04 93 de a0 00 01 6c 97 11 d1 \
        82 71 00 a0 24 42 df 7d 8d 6d d7 6b 00 13 10 10 \
        94 79 ec 1c 5d 61 e7 3c 00 00 00 00 00 00 00 01 \
        00 00 00 03 00 02 ff ff ff ff 00 90 00 00 00 00 \
        00 00 00 00 00 00 00 7c 00 00 80 40 00 00 00 00 \
        00 00 00 7c 80 09 00 3c 01 00 00 05 ef 79 6d 60 \
        ef 2b 99 46 b3 9e 85 31 f5 b7 f9 66 00 00 00 00 \
        00 00 80 00 00 00 af f0 00 00 00 3c 00 00 00 00 \
        00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 \
        00 00 00 00 00 20 00 38 01 00 04 93 31 32 33 34 \
        35 20 41 62 63 64 65 66 67 68 69 6a 6b 20 20 20 \
        30 30 37 20 20 20 20 20 20 20 20 20 20 20 20 20 \
        00 03 56 00 02 00 00 00 12 34 56 78 01 01 00 0e";

    use crate::test_fixtures::hex as unhex;

    const OBJECT_DEVICE: &str = "dea00000-6c97-11d1-8271-000100020493";
    const OBJECT_CPU: &str = "dea00000-6c97-11d1-8271-1064010e002a";
    const IFACE_DEVICE: &str = "dea00001-6c97-11d1-8271-00a02442df7d";
    const IFACE_CONTROLLER: &str = "dea00002-6c97-11d1-8271-00a02442df7d";
    const ACT_CONNECT: &str = "d2aca1ae-0032-1010-b058-ec1c5d61e73f";
    const ACT_READ: &str = "8d6dd76b-0013-1010-9479-ec1c5d61e73c";
    const ACT_APPREADY: &str = "14af198a-1234-1056-8079-8cf319cd19f8";

    /// What a capture must parse to.
    struct Expect {
        hex: &'static str,
        packet_type: PacketType,
        flags1: u8,
        little_endian: bool,
        object: &'static str,
        interface: &'static str,
        activity: &'static str,
        server_boot_time: u32,
        sequence_number: u32,
        opnum: u16,
        body_len: u16,
        ndr: Ndr,
        first_block: u16,
    }

    fn request(args_maximum: u32, len: u32) -> Ndr {
        Ndr::Request(NdrRequest {
            args_maximum,
            args_length: len,
            maximum_count: args_maximum,
            offset: 0,
            actual_count: len,
        })
    }

    fn response(maximum_count: u32, len: u32) -> Ndr {
        Ndr::Response(NdrResponse {
            status: PnioStatus::OK,
            args_length: len,
            maximum_count,
            offset: 0,
            actual_count: len,
        })
    }

    /// Parses a capture, checks every field, and re-emits it byte for byte, both from the
    /// parsed `Pdu` and from its parts through `emit_request` / `emit_response`.
    fn check(e: Expect) -> Vec<u8> {
        let bytes = unhex(e.hex);
        let p = Packet::new_checked(&bytes[..]).unwrap();
        assert_eq!(p.version(), RPC_VERSION);
        let drep0 = if e.little_endian { 0x10 } else { 0x00 };
        assert_eq!(p.drep(), [drep0, 0, 0]);
        assert_eq!(p.body().len(), usize::from(e.body_len));
        assert_eq!(bytes.len(), HEADER_LEN + usize::from(e.body_len));

        let h = Header::parse(&p).unwrap();
        assert_eq!(h.packet_type, e.packet_type);
        assert_eq!(h.flags1, e.flags1);
        assert_eq!(h.flags2, 0);
        assert_eq!(h.little_endian, e.little_endian);
        assert_eq!(h.serial, 0);
        assert_eq!(h.object.to_string(), e.object);
        assert_eq!(h.interface.to_string(), e.interface);
        assert_eq!(h.activity.to_string(), e.activity);
        assert_eq!(h.server_boot_time, e.server_boot_time);
        assert_eq!(h.interface_version, PNIO_INTERFACE_VERSION);
        assert_eq!(h.sequence_number, e.sequence_number);
        assert_eq!(h.opnum, e.opnum);
        assert_eq!((h.interface_hint, h.activity_hint), (NO_HINT, NO_HINT));
        assert_eq!(h.body_len, e.body_len);
        assert_eq!((h.fragment_number, h.auth_protocol), (0, 0));
        assert_eq!(h.buffer_len(), HEADER_LEN);

        let mut hdr = [0xa5u8; HEADER_LEN];
        h.emit(&mut hdr).unwrap();
        assert_eq!(&hdr[..], &bytes[..HEADER_LEN]);

        let pdu = Pdu::parse(&bytes).unwrap();
        assert_eq!(pdu.header, h);
        assert_eq!(pdu.ndr, e.ndr);
        assert_eq!(pdu.ndr.packet_type(), e.packet_type);
        assert!(pdu.ndr.is_consistent(pdu.blocks.len()));
        assert_eq!(usize::from(e.body_len), NDR_LEN + pdu.blocks.len());
        if let Some(status) = pdu.ndr.status() {
            assert!(status.is_ok());
            assert_eq!(describe(status), "OK");
        }
        // The first block header parses (a Write carries record data between its blocks).
        let first = BlockHeader::parse(pdu.blocks).unwrap();
        assert_eq!(first.block_type, e.first_block);
        assert_eq!(parse_pdu(&bytes).unwrap(), (h, e.ndr, pdu.blocks));

        // Re-emission: into a dirty buffer of exactly buffer_len bytes, then from the parts.
        assert_eq!(pdu.buffer_len(), bytes.len());
        let mut out = vec![0xa5u8; pdu.buffer_len()];
        pdu.emit(&mut out).unwrap();
        assert_eq!(out, bytes);
        let built = match e.ndr {
            Ndr::Request(r) => emit_request(&h, r.args_maximum, pdu.blocks),
            Ndr::Response(r) => emit_response(&h, r.status, r.maximum_count, pdu.blocks),
        };
        assert_eq!(built.unwrap(), bytes);
        bytes
    }

    #[test]
    fn connect_request_capture() {
        check(Expect {
            hex: CONNECT_REQ,
            packet_type: PacketType::Request,
            flags1: flags1::IDEMPOTENT,
            little_endian: true,
            object: OBJECT_DEVICE,
            interface: IFACE_DEVICE,
            activity: ACT_CONNECT,
            server_boot_time: 0,
            sequence_number: 0,
            opnum: opnum::CONNECT,
            body_len: 577,
            ndr: request(0x22d, 0x22d),
            first_block: 0x0101,
        });
    }

    #[test]
    fn connect_response_capture() {
        check(Expect {
            hex: CONNECT_RES,
            packet_type: PacketType::Response,
            flags1: flags1::NO_FACK | flags1::IDEMPOTENT,
            little_endian: false,
            object: OBJECT_DEVICE,
            interface: IFACE_DEVICE,
            activity: ACT_CONNECT,
            server_boot_time: 0,
            sequence_number: 0,
            opnum: opnum::CONNECT,
            body_len: 110,
            ndr: response(0x22d, 0x5a),
            first_block: 0x8101,
        });
    }

    #[test]
    fn write_request_capture() {
        check(Expect {
            hex: WRITE_REQ,
            packet_type: PacketType::Request,
            flags1: flags1::IDEMPOTENT,
            little_endian: true,
            object: OBJECT_DEVICE,
            interface: IFACE_DEVICE,
            activity: ACT_CONNECT,
            server_boot_time: 0,
            sequence_number: 1,
            opnum: opnum::WRITE,
            body_len: 364,
            ndr: request(0x158, 0x158),
            first_block: 0x0008,
        });
    }

    #[test]
    fn write_response_capture() {
        check(Expect {
            hex: WRITE_RES,
            packet_type: PacketType::Response,
            flags1: flags1::NO_FACK | flags1::IDEMPOTENT,
            little_endian: false,
            object: OBJECT_DEVICE,
            interface: IFACE_DEVICE,
            activity: ACT_CONNECT,
            server_boot_time: 0,
            sequence_number: 1,
            opnum: opnum::WRITE,
            body_len: 340,
            ndr: response(0x158, 0x140),
            first_block: 0x8008,
        });
    }

    #[test]
    fn prmend_request_capture() {
        check(Expect {
            hex: PRMEND_REQ,
            packet_type: PacketType::Request,
            flags1: flags1::IDEMPOTENT,
            little_endian: true,
            object: OBJECT_DEVICE,
            interface: IFACE_DEVICE,
            activity: ACT_CONNECT,
            server_boot_time: 0,
            sequence_number: 2,
            opnum: opnum::CONTROL,
            body_len: 52,
            ndr: request(0x20, 0x20),
            first_block: 0x0110,
        });
    }

    #[test]
    fn prmend_response_capture() {
        check(Expect {
            hex: PRMEND_RES,
            packet_type: PacketType::Response,
            flags1: flags1::NO_FACK | flags1::IDEMPOTENT,
            little_endian: false,
            object: OBJECT_DEVICE,
            interface: IFACE_DEVICE,
            activity: ACT_CONNECT,
            server_boot_time: 0,
            sequence_number: 2,
            opnum: opnum::CONTROL,
            body_len: 52,
            ndr: response(0x20, 0x20),
            first_block: 0x8110,
        });
    }

    #[test]
    fn application_ready_request_capture() {
        check(Expect {
            hex: APPREADY_REQ,
            packet_type: PacketType::Request,
            flags1: flags1::IDEMPOTENT,
            little_endian: false,
            object: OBJECT_CPU,
            interface: IFACE_CONTROLLER,
            activity: ACT_APPREADY,
            server_boot_time: 0,
            sequence_number: 0,
            opnum: opnum::CONTROL,
            body_len: 52,
            ndr: request(1340, 0x20),
            first_block: 0x0112,
        });
    }

    #[test]
    fn application_ready_response_capture() {
        check(Expect {
            hex: APPREADY_RES,
            packet_type: PacketType::Response,
            flags1: flags1::LAST_FRAGMENT | flags1::NO_FACK,
            little_endian: true,
            object: OBJECT_CPU,
            interface: IFACE_CONTROLLER,
            activity: ACT_APPREADY,
            server_boot_time: 0x5156,
            sequence_number: 0,
            opnum: opnum::CONTROL,
            body_len: 52,
            ndr: response(1340, 0x20),
            first_block: 0x8112,
        });
    }

    #[test]
    fn im0_read_request_captures() {
        for (hex, seq) in [(IM0_READ_REQ, 4), (IM0_READ_REQ_IF, 3)] {
            check(Expect {
                hex,
                packet_type: PacketType::Request,
                flags1: flags1::IDEMPOTENT,
                little_endian: true,
                object: OBJECT_DEVICE,
                interface: IFACE_DEVICE,
                activity: ACT_READ,
                server_boot_time: 0,
                sequence_number: seq,
                opnum: opnum::READ,
                body_len: 84,
                ndr: request(0x8040, 0x40),
                first_block: 0x0009,
            });
        }
    }

    #[test]
    fn im0_read_response_captures() {
        for (hex, seq) in [(IM0_READ_RES, 4), (IM0_READ_RES_IF, 3)] {
            check(Expect {
                hex,
                packet_type: PacketType::Response,
                flags1: flags1::NO_FACK | flags1::IDEMPOTENT,
                little_endian: false,
                object: OBJECT_DEVICE,
                interface: IFACE_DEVICE,
                activity: ACT_READ,
                server_boot_time: 0,
                sequence_number: seq,
                opnum: opnum::READ,
                body_len: 144,
                ndr: response(0x8040, 0x7c),
                first_block: 0x8009,
            });
        }
    }

    #[test]
    fn little_endian_pdu_re_emitted_big_endian() {
        let le = unhex(CONNECT_REQ);
        let pdu = Pdu::parse(&le).unwrap();
        let be_pdu = Pdu {
            header: Header {
                little_endian: false,
                ..pdu.header
            },
            ..pdu
        };
        let be = be_pdu.to_vec().unwrap();
        assert_eq!(be.len(), le.len());
        assert_eq!(be[4], DREP_BIG_ENDIAN);
        // The object UUID in field order, LengthOfBody 577 and ArgsMaximum 0x22d big-endian.
        assert_eq!(
            &be[8..16],
            &[0xde, 0xa0, 0x00, 0x00, 0x6c, 0x97, 0x11, 0xd1]
        );
        assert_eq!(&be[74..76], &[0x02, 0x41]);
        assert_eq!(&be[80..84], &[0x00, 0x00, 0x02, 0x2d]);
        assert_eq!(&be[100..], &le[100..]);
        let back = Pdu::parse(&be).unwrap();
        assert_eq!(
            back.header,
            Header {
                little_endian: false,
                ..pdu.header
            }
        );
        assert_eq!((back.ndr, back.blocks), (pdu.ndr, pdu.blocks));
        let mut h = Header::parse(&Packet::new_checked(&be[..]).unwrap()).unwrap();
        h.little_endian = true;
        assert_eq!(h, pdu.header);
        // And back to little-endian: the original bytes.
        assert_eq!(Pdu { header: h, ..back }.to_vec().unwrap(), le);
    }

    #[test]
    fn response_status_is_stored_in_drep_order() {
        let status = PnioStatus::from_bytes([0xdb, 0x81, 0x02, 0x09]);
        let ndr = NdrResponse::for_blocks(status, 0x22d, 0);
        let mut b = [0u8; NDR_LEN];
        ndr.emit(&mut b, true).unwrap();
        assert_eq!(&b[..4], &[0x09, 0x02, 0x81, 0xdb]);
        assert_eq!(&b[8..12], &[0x2d, 0x02, 0x00, 0x00]);
        assert_eq!(NdrResponse::parse(&b, true).unwrap(), ndr);
        ndr.emit(&mut b, false).unwrap();
        assert_eq!(&b[..4], &[0xdb, 0x81, 0x02, 0x09]);
        assert_eq!(NdrResponse::parse(&b, false).unwrap(), ndr);
        assert!(ndr.emit(&mut b[..19], false).is_err());
        assert!(NdrResponse::parse(&b[..19], false).is_err());
        assert!(NdrRequest::parse(&b[..0], true).is_err());
    }

    #[test]
    fn reply_echoes_the_call() {
        let req = Pdu::parse(&unhex(PRMEND_REQ)).unwrap().header;
        let res = Pdu::parse(&unhex(PRMEND_RES)).unwrap().header;
        let reply = req.reply(0);
        assert_eq!(reply.flags1, REPLY_FLAGS1);
        // p-net answers big-endian with NoFack | Idempotent; otherwise the same header.
        assert_eq!(
            Header {
                little_endian: false,
                flags1: 0x28,
                body_len: 52,
                ..reply
            },
            res
        );
        // The S7 answers with LastFragment | NoFack, little-endian, its boot time.
        let req = Pdu::parse(&unhex(APPREADY_REQ)).unwrap().header;
        let res = Pdu::parse(&unhex(APPREADY_RES)).unwrap().header;
        assert_eq!(
            Header {
                little_endian: true,
                body_len: 52,
                ..req.reply(0x5156)
            },
            res
        );
        let fresh = Header::request(
            object_uuid(1, 2, 0x0493),
            DEVICE_INTERFACE,
            req.activity,
            0,
            opnum::CONNECT,
        );
        assert_eq!((fresh.flags1, fresh.interface_version), (0x20, 1));
        assert_eq!(
            fresh.to_string(),
            "DCE/RPC request Connect seq 0 act 14af198a-1234-1056-8079-8cf319cd19f8 BE body 0"
        );
    }

    #[test]
    fn uuids() {
        assert_eq!(object_uuid(1, 2, 0x0493).to_string(), OBJECT_DEVICE);
        assert_eq!(DEVICE_INTERFACE.to_string(), IFACE_DEVICE);
        assert_eq!(CONTROLLER_INTERFACE.to_string(), IFACE_CONTROLLER);
        assert_eq!(
            SUPERVISOR_INTERFACE.to_string(),
            "dea00003-6c97-11d1-8271-00a02442df7d"
        );
        assert_eq!(
            PARAMETER_SERVER_INTERFACE.to_string(),
            "dea00004-6c97-11d1-8271-00a02442df7d"
        );
        assert_eq!(
            EPM_INTERFACE.to_string(),
            "e1af8308-5d1f-11c9-91a4-08002b14a0fa"
        );
        let cpu = Pdu::parse(&unhex(APPREADY_REQ)).unwrap().header.object;
        assert_eq!(object_uuid_parts(&cpu), Some((0x1064, 0x010e, 0x002a)));
        assert_eq!(object_uuid_parts(&DEVICE_INTERFACE), None);
        assert_eq!(opnum::name(5), Some("ReadImplicit"));
        assert_eq!(opnum::name(6), None);
        for v in 0..=255u8 {
            assert_eq!(u8::from(PacketType::from(v)), v);
        }
    }

    #[test]
    fn malformed_pdus_are_refused() {
        let good = unhex(PRMEND_REQ);
        for n in 0..good.len() {
            assert!(Packet::new_checked(&good[..n]).is_err(), "{n} bytes");
            assert!(Pdu::parse(&good[..n]).is_err());
        }
        let mut bad = good.clone();
        bad[0] = 5;
        assert!(Pdu::parse(&bad).is_err(), "RPCVersion 5");
        let mut bad = good.clone();
        bad[4] = 0x20;
        assert!(Pdu::parse(&bad).is_err(), "DREP integer representation 2");
        let mut frag = good.clone();
        frag[2] |= flags1::FRAGMENT;
        assert!(Header::parse(&Packet::new_checked(&frag[..]).unwrap()).is_ok());
        assert!(Pdu::parse(&frag).is_err(), "a fragment");
        let mut ping = good.clone();
        ping[1] = 1;
        assert!(Pdu::parse(&ping).is_err(), "a ping has no NDR header");
        // LengthOfBody 19: the NDR header does not fit the body.
        let mut short = good.clone();
        short[74..76].copy_from_slice(&19u16.to_le_bytes());
        assert!(Pdu::parse(&short).is_err());
        // Bytes after the body are ignored.
        let mut long = good.clone();
        long.extend_from_slice(&[1, 2, 3, 4]);
        let pdu = Pdu::parse(&long).unwrap();
        assert_eq!(pdu.to_vec().unwrap(), good);
        assert_eq!(Packet::new_checked(&long[..]).unwrap().body().len(), 52);
    }

    #[test]
    fn emission_errors() {
        let bytes = unhex(PRMEND_RES);
        let pdu = Pdu::parse(&bytes).unwrap();
        let mut buf = vec![0u8; pdu.buffer_len() - 1];
        assert!(pdu.emit(&mut buf).is_err());
        assert!(pdu.header.emit(&mut buf[..79]).is_err());
        let mismatched = Pdu {
            ndr: Ndr::Request(NdrRequest::for_blocks(0x20, 32)),
            ..pdu
        };
        assert!(mismatched.to_vec().is_err());
        let fragment = Pdu {
            header: Header {
                flags1: flags1::FRAGMENT,
                ..pdu.header
            },
            ..pdu
        };
        assert!(fragment.to_vec().is_err());
        let big = vec![0u8; usize::from(u16::MAX) - NDR_LEN];
        let v = emit_request(&pdu.header, 0, &big).unwrap();
        assert_eq!(v.len(), HEADER_LEN + usize::from(u16::MAX));
        let too_big = vec![0u8; usize::from(u16::MAX) - NDR_LEN + 1];
        assert!(emit_request(&pdu.header, 0, &too_big).is_err());
        assert!(emit_response(&pdu.header, PnioStatus::OK, 0, &too_big).is_err());
        assert_eq!(NdrRequest::for_blocks(7, usize::MAX).args_length, u32::MAX);
    }

    #[test]
    fn packet_setters_write_in_the_buffer_drep() {
        let mut buf = [0u8; HEADER_LEN + 4];
        let mut p = Packet::new_unchecked(&mut buf[..]);
        p.set_version(RPC_VERSION);
        p.set_drep(true);
        p.set_body_len(4);
        p.set_opnum(opnum::READ_IMPLICIT);
        p.set_serial(0x1234);
        p.set_interface_uuid(&DEVICE_INTERFACE);
        p.body_mut().copy_from_slice(&[1, 2, 3, 4]);
        assert_eq!(p.body(), &[1, 2, 3, 4]);
        assert_eq!((p.serial_high(), p.serial_low()), (0x12, 0x34));
        assert_eq!(&buf[68..70], &[5, 0]);
        assert_eq!(&buf[24..28], &[0x01, 0x00, 0xa0, 0xde]);
        let p = Packet::new_checked(&buf[..]).unwrap();
        assert_eq!(p.interface_uuid(), DEVICE_INTERFACE);
        assert_eq!(p.to_string(), format!("{}", Header::parse(&p).unwrap()));
        assert_eq!(
            Packet::new_unchecked(&buf[..10]).to_string(),
            "DCE/RPC (malformed)"
        );
    }

    #[test]
    fn status_descriptions() {
        let d = |b: [u8; 4]| describe(PnioStatus::from_bytes(b));
        assert_eq!(d([0, 0, 0, 0]), "OK");
        assert_eq!(
            d([0xdb, 0x81, 0x02, 0x09]),
            "Connect refused: IOCRBlockReq field 9 (FrameID)"
        );
        assert_eq!(
            d([0xdb, 0x81, 0x02, 0x11]),
            "Connect refused: IOCRBlockReq field 17 (IOCRTagHeader)"
        );
        assert_eq!(
            d([0xdb, 0x81, 0x01, 0x09]),
            "Connect refused: ARBlockReq field 9 (ARProperties)"
        );
        assert_eq!(
            d([0xdb, 0x81, 0x04, 0x0a]),
            "Connect refused: AlarmCRBlockReq field 10 (MaxAlarmDataLength)"
        );
        assert_eq!(
            d([0xdb, 0x81, 0x03, 0x00]),
            "Connect refused: ExpectedSubmoduleBlockReq field 0 (BlockType)"
        );
        assert_eq!(
            d([0xdb, 0x81, 0x07, 0x63]),
            "Connect refused: ARRPCBlockReq field 99"
        );
        assert_eq!(
            d([0xdb, 0x81, 0x40, 0x04]),
            "Connect refused: CMRPC: out of AR resources"
        );
        assert_eq!(
            d([0xdb, 0x81, 0x40, 0x07]),
            "Connect refused: CMRPC code 0x07"
        );
        assert_eq!(
            d([0xdb, 0x81, 0x3d, 0x00]),
            "Connect refused: device CM state machine (CMDEV), code 0x00"
        );
        assert_eq!(
            d([0xde, 0x80, 0xb0, 0x00]),
            "Read failed: access: invalid index"
        );
        assert_eq!(
            d([0xdf, 0x80, 0xb6, 0x05]),
            "Write failed: access: access denied, user code 0x05"
        );
        assert_eq!(
            d([0xde, 0x80, 0xa9, 0x00]),
            "Read failed: application: feature not supported"
        );
        assert_eq!(
            d([0xde, 0x80, 0xc3, 0x00]),
            "Read failed: resource: resource unavailable"
        );
        assert_eq!(
            d([0xde, 0x80, 0xbe, 0x00]),
            "Read failed: access error 0xbe"
        );
        assert_eq!(d([0xdf, 0x80, 0x12, 0x00]), "Write failed: ErrorCode1 0x12");
        assert_eq!(
            d([0xde, 0x81, 0x08, 0x0a]),
            "Read failed: faulty record, field 10"
        );
        assert_eq!(
            d([0xcf, 0x81, 0xfd, 0x05]),
            "RTA error: AR abort: consumer data hold timer expired"
        );
        assert_eq!(
            d([0xcf, 0x81, 0xfd, 0x0b]),
            "RTA error: AR abort: alarm indication with error"
        );
        assert_eq!(
            d([0xcf, 0x81, 0xfd, 0x77]),
            "RTA error: AR abort, code 0x77"
        );
        assert_eq!(
            d([0xdd, 0x82, 0x12, 0x34]),
            "Control refused: manufacturer specific 0x12 0x34"
        );
        assert_eq!(
            d([0xdc, 0x81, 0x55, 0x01]),
            "Release refused: ErrorCode1 0x55, ErrorCode2 0x01"
        );
        assert_eq!(
            d([0x42, 0x17, 0x01, 0x02]),
            "ErrorCode 0x42: ErrorDecode 0x17, ErrorCode1 0x01, ErrorCode2 0x02"
        );
        assert_eq!(
            StatusText(PnioStatus::from_u32(0xda81_0000)).to_string(),
            "AlarmAck failed: ErrorCode1 0x00, ErrorCode2 0x00"
        );
    }

    fn any_header() -> impl Strategy<Value = Header> {
        (
            (
                any::<u8>(),
                any::<u8>(),
                any::<u8>(),
                any::<bool>(),
                any::<u16>(),
            ),
            (any::<[u8; 16]>(), any::<[u8; 16]>(), any::<[u8; 16]>()),
            (any::<u32>(), any::<u32>(), any::<u32>(), any::<u16>()),
            (
                any::<u16>(),
                any::<u16>(),
                any::<u16>(),
                any::<u16>(),
                any::<u8>(),
            ),
        )
            .prop_map(
                |(
                    (packet_type, flags1, flags2, little_endian, serial),
                    (object, interface, activity),
                    (server_boot_time, interface_version, sequence_number, opnum),
                    (interface_hint, activity_hint, body_len, fragment_number, auth_protocol),
                )| Header {
                    packet_type: PacketType::from(packet_type),
                    flags1,
                    flags2,
                    little_endian,
                    serial,
                    object: Uuid(object),
                    interface: Uuid(interface),
                    activity: Uuid(activity),
                    server_boot_time,
                    interface_version,
                    sequence_number,
                    opnum,
                    interface_hint,
                    activity_hint,
                    body_len,
                    fragment_number,
                    auth_protocol,
                },
            )
    }

    /// Runs every parser and getter on `bytes`; must never panic.
    fn exercise(bytes: &[u8]) {
        let p = Packet::new_unchecked(bytes);
        let _ = p.to_string();
        if p.check_len().is_ok() {
            let h = Header::parse(&p).unwrap();
            assert_eq!(usize::from(h.body_len), p.body().len());
            let _ = (p.drep(), p.serial(), p.version(), h.to_string());
            if let Ok((ndr, _)) = parse_body(h.packet_type, h.little_endian, p.body()) {
                let _ = ndr.status().map(describe);
            }
        }
        if let Ok(pdu) = Pdu::parse(bytes) {
            // Identical up to the DREP character and float formats, which emit as 0.
            let out = pdu.to_vec().unwrap();
            let mut expected = bytes[..pdu.buffer_len()].to_vec();
            expected[4] &= 0xf0;
            expected[5..7].fill(0);
            assert_eq!(out, expected);
        }
        let _ = parse_pdu(bytes);
    }

    proptest! {
        #[test]
        fn parsing_arbitrary_bytes_never_panics(
            mut bytes in proptest::collection::vec(any::<u8>(), 0..1600),
            shape in any::<bool>(),
            little_endian in any::<bool>(),
            body_slack in 0usize..4,
        ) {
            exercise(&bytes);
            // Mostly valid headers too, to reach the NDR and block code.
            if shape && bytes.len() >= HEADER_LEN {
                bytes[0] = RPC_VERSION;
                bytes[1] &= 0x03;
                bytes[4] = if little_endian { 0x10 } else { 0x00 };
                let body = (bytes.len() - HEADER_LEN).saturating_sub(body_slack);
                let body = u16::try_from(body).unwrap();
                let b = if little_endian { body.to_le_bytes() } else { body.to_be_bytes() };
                bytes[74..76].copy_from_slice(&b);
                exercise(&bytes);
            }
        }

        #[test]
        fn header_round_trips_in_both_dreps(h in any_header()) {
            for little_endian in [false, true] {
                let h = Header { little_endian, ..h };
                let mut buf = vec![0xa5u8; HEADER_LEN + usize::from(h.body_len)];
                h.emit(&mut buf).unwrap();
                let p = Packet::new_checked(&buf[..]).unwrap();
                prop_assert_eq!(Header::parse(&p).unwrap(), h);
            }
        }

        #[test]
        fn pdu_round_trips(
            h in any_header(),
            is_request in any::<bool>(),
            words in any::<[u32; 5]>(),
            blocks in proptest::collection::vec(any::<u8>(), 0..300),
        ) {
            let ndr = if is_request {
                Ndr::Request(NdrRequest {
                    args_maximum: words[0],
                    args_length: words[1],
                    maximum_count: words[2],
                    offset: words[3],
                    actual_count: words[4],
                })
            } else {
                Ndr::Response(NdrResponse {
                    status: PnioStatus::from_u32(words[0]),
                    args_length: words[1],
                    maximum_count: words[2],
                    offset: words[3],
                    actual_count: words[4],
                })
            };
            let header = Header {
                packet_type: ndr.packet_type(),
                flags1: h.flags1 & !flags1::FRAGMENT,
                body_len: u16::try_from(NDR_LEN + blocks.len()).unwrap(),
                ..h
            };
            let pdu = Pdu { header, ndr, blocks: &blocks };
            let bytes = pdu.to_vec().unwrap();
            prop_assert_eq!(Pdu::parse(&bytes).unwrap(), pdu);
            let _ = describe(PnioStatus::from_u32(words[0]));
        }
    }
}
