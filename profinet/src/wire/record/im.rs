// SPDX-License-Identifier: MIT OR Apache-2.0
//! The identification and maintenance records I&M0 to I&M4 (indices 0xAFF0 to 0xAFF4): one
//! block each, version 1.0, fixed-size fields.
//!
//! ```text
//! I&M0 0x0020 (60 bytes)  VendorID(2) OrderID(20) SerialNumber(16) HardwareRevision(2)
//!                         SoftwareRevision(4) RevisionCounter(2) ProfileID(2)
//!                         ProfileSpecificType(2) IM_Version(2) IM_Supported(2)
//! I&M1 0x0021 (60 bytes)  IM_Tag_Function(32) IM_Tag_Location(22)
//! I&M2 0x0022 (22 bytes)  IM_Date(16) "YYYY-MM-DD hh:mm"
//! I&M3 0x0023 (60 bytes)  IM_Descriptor(54)
//! I&M4 0x0024 (60 bytes)  IM_Signature(54)
//! ```
//!
//! The text fields are visible ASCII padded with blanks; they are kept as bytes so that
//! parsing is lossless ([`blank_padded`] builds one from text). IM_Signature is binary
//! (the PROFIsafe signature), zero when unused. Parsing checks the block type and the
//! length, not the version; emitting writes 1.0.

use super::super::common::BLOCK_HEADER_LEN;
use super::super::cursor::{Reader, Writer};
use super::{BlockHeader, BlockType, EmitError, EmitResult, Error, Result};

/// Bytes of a whole I&M0 block.
pub const IM0_LEN: usize = 60;
/// Bytes of an I&M0 body (after the block header).
const IM0_BODY_LEN: usize = IM0_LEN - BLOCK_HEADER_LEN;

/// SoftwareRevision of I&M0: a prefix character and three numbers, e.g. `V0.2.0`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct SoftwareRevision {
    /// SWRevisionPrefix: an ASCII character, 'V' official release, 'R' revision,
    /// 'P' prototype, 'U' under test, 'T' test device.
    pub prefix: u8,
    /// SWRevisionFunctionalEnhancement.
    pub functional_enhancement: u8,
    /// SWRevisionBugFix.
    pub bug_fix: u8,
    /// SWRevisionInternalChange.
    pub internal_change: u8,
}

impl core::fmt::Display for SoftwareRevision {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        if self.prefix.is_ascii_graphic() {
            write!(f, "{}", char::from(self.prefix))?;
        } else {
            write!(f, "<{:#04x}>", self.prefix)?;
        }
        write!(
            f,
            "{}.{}.{}",
            self.functional_enhancement, self.bug_fix, self.internal_change
        )
    }
}

/// The I&M0 record (block 0x0020, 60 bytes), read at index 0xAFF0.
///
/// The strings are fixed-size, blank-padded visible ASCII; they are kept as bytes so that
/// parsing is lossless, see [`Im0::order_id_str`] and [`blank_padded`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Im0 {
    /// VendorID (MANUFACTURER_ID).
    pub vendor_id: u16,
    /// OrderID, 20 bytes.
    pub order_id: [u8; 20],
    /// IM_Serial_Number, 16 bytes.
    pub serial_number: [u8; 16],
    /// IM_Hardware_Revision.
    pub hardware_revision: u16,
    /// IM_Software_Revision.
    pub software_revision: SoftwareRevision,
    /// IM_Revision_Counter.
    pub revision_counter: u16,
    /// IM_Profile_ID.
    pub profile_id: u16,
    /// IM_Profile_Specific_Type.
    pub profile_specific_type: u16,
    /// IM_Version (major, minor), e.g. (1, 1).
    pub im_version: (u8, u8),
    /// IM_Supported: bit n set = I&Mn (n = 1..=15) is available.
    pub im_supported: u16,
}

impl Im0 {
    /// Parses the I&M0 block at the start of `b` (the record data of a Read response of
    /// index 0xAFF0). Another block type or a body of the wrong length gives [`Error`].
    pub fn parse(b: &[u8]) -> Result<Im0> {
        let h = BlockHeader::parse(b)?;
        if h.block_type != BlockType::Im0 || h.body_len() != IM0_BODY_LEN {
            return Err(Error);
        }
        let mut r = Reader::new(h.body(b));
        Ok(Im0 {
            vendor_id: r.u16()?,
            order_id: r.array()?,
            serial_number: r.array()?,
            hardware_revision: r.u16()?,
            software_revision: SoftwareRevision {
                prefix: r.u8()?,
                functional_enhancement: r.u8()?,
                bug_fix: r.u8()?,
                internal_change: r.u8()?,
            },
            revision_counter: r.u16()?,
            profile_id: r.u16()?,
            profile_specific_type: r.u16()?,
            im_version: (r.u8()?, r.u8()?),
            im_supported: r.u16()?,
        })
    }

    /// Bytes of the block ([`IM0_LEN`]).
    pub const fn buffer_len(&self) -> usize {
        IM0_LEN
    }

