// SPDX-License-Identifier: MIT OR Apache-2.0
//! The DiagnosisData block (0x0010) of the diagnosis records (0x800A–0x8013, 0xC00A–0xC013,
//! 0xE00A–0xE013, 0xF00A–0xF013, 0xF80C): one block per submodule and USI, several blocks
//! one after the other in a record.
//!
//! ```text
//! v1.0: BlockHeader Slot(2) Subslot(2) ChannelNumber(2) ChannelProperties(2) USI(2) data
//! v1.1: BlockHeader API(4) Slot(2) Subslot(2) ChannelNumber(2) ChannelProperties(2) USI(2) data
//! ```
//!
//! The USI and its data are the item an alarm carries too ([`AlarmItem`]): entries of 6
//! (0x8000), 12 (0x8002) or 16 (0x8003) bytes, or manufacturer data (0x0000–0x7FFF). For
//! channel diagnosis the block's own ChannelNumber is 0x8000 (the submodule) and its
//! ChannelProperties only say, in the specifier, whether a fault appears among the entries.

use super::super::common::{BLOCK_HEADER_LEN, blocks};
use super::super::cursor::{Reader, Writer};
use super::super::diagnosis::{AlarmItem, ChannelProperties};
use super::{BlockHeader, BlockType, EmitError, EmitResult, Error, RecordVersion, Result};

/// Bytes after the block header before the USI's data: version 1.0 and 1.1.
const FIXED_V1_0: usize = 10;
const FIXED_V1_1: usize = 14;

/// A DiagnosisData block.
///
/// [`RecordVersion::V1_0`] has no API field: parsing gives API 0, emitting another API gives
/// [`EmitError::Inconsistent`].
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct DiagnosisData {
    /// BlockVersion 1.0 (API 0 only) or 1.1.
    pub version: RecordVersion,
    /// API.
    pub api: u32,
    /// SlotNumber.
    pub slot: u16,
    /// SubslotNumber.
    pub subslot: u16,
    /// ChannelNumber (0x8000 for channel diagnosis).
    pub channel_number: u16,
    /// ChannelProperties.
    pub channel_properties: ChannelProperties,
    /// The USI and its data.
    pub item: AlarmItem,
}

impl DiagnosisData {
    /// Parses the block at the start of `b` (bytes after it are ignored). Another block type
    /// or version, or a body shorter than its fixed part, give [`Error`]; the data never does
    /// (what does not decode is kept raw in [`AlarmItem::Other`]).
    pub fn parse(b: &[u8]) -> Result<DiagnosisData> {
        let h = BlockHeader::parse(b)?;
        if h.block_type != BlockType::DiagnosisData {
            return Err(Error);
        }
        let version = RecordVersion::of(&h).ok_or(Error)?;
        let mut r = Reader::new(h.body(b));
        let api = match version {
            RecordVersion::V1_0 => 0,
            RecordVersion::V1_1 => r.u32()?,
        };
        let slot = r.u16()?;
        let subslot = r.u16()?;
        let channel_number = r.u16()?;
        let channel_properties = ChannelProperties(r.u16()?);
        let usi = r.u16()?;
        Ok(DiagnosisData {
            version,
            api,
            slot,
            subslot,
            channel_number,
            channel_properties,
            item: AlarmItem::parse(usi, r.rest()),
        })
    }

    /// Parses a whole diagnosis record: its blocks one after the other, to the last byte. An
    /// empty record (nothing to report) gives no block; any block that does not parse, or
    /// bytes that are not a whole block, give [`Error`].
    pub fn parse_record(b: &[u8]) -> Result<Vec<DiagnosisData>> {
        blocks(b)
            .map(|r| r.and_then(|(_, block)| DiagnosisData::parse(block)))
            .collect()
    }

    /// Bytes of the block, header included.
    pub fn buffer_len(&self) -> usize {
        let fixed = match self.version {
            RecordVersion::V1_0 => FIXED_V1_0,
            RecordVersion::V1_1 => FIXED_V1_1,
        };
        // The item's length counts its USI, which the fixed part counts already.
        (BLOCK_HEADER_LEN + fixed - 2).saturating_add(self.item.buffer_len())
    }

    /// Writes the block into the first [`buffer_len`](Self::buffer_len) bytes of `buf`. A
    /// shorter buffer, a block longer than BlockLength allows or version 1.0 with an API
    /// other than 0 give [`EmitError`].
    pub fn emit(&self, buf: &mut [u8]) -> EmitResult<()> {
        if self.version == RecordVersion::V1_0 && self.api != 0 {
            return Err(EmitError::Inconsistent(
                "DiagnosisData of version 1.0 has no API field: its API is 0",
            ));
        }
        let total = self.buffer_len();
        let header = BlockHeader {
            version_low: self.version.low(),
            ..BlockHeader::v1(BlockType::DiagnosisData, total - BLOCK_HEADER_LEN)?
        };
        EmitError::check_len("DiagnosisData", total, buf.len())?;
        let mut w = Writer::new("DiagnosisData", buf.get_mut(..total).unwrap_or_default());
        w.put(&header.to_bytes())?;
        if self.version == RecordVersion::V1_1 {
            w.u32(self.api)?;
        }
        w.u16(self.slot)?;
        w.u16(self.subslot)?;
        w.u16(self.channel_number)?;
        w.u16(self.channel_properties.0)?;
        self.item.emit(&mut w)?;
        w.finish()
    }

    /// The block as a new vector.
    pub fn to_vec(&self) -> EmitResult<Vec<u8>> {
        crate::wire::emit_to_vec(self.buffer_len(), |b| self.emit(b))
    }

    /// A whole record: the blocks one after the other (empty for no block).
    pub fn record_to_vec(blocks: &[DiagnosisData]) -> EmitResult<Vec<u8>> {
        let mut v = Vec::new();
        for b in blocks {
            v.extend_from_slice(&b.to_vec()?);
        }
        Ok(v)
    }
}
