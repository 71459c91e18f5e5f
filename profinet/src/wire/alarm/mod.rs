// SPDX-License-Identifier: MIT OR Apache-2.0
//! Alarms and diagnosis: the PNIO blocks an alarm carries (AlarmNotification with its
//! diagnosis and maintenance items, AlarmAck), the alarm's priority and the FrameIDs of its
//! two channels. The RTA PDUs that carry them over Ethernet are in [`super::rta_pdu`].
//!
//! Everything is big-endian. Alarms are not on the cyclic path, so the Reprs own their data.

use super::common::BLOCK_HEADER_LEN;
use super::cursor::{Reader, Writer};
use super::diagnosis::bit;
use super::{BlockHeader, BlockType, EmitError, EmitResult, Error, PnioStatus, Result, be16};

// The diagnosis items an alarm carries are shared with the diagnosis records; they are
// reachable here too, where they were first defined.
pub use super::diagnosis::{
    AlarmItem, CHANNEL_NUMBER_SUBMODULE, ChannelDiagnosis, ChannelDirection, ChannelProperties,
    ChannelSpecifier, Diagnosis, DiagnosisFormat, USI_CHANNEL_DIAGNOSIS, USI_EXT_CHANNEL_DIAGNOSIS,
    USI_MAINTENANCE, USI_MULTIPLE, USI_QUALIFIED_CHANNEL_DIAGNOSIS,
};

#[cfg(test)]
mod tests;

/// FrameID of high-priority alarms.
pub const FRAME_ID_ALARM_HIGH: u16 = 0xfc01;
/// FrameID of low-priority alarms.
pub const FRAME_ID_ALARM_LOW: u16 = 0xfe01;

/// The priority of an alarm channel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Priority {
    /// High priority: FrameID 0xFC01, blocks 0x0001/0x8001, PCP 6 (p-net: process alarms).
    High,
    /// Low priority: FrameID 0xFE01, blocks 0x0002/0x8002, PCP 5 (p-net: diagnosis alarms).
    Low,
}

impl Priority {
    /// The FrameID of this priority's RTA frames.
    pub const fn frame_id(self) -> u16 {
        match self {
            Priority::High => FRAME_ID_ALARM_HIGH,
            Priority::Low => FRAME_ID_ALARM_LOW,
        }
    }

    /// The priority of an RTA FrameID; `None` for any other FrameID.
    pub const fn from_frame_id(frame_id: u16) -> Option<Priority> {
        match frame_id {
            FRAME_ID_ALARM_HIGH => Some(Priority::High),
            FRAME_ID_ALARM_LOW => Some(Priority::Low),
            _ => None,
        }
    }

    /// BlockType of an AlarmNotification of this priority.
    pub const fn notification_block_type(self) -> BlockType {
        match self {
            Priority::High => BlockType::AlarmNotificationHigh,
            Priority::Low => BlockType::AlarmNotificationLow,
        }
    }

    /// BlockType of an AlarmAck of this priority.
    pub const fn ack_block_type(self) -> BlockType {
        match self {
            Priority::High => BlockType::AlarmAckHigh,
            Priority::Low => BlockType::AlarmAckLow,
        }
    }

    /// The 802.1Q priority code point the frames are sent with (AlarmCRTagHeaderHigh/Low).
    pub const fn pcp(self) -> u8 {
        match self {
            Priority::High => 6,
            Priority::Low => 5,
        }
    }
}

impl core::fmt::Display for Priority {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Priority::High => "high",
            Priority::Low => "low",
        })
    }
}

