// SPDX-License-Identifier: MIT OR Apache-2.0
//! Types several PROFINET formats share: UUIDs, the PNIO block types and block header,
//! PNIOStatus.

use super::{EmitError, EmitResult, Error, Field, Result, be16};

/// A UUID as 16 bytes in big-endian field order (how PNIO blocks carry it). The DCE/RPC
/// header carries its first three fields in the PDU's DREP byte order instead; see
/// [`Uuid::from_drep`] and [`Uuid::to_drep`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Uuid(pub [u8; 16]);

impl Uuid {
    /// The nil UUID.
    pub const NIL: Uuid = Uuid([0; 16]);

    /// From its fields.
    pub const fn from_fields(data1: u32, data2: u16, data3: u16, data4: [u8; 8]) -> Uuid {
        let a = data1.to_be_bytes();
        let b = data2.to_be_bytes();
        let c = data3.to_be_bytes();
        Uuid([
            a[0], a[1], a[2], a[3], b[0], b[1], c[0], c[1], data4[0], data4[1], data4[2], data4[3],
            data4[4], data4[5], data4[6], data4[7],
        ])
    }

    /// From 16 bytes in DREP order: `little_endian` swaps data1, data2 and data3.
    pub fn from_drep(b: &[u8; 16], little_endian: bool) -> Uuid {
        let mut u = *b;
        if little_endian {
            u[0..4].reverse();
            u[4..6].reverse();
            u[6..8].reverse();
        }
        Uuid(u)
    }

    /// The 16 bytes in DREP order.
    pub fn to_drep(&self, little_endian: bool) -> [u8; 16] {
        Uuid::from_drep(&self.0, little_endian).0
    }

    /// Whether it is the nil UUID.
    pub fn is_nil(&self) -> bool {
        self.0 == [0; 16]
    }
}

impl core::fmt::Display for Uuid {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let b = &self.0;
        write!(
            f,
            "{:02x}{:02x}{:02x}{:02x}-{:02x}{:02x}-{:02x}{:02x}-{:02x}{:02x}-{:02x}{:02x}{:02x}{:02x}{:02x}{:02x}",
            b[0],
            b[1],
            b[2],
            b[3],
            b[4],
            b[5],
            b[6],
            b[7],
            b[8],
            b[9],
            b[10],
            b[11],
            b[12],
            b[13],
            b[14],
            b[15]
        )
    }
}

