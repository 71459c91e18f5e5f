// SPDX-License-Identifier: MIT OR Apache-2.0
//! The AgentX PDU codec (RFC 2741 §5 encodings, §6 PDUs), in the smoltcp style.
//!
//! A PDU is a 20-byte header ([`Header`], [`HeaderRepr`]) followed by `payload_length`
//! bytes; [`PduRepr`] is a whole PDU as plain data (header fields, the optional non-default
//! context and the typed [`Pdu`]) with `parse`, `buffer_len` and `emit`. On a stream,
//! [`frame_len`] tells how many bytes the PDU at the front of a buffer takes.
//!
//! The contract:
//! - once [`Header::check_len`] (or `new_checked`) has returned `Ok`, no getter panics;
//! - every parser ([`PduRepr::parse`], [`frame_len`], [`HeaderRepr::parse`]) never panics,
//!   on any input: malformed bytes give a [`ParseError`] that names what is wrong;
//! - `emit` never panics: it returns [`EmitError`] when the buffer is shorter than
//!   `buffer_len()` or a value does not fit its wire field;
//! - byte order is explicit: every multi-byte field is read and written in the order the
//!   header's NETWORK_BYTE_ORDER flag says ([`ByteOrder`]), never transmuted.

mod codec;
mod enums;
mod header;
mod oid;
mod payload;
mod repr;
mod search;
mod varbind;

#[cfg(test)]
mod tests;

pub use enums::{CloseReason, PduType, ResponseError};
pub use header::{Flags, HEADER_LEN, Header, HeaderRepr, VERSION};
pub use oid::{Oid, OidParseError};
pub use payload::{AddAgentCaps, Close, GetBulk, Open, Pdu, Register, Response, Unregister};
pub use repr::PduRepr;
pub use search::SearchRange;
pub use varbind::{Value, VarBind};

/// The largest payload this codec accepts (1 MiB). AgentX sets no limit; net-snmp's PDUs
/// stay far below it. A larger `payload_length` means the stream is out of step.
pub const MAX_PAYLOAD_LEN: u32 = 1 << 20;

/// The byte order of a PDU's multi-byte fields (RFC 2741 §5: the header's
/// NETWORK_BYTE_ORDER flag).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ByteOrder {
    /// NETWORK_BYTE_ORDER set: most significant byte first. What this crate sends.
    #[default]
    Big,
    /// NETWORK_BYTE_ORDER clear: least significant byte first.
    Little,
}

/// What is wrong with bytes that should hold an AgentX PDU.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ParseError {
    /// The bytes end inside a field.
    #[error(
        "the AgentX PDU ends inside its {field}: pass the whole PDU (the 20-byte header and payload_length more bytes)"
    )]
    Truncated {
        /// The field that was cut short.
        field: &'static str,
    },
    /// The header's version is not 1.
    #[error(
        "AgentX version {0} is not supported (only version 1): the peer on the socket is not an AgentX master agent"
    )]
    Version(u8),
    /// `payload_length` is not a multiple of 4, as every AgentX payload is.
    #[error(
        "payload_length {0} is not a multiple of 4: the stream is out of step; close the connection and open a new session"
    )]
    PayloadAlignment(u32),
    /// `payload_length` is over [`MAX_PAYLOAD_LEN`].
    #[error(
        "payload_length {0} is over the 1 MiB limit: the stream is out of step; close the connection and open a new session"
    )]
    PayloadTooLong(u32),
    /// The bytes given are not exactly one PDU.
    #[error(
        "{given} bytes were given for a PDU of {expected} (header and payload_length): split the stream with frame_len first"
    )]
    Length {
        /// 20 + payload_length.
        expected: usize,
        /// What was given.
        given: usize,
    },
    /// The payload goes on after the PDU type's last field.
    #[error(
        "the payload of a {0} PDU goes on after its last field: the peer encodes it differently from RFC 2741 §6.2"
    )]
    TrailingBytes(PduType),
    /// The header names no AgentX PDU type.
    #[error("PDU type {0} is not an AgentX PDU type (1 to 18)")]
    PduType(u8),
    /// A VarBind's type is not one of RFC 2741 §5.4.
    #[error("VarBind type {0} is not an AgentX value type (RFC 2741 §5.4)")]
    ValueType(u16),
    /// An IpAddress value is not 4 bytes long.
    #[error("an IpAddress value holds {0} bytes instead of 4")]
    IpAddressLength(u32),
}

/// Why a PDU could not be written.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum EmitError {
    /// The buffer is shorter than `buffer_len()`.
    #[error(
        "the buffer holds {got} bytes, the PDU needs {needed}: pass a buffer of buffer_len() bytes"
    )]
    BufferTooShort {
        /// What the PDU needs.
        needed: usize,
        /// What the buffer holds.
        got: usize,
    },
    /// An OID has more subidentifiers than n_subid (one byte) can count.
    #[error(
        "an OID of {0} subidentifiers does not fit AgentX's n_subid (at most 255 after the 1.3.6.1.x prefix): shorten it"
    )]
    OidTooLong(usize),
    /// An octet string is longer than its 32-bit length can say.
    #[error("an octet string of {0} bytes is over AgentX's 32-bit length: shorten it")]
    OctetStringTooLong(usize),
    /// The payload is over [`MAX_PAYLOAD_LEN`].
    #[error("the payload would be {0} bytes, over the 1 MiB limit: send fewer VarBinds in one PDU")]
    PayloadTooLong(usize),
    /// A context was given for a PDU type that carries none (RFC 2741 §6.1.1).
    #[error(
        "a {0} PDU carries no context (only Register, Unregister, Get, GetNext, GetBulk, TestSet, Notify, Ping, IndexAllocate, IndexDeallocate and the AgentCaps PDUs do): leave context None"
    )]
    ContextNotCarried(PduType),
}

/// How many bytes the PDU at the front of `buffer` takes (20 + payload_length), once its
/// header is there; `Ok(None)` while fewer than 20 bytes are. A header that cannot start a
/// PDU (another version, a payload length that is not a multiple of 4 or over
/// [`MAX_PAYLOAD_LEN`]) is an error: the stream cannot be resynchronised after it.
pub fn frame_len(buffer: &[u8]) -> Result<Option<usize>, ParseError> {
    let Ok(header) = Header::new_checked(buffer) else {
        return Ok(None);
    };
    let version = header.version();
    if version != VERSION {
        return Err(ParseError::Version(version));
    }
    let len = header.payload_length();
    if len % 4 != 0 {
        return Err(ParseError::PayloadAlignment(len));
    }
    if len > MAX_PAYLOAD_LEN {
        return Err(ParseError::PayloadTooLong(len));
    }
    // At most 1 MiB + 20: fits usize on every target this crate builds for.
    Ok(Some(HEADER_LEN + len as usize))
}