coded_enum! {
    /// AlarmType.
    pub enum AlarmType(u16) {
        /// 0x0001 diagnosis (appears).
        Diagnosis = 0x0001 => "diagnosis",
        /// 0x0002 process alarm.
        Process = 0x0002 => "process",
        /// 0x0003 pull (submodule).
        Pull = 0x0003 => "pull",
        /// 0x0004 plug.
        Plug = 0x0004 => "plug",
        /// 0x0005 status.
        Status = 0x0005 => "status",
        /// 0x0006 update.
        Update = 0x0006 => "update",
        /// 0x0007 media redundancy.
        MediaRedundancy = 0x0007 => "media redundancy",
        /// 0x0008 controlled by supervisor.
        ControlledBySupervisor = 0x0008 => "controlled by supervisor",
        /// 0x0009 released.
        Released = 0x0009 => "released",
        /// 0x000A plug wrong submodule.
        PlugWrongSubmodule = 0x000a => "plug wrong submodule",
        /// 0x000B return of submodule.
        ReturnOfSubmodule = 0x000b => "return of submodule",
        /// 0x000C diagnosis disappears.
        DiagnosisDisappears = 0x000c => "diagnosis disappears",
        /// 0x000D multicast communication mismatch.
        MulticastCommunicationMismatch = 0x000d => "multicast communication mismatch",
        /// 0x000E port data change notification.
        PortDataChange = 0x000e => "port data change",
        /// 0x000F sync data changed.
        SyncDataChanged = 0x000f => "sync data changed",
        /// 0x0010 isochronous mode problem.
        IsochronousModeProblem = 0x0010 => "isochronous mode problem",
        /// 0x0011 network component problem.
        NetworkComponentProblem = 0x0011 => "network component problem",
        /// 0x0012 time data changed.
        TimeDataChanged = 0x0012 => "time data changed",
        /// 0x0013 dynamic frame packing problem.
        DynamicFramePackingProblem = 0x0013 => "dynamic frame packing problem",
        /// 0x0014 MRPD problem.
        MrpdProblem = 0x0014 => "MRPD problem",
        /// 0x0016 multiple interface mismatch.
        MultipleInterfaceMismatch = 0x0016 => "multiple interface mismatch",
        /// 0x001E upload and retrieval notification.
        UploadAndRetrieval = 0x001e => "upload and retrieval notification",
        /// 0x001F pull module.
        PullModule = 0x001f => "pull module",
    }
}

impl core::fmt::Display for AlarmType {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match (self.name(), *self) {
            (Some(name), _) => f.write_str(name),
            (None, AlarmType::Unknown(v @ 0x0020..=0x007f)) => {
                write!(f, "manufacturer specific ({v:#06x})")
            }
            (None, AlarmType::Unknown(v @ 0x0080..=0x00ff)) => {
                write!(f, "profile specific ({v:#06x})")
            }
            (None, other) => write!(f, "reserved ({:#06x})", u16::from(other)),
        }
    }
}

/// AlarmSpecifier: the alarm's sequence number and four diagnosis-state flags.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct AlarmSpecifier {
    /// Bits 0–10: the alarm sequence number (0..=2047), counted per submodule by the sender.
    pub sequence_number: u16,
    /// Bit 11: channel diagnosis is present.
    pub channel_diagnosis: bool,
    /// Bit 12: manufacturer-specific diagnosis is present.
    pub manufacturer_diagnosis: bool,
    /// Bit 13: the submodule has at least one diagnosis.
    pub submodule_diagnosis: bool,
    /// Bit 15: some submodule of the AR has a diagnosis.
    pub ar_diagnosis: bool,
}

impl AlarmSpecifier {
    /// Mask of the sequence number.
    pub const SEQUENCE_MASK: u16 = 0x07ff;

    /// Decodes the 16-bit value (the reserved bit 14 is dropped).
    pub const fn from_u16(v: u16) -> AlarmSpecifier {
        AlarmSpecifier {
            sequence_number: v & Self::SEQUENCE_MASK,
            channel_diagnosis: v & (1 << 11) != 0,
            manufacturer_diagnosis: v & (1 << 12) != 0,
            submodule_diagnosis: v & (1 << 13) != 0,
            ar_diagnosis: v & (1 << 15) != 0,
        }
    }

