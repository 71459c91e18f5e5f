// SPDX-License-Identifier: MIT OR Apache-2.0
//! Record data Read and Write: the IOD request and response headers, WriteMultiple (index
//! 0xE040), the I&M0 record and the PNIORW error codes.
//!
//! A Read (opnum 2, or 5 for ReadImplicit) or Write (opnum 3) carries, after the RPC and NDR
//! headers, one header block with a 58-byte body (BlockLength 0x003C, 64 bytes in all),
//! followed by RecordDataLength bytes of record data in a Write request and a Read response:
//!
//! ```text
//! BlockHeader(6) SeqNumber(2) ARUUID(16) API(4) Slot(2) Subslot(2) Padding(2) Index(2)
//! RecordDataLength(4) then 24 bytes:
//!   0x0009 IODReadReqHeader   TargetARUUID(16) Padding(8)
//!   0x0008 IODWriteReqHeader  Padding(24)
//!   0x8009 IODReadResHeader   AdditionalValue1(2) AdditionalValue2(2) Padding(20)
//!   0x8008 IODWriteResHeader  AdditionalValue1(2) AdditionalValue2(2) PNIOStatus(4) Padding(16)
//! ```
//!
//! A WriteMultiple request is an outer IODWriteReqHeader with Index 0xE040 (API 0xFFFFFFFF,
//! Slot and Subslot 0xFFFF, as an S7 sends it) whose record data is a sequence of
//! IODWriteReqHeader + data, each padded to a 4-byte boundary (counted from the start of the
//! outer record data, which is also 4-aligned in the RPC body). The response is the outer
//! IODWriteResHeader followed by one IODWriteResHeader per write (p-net answers every
//! RecordDataLength with 0).
//!
//! All blocks are big-endian. Padding bytes are ignored on parsing and written as zeros;
//! block versions are not checked and written as 1.0.

use super::common::BLOCK_HEADER_LEN;
use super::cursor::{Reader, Writer};
use super::{BlockHeader, BlockType, EmitError, EmitResult, Error, PnioStatus, Result, Uuid};

/// Index of a WriteMultiple.
pub const INDEX_WRITE_MULTIPLE: u16 = 0xe040;
/// Index of I&M0 (I&M1..I&M15 follow at 0xAFF1..0xAFFF).
pub const INDEX_IM0: u16 = 0xaff0;
/// Index of I&M0FilterData (which submodules carry their own I&M0).
pub const INDEX_IM0_FILTER_DATA: u16 = 0xf840;
/// API of the outer header of a WriteMultiple.
pub const WRITE_MULTIPLE_API: u32 = 0xffff_ffff;
/// Slot and subslot of the outer header of a WriteMultiple.
pub const WRITE_MULTIPLE_SLOT: u16 = 0xffff;
/// Alignment of the writes inside a WriteMultiple.
pub const WRITE_MULTIPLE_ALIGN: usize = 4;

/// Bytes of an IOD header body (after the block header).
pub const IOD_HEADER_BODY_LEN: usize = 58;
/// Bytes of a whole IOD header block.
pub const IOD_HEADER_LEN: usize = BLOCK_HEADER_LEN + IOD_HEADER_BODY_LEN;
/// Bytes of a whole I&M0 block.
pub const IM0_LEN: usize = 60;
/// Bytes of an I&M0 body (after the block header).
const IM0_BODY_LEN: usize = IM0_LEN - BLOCK_HEADER_LEN;

/// ErrorCode of a failed record read (IODReadRes).
pub const ERROR_CODE_READ: u8 = 0xde;
/// ErrorCode of a failed record write (IODWriteRes).
pub const ERROR_CODE_WRITE: u8 = 0xdf;
/// ErrorDecode "PNIORW": ErrorCode1 is a [`RecordErrorCode`], ErrorCode2 user specific.
pub const ERROR_DECODE_PNIORW: u8 = 0x80;

/// Which of the four IOD headers a block is. An IOD header has one of these four block
/// types and no other, so there is no unknown kind to keep: [`IodKind::from_block_type`] says
/// `None` for every other [`BlockType`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum IodKind {
    /// 0x0008 IODWriteReqHeader: record data follows.
    WriteReq,
    /// 0x0009 IODReadReqHeader: RecordDataLength is the most the client accepts.
    ReadReq,
    /// 0x8008 IODWriteResHeader.
    WriteRes,
    /// 0x8009 IODReadResHeader: record data follows.
    ReadRes,
}

impl IodKind {
    /// The BlockType.
    pub const fn block_type(self) -> BlockType {
        match self {
            IodKind::WriteReq => BlockType::IodWriteReqHeader,
            IodKind::ReadReq => BlockType::IodReadReqHeader,
            IodKind::WriteRes => BlockType::IodWriteResHeader,
            IodKind::ReadRes => BlockType::IodReadResHeader,
        }
    }

    /// The kind of a BlockType; `None` for other blocks.
    pub const fn from_block_type(block_type: BlockType) -> Option<IodKind> {
        match block_type {
            BlockType::IodWriteReqHeader => Some(IodKind::WriteReq),
            BlockType::IodReadReqHeader => Some(IodKind::ReadReq),
            BlockType::IodWriteResHeader => Some(IodKind::WriteRes),
            BlockType::IodReadResHeader => Some(IodKind::ReadRes),
            _ => None,
        }
    }

    /// Whether it is a request header.
    pub const fn is_request(self) -> bool {
        matches!(self, IodKind::WriteReq | IodKind::ReadReq)
    }

