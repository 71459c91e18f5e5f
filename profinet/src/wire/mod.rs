// SPDX-License-Identifier: MIT OR Apache-2.0
//! PROFINET wire formats, in the smoltcp style.
//!
//! Every format has a buffer view (`Packet<T: AsRef<[u8]>>` or a named equivalent) with
//! `new_unchecked`, `check_len` and `new_checked`, field getters, setters on an `AsMut` impl,
//! and a `Repr` with `parse`, `buffer_len` and `emit`.
//!
//! The contract:
//! - once `check_len` (or `new_checked`) has returned `Ok`, no getter panics;
//! - `Repr::parse` never panics, on any input: malformed bytes give [`Error`];
//! - `Repr::emit` never panics: it returns [`EmitError`] when the buffer is shorter than
//!   `buffer_len()` or a value does not fit its wire field (a length or count over its 16
//!   bits, fields that contradict each other), and writes nothing truncated;
//! - byte order is explicit (big-endian on the wire unless a format says otherwise); wire
//!   bytes are never transmuted.

/// Declares a buffer view `$name<T: AsRef<[u8]>>` over a wire format with the constructors
/// every view shares: `new_unchecked`, `new_checked` (which runs the view's own `check_len`,
/// written next to its getters) and `into_inner`.
///
/// A macro because a function cannot declare a type and its inherent constructors; a trait
/// would make every caller import it to call `Packet::new_checked`.
macro_rules! buffer_view {
    ($(#[$m:meta])* pub struct $name:ident;) => {
        $(#[$m])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        pub struct $name<T: AsRef<[u8]>> {
            buffer: T,
        }

        impl<T: AsRef<[u8]>> $name<T> {
            /// Wraps a buffer without checking it.
            pub const fn new_unchecked(buffer: T) -> $name<T> {
                $name { buffer }
            }

            /// Wraps a buffer after [`check_len`](Self::check_len).
            pub fn new_checked(buffer: T) -> $crate::wire::Result<$name<T>> {
                let view = $name::new_unchecked(buffer);
                view.check_len()?;
                Ok(view)
            }

            /// The buffer.
            pub fn into_inner(self) -> T {
                self.buffer
            }
        }
    };
}

pub mod alarm;
pub mod common;
pub mod connect;
pub mod control;
mod cursor;
pub mod dcp;
pub mod diagnosis;
pub mod ethernet;
pub mod lldp;
pub mod record;
pub mod rpc;
pub mod rt;
pub mod rta_pdu;
#[cfg(test)]
pub(crate) mod test_captures;
#[cfg(test)]
pub(crate) mod test_strategies;

pub use common::{BlockHeader, BlockType, PnioStatus, Uuid};

/// A malformed or truncated frame. Callers count and drop such frames.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Error;

impl core::fmt::Display for Error {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("malformed PROFINET frame")
    }
}

impl core::error::Error for Error {}

/// The result of parsing.
pub type Result<T> = core::result::Result<T, Error>;

/// Why a frame, PDU or block could not be written. Every `emit`, `to_vec` and builder of wire
/// bytes returns it instead of panicking or truncating.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum EmitError {
    /// The buffer is shorter than what is to be written.
    BufferTooShort {
        /// What was being written.
        what: &'static str,
        /// Bytes it needs.
        needed: usize,
        /// Bytes the buffer has.
        len: usize,
    },
    /// A length or count does not fit its wire field.
    TooLong {
        /// The wire field.
        field: &'static str,
        /// The value it would have to hold.
        value: usize,
        /// The largest value the field holds.
        max: usize,
    },
    /// What was written does not fill the length computed for it: the length and the
    /// encoding of a format disagree.
    LengthMismatch {
        /// What was being written.
        what: &'static str,
        /// Bytes its computed length says.
        computed: usize,
        /// Bytes written.
        written: usize,
    },
    /// The fields contradict each other, so there is no encoding to write.
    Inconsistent(&'static str),
}