    /// Encodes it (the sequence number is masked to 11 bits).
    pub const fn to_u16(&self) -> u16 {
        (self.sequence_number & Self::SEQUENCE_MASK)
            | bit(self.channel_diagnosis, 11)
            | bit(self.manufacturer_diagnosis, 12)
            | bit(self.submodule_diagnosis, 13)
            | bit(self.ar_diagnosis, 15)
    }
}

/// A MaintenanceItem: on the wire USI 0x8100, then a block 0x0F00 v1.0 with 2 reserved bytes
/// and MaintenanceStatus (14 bytes in all).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct MaintenanceItem {
    /// MaintenanceStatus: bit 0 maintenance required, bit 1 maintenance demanded.
    pub status: u32,
}

impl MaintenanceItem {
    /// MaintenanceStatus bit: maintenance required.
    pub const REQUIRED: u32 = 1;
    /// MaintenanceStatus bit: maintenance demanded.
    pub const DEMANDED: u32 = 2;
    /// Bytes on the wire, USI included.
    pub const LEN: usize = 2 + BLOCK_HEADER_LEN + 2 + 4;

    /// Whether maintenance is required.
    pub const fn maintenance_required(&self) -> bool {
        self.status & Self::REQUIRED != 0
    }

    /// Whether maintenance is demanded.
    pub const fn maintenance_demanded(&self) -> bool {
        self.status & Self::DEMANDED != 0
    }

    /// The item at the start of `b`, if `b` starts with exactly the encoding `emit` writes
    /// (USI 0x8100, block 0x0F00 length 8 version 1.0, reserved 0); the rest of `b` after it.
    fn parse(b: &[u8]) -> Option<(MaintenanceItem, &[u8])> {
        let mut r = Reader::new(b);
        let head = r.take(MaintenanceItem::LEN - 4).ok()?;
        let prefix = [0x81, 0x00, 0x0f, 0x00, 0x00, 0x08, 0x01, 0x00, 0x00, 0x00];
        if head != prefix {
            return None;
        }
        let status = r.u32().ok()?;
        Some((MaintenanceItem { status }, r.rest()))
    }

    fn emit(&self, w: &mut Writer<'_>) -> EmitResult<()> {
        w.u16(USI_MAINTENANCE)?;
        w.block_header(BlockType::MaintenanceItem, 6)?;
        w.u16(0)?;
        w.u32(self.status)
    }
}

/// Bytes of an AlarmNotification body before its items (after the block header).
const NOTIFICATION_FIXED_LEN: usize = 20;

/// An AlarmNotification block (0x0001 high / 0x0002 low, v1.0).
///
/// Parsing accepts any BlockVersion; emitting writes 1.0.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct AlarmNotification {
    /// The priority (from the BlockType).
    pub priority: Priority,
    /// AlarmType.
    pub alarm_type: AlarmType,
    /// API.
    pub api: u32,
    /// SlotNumber.
    pub slot: u16,
    /// SubslotNumber.
    pub subslot: u16,
    /// ModuleIdentNumber.
    pub module_ident: u32,
    /// SubmoduleIdentNumber.
    pub submodule_ident: u32,
    /// AlarmSpecifier.
    pub specifier: AlarmSpecifier,
    /// A MaintenanceItem (USI 0x8100 + block 0x0F00) right after the specifier, if any.
    pub maintenance: Option<MaintenanceItem>,
    /// The USI and its data after that, if any.
    pub item: Option<AlarmItem>,
}

