// SPDX-License-Identifier: MIT OR Apache-2.0
//! Record data Read and Write: the IOD request and response headers, WriteMultiple (index
//! 0xE040), the PNIORW error codes, and the records a device serves itself: I&M0–I&M4
//! ([`Im0`] to [`Im4`]), the diagnosis records ([`DiagnosisData`]), the identification records and
//! I&M0FilterData ([`IdentificationData`], [`Im0FilterData`]).
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

mod ar_data;
mod diagnosis;
mod identification;
mod im;
mod pdev;
pub mod pe;
mod port_check;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod tests_examples;

pub use ar_data::{
    ApiData, ArData, ArDataEntry, ArDataIocr, INDEX_API_DATA, INDEX_AR_DATA, INDEX_LOG_BOOK_DATA,
    LogBookData, LogEntry,
};
pub use diagnosis::DiagnosisData;
pub use identification::{
    IdentApi, IdentModule, IdentSubmodule, IdentificationData, IdentificationKind, Im0FilterData,
    Im0FilterKind,
};
pub use im::{IM0_LEN, IM1_LEN, IM2_LEN, Im0, Im1, Im2, Im3, Im4, SoftwareRevision, blank_padded};
pub use pdev::{
    INDEX_PD_EXPECTED_DATA, INDEX_PD_INTERFACE_DATA_REAL, INDEX_PD_PORT_DATA_ADJUST,
    INDEX_PD_PORT_DATA_CHECK, INDEX_PD_PORT_DATA_REAL, INDEX_PD_PORT_STATISTIC, INDEX_PD_REAL_DATA,
    LINK_DOWN, LINK_UP, MEDIA_COPPER, MEDIA_UNKNOWN, MultipleBlockHeader, PORT_STATE_FORWARDING,
    PORT_STATE_UNKNOWN, PdInterfaceDataReal, PdPortDataReal, PdPortStatistic, PeerReal,
};
pub use port_check::{
    CheckedPeer, DCP_BOUNDARY_HELLO, DCP_BOUNDARY_IDENTIFY, PEER_TO_PEER_NO_LLDP, PdPortDataAdjust,
    PdPortDataCheck, PortAdjust, PortCheck,
};

/// BlockVersion of the diagnosis and identification records: 1.0 knows API 0 alone and has
/// no field for the API, 1.1 carries it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RecordVersion {
    /// 1.0: API 0 implied.
    V1_0,
    /// 1.1: with the API.
    V1_1,
}

impl RecordVersion {
    /// BlockVersionLow.
    pub const fn low(self) -> u8 {
        match self {
            RecordVersion::V1_0 => 0,
            RecordVersion::V1_1 => 1,
        }
    }

    /// The version of a block header; `None` for anything but 1.0 and 1.1.
    pub(crate) const fn of(h: &BlockHeader) -> Option<RecordVersion> {
        match (h.version_high, h.version_low) {
            (1, 0) => Some(RecordVersion::V1_0),
            (1, 1) => Some(RecordVersion::V1_1),
            _ => None,
        }
    }
}

/// Index of a WriteMultiple.
pub const INDEX_WRITE_MULTIPLE: u16 = 0xe040;
/// Index of I&M0 (I&M1..I&M15 follow at 0xAFF1..0xAFFF).
pub const INDEX_IM0: u16 = 0xaff0;
/// Index of I&M4, the last I&M record the device serves.
pub const INDEX_IM4: u16 = 0xaff4;
/// Index of I&M0FilterData (which submodules carry their own I&M0).
pub const INDEX_IM0_FILTER_DATA: u16 = 0xf840;
/// Index of the ModuleDiffBlock of an AR.
pub const INDEX_MODULE_DIFF: u16 = 0xe002;
/// Index of the device-level diagnosis record (diagnosis, maintenance, qualified, status).
pub const INDEX_DEVICE_DIAGNOSIS: u16 = 0xf80c;
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
    /// A Read or Write request header (`kind`) for record `index` of a submodule: `len` is
    /// the data written, or the most a read takes.
    #[allow(clippy::too_many_arguments)]
    pub const fn request(
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

coded_enum! {
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

/// Writes a block of `block_type` and version 1.`version_low` whose body `body_len` bytes
/// `body` fills, into the first bytes of `buf`; the bytes written.
pub(super) fn emit_block(
    what: &'static str,
    block_type: BlockType,
    version_low: u8,
    body_len: usize,
    buf: &mut [u8],
    body: impl FnOnce(&mut Writer<'_>) -> EmitResult<()>,
) -> EmitResult<usize> {
    let header = BlockHeader {
        version_low,
        ..BlockHeader::v1(block_type, body_len)?
    };
    let total = header.total_len();
    EmitError::check_len(what, total, buf.len())?;
    let out = buf.get_mut(..total).unwrap_or_default();
    let mut w = Writer::new(what, out);
    w.put(&header.to_bytes())?;
    body(&mut w)?;
    w.finish()?;
    Ok(total)
}