impl EmitError {
    /// `TooLong` for a 16-bit length or count field.
    pub(crate) const fn too_long_u16(field: &'static str, value: usize) -> EmitError {
        EmitError::TooLong {
            field,
            value,
            max: u16::MAX as usize,
        }
    }

    /// `Ok` when a buffer of `len` bytes holds the `needed` bytes of `what`.
    pub(crate) const fn check_len(
        what: &'static str,
        needed: usize,
        len: usize,
    ) -> core::result::Result<(), EmitError> {
        if len < needed {
            Err(EmitError::BufferTooShort { what, needed, len })
        } else {
            Ok(())
        }
    }
}

impl core::fmt::Display for EmitError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            EmitError::BufferTooShort { what, needed, len } => {
                write!(f, "buffer of {len} bytes, the {what} needs {needed}")
            }
            EmitError::TooLong { field, value, max } => {
                write!(
                    f,
                    "{field} would be {value}, over the {max} its wire field holds"
                )
            }
            EmitError::LengthMismatch {
                what,
                computed,
                written,
            } => write!(
                f,
                "the {what} wrote {written} bytes where its computed length is {computed}"
            ),
            EmitError::Inconsistent(why) => write!(f, "nothing to emit: {why}"),
        }
    }
}

impl core::error::Error for EmitError {}

/// The result of emitting.
pub type EmitResult<T> = core::result::Result<T, EmitError>;

/// A new vector of `buffer_len` bytes that `emit` fills: the body of every `to_vec`.
pub(crate) fn emit_to_vec(
    buffer_len: usize,
    emit: impl FnOnce(&mut [u8]) -> EmitResult<()>,
) -> EmitResult<Vec<u8>> {
    let mut v = vec![0u8; buffer_len];
    emit(&mut v)?;
    Ok(v)
}

/// A byte range of a fixed field.
pub(crate) type Field = core::ops::Range<usize>;
/// The rest of a buffer from an offset.
pub(crate) type Rest = core::ops::RangeFrom<usize>;

/// Reads a big-endian u16 from a 2-byte slice.
pub(crate) fn be16(b: &[u8]) -> u16 {
    u16::from_be_bytes([b[0], b[1]])
}

/// Reads a big-endian u32 from a 4-byte slice.
pub(crate) fn be32(b: &[u8]) -> u32 {
    u32::from_be_bytes([b[0], b[1], b[2], b[3]])
}

/// `Ok` when `b` holds a header of `header_len` bytes and the payload whose length the
/// header's big-endian u16 at `len_field` announces. Bytes after the payload (Ethernet
/// padding) are allowed, so a view never reads them as data.
pub(crate) fn check_announced_len(b: &[u8], len_field: Field, header_len: usize) -> Result<()> {
    let Some(len) = b.get(len_field) else {
        return Err(Error);
    };
    if b.len() < header_len + usize::from(be16(len)) {
        Err(Error)
    } else {
        Ok(())
    }
}

/// A MAC address.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct MacAddress(pub [u8; 6]);

impl MacAddress {
    /// The DCP Identify multicast address 01:0E:CF:00:00:00.
    pub const DCP_IDENTIFY: MacAddress = MacAddress([0x01, 0x0e, 0xcf, 0x00, 0x00, 0x00]);
    /// The DCP Hello multicast address 01:0E:CF:00:00:01.
    pub const DCP_HELLO: MacAddress = MacAddress([0x01, 0x0e, 0xcf, 0x00, 0x00, 0x01]);

    /// From the first 6 bytes of `b` (which must hold them).
    pub(crate) fn from_slice(b: &[u8]) -> MacAddress {
        let mut m = [0u8; 6];
        m.copy_from_slice(&b[..6]);
        MacAddress(m)
    }

    /// Whether the group bit is set (multicast or broadcast).
    pub const fn is_multicast(&self) -> bool {
        self.0[0] & 1 != 0
    }
}

impl core::fmt::Display for MacAddress {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let m = self.0;
        write!(
            f,
            "{:02x}:{:02x}:{:02x}:{:02x}:{:02x}:{:02x}",
            m[0], m[1], m[2], m[3], m[4], m[5]
        )
    }
}