impl AlarmNotification {
    /// Parses the block at the start of `b`. A block of another type, a body shorter than the
    /// fixed part, or a single stray byte after it give [`Error`]; item data never does.
    pub fn parse(b: &[u8]) -> Result<AlarmNotification> {
        let h = BlockHeader::parse(b)?;
        let priority = match h.block_type {
            BlockType::AlarmNotificationHigh => Priority::High,
            BlockType::AlarmNotificationLow => Priority::Low,
            _ => return Err(Error),
        };
        let mut r = Reader::new(h.body(b));
        let alarm_type = AlarmType::from(r.u16()?);
        let api = r.u32()?;
        let slot = r.u16()?;
        let subslot = r.u16()?;
        let module_ident = r.u32()?;
        let submodule_ident = r.u32()?;
        let specifier = AlarmSpecifier::from_u16(r.u16()?);
        let mut rest = r.rest();
        let mut maintenance = None;
        if let Some((m, after)) = MaintenanceItem::parse(rest) {
            maintenance = Some(m);
            rest = after;
        }
        let item = match rest.split_at_checked(2) {
            Some((usi, data)) => Some(AlarmItem::parse(be16(usi), data)),
            None if rest.is_empty() => None,
            None => return Err(Error),
        };
        Ok(AlarmNotification {
            priority,
            alarm_type,
            api,
            slot,
            subslot,
            module_ident,
            submodule_ident,
            specifier,
            maintenance,
            item,
        })
    }

    /// Bytes of the body after the block header.
    fn body_len(&self) -> usize {
        let m = if self.maintenance.is_some() {
            MaintenanceItem::LEN
        } else {
            0
        };
        let item = self.item.as_ref().map_or(0, AlarmItem::buffer_len);
        NOTIFICATION_FIXED_LEN
            .saturating_add(m)
            .saturating_add(item)
    }

    /// Bytes of the whole block.
    pub fn buffer_len(&self) -> usize {
        BLOCK_HEADER_LEN.saturating_add(self.body_len())
    }

    /// Writes the block into the first [`buffer_len`](Self::buffer_len) bytes of `buf`. A
    /// shorter buffer or a block longer than BlockLength allows give [`EmitError`].
    pub fn emit(&self, buf: &mut [u8]) -> EmitResult<()> {
        EmitError::check_len("AlarmNotification", self.buffer_len(), buf.len())?;
        let mut w = Writer::new("AlarmNotification", buf);
        self.write(&mut w)
    }

    fn write(&self, w: &mut Writer<'_>) -> EmitResult<()> {
        w.block_header(self.priority.notification_block_type(), self.body_len())?;
        w.u16(self.alarm_type.into())?;
        w.u32(self.api)?;
        w.u16(self.slot)?;
        w.u16(self.subslot)?;
        w.u32(self.module_ident)?;
        w.u32(self.submodule_ident)?;
        w.u16(self.specifier.to_u16())?;
        if let Some(m) = &self.maintenance {
            m.emit(w)?;
        }
        if let Some(item) = &self.item {
            item.emit(w)?;
        }
        Ok(())
    }

    /// The channel diagnosis entries of the item, if it carries channel diagnosis.
    pub fn diagnosis(&self) -> Option<&Diagnosis> {
        self.item.as_ref().and_then(AlarmItem::diagnosis)
    }
}

/// Bytes of an AlarmAck body (after the block header).
const ACK_BODY_LEN: usize = 16;

/// An AlarmAck block (0x8001 high / 0x8002 low, v1.0): the application's answer to an
/// AlarmNotification, sent as a DATA-RTA of its own.
///
/// Parsing accepts any BlockVersion; emitting writes 1.0.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct AlarmAck {
    /// The priority (from the BlockType).
    pub priority: Priority,
    /// AlarmType of the acknowledged notification.
    pub alarm_type: AlarmType,
    /// API.
    pub api: u32,
    /// SlotNumber.
    pub slot: u16,
    /// SubslotNumber.
    pub subslot: u16,
    /// AlarmSpecifier of the acknowledged notification.
    pub specifier: AlarmSpecifier,
    /// PNIOStatus (OK, or why the alarm was not accepted).
    pub status: PnioStatus,
}

impl AlarmAck {
    /// Bytes of the whole block.
    pub const LEN: usize = BLOCK_HEADER_LEN + ACK_BODY_LEN;

    /// The ack of a notification, with `status`.
    pub const fn for_notification(n: &AlarmNotification, status: PnioStatus) -> AlarmAck {
        AlarmAck {
            priority: n.priority,
            alarm_type: n.alarm_type,
            api: n.api,
            slot: n.slot,
            subslot: n.subslot,
            specifier: n.specifier,
            status,
        }
    }