coded_enum! {
    /// The BlockType of a PNIO block: the ones this crate reads or writes. Bit 15 is set in
    /// the response (or acknowledgement) counterpart of a request block type.
    pub enum BlockType(u16) {
        /// 0x0001 AlarmNotificationHigh.
        AlarmNotificationHigh = 0x0001 => "AlarmNotificationHigh",
        /// 0x0002 AlarmNotificationLow.
        AlarmNotificationLow = 0x0002 => "AlarmNotificationLow",
        /// 0x0008 IODWriteReqHeader.
        IodWriteReqHeader = 0x0008 => "IODWriteReqHeader",
        /// 0x0009 IODReadReqHeader.
        IodReadReqHeader = 0x0009 => "IODReadReqHeader",
        /// 0x0010 DiagnosisData (the diagnosis records).
        DiagnosisData = 0x0010 => "DiagnosisData",
        /// 0x0012 ExpectedIdentificationData (records 0x8000, 0xC000, 0xE000).
        ExpectedIdentificationData = 0x0012 => "ExpectedIdentificationData",
        /// 0x0013 RealIdentificationData (records 0x8001, 0xC001, 0xE001, 0xF000).
        RealIdentificationData = 0x0013 => "RealIdentificationData",
        /// 0x0020 I&M0.
        Im0 = 0x0020 => "I&M0",
        /// 0x0021 I&M1.
        Im1 = 0x0021 => "I&M1",
        /// 0x0022 I&M2.
        Im2 = 0x0022 => "I&M2",
        /// 0x0023 I&M3.
        Im3 = 0x0023 => "I&M3",
        /// 0x0024 I&M4.
        Im4 = 0x0024 => "I&M4",
        /// 0x0030 I&M0FilterDataSubmodule (record 0xF840).
        Im0FilterDataSubmodule = 0x0030 => "I&M0FilterDataSubmodule",
        /// 0x0031 I&M0FilterDataModule (record 0xF840).
        Im0FilterDataModule = 0x0031 => "I&M0FilterDataModule",
        /// 0x0032 I&M0FilterDataDevice (record 0xF840).
        Im0FilterDataDevice = 0x0032 => "I&M0FilterDataDevice",
        /// 0x0018 ARData (records 0xF820, 0xF020).
        ArData = 0x0018 => "ARData",
        /// 0x0019 LogBookData (record 0xF830).
        LogBookData = 0x0019 => "LogBookData",
        /// 0x001A APIData (record 0xF821).
        ApiData = 0x001a => "APIData",
        /// 0x0101 ARBlockReq.
        ArBlockReq = 0x0101 => "ARBlockReq",
        /// 0x0102 IOCRBlockReq.
        IocrBlockReq = 0x0102 => "IOCRBlockReq",
        /// 0x0103 AlarmCRBlockReq.
        AlarmCrBlockReq = 0x0103 => "AlarmCRBlockReq",
        /// 0x0104 ExpectedSubmoduleBlockReq.
        ExpectedSubmoduleBlockReq = 0x0104 => "ExpectedSubmoduleBlockReq",
        /// 0x0107 ARRPCBlockReq.
        ArRpcBlockReq = 0x0107 => "ARRPCBlockReq",
        /// 0x0110 IODControlReq PrmEnd (IOC → IOD).
        PrmEndReq = 0x0110 => "IODControlReq PrmEnd",
        /// 0x0111 IODControlReq PrmEnd after a plug alarm.
        PlugPrmEndReq = 0x0111 => "IODControlReq Plug PrmEnd",
        /// 0x0112 IOXControlReq ApplicationReady (IOD → IOC).
        ApplicationReadyReq = 0x0112 => "IOXControlReq ApplicationReady",
        /// 0x0113 IOXControlReq ApplicationReady after a plug alarm.
        PlugApplicationReadyReq = 0x0113 => "IOXControlReq Plug ApplicationReady",
        /// 0x0114 IODReleaseReq (IOC → IOD, RPC opnum 1).
        ReleaseReq = 0x0114 => "IODReleaseReq",
        /// 0x0118 IODControlReq PrmBegin (re-parameterization, advanced startup).
        PrmBeginReq = 0x0118 => "IODControlReq PrmBegin",
        /// 0x0200 PDPortDataCheck (record 0x802B).
        PdPortDataCheck = 0x0200 => "PDPortDataCheck",
        /// 0x0202 PDPortDataAdjust (record 0x802F).
        PdPortDataAdjust = 0x0202 => "PDPortDataAdjust",
        /// 0x0209 AdjustDomainBoundary.
        AdjustDomainBoundary = 0x0209 => "AdjustDomainBoundary",
        /// 0x020A CheckPeers.
        CheckPeers = 0x020a => "CheckPeers",
        /// 0x020B CheckLineDelay.
        CheckLineDelay = 0x020b => "CheckLineDelay",
        /// 0x020C CheckMAUType.
        CheckMauType = 0x020c => "CheckMAUType",
        /// 0x020E AdjustMAUType.
        AdjustMauType = 0x020e => "AdjustMAUType",
        /// 0x020F PDPortDataReal (record 0x802A).
        PdPortDataReal = 0x020f => "PDPortDataReal",
        /// 0x0210 AdjustMulticastBoundary.
        AdjustMulticastBoundary = 0x0210 => "AdjustMulticastBoundary",
        /// 0x021B AdjustLinkState.
        AdjustLinkState = 0x021b => "AdjustLinkState",
        /// 0x021C CheckLinkState.
        CheckLinkState = 0x021c => "CheckLinkState",
        /// 0x021E CheckSyncDifference.
        CheckSyncDifference = 0x021e => "CheckSyncDifference",
        /// 0x021F CheckMAUTypeDifference.
        CheckMauTypeDifference = 0x021f => "CheckMAUTypeDifference",
        /// 0x0224 AdjustPeerToPeerBoundary.
        AdjustPeerToPeerBoundary = 0x0224 => "AdjustPeerToPeerBoundary",
        /// 0x0225 AdjustDCPBoundary.
        AdjustDcpBoundary = 0x0225 => "AdjustDCPBoundary",
        /// 0x0240 PDInterfaceDataReal (record 0x8080).
        PdInterfaceDataReal = 0x0240 => "PDInterfaceDataReal",
        /// 0x0250 PDInterfaceAdjust (record 0x8071).
        PdInterfaceAdjust = 0x0250 => "PDInterfaceAdjust",
        /// 0x0251 PDPortStatistic (record 0x8072).
        PdPortStatistic = 0x0251 => "PDPortStatistic",
        /// 0x0400 MultipleBlockHeader (records 0xF841, 0xF842).
        MultipleBlockHeader = 0x0400 => "MultipleBlockHeader",
        /// 0x0800 PROFIenergy ServiceRequest (record 0x80A0).
        PeServiceRequest = 0x0800 => "PE ServiceRequest",
        /// 0x0801 PROFIenergy ServiceResponse (record 0x80A0).
        PeServiceResponse = 0x0801 => "PE ServiceResponse",
        /// 0x0F00 MaintenanceItem.
        MaintenanceItem = 0x0f00 => "MaintenanceItem",
        /// 0x8001 AlarmAckHigh.
        AlarmAckHigh = 0x8001 => "AlarmAckHigh",
        /// 0x8002 AlarmAckLow.
        AlarmAckLow = 0x8002 => "AlarmAckLow",
        /// 0x8008 IODWriteResHeader.
        IodWriteResHeader = 0x8008 => "IODWriteResHeader",
        /// 0x8009 IODReadResHeader.
        IodReadResHeader = 0x8009 => "IODReadResHeader",
        /// 0x8101 ARBlockRes.
        ArBlockRes = 0x8101 => "ARBlockRes",
        /// 0x8102 IOCRBlockRes.
        IocrBlockRes = 0x8102 => "IOCRBlockRes",
        /// 0x8103 AlarmCRBlockRes.
        AlarmCrBlockRes = 0x8103 => "AlarmCRBlockRes",
        /// 0x8104 ModuleDiffBlock (also the body of record 0xE002 and a companion of
        /// ApplicationReady).
        ModuleDiffBlock = 0x8104 => "ModuleDiffBlock",
        /// 0x8106 ARServerBlock.
        ArServerBlock = 0x8106 => "ARServerBlock",
        /// 0x8107 ARRPCBlockRes.
        ArRpcBlockRes = 0x8107 => "ARRPCBlockRes",
        /// 0x8110 IODControlRes PrmEnd.
        PrmEndRes = 0x8110 => "IODControlRes PrmEnd",
        /// 0x8111 IODControlRes PrmEnd after a plug alarm.
        PlugPrmEndRes = 0x8111 => "IODControlRes Plug PrmEnd",
        /// 0x8112 IOXControlRes ApplicationReady.
        ApplicationReadyRes = 0x8112 => "IOXControlRes ApplicationReady",
        /// 0x8113 IOXControlRes ApplicationReady after a plug alarm.
        PlugApplicationReadyRes = 0x8113 => "IOXControlRes Plug ApplicationReady",
        /// 0x8114 IODReleaseRes.
        ReleaseRes = 0x8114 => "IODReleaseRes",
        /// 0x8118 IODControlRes PrmBegin.
        PrmBeginRes = 0x8118 => "IODControlRes PrmBegin",
    }
}