    /// Whether RecordDataLength bytes of record data follow the header (Write request, Read
    /// response).
    pub const fn carries_data(self) -> bool {
        matches!(self, IodKind::WriteReq | IodKind::ReadRes)
    }

    /// The response kind of a request kind (a response kind maps to itself).
    pub const fn response(self) -> IodKind {
        match self {
            IodKind::WriteReq | IodKind::WriteRes => IodKind::WriteRes,
            IodKind::ReadReq | IodKind::ReadRes => IodKind::ReadRes,
        }
    }
}

/// An IODReadReqHeader, IODWriteReqHeader, IODReadResHeader or IODWriteResHeader.
///
/// `target_ar_uuid` exists only in a Read request, `add_value1`/`add_value2` only in
/// responses and `status` only in a Write response: parsing leaves them nil/0/OK for the other
/// kinds and emitting ignores them there.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct IodHeader {
    /// Which header.
    pub kind: IodKind,
    /// SeqNumber (the client's counter, echoed).
    pub seq_number: u16,
    /// ARUUID (nil for ReadImplicit).
    pub ar_uuid: Uuid,
    /// API.
    pub api: u32,
    /// SlotNumber.
    pub slot: u16,
    /// SubslotNumber.
    pub subslot: u16,
    /// Index.
    pub index: u16,
    /// RecordDataLength: bytes that follow (Write request, Read response), the most the client
    /// accepts (Read request), or the written length (Write response).
    pub record_data_length: u32,
    /// TargetARUUID (Read request: nil, or the AR an implicit read addresses).
    pub target_ar_uuid: Uuid,
    /// AdditionalValue1 (responses).
    pub add_value1: u16,
    /// AdditionalValue2 (responses).
    pub add_value2: u16,
    /// PNIOStatus (Write response; a failed Read reports it in the RPC header only).
    pub status: PnioStatus,
}

impl IodHeader {
    #[allow(clippy::too_many_arguments)]
    const fn request(
        kind: IodKind,
        seq_number: u16,
        ar_uuid: Uuid,
        api: u32,
        slot: u16,
        subslot: u16,
        index: u16,
        record_data_length: u32,
    ) -> IodHeader {
        IodHeader {
            kind,
            seq_number,
            ar_uuid,
            api,
            slot,
            subslot,
            index,
            record_data_length,
            target_ar_uuid: Uuid::NIL,
            add_value1: 0,
            add_value2: 0,
            status: PnioStatus::OK,
        }
    }

    /// A Read request for at most `max_len` bytes (TargetARUUID nil).
    pub const fn read_request(
        seq_number: u16,
        ar_uuid: Uuid,
        api: u32,
        slot: u16,
        subslot: u16,
        index: u16,
        max_len: u32,
    ) -> IodHeader {
        IodHeader::request(
            IodKind::ReadReq,
            seq_number,
            ar_uuid,
            api,
            slot,
            subslot,
            index,
            max_len,
        )
    }

    /// A Write request header for `len` bytes of record data.
    pub const fn write_request(
        seq_number: u16,
        ar_uuid: Uuid,
        api: u32,
        slot: u16,
        subslot: u16,
        index: u16,
        len: u32,
    ) -> IodHeader {
        IodHeader::request(
            IodKind::WriteReq,
            seq_number,
            ar_uuid,
            api,
            slot,
            subslot,
            index,
            len,
        )
    }

    /// The outer header of a WriteMultiple whose record data (the joined writes, see
    /// [`join_write_multiple`]) has `data_len` bytes.
    pub const fn write_multiple(seq_number: u16, ar_uuid: Uuid, data_len: u32) -> IodHeader {
        IodHeader::write_request(
            seq_number,
            ar_uuid,
            WRITE_MULTIPLE_API,
            WRITE_MULTIPLE_SLOT,
            WRITE_MULTIPLE_SLOT,
            INDEX_WRITE_MULTIPLE,
            data_len,
        )
    }

    /// The (successful) response header to this request: the same SeqNumber, ARUUID, address
    /// and index, `record_data_length`, status OK and additional values 0.
    pub const fn response(&self, record_data_length: u32) -> IodHeader {
        IodHeader {
            kind: self.kind.response(),
            record_data_length,
            target_ar_uuid: Uuid::NIL,
            add_value1: 0,
            add_value2: 0,
            status: PnioStatus::OK,
            ..*self
        }
    }

    /// Whether it is the outer header of a WriteMultiple.
    pub const fn is_write_multiple(&self) -> bool {
        self.index == INDEX_WRITE_MULTIPLE
    }

    /// Parses the header block at the start of `b` (bytes after it are ignored). Another block
    /// type or a body other than 58 bytes gives [`Error`].
    pub fn parse(b: &[u8]) -> Result<IodHeader> {
        let h = BlockHeader::parse(b)?;
        let kind = IodKind::from_block_type(h.block_type).ok_or(Error)?;
        if h.body_len() != IOD_HEADER_BODY_LEN {
            return Err(Error);
        }
        let mut r = Reader::new(h.body(b));
        let seq_number = r.u16()?;
        let ar_uuid = r.uuid()?;
        let api = r.u32()?;
        let slot = r.u16()?;
        let subslot = r.u16()?;
        r.take(2)?;
        let index = r.u16()?;
        let record_data_length = r.u32()?;
        let mut hdr = IodHeader::request(
            kind,
            seq_number,
            ar_uuid,
            api,
            slot,
            subslot,
            index,
            record_data_length,
        );
        match kind {
            IodKind::ReadReq => hdr.target_ar_uuid = r.uuid()?,
            IodKind::WriteReq => {}
            IodKind::ReadRes | IodKind::WriteRes => {
                hdr.add_value1 = r.u16()?;
                hdr.add_value2 = r.u16()?;
                if kind == IodKind::WriteRes {
                    hdr.status = PnioStatus::from_u32(r.u32()?);
                }
            }
        }
        Ok(hdr)
    }