    /// Parses the block at the start of `b`; another type or a body of the wrong length gives
    /// [`Error`].
    pub fn parse(b: &[u8]) -> Result<AlarmAck> {
        let h = BlockHeader::parse(b)?;
        let priority = match h.block_type {
            BlockType::AlarmAckHigh => Priority::High,
            BlockType::AlarmAckLow => Priority::Low,
            _ => return Err(Error),
        };
        if h.body_len() != ACK_BODY_LEN {
            return Err(Error);
        }
        let mut r = Reader::new(h.body(b));
        Ok(AlarmAck {
            priority,
            alarm_type: AlarmType::from(r.u16()?),
            api: r.u32()?,
            slot: r.u16()?,
            subslot: r.u16()?,
            specifier: AlarmSpecifier::from_u16(r.u16()?),
            status: PnioStatus::from_u32(r.u32()?),
        })
    }

    /// Bytes of the block ([`AlarmAck::LEN`]).
    pub const fn buffer_len(&self) -> usize {
        AlarmAck::LEN
    }

    /// Writes the block into the first [`AlarmAck::LEN`] bytes of `buf`; a shorter buffer gives
    /// [`EmitError::BufferTooShort`].
    pub fn emit(&self, buf: &mut [u8]) -> EmitResult<()> {
        EmitError::check_len("AlarmAck", AlarmAck::LEN, buf.len())?;
        let mut w = Writer::new("AlarmAck", buf);
        self.write(&mut w)
    }

    fn write(&self, w: &mut Writer<'_>) -> EmitResult<()> {
        w.block_header(self.priority.ack_block_type(), ACK_BODY_LEN)?;
        w.u16(self.alarm_type.into())?;
        w.u32(self.api)?;
        w.u16(self.slot)?;
        w.u16(self.subslot)?;
        w.u16(self.specifier.to_u16())?;
        w.u32(self.status.to_u32())
    }
}

/// One block of a DATA-RTA.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum AlarmBlock {
    /// An AlarmNotification.
    Notification(AlarmNotification),
    /// An AlarmAck.
    Ack(AlarmAck),
    /// Any other block, kept as it is.
    Other {
        /// BlockType.
        block_type: BlockType,
        /// BlockVersionHigh and BlockVersionLow.
        version: (u8, u8),
        /// The body after the block header.
        body: Vec<u8>,
    },
}

impl AlarmBlock {
    /// Parses the block at the start of `b`.
    pub fn parse(b: &[u8]) -> Result<AlarmBlock> {
        let h = BlockHeader::parse(b)?;
        match h.block_type {
            BlockType::AlarmNotificationHigh | BlockType::AlarmNotificationLow => {
                AlarmNotification::parse(b).map(AlarmBlock::Notification)
            }
            BlockType::AlarmAckHigh | BlockType::AlarmAckLow => {
                AlarmAck::parse(b).map(AlarmBlock::Ack)
            }
            block_type => Ok(AlarmBlock::Other {
                block_type,
                version: (h.version_high, h.version_low),
                body: h.body(b).to_vec(),
            }),
        }
    }

    /// Bytes of the whole block.
    pub fn buffer_len(&self) -> usize {
        match self {
            AlarmBlock::Notification(n) => n.buffer_len(),
            AlarmBlock::Ack(a) => a.buffer_len(),
            AlarmBlock::Other { body, .. } => BLOCK_HEADER_LEN.saturating_add(body.len()),
        }
    }

    pub(super) fn write(&self, w: &mut Writer<'_>) -> EmitResult<()> {
        match self {
            AlarmBlock::Notification(n) => n.write(w),
            AlarmBlock::Ack(a) => a.write(w),
            AlarmBlock::Other {
                block_type,
                version,
                body,
            } => {
                let header = BlockHeader {
                    version_high: version.0,
                    version_low: version.1,
                    ..BlockHeader::v1(*block_type, body.len())?
                };
                w.put(&header.to_bytes())?;
                w.put(body)
            }
        }
    }
}