impl BlockType {
    /// Bit 15 of a BlockType: set in responses.
    pub const RESPONSE_BIT: u16 = 0x8000;

    /// Whether bit 15 (response) is set.
    pub const fn is_response(self) -> bool {
        self.raw() & BlockType::RESPONSE_BIT != 0
    }

    /// The block type with bit 15 set: the response to a request block type.
    pub const fn response(self) -> BlockType {
        BlockType::from_raw(self.raw() | BlockType::RESPONSE_BIT)
    }

    /// The block type with bit 15 cleared: the request a response block type answers.
    pub const fn request(self) -> BlockType {
        BlockType::from_raw(self.raw() & !BlockType::RESPONSE_BIT)
    }
}

impl core::fmt::Display for BlockType {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self.name() {
            Some(name) => write!(f, "{name} ({:#06x})", self.raw()),
            None => write!(f, "BlockType {:#06x}", self.raw()),
        }
    }
}

mod field {
    use super::Field;
    pub const TYPE: Field = 0..2;
    pub const LENGTH: Field = 2..4;
    pub const VERSION_HIGH: usize = 4;
    pub const VERSION_LOW: usize = 5;
    pub const BODY: usize = 6;
}

/// Bytes of a block header.
pub const BLOCK_HEADER_LEN: usize = field::BODY;

