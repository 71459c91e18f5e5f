// SPDX-License-Identifier: MIT OR Apache-2.0
//! The AgentX header (RFC 2741 §6.1): 20 bytes in front of every PDU.
//!
//! ```text
//! 0        1        2        3
//! version  type     flags    reserved
//! sessionID
//! transactionID
//! packetID
//! payload_length
//! ```
//!
//! The four 32-bit fields are in the byte order that the flags' NETWORK_BYTE_ORDER bit
//! says, like every multi-byte field of the payload.

use super::{ByteOrder, EmitError, ParseError, PduType};

/// The AgentX protocol version this crate speaks.
pub const VERSION: u8 = 1;
/// The length of the header.
pub const HEADER_LEN: usize = field::PAYLOAD_LENGTH.end;

mod field {
    use core::ops::Range;

    pub const VERSION: usize = 0;
    pub const TYPE: usize = 1;
    pub const FLAGS: usize = 2;
    pub const SESSION_ID: Range<usize> = 4..8;
    pub const TRANSACTION_ID: Range<usize> = 8..12;
    pub const PACKET_ID: Range<usize> = 12..16;
    pub const PAYLOAD_LENGTH: Range<usize> = 16..20;
}

/// h.flags (RFC 2741 §6.1). NETWORK_BYTE_ORDER and NON_DEFAULT_CONTEXT are kept apart
/// from the others in [`PduRepr`](super::PduRepr) (its byte order and context), so a
/// `Flags` value in a repr holds only the three below.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Flags(pub u8);

impl Flags {
    /// Register: the subtree names one object instance, not a whole subtree.
    pub const INSTANCE_REGISTRATION: Flags = Flags(0x01);
    /// IndexAllocate: allocate an index value not used before.
    pub const NEW_INDEX: Flags = Flags(0x02);
    /// IndexAllocate: allocate any index value not in use.
    pub const ANY_INDEX: Flags = Flags(0x04);
    /// A context octet string follows the header.
    pub const NON_DEFAULT_CONTEXT: Flags = Flags(0x08);
    /// Multi-byte fields are big-endian.
    pub const NETWORK_BYTE_ORDER: Flags = Flags(0x10);
    /// The flags a repr keeps as such: INSTANCE_REGISTRATION, NEW_INDEX and ANY_INDEX.
    pub const REPR_MASK: u8 = 0x07;

    /// Whether every bit of `other` is set.
    pub const fn contains(self, other: Flags) -> bool {
        self.0 & other.0 == other.0
    }

    /// Both sets of bits.
    pub const fn union(self, other: Flags) -> Flags {
        Flags(self.0 | other.0)
    }
}

/// A view of the 20 header bytes at the front of a buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Header<T: AsRef<[u8]>> {
    buffer: T,
}

impl<T: AsRef<[u8]>> Header<T> {
    /// Wraps a buffer without checking it.
    pub const fn new_unchecked(buffer: T) -> Header<T> {
        Header { buffer }
    }

    /// Wraps a buffer after [`check_len`](Self::check_len).
    pub fn new_checked(buffer: T) -> Result<Header<T>, ParseError> {
        let view = Header::new_unchecked(buffer);
        view.check_len()?;
        Ok(view)
    }

    /// `Ok` when the buffer holds the 20 header bytes; then no getter panics.
    pub fn check_len(&self) -> Result<(), ParseError> {
        if self.buffer.as_ref().len() < HEADER_LEN {
            Err(ParseError::Truncated { field: "header" })
        } else {
            Ok(())
        }
    }

    /// The buffer.
    pub fn into_inner(self) -> T {
        self.buffer
    }

    fn byte(&self, at: usize) -> u8 {
        self.buffer.as_ref().get(at).copied().unwrap_or(0)
    }

    fn word(&self, range: core::ops::Range<usize>) -> u32 {
        let bytes: [u8; 4] = self
            .buffer
            .as_ref()
            .get(range)
            .and_then(|b| b.try_into().ok())
            .unwrap_or([0; 4]);
        match self.byte_order() {
            ByteOrder::Big => u32::from_be_bytes(bytes),
            ByteOrder::Little => u32::from_le_bytes(bytes),
        }
    }

    /// h.version.
    pub fn version(&self) -> u8 {
        self.byte(field::VERSION)
    }

    /// h.type.
    pub fn pdu_type(&self) -> PduType {
        PduType::from_raw(self.byte(field::TYPE))
    }

    /// h.flags.
    pub fn flags(&self) -> Flags {
        Flags(self.byte(field::FLAGS))
    }