    /// Parses the header at the start of `b` and splits off what follows it: the record data
    /// (RecordDataLength bytes for a Write request or Read response, empty otherwise) and the
    /// rest. Record data running past `b` gives [`Error`].
    pub fn split(b: &[u8]) -> Result<(IodHeader, &[u8], &[u8])> {
        let h = IodHeader::parse(b)?;
        let rest = b.get(IOD_HEADER_LEN..).ok_or(Error)?;
        let n = if h.kind.carries_data() {
            usize::try_from(h.record_data_length).map_err(|_| Error)?
        } else {
            0
        };
        let (data, rest) = rest.split_at_checked(n).ok_or(Error)?;
        Ok((h, data, rest))
    }

    /// Bytes of the block ([`IOD_HEADER_LEN`]).
    pub const fn buffer_len(&self) -> usize {
        IOD_HEADER_LEN
    }

    /// Writes the block into the first [`IOD_HEADER_LEN`] bytes of `buf`; a shorter buffer
    /// gives [`EmitError::BufferTooShort`].
    pub fn emit(&self, buf: &mut [u8]) -> EmitResult<()> {
        let len = buf.len();
        let out = buf
            .get_mut(..IOD_HEADER_LEN)
            .ok_or(EmitError::BufferTooShort {
                what: "IOD header",
                needed: IOD_HEADER_LEN,
                len,
            })?;
        out.fill(0);
        let mut w = Writer::new("IOD header", out);
        w.block_header(self.kind.block_type(), IOD_HEADER_BODY_LEN)?;
        w.u16(self.seq_number)?;
        w.put(&self.ar_uuid.0)?;
        w.u32(self.api)?;
        w.u16(self.slot)?;
        w.u16(self.subslot)?;
        w.u16(0)?;
        w.u16(self.index)?;
        w.u32(self.record_data_length)?;
        match self.kind {
            IodKind::ReadReq => w.put(&self.target_ar_uuid.0)?,
            IodKind::WriteReq => {}
            IodKind::ReadRes | IodKind::WriteRes => {
                w.u16(self.add_value1)?;
                w.u16(self.add_value2)?;
                if self.kind == IodKind::WriteRes {
                    w.u32(self.status.to_u32())?;
                }
            }
        }
        Ok(())
    }

    /// The block as 64 bytes.
    pub fn to_bytes(&self) -> [u8; IOD_HEADER_LEN] {
        let mut b = [0u8; IOD_HEADER_LEN];
        // Cannot fail: the buffer has exactly the length emit needs.
        let _ = self.emit(&mut b);
        b
    }
}

/// Bytes of the padding after `len` bytes to reach [`WRITE_MULTIPLE_ALIGN`].
const fn pad_len(len: usize) -> usize {
    (WRITE_MULTIPLE_ALIGN - len % WRITE_MULTIPLE_ALIGN) % WRITE_MULTIPLE_ALIGN
}

/// Splits the record data of a WriteMultiple (what follows its outer header) into its writes:
/// each an IODWriteReqHeader and its record data. Padding to the next 4-byte boundary may
/// follow every write, the last one included (it may also be missing after the last one).
/// Another header kind or a write running past `data` gives [`Error`].
pub fn split_write_multiple(data: &[u8]) -> Result<Vec<(IodHeader, &[u8])>> {
    let mut writes = Vec::new();
    let mut rest = data;
    while !rest.is_empty() {
        let (h, d, after) = IodHeader::split(rest)?;
        if h.kind != IodKind::WriteReq {
            return Err(Error);
        }
        writes.push((h, d));
        let offset = data.len() - after.len();
        let pad = pad_len(offset).min(after.len());
        rest = after.get(pad..).ok_or(Error)?;
    }
    Ok(writes)
}

/// Bytes of the record data [`join_write_multiple`] writes: every write padded to 4 bytes.
pub fn write_multiple_len(writes: &[(IodHeader, &[u8])]) -> usize {
    writes.iter().fold(0usize, |n, (_, d)| {
        let len = IOD_HEADER_LEN.saturating_add(d.len());
        n.saturating_add(len).saturating_add(pad_len(len))
    })
}

/// Joins writes into the record data of a WriteMultiple (to follow
/// [`IodHeader::write_multiple`]): each header, its data and zero padding to the next 4-byte
/// boundary, the last one included. Returns the bytes written
/// ([`write_multiple_len`]). A header that is not a Write request, a RecordDataLength other
/// than its data's length or a short buffer give [`EmitError`].
pub fn join_write_multiple(writes: &[(IodHeader, &[u8])], buf: &mut [u8]) -> EmitResult<usize> {
    EmitError::check_len("WriteMultiple", write_multiple_len(writes), buf.len())?;
    let mut w = Writer::new("WriteMultiple", buf);
    for (h, d) in writes {
        if h.kind != IodKind::WriteReq {
            return Err(EmitError::Inconsistent(
                "a write of a WriteMultiple has a header other than IODWriteReqHeader",
            ));
        }
        if usize::try_from(h.record_data_length) != Ok(d.len()) {
            return Err(EmitError::Inconsistent(
                "a write's RecordDataLength differs from its data's length",
            ));
        }
        let start = w.position();
        w.reserve(IOD_HEADER_LEN).and_then(|b| h.emit(b))?;
        w.put(d)?;
        w.zeros(pad_len(w.position() - start))?;
    }
    Ok(w.position())
}