/// The header every PNIO block starts with: BlockType, BlockLength (counted from the version
/// bytes to the end of the block, i.e. total − 4), BlockVersionHigh/Low. Always big-endian.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BlockHeader {
    /// BlockType.
    pub block_type: BlockType,
    /// BlockLength (total − 4).
    pub length: u16,
    /// BlockVersionHigh.
    pub version_high: u8,
    /// BlockVersionLow.
    pub version_low: u8,
}

impl BlockHeader {
    /// A version 1.0 header for a block whose body (after the 6 header bytes) has `body_len`
    /// bytes; a body too long for the 16-bit BlockLength gives [`EmitError::TooLong`].
    pub fn v1(block_type: BlockType, body_len: usize) -> EmitResult<BlockHeader> {
        let value = body_len.saturating_add(2);
        let length =
            u16::try_from(value).map_err(|_| EmitError::too_long_u16("BlockLength", value))?;
        Ok(BlockHeader {
            block_type,
            length,
            version_high: 1,
            version_low: 0,
        })
    }

    /// Parses the header at the start of `b`; checks the block fits in `b`.
    pub fn parse(b: &[u8]) -> Result<BlockHeader> {
        if b.len() < BLOCK_HEADER_LEN {
            return Err(Error);
        }
        let h = BlockHeader {
            block_type: BlockType::from_raw(be16(&b[field::TYPE])),
            length: be16(&b[field::LENGTH]),
            version_high: b[field::VERSION_HIGH],
            version_low: b[field::VERSION_LOW],
        };
        if h.length < 2 || h.total_len() > b.len() {
            return Err(Error);
        }
        Ok(h)
    }

    /// Bytes of the whole block, header included.
    pub const fn total_len(&self) -> usize {
        self.length as usize + 4
    }

    /// Bytes of the body after the header.
    pub const fn body_len(&self) -> usize {
        self.total_len() - BLOCK_HEADER_LEN
    }

    /// The 6 header bytes.
    pub const fn to_bytes(&self) -> [u8; BLOCK_HEADER_LEN] {
        let [t0, t1] = self.block_type.raw().to_be_bytes();
        let [l0, l1] = self.length.to_be_bytes();
        [t0, t1, l0, l1, self.version_high, self.version_low]
    }

    /// Writes the 6 header bytes at the start of `b`; a shorter `b` gives
    /// [`EmitError::BufferTooShort`].
    pub fn emit(&self, b: &mut [u8]) -> EmitResult<()> {
        let len = b.len();
        let out = b
            .get_mut(..BLOCK_HEADER_LEN)
            .ok_or(EmitError::BufferTooShort {
                what: "block header",
                needed: BLOCK_HEADER_LEN,
                len,
            })?;
        out.copy_from_slice(&self.to_bytes());
        Ok(())
    }

    /// The body of the block at the start of `b` (which `parse` checked holds it).
    pub fn body<'a>(&self, b: &'a [u8]) -> &'a [u8] {
        &b[BLOCK_HEADER_LEN..self.total_len()]
    }
}

/// Splits a sequence of PNIO blocks: yields each block's header and whole bytes, or one
/// `Err` and stops when a block does not fit.
pub fn blocks(mut b: &[u8]) -> impl Iterator<Item = Result<(BlockHeader, &[u8])>> {
    core::iter::from_fn(move || {
        if b.is_empty() {
            return None;
        }
        match BlockHeader::parse(b) {
            Ok(h) => {
                let (block, rest) = b.split_at(h.total_len());
                b = rest;
                Some(Ok((h, block)))
            }
            Err(e) => {
                b = &[];
                Some(Err(e))
            }
        }
    })
}