    /// The byte order of the multi-byte fields.
    pub fn byte_order(&self) -> ByteOrder {
        if self.flags().contains(Flags::NETWORK_BYTE_ORDER) {
            ByteOrder::Big
        } else {
            ByteOrder::Little
        }
    }

    /// h.sessionID.
    pub fn session_id(&self) -> u32 {
        self.word(field::SESSION_ID)
    }

    /// h.transactionID.
    pub fn transaction_id(&self) -> u32 {
        self.word(field::TRANSACTION_ID)
    }

    /// h.packetID.
    pub fn packet_id(&self) -> u32 {
        self.word(field::PACKET_ID)
    }

    /// h.payload_length: the bytes after the header.
    pub fn payload_length(&self) -> u32 {
        self.word(field::PAYLOAD_LENGTH)
    }
}

impl<T: AsRef<[u8]> + AsMut<[u8]>> Header<T> {
    fn set_byte(&mut self, at: usize, v: u8) {
        if let Some(b) = self.buffer.as_mut().get_mut(at) {
            *b = v;
        }
    }

    fn set_word(&mut self, range: core::ops::Range<usize>, v: u32) {
        let bytes = match self.byte_order() {
            ByteOrder::Big => v.to_be_bytes(),
            ByteOrder::Little => v.to_le_bytes(),
        };
        if let Some(b) = self.buffer.as_mut().get_mut(range) {
            b.copy_from_slice(&bytes);
        }
    }

    /// Sets h.version.
    pub fn set_version(&mut self, v: u8) {
        self.set_byte(field::VERSION, v);
    }

    /// Sets h.type.
    pub fn set_pdu_type(&mut self, v: PduType) {
        self.set_byte(field::TYPE, v.raw());
    }

    /// Sets h.flags; set them before the 32-bit fields, whose byte order they choose.
    pub fn set_flags(&mut self, v: Flags) {
        self.set_byte(field::FLAGS, v.0);
    }

    /// Sets h.sessionID.
    pub fn set_session_id(&mut self, v: u32) {
        self.set_word(field::SESSION_ID, v);
    }

    /// Sets h.transactionID.
    pub fn set_transaction_id(&mut self, v: u32) {
        self.set_word(field::TRANSACTION_ID, v);
    }

    /// Sets h.packetID.
    pub fn set_packet_id(&mut self, v: u32) {
        self.set_word(field::PACKET_ID, v);
    }

    /// Sets h.payload_length.
    pub fn set_payload_length(&mut self, v: u32) {
        self.set_word(field::PAYLOAD_LENGTH, v);
    }
}

/// The header as plain data.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct HeaderRepr {
    /// h.type.
    pub pdu_type: PduType,
    /// h.flags, all of them (the byte order included).
    pub flags: Flags,
    /// h.sessionID.
    pub session_id: u32,
    /// h.transactionID.
    pub transaction_id: u32,
    /// h.packetID.
    pub packet_id: u32,
    /// h.payload_length.
    pub payload_length: u32,
}

impl HeaderRepr {
    /// Parses a header view (its buffer may go on after the header); version 1 only.
    pub fn parse<T: AsRef<[u8]>>(header: &Header<T>) -> Result<HeaderRepr, ParseError> {
        header.check_len()?;
        if header.version() != VERSION {
            return Err(ParseError::Version(header.version()));
        }
        Ok(HeaderRepr {
            pdu_type: header.pdu_type(),
            flags: header.flags(),
            session_id: header.session_id(),
            transaction_id: header.transaction_id(),
            packet_id: header.packet_id(),
            payload_length: header.payload_length(),
        })
    }

    /// The byte order the flags say.
    pub const fn byte_order(&self) -> ByteOrder {
        if self.flags.contains(Flags::NETWORK_BYTE_ORDER) {
            ByteOrder::Big
        } else {
            ByteOrder::Little
        }
    }

    /// The header's length: 20.
    pub const fn buffer_len(&self) -> usize {
        HEADER_LEN
    }

    /// Writes the header into the first 20 bytes of `buffer`.
    pub fn emit(&self, buffer: &mut [u8]) -> Result<(), EmitError> {
        let got = buffer.len();
        let head = buffer
            .get_mut(..HEADER_LEN)
            .ok_or(EmitError::BufferTooShort {
                needed: HEADER_LEN,
                got,
            })?;
        head.fill(0);
        let mut header = Header::new_unchecked(head);
        header.set_version(VERSION);
        header.set_pdu_type(self.pdu_type);
        header.set_flags(self.flags);
        header.set_session_id(self.session_id);
        header.set_transaction_id(self.transaction_id);
        header.set_packet_id(self.packet_id);
        header.set_payload_length(self.payload_length);
        Ok(())
    }
}