    /// Writes the block into the first [`IM0_LEN`] bytes of `buf`; a shorter buffer gives
    /// [`EmitError::BufferTooShort`].
    pub fn emit(&self, buf: &mut [u8]) -> EmitResult<()> {
        EmitError::check_len("I&M0 block", IM0_LEN, buf.len())?;
        let mut w = Writer::new("I&M0 block", buf);
        w.block_header(BlockType::Im0, IM0_BODY_LEN)?;
        w.u16(self.vendor_id)?;
        w.put(&self.order_id)?;
        w.put(&self.serial_number)?;
        w.u16(self.hardware_revision)?;
        let s = self.software_revision;
        w.put(&[
            s.prefix,
            s.functional_enhancement,
            s.bug_fix,
            s.internal_change,
        ])?;
        w.u16(self.revision_counter)?;
        w.u16(self.profile_id)?;
        w.u16(self.profile_specific_type)?;
        w.put(&[self.im_version.0, self.im_version.1])?;
        w.u16(self.im_supported)
    }

    /// The block as 60 bytes.
    pub fn to_bytes(&self) -> [u8; IM0_LEN] {
        let mut b = [0u8; IM0_LEN];
        // Cannot fail: the buffer has exactly the length emit needs.
        let _ = self.emit(&mut b);
        b
    }

    /// OrderID without the trailing blanks; `None` if it is not UTF-8.
    pub fn order_id_str(&self) -> Option<&str> {
        trimmed(&self.order_id)
    }

    /// IM_Serial_Number without the trailing blanks; `None` if it is not UTF-8.
    pub fn serial_number_str(&self) -> Option<&str> {
        trimmed(&self.serial_number)
    }

    /// Whether I&Mn is available according to IM_Supported (`n` in 1..=15; false otherwise).
    pub const fn supports(&self, n: u8) -> bool {
        n >= 1 && n <= 15 && self.im_supported & (1 << n) != 0
    }
}

/// `b` without trailing blanks and NULs, as text.
fn trimmed(b: &[u8]) -> Option<&str> {
    let end = b
        .iter()
        .rposition(|&c| c != b' ' && c != 0)
        .map_or(0, |i| i + 1);
    core::str::from_utf8(b.get(..end)?).ok()
}

/// `s` as an `N`-byte blank-padded field (I&M strings). Anything but visible ASCII and blanks,
/// or more than `N` bytes, gives [`Error`].
pub fn blank_padded<const N: usize>(s: &str) -> Result<[u8; N]> {
    let mut out = [b' '; N];
    if s.len() > N || !s.bytes().all(|c| c == b' ' || c.is_ascii_graphic()) {
        return Err(Error);
    }
    out.get_mut(..s.len())
        .ok_or(Error)?
        .copy_from_slice(s.as_bytes());
    Ok(out)
}

/// The body of the block at the start of `b` if it has type `block_type` and a body of
/// exactly `len` bytes.
fn fixed_body(b: &[u8], block_type: BlockType, len: usize) -> Result<&[u8]> {
    let h = BlockHeader::parse(b)?;
    if h.block_type != block_type || h.body_len() != len {
        return Err(Error);
    }
    Ok(h.body(b))
}

/// Writes a v1.0 block of `block_type` whose body is `fields` one after the other.
fn emit_fixed(
    what: &'static str,
    block_type: BlockType,
    fields: &[&[u8]],
    buf: &mut [u8],
) -> EmitResult<()> {
    let body: usize = fields.iter().map(|f| f.len()).sum();
    EmitError::check_len(what, BLOCK_HEADER_LEN + body, buf.len())?;
    let mut w = Writer::new(what, buf);
    w.block_header(block_type, body)?;
    fields.iter().try_for_each(|f| w.put(f))
}

/// Bytes of a whole I&M1, I&M3 or I&M4 block.
pub const IM1_LEN: usize = 60;
/// Bytes of a whole I&M2 block.
pub const IM2_LEN: usize = 22;

/// The I&M1 record (block 0x0021, index 0xAFF1): where the device sits in the plant.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Im1 {
    /// IM_Tag_Function: the plant-wide function tag, 32 bytes.
    pub tag_function: [u8; 32],
    /// IM_Tag_Location: the installation location, 22 bytes.
    pub tag_location: [u8; 22],
}

impl Default for Im1 {
    /// Blanks: nothing written yet.
    fn default() -> Im1 {
        Im1 {
            tag_function: [b' '; 32],
            tag_location: [b' '; 22],
        }
    }
}

impl Im1 {
    /// Parses the I&M1 block at the start of `b`; another block type or length gives
    /// [`Error`].
    pub fn parse(b: &[u8]) -> Result<Im1> {
        let mut r = Reader::new(fixed_body(b, BlockType::Im1, IM1_LEN - BLOCK_HEADER_LEN)?);
        Ok(Im1 {
            tag_function: r.array()?,
            tag_location: r.array()?,
        })
    }

    /// Bytes of the block ([`IM1_LEN`]).
    pub const fn buffer_len(&self) -> usize {
        IM1_LEN
    }