/// PNIOStatus: ErrorCode, ErrorDecode, ErrorCode1, ErrorCode2 (0 0 0 0 = OK). In blocks it is
/// big-endian; at the RPC level (NDR response header) the 32-bit value is in DREP order with
/// ErrorCode as the most significant byte.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct PnioStatus {
    /// ErrorCode (0x81 PNIO, 0xCF RTA error, 0xDB/0xDD/0xDE/0xDF CM/record services...).
    pub error_code: u8,
    /// ErrorDecode (0x80 PNIORW, 0x81 PNIO, 0x82 manufacturer specific).
    pub error_decode: u8,
    /// ErrorCode1.
    pub error_code1: u8,
    /// ErrorCode2.
    pub error_code2: u8,
}

impl PnioStatus {
    /// Success.
    pub const OK: PnioStatus = PnioStatus {
        error_code: 0,
        error_decode: 0,
        error_code1: 0,
        error_code2: 0,
    };

    /// From the 4 big-endian bytes.
    pub const fn from_bytes(b: [u8; 4]) -> PnioStatus {
        PnioStatus {
            error_code: b[0],
            error_decode: b[1],
            error_code1: b[2],
            error_code2: b[3],
        }
    }

    /// The 4 big-endian bytes.
    pub const fn to_bytes(&self) -> [u8; 4] {
        [
            self.error_code,
            self.error_decode,
            self.error_code1,
            self.error_code2,
        ]
    }

    /// As the 32-bit value (ErrorCode most significant).
    pub const fn to_u32(&self) -> u32 {
        u32::from_be_bytes(self.to_bytes())
    }

    /// From the 32-bit value.
    pub const fn from_u32(v: u32) -> PnioStatus {
        PnioStatus::from_bytes(v.to_be_bytes())
    }

    /// Whether it says OK.
    pub const fn is_ok(&self) -> bool {
        self.to_u32() == 0
    }
}

impl core::fmt::Display for PnioStatus {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(
            f,
            "PNIOStatus {:02x} {:02x} {:02x} {:02x}",
            self.error_code, self.error_decode, self.error_code1, self.error_code2
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uuid_drep_swaps_the_first_three_fields() {
        // The PNIO device interface DEA00001-6C97-11D1-8271-00A02442DF7D as a LE RPC header
        // carries it.
        let le = [
            0x01, 0x00, 0xa0, 0xde, 0x97, 0x6c, 0xd1, 0x11, 0x82, 0x71, 0x00, 0xa0, 0x24, 0x42,
            0xdf, 0x7d,
        ];
        let u = Uuid::from_drep(&le, true);
        assert_eq!(u.to_string(), "dea00001-6c97-11d1-8271-00a02442df7d");
        assert_eq!(u.to_drep(true), le);
        assert_eq!(u.to_drep(false), u.0);
    }

    #[test]
    fn block_header_round_trip_and_bounds() {
        // The S7 PrmEnd block header: 0110 001c 0100.
        let b = [0x01, 0x10, 0x00, 0x1c, 0x01, 0x00];
        assert!(BlockHeader::parse(&b).is_err(), "the body is missing");
        let mut full = vec![0u8; 32];
        full[..6].copy_from_slice(&b);
        let h = BlockHeader::parse(&full).unwrap();
        assert_eq!(
            (h.block_type, h.total_len(), h.body_len()),
            (BlockType::PrmEndReq, 32, 26)
        );
        assert_eq!(Ok(h), BlockHeader::v1(BlockType::PrmEndReq, 26));
        let mut out = [0u8; 6];
        h.emit(&mut out).unwrap();
        assert_eq!(out, b);
        assert!(h.emit(&mut out[..5]).is_err());
        assert!(BlockHeader::v1(BlockType::PrmEndReq, 65533).is_ok());
        assert_eq!(
            BlockHeader::v1(BlockType::PrmEndReq, 65534),
            Err(EmitError::TooLong {
                field: "BlockLength",
                value: 65536,
                max: 65535
            })
        );
        assert_eq!(
            BlockHeader::v1(BlockType::PrmEndReq, 65534)
                .unwrap_err()
                .to_string(),
            "BlockLength would be 65536, over the 65535 its wire field holds"
        );
        assert_eq!(blocks(&full).count(), 1);
    }

    proptest::proptest! {
        #[test]
        fn block_splitting_never_panics(b in proptest::collection::vec(proptest::prelude::any::<u8>(), 0..512)) {
            for (h, block) in blocks(&b).flatten() {
                proptest::prop_assert_eq!(block.len(), h.total_len());
            }
        }
    }
}