/// [`join_write_multiple`] into a new vector.
pub fn join_write_multiple_to_vec(writes: &[(IodHeader, &[u8])]) -> EmitResult<Vec<u8>> {
    let mut v = vec![0u8; write_multiple_len(writes)];
    let n = join_write_multiple(writes, &mut v)?;
    v.truncate(n);
    Ok(v)
}

/// Splits the blocks of a WriteMultiple response: the outer IODWriteResHeader and one
/// IODWriteResHeader per write. Another block, or record data claimed by a header kind that
/// carries some, gives [`Error`].
pub fn split_write_multiple_response(b: &[u8]) -> Result<(IodHeader, Vec<IodHeader>)> {
    let mut headers = Vec::new();
    let mut rest = b;
    while !rest.is_empty() {
        let (h, _, after) = IodHeader::split(rest)?;
        if h.kind != IodKind::WriteRes {
            return Err(Error);
        }
        headers.push(h);
        rest = after;
    }
    if headers.is_empty() {
        return Err(Error);
    }
    let outer = headers.remove(0);
    Ok((outer, headers))
}

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

/// The class of a PNIORW ErrorCode1 (its high nibble).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ErrorClass {
    /// 0xA: application.
    Application,
    /// 0xB: access.
    Access,
    /// 0xC: resource.
    Resource,
    /// 0xD..=0xF: user specific.
    UserSpecific,
    /// 0x0..=0x9: reserved.
    Reserved,
}

impl ErrorClass {
    /// The class of an ErrorCode1.
    pub const fn of(error_code1: u8) -> ErrorClass {
        match error_code1 >> 4 {
            0xa => ErrorClass::Application,
            0xb => ErrorClass::Access,
            0xc => ErrorClass::Resource,
            0xd..=0xf => ErrorClass::UserSpecific,
            _ => ErrorClass::Reserved,
        }
    }
}

impl core::fmt::Display for ErrorClass {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            ErrorClass::Application => "application",
            ErrorClass::Access => "access",
            ErrorClass::Resource => "resource",
            ErrorClass::UserSpecific => "user specific",
            ErrorClass::Reserved => "reserved",
        })
    }
}

enum_with_unknown! {
    /// PNIORW ErrorCode1: error class (high nibble) and code (low nibble).
    pub enum RecordErrorCode(u8) {
        /// 0xA0 application: read error.
        ReadError = 0xa0 => "read error",
        /// 0xA1 application: write error.
        WriteError = 0xa1 => "write error",
        /// 0xA2 application: module failure.
        ModuleFailure = 0xa2 => "module failure",
        /// 0xA7 application: busy.
        Busy = 0xa7 => "busy",
        /// 0xA8 application: version conflict.
        VersionConflict = 0xa8 => "version conflict",
        /// 0xA9 application: feature not supported.
        FeatureNotSupported = 0xa9 => "feature not supported",
        /// 0xB0 access: invalid index.
        InvalidIndex = 0xb0 => "invalid index",
        /// 0xB1 access: write length error.
        WriteLengthError = 0xb1 => "write length error",
        /// 0xB2 access: invalid slot/subslot.
        InvalidSlotSubslot = 0xb2 => "invalid slot/subslot",
        /// 0xB3 access: type conflict.
        TypeConflict = 0xb3 => "type conflict",
        /// 0xB4 access: invalid area/API.
        InvalidAreaOrApi = 0xb4 => "invalid area/API",
        /// 0xB5 access: state conflict.
        StateConflict = 0xb5 => "state conflict",
        /// 0xB6 access: access denied.
        AccessDenied = 0xb6 => "access denied",
        /// 0xB7 access: invalid range.
        InvalidRange = 0xb7 => "invalid range",
        /// 0xB8 access: invalid parameter.
        InvalidParameter = 0xb8 => "invalid parameter",
        /// 0xB9 access: invalid type.
        InvalidType = 0xb9 => "invalid type",
        /// 0xBA access: backup.
        Backup = 0xba => "backup",
        /// 0xC0 resource: read constrain conflict.
        ReadConstrainConflict = 0xc0 => "read constrain conflict",
        /// 0xC1 resource: write constrain conflict.
        WriteConstrainConflict = 0xc1 => "write constrain conflict",
        /// 0xC2 resource: resource busy.
        ResourceBusy = 0xc2 => "resource busy",
        /// 0xC3 resource: resource unavailable.
        ResourceUnavailable = 0xc3 => "resource unavailable",
    }
}

impl RecordErrorCode {
    /// The error class.
    pub fn class(self) -> ErrorClass {
        ErrorClass::of(self.into())
    }
}

impl core::fmt::Display for RecordErrorCode {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let code = u8::from(*self);
        let class = self.class();
        match self.name() {
            Some(name) => write!(f, "{class}: {name}"),
            None => {
                // Codes the class leaves to the user: A.A-F, B.B-F, C.8-F and classes D-F.
                let user = match class {
                    ErrorClass::Application => code & 0x0f >= 0x0a,
                    ErrorClass::Access => code & 0x0f >= 0x0b,
                    ErrorClass::Resource => code & 0x0f >= 0x08,
                    ErrorClass::UserSpecific => true,
                    ErrorClass::Reserved => false,
                };
                let what = if user { "user specific" } else { "reserved" };
                if class == ErrorClass::UserSpecific || class == ErrorClass::Reserved {
                    write!(f, "{what} ({code:#04x})")
                } else {
                    write!(f, "{class}: {what} ({code:#04x})")
                }
            }
        }
    }
}

