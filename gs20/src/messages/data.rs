// SPDX-License-Identifier: MIT OR Apache-2.0
//! The IO data of Run mode: Set Bus Data (0x30) and Adapter Data (0x31), both with a
//! two-byte LEN (reference §1.4, §1.5).
//!
//! The reference names them from two points of view: its frame tables call 0x30 the
//! "output" data (the host's output), its §4.1 the items' *input* data (PROFINET's view).
//! This crate uses PROFINET's: 0x30 carries the items' input bytes (host → PLC), 0x31 their
//! output bytes (PLC → host), each the concatenation of the items in the order they were
//! added (§1.7). The data carries no IOPS/IOCS.

use super::{Message, ParseError, Writer, check_len};
use crate::frame::{EmitError, FrameId};

/// Set Bus Data (0x30, host → module): the items' input bytes. Its length must equal the
/// configured input total, or the module answers with error bit 7 and the PLC gets nothing
/// of it (a check of the link, not of the frame).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct SetBusData<'a> {
    /// The bytes, 0 to 384.
    pub data: &'a [u8],
}

/// Adapter Data (0x31, module → host): the items' output bytes, as the PLC wrote them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct AdapterData<'a> {
    /// The bytes, 0 to 384.
    pub data: &'a [u8],
}

macro_rules! data_message {
    ($($ty:ident),+) => {$(
        impl<'a> Message<'a> for $ty<'a> {
            const ID: FrameId = FrameId::$ty;

            fn parse_payload(payload: &'a [u8]) -> Result<$ty<'a>, ParseError> {
                check_len(Self::ID, payload)?;
                Ok($ty { data: payload })
            }

            fn payload_len(&self) -> usize {
                self.data.len()
            }

            fn emit_payload(&self, out: &mut [u8]) -> Result<(), EmitError> {
                Writer::new(out).bytes(self.data).finish()
            }
        }
    )+};
}

data_message!(SetBusData, AdapterData);