    /// Writes the block into the first [`IM1_LEN`] bytes of `buf`; a shorter buffer gives
    /// [`EmitError::BufferTooShort`].
    pub fn emit(&self, buf: &mut [u8]) -> EmitResult<()> {
        let fields: [&[u8]; 2] = [&self.tag_function, &self.tag_location];
        emit_fixed("I&M1 block", BlockType::Im1, &fields, buf)
    }

    /// The block as 60 bytes.
    pub fn to_bytes(&self) -> [u8; IM1_LEN] {
        let mut b = [0u8; IM1_LEN];
        // Cannot fail: the buffer has exactly the length emit needs.
        let _ = self.emit(&mut b);
        b
    }
}

/// The I&M2 record (block 0x0022, index 0xAFF2): the installation date.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Im2 {
    /// IM_Date: "YYYY-MM-DD hh:mm", 16 bytes.
    pub date: [u8; 16],
}

impl Default for Im2 {
    /// Blanks: nothing written yet.
    fn default() -> Im2 {
        Im2 { date: [b' '; 16] }
    }
}

impl Im2 {
    /// Parses the I&M2 block at the start of `b`; another block type or length gives
    /// [`Error`].
    pub fn parse(b: &[u8]) -> Result<Im2> {
        let mut r = Reader::new(fixed_body(b, BlockType::Im2, IM2_LEN - BLOCK_HEADER_LEN)?);
        Ok(Im2 { date: r.array()? })
    }

    /// Bytes of the block ([`IM2_LEN`]).
    pub const fn buffer_len(&self) -> usize {
        IM2_LEN
    }

    /// Writes the block into the first [`IM2_LEN`] bytes of `buf`; a shorter buffer gives
    /// [`EmitError::BufferTooShort`].
    pub fn emit(&self, buf: &mut [u8]) -> EmitResult<()> {
        emit_fixed("I&M2 block", BlockType::Im2, &[&self.date], buf)
    }

    /// The block as 22 bytes.
    pub fn to_bytes(&self) -> [u8; IM2_LEN] {
        let mut b = [0u8; IM2_LEN];
        // Cannot fail: the buffer has exactly the length emit needs.
        let _ = self.emit(&mut b);
        b
    }
}

/// The I&M3 record (block 0x0023, index 0xAFF3): a free comment.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Im3 {
    /// IM_Descriptor, 54 bytes.
    pub descriptor: [u8; 54],
}

impl Default for Im3 {
    /// Blanks: nothing written yet.
    fn default() -> Im3 {
        Im3 {
            descriptor: [b' '; 54],
        }
    }
}

impl Im3 {
    /// Parses the I&M3 block at the start of `b`; another block type or length gives
    /// [`Error`].
    pub fn parse(b: &[u8]) -> Result<Im3> {
        let mut r = Reader::new(fixed_body(b, BlockType::Im3, IM1_LEN - BLOCK_HEADER_LEN)?);
        Ok(Im3 {
            descriptor: r.array()?,
        })
    }

    /// Bytes of the block ([`IM1_LEN`]).
    pub const fn buffer_len(&self) -> usize {
        IM1_LEN
    }

    /// Writes the block into the first [`IM1_LEN`] bytes of `buf`; a shorter buffer gives
    /// [`EmitError::BufferTooShort`].
    pub fn emit(&self, buf: &mut [u8]) -> EmitResult<()> {
        emit_fixed("I&M3 block", BlockType::Im3, &[&self.descriptor], buf)
    }

    /// The block as 60 bytes.
    pub fn to_bytes(&self) -> [u8; IM1_LEN] {
        let mut b = [0u8; IM1_LEN];
        // Cannot fail: the buffer has exactly the length emit needs.
        let _ = self.emit(&mut b);
        b
    }
}

/// The I&M4 record (block 0x0024, index 0xAFF4): the safety signature.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Im4 {
    /// IM_Signature, 54 bytes (binary; zeros when there is none).
    pub signature: [u8; 54],
}

impl Default for Im4 {
    /// Zeros: no signature.
    fn default() -> Im4 {
        Im4 { signature: [0; 54] }
    }
}

impl Im4 {
    /// Parses the I&M4 block at the start of `b`; another block type or length gives
    /// [`Error`].
    pub fn parse(b: &[u8]) -> Result<Im4> {
        let mut r = Reader::new(fixed_body(b, BlockType::Im4, IM1_LEN - BLOCK_HEADER_LEN)?);
        Ok(Im4 {
            signature: r.array()?,
        })
    }

    /// Bytes of the block ([`IM1_LEN`]).
    pub const fn buffer_len(&self) -> usize {
        IM1_LEN
    }

    /// Writes the block into the first [`IM1_LEN`] bytes of `buf`; a shorter buffer gives
    /// [`EmitError::BufferTooShort`].
    pub fn emit(&self, buf: &mut [u8]) -> EmitResult<()> {
        emit_fixed("I&M4 block", BlockType::Im4, &[&self.signature], buf)
    }

    /// The block as 60 bytes.
    pub fn to_bytes(&self) -> [u8; IM1_LEN] {
        let mut b = [0u8; IM1_LEN];
        // Cannot fail: the buffer has exactly the length emit needs.
        let _ = self.emit(&mut b);
        b
    }
}