/// A record Read/Write failure: a PNIOStatus with ErrorDecode PNIORW (0x80).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct RecordError {
    /// ErrorCode: [`ERROR_CODE_READ`] or [`ERROR_CODE_WRITE`] (others are kept as they are).
    pub error_code: u8,
    /// ErrorCode1.
    pub code: RecordErrorCode,
    /// ErrorCode2 (user specific).
    pub error_code2: u8,
}

impl RecordError {
    /// A failed read.
    pub const fn read(code: RecordErrorCode, error_code2: u8) -> RecordError {
        RecordError {
            error_code: ERROR_CODE_READ,
            code,
            error_code2,
        }
    }

    /// A failed write.
    pub const fn write(code: RecordErrorCode, error_code2: u8) -> RecordError {
        RecordError {
            error_code: ERROR_CODE_WRITE,
            code,
            error_code2,
        }
    }

    /// Decodes a PNIOStatus; `None` unless its ErrorDecode is PNIORW.
    pub fn from_status(status: PnioStatus) -> Option<RecordError> {
        (status.error_decode == ERROR_DECODE_PNIORW).then(|| RecordError {
            error_code: status.error_code,
            code: RecordErrorCode::from(status.error_code1),
            error_code2: status.error_code2,
        })
    }

    /// The PNIOStatus.
    pub fn status(&self) -> PnioStatus {
        PnioStatus {
            error_code: self.error_code,
            error_decode: ERROR_DECODE_PNIORW,
            error_code1: self.code.into(),
            error_code2: self.error_code2,
        }
    }
}

impl core::fmt::Display for RecordError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self.error_code {
            ERROR_CODE_READ => f.write_str("record read error: ")?,
            ERROR_CODE_WRITE => f.write_str("record write error: ")?,
            other => write!(f, "record error (ErrorCode {other:#04x}): ")?,
        }
        write!(f, "{} (ErrorCode2 {:#04x})", self.code, self.error_code2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_fixtures::hex;
    use proptest::prelude::*;

    // The captures below come from the test data of the `pnio` crate 0.1.0
    // (core-engineering/pnio-rs, MIT OR Apache-2.0): an S7-1515 talking to the p-net sample
    // device. Only the blocks part of each frame: from byte 142 (Ethernet 14 + IPv4 20 +
    // UDP 8 + RPC header 80 + NDR header 20) to the end.

    /// alarm/im0_read_req.hex: Read request, slot 0 subslot 1, index 0xAFF0, up to 0x8000 bytes.
    const IM0_READ_REQ: &str = concat!(
        "0009003c01000006ef796d60ef2b9946b39e8531f5b7f9660000000000000001",
        "0000aff000008000000000000000000000000000000000000000000000000000",
    );
    /// alarm/im0_read_res.hex: p-net's Read response with its I&M0 block.
    const IM0_READ_RES: &str = concat!(
        "8009003c01000006ef796d60ef2b9946b39e8531f5b7f9660000000000000001",
        "0000aff00000003c000000000000000000000000000000000000000000000000",
        "00200038010004933132333435204162636465666768696a6b20202030303720",
        "2020202020202020202020200003560002000000123456780101000e",
    );
    /// alarm/im0_read_req_if.hex: Read request of I&M0 on the interface submodule 0x8000.
    const IM0_READ_REQ_IF: &str = concat!(
        "0009003c01000005ef796d60ef2b9946b39e8531f5b7f9660000000000008000",
        "0000aff000008000000000000000000000000000000000000000000000000000",
    );
    /// alarm/im0_read_res_if.hex: the response to it.
    const IM0_READ_RES_IF: &str = concat!(
        "8009003c01000005ef796d60ef2b9946b39e8531f5b7f9660000000000008000",
        "0000aff00000003c000000000000000000000000000000000000000000000000",
        "00200038010004933132333435204162636465666768696a6b20202030303720",
        "2020202020202020202020200003560002000000123456780101000e",
    );
    /// cm/write_req.hex: the S7's WriteMultiple (PDInterfaceAdjust 0x8071, user records
    /// 123, 124 and 125).
    const WRITE_REQ: &str = concat!(
        "0008003c01000000e5e1aeccb1334b4db187cc68b0211ed2ffffffffffffffff",
        "0000e04000000118000000000000000000000000000000000000000000000000",
        "0008003c01000001e5e1aeccb1334b4db187cc68b0211ed20000000000008000",
        "000080710000000c000000000000000000000000000000000000000000000000",
        "0250000801000000000000010008003c01000002e5e1aeccb1334b4db187cc68",
        "b0211ed200000000000300010000007b00000004000000000000000000000000",
        "000000000000000000000000000000010008003c01000003e5e1aeccb1334b4d",
        "b187cc68b0211ed200000000000300010000007c000000040000000000000000",
        "00000000000000000000000000000000000000020008003c01000004e5e1aecc",
        "b1334b4db187cc68b0211ed200000000000400010000007d0000000400000000",
        "000000000000000000000000000000000000000000000002",
    );
    /// cm/write_res.hex: p-net's response to it.
    const WRITE_RES: &str = concat!(
        "8008003c01000000e5e1aeccb1334b4db187cc68b0211ed2ffffffffffffffff",
        "0000e04000000000000000000000000000000000000000000000000000000000",
        "8008003c01000001e5e1aeccb1334b4db187cc68b0211ed20000000000008000",
        "0000807100000000000000000000000000000000000000000000000000000000",
        "8008003c01000002e5e1aeccb1334b4db187cc68b0211ed20000000000030001",
        "0000007b00000000000000000000000000000000000000000000000000000000",
        "8008003c01000003e5e1aeccb1334b4db187cc68b0211ed20000000000030001",
        "0000007c00000000000000000000000000000000000000000000000000000000",
        "8008003c01000004e5e1aeccb1334b4db187cc68b0211ed20000000000040001",
        "0000007d00000000000000000000000000000000000000000000000000000000",
    );

    /// ARUUID of the I&M0 reads.
    const READ_AR: Uuid = Uuid::from_fields(
        0xef79_6d60,
        0xef2b,
        0x9946,
        [0xb3, 0x9e, 0x85, 0x31, 0xf5, 0xb7, 0xf9, 0x66],
    );
    /// ARUUID of the WriteMultiple.
    const WRITE_AR: Uuid = Uuid::from_fields(
        0xe5e1_aecc,
        0xb133,
        0x4b4d,
        [0xb1, 0x87, 0xcc, 0x68, 0xb0, 0x21, 0x1e, 0xd2],
    );

    /// Splits the header off `b` and checks it re-emits to its 64 bytes.
    fn header(b: &[u8]) -> (IodHeader, &[u8], &[u8]) {
        let (h, data, rest) = IodHeader::split(b).unwrap();
        assert_eq!(h.to_bytes()[..], b[..IOD_HEADER_LEN]);
        (h, data, rest)
    }

    #[test]
    fn im0_read_requests() {
        for (hex_str, seq, subslot) in [(IM0_READ_REQ, 6, 1), (IM0_READ_REQ_IF, 5, 0x8000)] {
            let b = hex(hex_str);
            let (h, data, rest) = header(&b);
            assert!(data.is_empty() && rest.is_empty());
            let expected = IodHeader::read_request(seq, READ_AR, 0, 0, subslot, INDEX_IM0, 0x8000);
            assert_eq!(h, expected);
            assert_eq!(h.kind, IodKind::ReadReq);
            assert_eq!(h.target_ar_uuid, Uuid::NIL);
        }
    }

    #[test]
    fn im0_read_responses() {
        for (req, res) in [
            (IM0_READ_REQ, IM0_READ_RES),
            (IM0_READ_REQ_IF, IM0_READ_RES_IF),
        ] {
            let req = IodHeader::parse(&hex(req)).unwrap();
            let b = hex(res);
            let (h, data, rest) = header(&b);
            assert!(rest.is_empty());
            assert_eq!(h.kind, IodKind::ReadRes);
            assert_eq!(h, req.response(IM0_LEN as u32));
            assert_eq!((h.add_value1, h.add_value2), (0, 0));
            assert_eq!(data.len(), IM0_LEN);

            let im0 = Im0::parse(data).unwrap();
            let expected = Im0 {
                vendor_id: 0x0493,
                order_id: blank_padded("12345 Abcdefghijk").unwrap(),
                serial_number: blank_padded("007").unwrap(),
                hardware_revision: 3,
                software_revision: SoftwareRevision {
                    prefix: b'V',
                    functional_enhancement: 0,
                    bug_fix: 2,
                    internal_change: 0,
                },
                revision_counter: 0,
                profile_id: 0x1234,
                profile_specific_type: 0x5678,
                im_version: (1, 1),
                im_supported: 0x000e,
            };
            assert_eq!(im0, expected);
            assert_eq!(im0.order_id_str(), Some("12345 Abcdefghijk"));
            assert_eq!(im0.serial_number_str(), Some("007"));
            assert_eq!(im0.software_revision.to_string(), "V0.2.0");
            assert!(im0.supports(1) && im0.supports(2) && im0.supports(3));
            assert!(!im0.supports(0) && !im0.supports(4) && !im0.supports(16));
            assert_eq!(im0.to_bytes()[..], data[..]);
        }
    }

    #[test]
    fn write_multiple_request() {
        let b = hex(WRITE_REQ);
        let (outer, data, rest) = header(&b);
        assert!(rest.is_empty());
        assert!(outer.is_write_multiple());
        assert_eq!(outer, IodHeader::write_multiple(0, WRITE_AR, 280));
        assert_eq!(data.len(), 280);

        let writes = split_write_multiple(data).unwrap();
        let expected: [(u16, u16, u16, u16, &[u8]); 4] = [
            (
                1,
                0,
                0x8000,
                0x8071,
                &[0x02, 0x50, 0, 8, 1, 0, 0, 0, 0, 0, 0, 1],
            ),
            (2, 3, 1, 123, &[0, 0, 0, 1]),
            (3, 3, 1, 124, &[0, 0, 0, 2]),
            (4, 4, 1, 125, &[0, 0, 0, 2]),
        ];
        assert_eq!(writes.len(), expected.len());
        for ((h, d), (seq, slot, subslot, index, bytes)) in writes.iter().zip(expected) {
            let len = bytes.len() as u32;
            let e = IodHeader::write_request(seq, WRITE_AR, 0, slot, subslot, index, len);
            assert_eq!(h, &e);
            assert_eq!(*d, bytes);
        }
        assert_eq!(write_multiple_len(&writes), data.len());
        assert_eq!(join_write_multiple_to_vec(&writes).unwrap(), data);
        let mut out = outer.to_bytes().to_vec();
        out.extend_from_slice(&join_write_multiple_to_vec(&writes).unwrap());
        assert_eq!(out, b);
    }

    #[test]
    fn write_multiple_response() {
        let b = hex(WRITE_RES);
        let (outer, writes) = split_write_multiple_response(&b).unwrap();
        assert_eq!(outer.kind, IodKind::WriteRes);
        assert!(outer.is_write_multiple());
        assert!(outer.status.is_ok());
        // p-net answers RecordDataLength 0 everywhere.
        let req = hex(WRITE_REQ);
        let (req_outer, data, _) = IodHeader::split(&req).unwrap();
        assert_eq!(outer, req_outer.response(0));
        let requests = split_write_multiple(data).unwrap();
        assert_eq!(writes.len(), requests.len());
        for (res, (req, _)) in writes.iter().zip(&requests) {
            assert_eq!(res, &req.response(0));
        }
        let mut out = outer.to_bytes().to_vec();
        for w in &writes {
            out.extend_from_slice(&w.to_bytes());
        }
        assert_eq!(out, b);
    }

    #[test]
    fn write_multiple_padding() {
        let a = IodHeader::write_request(1, WRITE_AR, 0, 1, 1, 100, 3);
        let b = IodHeader::write_request(2, WRITE_AR, 0, 1, 1, 101, 5);
        let writes: [(IodHeader, &[u8]); 2] = [(a, &[1, 2, 3]), (b, &[4, 5, 6, 7, 8])];
        let joined = join_write_multiple_to_vec(&writes).unwrap();
        assert_eq!(joined.len(), 68 + 72);
        assert_eq!(&joined[64..68], &[1, 2, 3, 0]);
        assert_eq!(&joined[68..70], &[0x00, 0x08]);
        assert_eq!(&joined[132..140], &[4, 5, 6, 7, 8, 0, 0, 0]);
        assert_eq!(split_write_multiple(&joined).unwrap(), writes.to_vec());
        // Without the padding after the last write.
        assert_eq!(
            split_write_multiple(&joined[..137]).unwrap(),
            writes.to_vec()
        );
        // A length that does not match the data, a response header, a short buffer.
        let bad: [(IodHeader, &[u8]); 1] = [(a, &[1, 2])];
        assert!(matches!(
            join_write_multiple_to_vec(&bad),
            Err(EmitError::Inconsistent(_))
        ));
        let bad: [(IodHeader, &[u8]); 1] = [(a.response(3), &[1, 2, 3])];
        assert!(matches!(
            join_write_multiple_to_vec(&bad),
            Err(EmitError::Inconsistent(_))
        ));
        let mut short = [0u8; 67];
        assert_eq!(
            join_write_multiple(&writes[..1], &mut short),
            Err(EmitError::BufferTooShort {
                what: "WriteMultiple",
                needed: 68,
                len: 67
            })
        );
        // A write running past the data.
        assert_eq!(split_write_multiple(&joined[..130]), Err(Error));
    }

    #[test]
    fn malformed() {
        let b = hex(IM0_READ_RES);
        for n in 0..IOD_HEADER_LEN {
            assert_eq!(IodHeader::parse(&b[..n]), Err(Error));
        }
        // Record data past the end.
        assert_eq!(IodHeader::split(&b[..b.len() - 1]), Err(Error));
        // Wrong body length, unknown block type.
        let mut bad = b.clone();
        bad[3] = 0x3b;
        assert_eq!(IodHeader::parse(&bad), Err(Error));
        let mut bad = b.clone();
        bad[1] = 0x0a;
        assert_eq!(IodHeader::parse(&bad), Err(Error));
        // I&M0 of the wrong length or type.
        let im0 = &b[IOD_HEADER_LEN..];
        assert_eq!(Im0::parse(&im0[..IM0_LEN - 1]), Err(Error));
        let mut bad = im0.to_vec();
        bad[1] = 0x21;
        assert_eq!(Im0::parse(&bad), Err(Error));
        // Emit into short buffers.
        let h = IodHeader::parse(&b).unwrap();
        assert!(matches!(
            h.emit(&mut [0u8; IOD_HEADER_LEN - 1]),
            Err(EmitError::BufferTooShort { needed: 64, .. })
        ));
        let i = Im0::parse(im0).unwrap();
        assert!(matches!(
            i.emit(&mut [0u8; IM0_LEN - 1]),
            Err(EmitError::BufferTooShort { needed: 60, .. })
        ));
        // A response of nothing.
        assert_eq!(split_write_multiple_response(&[]), Err(Error));
        // Blank padding.
        assert_eq!(blank_padded::<4>("ab"), Ok(*b"ab  "));
        assert_eq!(blank_padded::<2>("abc"), Err(Error));
        assert_eq!(blank_padded::<4>("a\u{e9}"), Err(Error));
    }

    #[test]
    fn record_errors() {
        let e = RecordError::from_status(PnioStatus::from_bytes([0xde, 0x80, 0xb0, 0x00])).unwrap();
        assert_eq!(e, RecordError::read(RecordErrorCode::InvalidIndex, 0));
        assert_eq!(e.code.class(), ErrorClass::Access);
        assert_eq!(
            e.to_string(),
            "record read error: access: invalid index (ErrorCode2 0x00)"
        );
        let e = RecordError::write(RecordErrorCode::ResourceBusy, 7);
        assert_eq!(e.status().to_bytes(), [0xdf, 0x80, 0xc2, 0x07]);
        assert_eq!(RecordError::from_status(e.status()), Some(e));
        assert_eq!(
            e.to_string(),
            "record write error: resource: resource busy (ErrorCode2 0x07)"
        );
        let text = |code1: u8| RecordErrorCode::from(code1).to_string();
        assert_eq!(text(0xa9), "application: feature not supported");
        assert_eq!(text(0xab), "application: user specific (0xab)");
        assert_eq!(text(0xa4), "application: reserved (0xa4)");
        assert_eq!(text(0xbf), "access: user specific (0xbf)");
        assert_eq!(text(0xc5), "resource: reserved (0xc5)");
        assert_eq!(text(0xc8), "resource: user specific (0xc8)");
        assert_eq!(text(0xd1), "user specific (0xd1)");
        assert_eq!(text(0x12), "reserved (0x12)");
        // Not PNIORW: a Connect error, success.
        let connect = PnioStatus::from_bytes([0xdb, 0x81, 0x01, 0x04]);
        assert_eq!(RecordError::from_status(connect), None);
        assert_eq!(RecordError::from_status(PnioStatus::OK), None);
    }

    fn uuid() -> impl Strategy<Value = Uuid> {
        any::<[u8; 16]>().prop_map(Uuid)
    }

    fn iod_header() -> impl Strategy<Value = IodHeader> {
        let kind = prop_oneof![
            Just(IodKind::WriteReq),
            Just(IodKind::ReadReq),
            Just(IodKind::WriteRes),
            Just(IodKind::ReadRes),
        ];
        (
            kind,
            any::<(u16, u32, u16, u16, u16, u32)>(),
            uuid(),
            uuid(),
            any::<(u16, u16, u32)>(),
        )
            .prop_map(
                |(kind, (seq, api, slot, subslot, index, len), ar, target, (a1, a2, s))| {
                    let mut h = IodHeader::request(kind, seq, ar, api, slot, subslot, index, len);
                    if kind == IodKind::ReadReq {
                        h.target_ar_uuid = target;
                    }
                    if !kind.is_request() {
                        h.add_value1 = a1;
                        h.add_value2 = a2;
                    }
                    if kind == IodKind::WriteRes {
                        h.status = PnioStatus::from_u32(s);
                    }
                    h
                },
            )
    }

    fn im0() -> impl Strategy<Value = Im0> {
        (
            any::<(u16, [u8; 20], [u8; 16], u16, [u8; 4])>(),
            any::<(u16, u16, u16, (u8, u8), u16)>(),
        )
            .prop_map(
                |((vendor, order, serial, hw, sw), (rc, pid, pst, v, sup))| Im0 {
                    vendor_id: vendor,
                    order_id: order,
                    serial_number: serial,
                    hardware_revision: hw,
                    software_revision: SoftwareRevision {
                        prefix: sw[0],
                        functional_enhancement: sw[1],
                        bug_fix: sw[2],
                        internal_change: sw[3],
                    },
                    revision_counter: rc,
                    profile_id: pid,
                    profile_specific_type: pst,
                    im_version: v,
                    im_supported: sup,
                },
            )
    }

    proptest! {
        #[test]
        fn parse_never_panics(bytes in proptest::collection::vec(any::<u8>(), 0..400)) {
            if let Ok(h) = IodHeader::parse(&bytes) {
                prop_assert_eq!(h.buffer_len(), IOD_HEADER_LEN);
            }
            let _ = IodHeader::split(&bytes);
            let _ = Im0::parse(&bytes);
            let _ = split_write_multiple(&bytes);
            let _ = split_write_multiple_response(&bytes);
            if let Ok(i) = Im0::parse(&bytes) {
                let _ = (i.order_id_str(), i.serial_number_str(), i.software_revision.to_string());
            }
        }

        #[test]
        fn parse_never_panics_on_plausible_headers(
            block_type in prop_oneof![Just(8u16), Just(9u16), Just(0x8008u16), Just(0x8009u16)],
            body in proptest::collection::vec(any::<u8>(), 60..61),
            tail in proptest::collection::vec(any::<u8>(), 0..200),
        ) {
            let mut b = block_type.to_be_bytes().to_vec();
            b.extend_from_slice(&[0, 0x3c]);
            b.extend_from_slice(&body);
            b.extend_from_slice(&tail);
            let h = IodHeader::parse(&b).unwrap();
            prop_assert_eq!(IodHeader::parse(&h.to_bytes()).unwrap(), h);
            let _ = IodHeader::split(&b);
            let _ = split_write_multiple(&b);
        }

        #[test]
        fn record_errors_never_panic(v in any::<u32>()) {
            let s = PnioStatus::from_u32(v);
            if let Some(e) = RecordError::from_status(s) {
                prop_assert_eq!(e.status(), s);
                let _ = e.to_string();
            }
        }

        #[test]
        fn iod_header_round_trip(h in iod_header()) {
            let bytes = h.to_bytes();
            prop_assert_eq!(IodHeader::parse(&bytes).unwrap(), h);
        }

        #[test]
        fn im0_round_trip(i in im0()) {
            prop_assert_eq!(Im0::parse(&i.to_bytes()).unwrap(), i);
        }

        #[test]
        fn write_multiple_round_trip(
            writes in proptest::collection::vec(
                (iod_header(), proptest::collection::vec(any::<u8>(), 0..12)),
                0..5,
            ),
        ) {
            let writes: Vec<(IodHeader, Vec<u8>)> = writes
                .into_iter()
                .map(|(mut h, d)| {
                    h = IodHeader::write_request(
                        h.seq_number, h.ar_uuid, h.api, h.slot, h.subslot, h.index, d.len() as u32,
                    );
                    (h, d)
                })
                .collect();
            let refs: Vec<(IodHeader, &[u8])> =
                writes.iter().map(|(h, d)| (*h, d.as_slice())).collect();
            let joined = join_write_multiple_to_vec(&refs).unwrap();
            prop_assert_eq!(joined.len() % WRITE_MULTIPLE_ALIGN, 0);
            prop_assert_eq!(joined.len(), write_multiple_len(&refs));
            prop_assert_eq!(split_write_multiple(&joined).unwrap(), refs);
        }
    }
}
