// SPDX-License-Identifier: MIT OR Apache-2.0
//! Alarms and diagnosis: the PNIO blocks an alarm carries (AlarmNotification with its
//! diagnosis and maintenance items, AlarmAck), the alarm's priority and the FrameIDs of its
//! two channels. The RTA PDUs that carry them over Ethernet are in [`super::rta_pdu`].
//!
//! Everything is big-endian. Alarms are not on the cyclic path, so the Reprs own their data.

use super::common::BLOCK_HEADER_LEN;
use super::cursor::{Reader, Writer};
use super::{BlockHeader, BlockType, EmitError, EmitResult, Error, PnioStatus, Result, be16};

/// FrameID of high-priority alarms.
pub const FRAME_ID_ALARM_HIGH: u16 = 0xfc01;
/// FrameID of low-priority alarms.
pub const FRAME_ID_ALARM_LOW: u16 = 0xfe01;

/// USI of channel diagnosis (6-byte entries).
pub const USI_CHANNEL_DIAGNOSIS: u16 = 0x8000;
/// USI "multiple": the data is a sequence of blocks (not decoded here).
pub const USI_MULTIPLE: u16 = 0x8001;
/// USI of extended channel diagnosis (12-byte entries).
pub const USI_EXT_CHANNEL_DIAGNOSIS: u16 = 0x8002;
/// USI of qualified channel diagnosis (16-byte entries).
pub const USI_QUALIFIED_CHANNEL_DIAGNOSIS: u16 = 0x8003;
/// USI of a maintenance item.
pub const USI_MAINTENANCE: u16 = 0x8100;
/// ChannelNumber meaning "the whole submodule".
pub const CHANNEL_NUMBER_SUBMODULE: u16 = 0x8000;

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

enum_with_unknown! {
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

/// `1 << n` if `b`, else 0.
const fn bit(b: bool, n: u16) -> u16 {
    if b { 1 << n } else { 0 }
}

/// ChannelSpecifier (bits 11–12 of ChannelProperties). Every 2-bit value has a meaning, so
/// unlike the wider fields there is no unknown value to keep.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ChannelSpecifier {
    /// 0: all (subordinate) diagnoses disappear.
    AllDisappear,
    /// 1: the diagnosis appears (is pending).
    Appears,
    /// 2: the diagnosis disappears and no other remains.
    Disappears,
    /// 3: the diagnosis disappears but others remain.
    DisappearsOthersRemain,
}

impl ChannelSpecifier {
    /// From the 2-bit value (higher bits are ignored).
    pub const fn from_bits(v: u16) -> ChannelSpecifier {
        match v & 3 {
            0 => ChannelSpecifier::AllDisappear,
            1 => ChannelSpecifier::Appears,
            2 => ChannelSpecifier::Disappears,
            _ => ChannelSpecifier::DisappearsOthersRemain,
        }
    }

    /// The 2-bit value.
    pub const fn bits(self) -> u16 {
        match self {
            ChannelSpecifier::AllDisappear => 0,
            ChannelSpecifier::Appears => 1,
            ChannelSpecifier::Disappears => 2,
            ChannelSpecifier::DisappearsOthersRemain => 3,
        }
    }
}

enum_with_unknown! {
    /// ChannelDirection (bits 13–15 of ChannelProperties). Values 4..=7 are reserved.
    pub enum ChannelDirection(u8) {
        /// 0: manufacturer specific.
        Manufacturer = 0 => "manufacturer specific",
        /// 1: input.
        Input = 1 => "input",
        /// 2: output.
        Output = 2 => "output",
        /// 3: input/output.
        InputOutput = 3 => "input/output",
    }
}

impl ChannelDirection {
    /// From the 3-bit value (higher bits are ignored).
    pub const fn from_bits(v: u16) -> ChannelDirection {
        // Masked to 3 bits, so the cast keeps every bit.
        ChannelDirection::from_raw((v & 7) as u8)
    }

    /// The 3-bit value (higher bits of an `Unknown` are dropped).
    pub const fn bits(self) -> u16 {
        (self.raw() & 7) as u16
    }
}

/// ChannelProperties, kept as the raw 16-bit value with typed accessors.
///
/// Bits 0–7 Type (channel data width: 0 for the whole submodule, 1 = 1 bit, 2 = 2 bit,
/// 3 = 4 bit, 4 = 8 bit, 5 = 16 bit, 6 = 32 bit, 7 = 64 bit), 8 Accumulative, 9
/// MaintenanceRequired, 10 MaintenanceDemanded, 11–12 [`ChannelSpecifier`], 13–15
/// [`ChannelDirection`]. E.g. 0x2801 = 1 bit, appears, input.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ChannelProperties(pub u16);

impl ChannelProperties {
    /// From its fields.
    pub const fn new(
        data_type: u8,
        accumulative: bool,
        maintenance_required: bool,
        maintenance_demanded: bool,
        specifier: ChannelSpecifier,
        direction: ChannelDirection,
    ) -> ChannelProperties {
        ChannelProperties(
            data_type as u16
                | bit(accumulative, 8)
                | bit(maintenance_required, 9)
                | bit(maintenance_demanded, 10)
                | (specifier.bits() << 11)
                | (direction.bits() << 13),
        )
    }

    /// Type: the channel data width code (bits 0–7).
    pub const fn data_type(self) -> u8 {
        // Masked to 8 bits, so the cast keeps every bit.
        (self.0 & 0xff) as u8
    }

    /// Accumulative: a group message for several channels.
    pub const fn accumulative(self) -> bool {
        self.0 & (1 << 8) != 0
    }

    /// MaintenanceRequired.
    pub const fn maintenance_required(self) -> bool {
        self.0 & (1 << 9) != 0
    }

    /// MaintenanceDemanded.
    pub const fn maintenance_demanded(self) -> bool {
        self.0 & (1 << 10) != 0
    }

    /// The specifier (appears / disappears…).
    pub const fn specifier(self) -> ChannelSpecifier {
        ChannelSpecifier::from_bits(self.0 >> 11)
    }

    /// The direction.
    pub const fn direction(self) -> ChannelDirection {
        ChannelDirection::from_bits(self.0 >> 13)
    }
}

/// The channel diagnosis formats (USIs 0x8000, 0x8002, 0x8003).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DiagnosisFormat {
    /// USI 0x8000: ChannelNumber, ChannelProperties, ChannelErrorType (6 bytes).
    Channel,
    /// USI 0x8002: + ExtChannelErrorType, ExtChannelAddValue (12 bytes).
    Extended,
    /// USI 0x8003: + QualifiedChannelQualifier (16 bytes).
    Qualified,
}

impl DiagnosisFormat {
    /// The format of a USI; `None` for USIs that are not channel diagnosis.
    pub const fn from_usi(usi: u16) -> Option<DiagnosisFormat> {
        match usi {
            USI_CHANNEL_DIAGNOSIS => Some(DiagnosisFormat::Channel),
            USI_EXT_CHANNEL_DIAGNOSIS => Some(DiagnosisFormat::Extended),
            USI_QUALIFIED_CHANNEL_DIAGNOSIS => Some(DiagnosisFormat::Qualified),
            _ => None,
        }
    }

    /// The USI.
    pub const fn usi(self) -> u16 {
        match self {
            DiagnosisFormat::Channel => USI_CHANNEL_DIAGNOSIS,
            DiagnosisFormat::Extended => USI_EXT_CHANNEL_DIAGNOSIS,
            DiagnosisFormat::Qualified => USI_QUALIFIED_CHANNEL_DIAGNOSIS,
        }
    }

    /// Bytes of one entry.
    pub const fn entry_len(self) -> usize {
        match self {
            DiagnosisFormat::Channel => 6,
            DiagnosisFormat::Extended => 12,
            DiagnosisFormat::Qualified => 16,
        }
    }
}

/// One channel diagnosis entry. The fields after `channel_error_type` exist only in the
/// extended (`ext_*`) and qualified (`ext_*`, `qualifier`) formats: parsing leaves them 0
/// where the format has none, emitting ignores them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ChannelDiagnosis {
    /// ChannelNumber (0..=0x7FFF, or [`CHANNEL_NUMBER_SUBMODULE`]).
    pub channel_number: u16,
    /// ChannelProperties.
    pub channel_properties: ChannelProperties,
    /// ChannelErrorType (1 short circuit, 2 undervoltage, 3 overvoltage, 4 overload,
    /// 5 overtemperature, 6 wire break, 7/8 upper/lower limit, 9 error, …).
    pub channel_error_type: u16,
    /// ExtChannelErrorType (extended and qualified formats).
    pub ext_channel_error_type: u16,
    /// ExtChannelAddValue (extended and qualified formats).
    pub ext_channel_add_value: u32,
    /// QualifiedChannelQualifier (qualified format).
    pub qualifier: u32,
}

impl ChannelDiagnosis {
    /// A plain (USI 0x8000) entry.
    pub const fn new(
        channel_number: u16,
        channel_properties: ChannelProperties,
        channel_error_type: u16,
    ) -> ChannelDiagnosis {
        ChannelDiagnosis {
            channel_number,
            channel_properties,
            channel_error_type,
            ext_channel_error_type: 0,
            ext_channel_add_value: 0,
            qualifier: 0,
        }
    }

    fn parse(format: DiagnosisFormat, r: &mut Reader<'_>) -> Result<ChannelDiagnosis> {
        let mut d = ChannelDiagnosis::new(r.u16()?, ChannelProperties(r.u16()?), r.u16()?);
        if format != DiagnosisFormat::Channel {
            d.ext_channel_error_type = r.u16()?;
            d.ext_channel_add_value = r.u32()?;
        }
        if format == DiagnosisFormat::Qualified {
            d.qualifier = r.u32()?;
        }
        Ok(d)
    }

    fn emit(&self, format: DiagnosisFormat, w: &mut Writer<'_>) -> EmitResult<()> {
        w.u16(self.channel_number)?;
        w.u16(self.channel_properties.0)?;
        w.u16(self.channel_error_type)?;
        if format != DiagnosisFormat::Channel {
            w.u16(self.ext_channel_error_type)?;
            w.u32(self.ext_channel_add_value)?;
        }
        if format == DiagnosisFormat::Qualified {
            w.u32(self.qualifier)?;
        }
        Ok(())
    }
}

/// The data of a channel diagnosis USI: entries of one format.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Diagnosis {
    /// The format (which USI).
    pub format: DiagnosisFormat,
    /// The entries, in order.
    pub entries: Vec<ChannelDiagnosis>,
}

impl Diagnosis {
    /// Decodes the data of `usi`. `None` when the USI is not channel diagnosis or the data is
    /// not a whole number of entries.
    pub fn parse(usi: u16, data: &[u8]) -> Option<Diagnosis> {
        let format = DiagnosisFormat::from_usi(usi)?;
        if !data.len().is_multiple_of(format.entry_len()) {
            return None;
        }
        let mut r = Reader::new(data);
        let mut entries = Vec::with_capacity(data.len() / format.entry_len());
        while !r.is_empty() {
            entries.push(ChannelDiagnosis::parse(format, &mut r).ok()?);
        }
        Some(Diagnosis { format, entries })
    }

    /// The USI.
    pub const fn usi(&self) -> u16 {
        self.format.usi()
    }

    /// Bytes of the data (after the USI).
    pub fn data_len(&self) -> usize {
        self.entries.len().saturating_mul(self.format.entry_len())
    }

    fn emit_data(&self, w: &mut Writer<'_>) -> EmitResult<()> {
        self.entries.iter().try_for_each(|e| e.emit(self.format, w))
    }
}

/// The item after the AlarmSpecifier: a USI and its data.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum AlarmItem {
    /// USI 0x8000/0x8002/0x8003 with a whole number of entries.
    Diagnosis(Diagnosis),
    /// Any other USI (manufacturer 0x0000..=0x7FFF, 0x8001 multiple, profiles…), or a
    /// diagnosis USI whose data does not decode; the data bytes are kept as they are.
    Other {
        /// UserStructureIdentifier.
        usi: u16,
        /// The data after it.
        data: Vec<u8>,
    },
}

impl AlarmItem {
    /// Decodes the data of `usi`; never fails (what does not decode is [`AlarmItem::Other`]).
    pub fn parse(usi: u16, data: &[u8]) -> AlarmItem {
        Diagnosis::parse(usi, data)
            .map(AlarmItem::Diagnosis)
            .unwrap_or_else(|| AlarmItem::Other {
                usi,
                data: data.to_vec(),
            })
    }

    /// The USI.
    pub fn usi(&self) -> u16 {
        match self {
            AlarmItem::Diagnosis(d) => d.usi(),
            AlarmItem::Other { usi, .. } => *usi,
        }
    }

    /// The channel diagnosis, if it is one.
    pub fn diagnosis(&self) -> Option<&Diagnosis> {
        match self {
            AlarmItem::Diagnosis(d) => Some(d),
            AlarmItem::Other { .. } => None,
        }
    }

    /// Bytes on the wire, USI included.
    pub fn buffer_len(&self) -> usize {
        let data = match self {
            AlarmItem::Diagnosis(d) => d.data_len(),
            AlarmItem::Other { data, .. } => data.len(),
        };
        data.saturating_add(2)
    }

    fn emit(&self, w: &mut Writer<'_>) -> EmitResult<()> {
        w.u16(self.usi())?;
        match self {
            AlarmItem::Diagnosis(d) => d.emit_data(w),
            AlarmItem::Other { data, .. } => w.put(data),
        }
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

#[cfg(test)]
mod tests {
    use super::super::ethernet::{ETHERTYPE_PROFINET, Frame};
    use super::super::rta_pdu::*;
    use super::*;
    use crate::test_fixtures::hex;
    use proptest::prelude::*;

    // The captures below come from the test data of the `pnio` crate 0.1.0
    // (core-engineering/pnio-rs, MIT OR Apache-2.0): an S7-1515 ("CPU") talking to the p-net
    // sample device ("dev"), frames of plan5-alarm.pcapng. Hex from the Ethernet header, VLAN
    // tagged, trailing Ethernet padding included (the S7 pads with stale bytes).

    /// alarm_process_notif.hex: p-net → CPU, high, DATA AlarmNotification Process, USI 0x0010.
    const PROCESS_NOTIF: &str = concat!(
        "ec1c5d61e73c8cf319cd19f88100c0008892fc01000000001111fffffffe001d",
        "0001001901000002000000000001000100000030000001300000001001",
    );
    /// alarm_ack_rta_high_cpu.hex: CPU → p-net, high ACK-RTA for the process notification.
    const ACK_RTA_HIGH_CPU: &str = concat!(
        "8cf319cd19f8ec1c5d61e73c8100c0008892fc01000000001301fffeffff0000",
        "0000000000000000000000000000000000000000000000000000000000000000",
    );
    /// alarm_ack_high_cpu.hex: CPU → p-net, high DATA AlarmAck Process, PNIOStatus OK.
    const ACK_HIGH_CPU: &str = concat!(
        "8cf319cd19f8ec1c5d61e73c8100c0008892fc01000000001111ffffffff0016",
        "8001001201000002000000000001000100000000000000000000000000000000",
    );
    /// alarm_ack_rta_high_dev.hex: p-net → CPU, high ACK-RTA for the CPU's AlarmAck.
    const ACK_RTA_HIGH_DEV: &str =
        "ec1c5d61e73c8cf319cd19f88100c0008892fc01000000001301ffffffff0000";
    /// alarm_diag_notif.hex: p-net → CPU, low DATA AlarmNotification Diagnosis, USI 0x8002.
    const DIAG_NOTIF: &str = concat!(
        "ec1c5d61e73c8cf319cd19f88100a0008892fe01000000001111fffffffe0028",
        "000200240100000100000000000100010000003000000130a800800200042801",
        "0001000000000000",
    );
    /// alarm_ack_rta_low_cpu.hex: CPU → p-net, low ACK-RTA for the diagnosis notification.
    const ACK_RTA_LOW_CPU: &str = concat!(
        "8cf319cd19f8ec1c5d61e73c8100a0008892fe01000000001301fffeffff0000",
        "0000000000000000000000000000000000000000000000000000000000000000",
    );
    /// alarm_diag_ack_cpu.hex: CPU → p-net, low DATA AlarmAck Diagnosis, PNIOStatus OK.
    const DIAG_ACK_CPU: &str = concat!(
        "8cf319cd19f8ec1c5d61e73c8100a0008892fe01000000001111ffffffff0016",
        "80020012010000010000000000010001a8000000000000000000000000000000",
    );
    /// alarm_ack_rta_low_dev.hex: p-net → CPU, low ACK-RTA for the CPU's AlarmAck.
    const ACK_RTA_LOW_DEV: &str =
        "ec1c5d61e73c8cf319cd19f88100a0008892fe01000000001301ffffffff0000";
    /// alarm_diag_update_appears.hex: p-net → CPU, Diagnosis 0x2801 appears.
    const DIAG_UPDATE_APPEARS: &str = concat!(
        "ec1c5d61e73c8cf319cd19f88100a0008892fe010000000011110000ffff0028",
        "000200240100000100000000000100010000003000000130a801800200042801",
        "00010000000004d2",
    );
    /// alarm_diag_update_others_remain.hex: p-net → CPU, Diagnosis 0x3801 disappears, others
    /// remain.
    const DIAG_UPDATE_OTHERS_REMAIN: &str = concat!(
        "ec1c5d61e73c8cf319cd19f88100a0008892fe01000000001111000100000028",
        "000200240100000100000000000100010000003000000130a802800200043801",
        "0001000000000000",
    );
    /// alarm_diag_usi_disappears.hex: p-net → CPU, DiagnosisDisappears, USI 0x1234, no data.
    const DIAG_USI_DISAPPEARS: &str = concat!(
        "ec1c5d61e73c8cf319cd19f88100a0008892fe0100000000111100040003001c",
        "000200180100000c00000000000100010000003000000130a8051234",
    );
    /// alarm_diag_std_remove.hex: p-net → CPU, Diagnosis 0x2001 (all disappear).
    const DIAG_STD_REMOVE: &str = concat!(
        "ec1c5d61e73c8cf319cd19f88100a0008892fe01000000001111000500040028",
        "0002002401000001000000000001000100000030000001300006800200042001",
        "00010000000004d2",
    );
    /// alarm_err_rta_dev.hex: p-net → CPU, ERR-RTA CF 81 FD 00.
    const ERR_RTA_DEV: &str = concat!(
        "ec1c5d61e73c8cf319cd19f88100a0008892fe01000000001401000600050004",
        "cf81fd00",
    );
    /// alarm_err_rta_cpu.hex: CPU → p-net, ERR-RTA CF 81 FD 0B, stale bytes as padding.
    const ERR_RTA_CPU: &str = concat!(
        "8cf319cd19f8ec1c5d61e73c8100a0008892fe01000000001401000500050004",
        "cf81fd0b002a010e8004000c010b000000160160cf81fd000000000000000000",
    );
    /// alarm_err_rta_cpu_removed.hex: CPU → p-net, ERR-RTA CF 81 FD 11 at a TIA download.
    const ERR_RTA_CPU_REMOVED: &str = concat!(
        "8cf319cd19f8ec1c5d61e73c8100a0008892fe01000000001401fffefffe0004",
        "cf81fd11002a010e8004000c01110000028006978181fd110000000000000000",
    );
    /// alarm_err_rta_dev_removed_reply.hex: p-net → CPU, ERR-RTA reply CF 81 FD 11.
    const ERR_RTA_DEV_REMOVED_REPLY: &str = concat!(
        "ec1c5d61e73c8cf319cd19f88100a0008892fe01000000001401fffffffe0004",
        "cf81fd11",
    );

    /// Parses a captured frame's RTA PDU and checks it re-emits to the PDU bytes (padding
    /// excluded). Returns the Repr.
    fn capture(frame_hex: &str) -> RtaPdu {
        let frame = hex(frame_hex);
        let f = Frame::new_checked(&frame[..]).unwrap();
        assert_eq!(f.ethertype(), ETHERTYPE_PROFINET);
        let bytes = f.payload();
        let packet = Packet::new_checked(bytes).unwrap();
        let pdu = RtaPdu::parse(&packet).unwrap();
        let len = HEADER_LEN + usize::from(packet.var_part_len());
        assert_eq!(pdu.buffer_len(), len);
        let mut buf = vec![0xa5u8; len];
        pdu.emit(&mut buf).unwrap();
        assert_eq!(&buf[..], &bytes[..len]);
        assert_eq!(pdu.header.var_part_len, packet.var_part_len());
        assert_eq!(pdu.header.pdu_type, pdu.body.pdu_type());
        let _ = packet.to_string();
        pdu
    }

    fn seqs(p: &RtaPdu) -> (u16, u16) {
        (p.header.send_seq, p.header.ack_seq)
    }

    const fn spec(seq: u16) -> AlarmSpecifier {
        // Bits 11, 13 and 15, as p-net sets them for its diagnosis alarms (0xA8xx).
        AlarmSpecifier {
            sequence_number: seq,
            channel_diagnosis: true,
            manufacturer_diagnosis: false,
            submodule_diagnosis: true,
            ar_diagnosis: true,
        }
    }

    #[test]
    fn process_notification() {
        let p = capture(PROCESS_NOTIF);
        assert_eq!(p.priority, Priority::High);
        assert_eq!(
            p.header,
            RtaHeader {
                dst_endpoint: 0,
                src_endpoint: 0,
                pdu_type: PduType::Data,
                version: 1,
                window_size: 1,
                tack: true,
                send_seq: SEQ_INITIAL,
                ack_seq: SEQ_INITIAL_LAST,
                var_part_len: 0x1d,
            }
        );
        let n = p.notification().unwrap();
        let expected = AlarmNotification {
            priority: Priority::High,
            alarm_type: AlarmType::Process,
            api: 0,
            slot: 1,
            subslot: 1,
            module_ident: 0x30,
            submodule_ident: 0x130,
            specifier: AlarmSpecifier::default(),
            maintenance: None,
            item: Some(AlarmItem::Other {
                usi: 0x0010,
                data: vec![0x01],
            }),
        };
        assert_eq!(n, &expected);
        assert_eq!(
            p,
            RtaPdu::data(
                Priority::High,
                0,
                0,
                0xffff,
                0xfffe,
                vec![AlarmBlock::Notification(expected)]
            )
        );
        assert!(p.to_string().starts_with("RTA high DATA"));
    }

    #[test]
    fn ack_rtas() {
        for (hex, priority, send, ack) in [
            (ACK_RTA_HIGH_CPU, Priority::High, 0xfffe, 0xffff),
            (ACK_RTA_HIGH_DEV, Priority::High, 0xffff, 0xffff),
            (ACK_RTA_LOW_CPU, Priority::Low, 0xfffe, 0xffff),
            (ACK_RTA_LOW_DEV, Priority::Low, 0xffff, 0xffff),
        ] {
            let p = capture(hex);
            assert_eq!(p.body, RtaBody::Ack);
            assert_eq!(p.priority, priority);
            assert_eq!(seqs(&p), (send, ack));
            assert!(!p.header.tack);
            assert_eq!(p.header.window_size, 1);
            assert_eq!(p, RtaPdu::ack(priority, 0, 0, send, ack));
        }
    }

    #[test]
    fn alarm_acks() {
        let p = capture(ACK_HIGH_CPU);
        assert_eq!(seqs(&p), (0xffff, 0xffff));
        let a = *p.alarm_ack().unwrap();
        assert_eq!(
            a,
            AlarmAck {
                priority: Priority::High,
                alarm_type: AlarmType::Process,
                api: 0,
                slot: 1,
                subslot: 1,
                specifier: AlarmSpecifier::default(),
                status: PnioStatus::OK,
            }
        );
        let n = capture(PROCESS_NOTIF).notification().cloned().unwrap();
        assert_eq!(AlarmAck::for_notification(&n, PnioStatus::OK), a);

        let p = capture(DIAG_ACK_CPU);
        let a = *p.alarm_ack().unwrap();
        assert_eq!(a.priority, Priority::Low);
        assert_eq!(a.alarm_type, AlarmType::Diagnosis);
        assert_eq!((a.slot, a.subslot), (1, 1));
        assert_eq!(a.specifier, spec(0));
        assert!(a.status.is_ok());
        let n = capture(DIAG_NOTIF).notification().cloned().unwrap();
        assert_eq!(AlarmAck::for_notification(&n, PnioStatus::OK), a);
    }

    #[test]
    fn diagnosis_notifications() {
        let appears = ChannelProperties(0x2801);
        assert_eq!(appears.data_type(), 1);
        assert_eq!(appears.specifier(), ChannelSpecifier::Appears);
        assert_eq!(appears.direction(), ChannelDirection::Input);
        assert!(!appears.accumulative() && !appears.maintenance_required());
        assert_eq!(
            appears,
            ChannelProperties::new(
                1,
                false,
                false,
                false,
                ChannelSpecifier::Appears,
                ChannelDirection::Input
            )
        );
        let cases = [
            (DIAG_NOTIF, (0xffff, 0xfffe), 0x0001, spec(0), 0x2801, 0),
            (
                DIAG_UPDATE_APPEARS,
                (0, 0xffff),
                0x0001,
                spec(1),
                0x2801,
                1234,
            ),
            (
                DIAG_UPDATE_OTHERS_REMAIN,
                (1, 0),
                0x0001,
                spec(2),
                0x3801,
                0,
            ),
            (
                DIAG_STD_REMOVE,
                (5, 4),
                0x0001,
                AlarmSpecifier::from_u16(6),
                0x2001,
                1234,
            ),
        ];
        for (hex, seq, alarm_type, specifier, props, add_value) in cases {
            let p = capture(hex);
            assert_eq!(p.priority, Priority::Low);
            assert_eq!(seqs(&p), seq);
            let n = p.notification().unwrap();
            assert_eq!(n.alarm_type, AlarmType::from(alarm_type));
            assert_eq!((n.api, n.slot, n.subslot), (0, 1, 1));
            assert_eq!((n.module_ident, n.submodule_ident), (0x30, 0x130));
            assert_eq!(n.specifier, specifier);
            assert_eq!(n.maintenance, None);
            let d = n.diagnosis().unwrap();
            assert_eq!(d.format, DiagnosisFormat::Extended);
            assert_eq!(d.usi(), USI_EXT_CHANNEL_DIAGNOSIS);
            assert_eq!(
                d.entries,
                vec![ChannelDiagnosis {
                    channel_number: 4,
                    channel_properties: ChannelProperties(props),
                    channel_error_type: 1,
                    ext_channel_error_type: 0,
                    ext_channel_add_value: add_value,
                    qualifier: 0,
                }]
            );
        }
        let others = ChannelProperties(0x3801).specifier();
        assert_eq!(others, ChannelSpecifier::DisappearsOthersRemain);
        let all = ChannelProperties(0x2001).specifier();
        assert_eq!(all, ChannelSpecifier::AllDisappear);
        let spec6 = AlarmSpecifier::from_u16(6);
        assert_eq!(spec6.sequence_number, 6);
        assert!(!spec6.channel_diagnosis && !spec6.submodule_diagnosis && !spec6.ar_diagnosis);
    }

    #[test]
    fn manufacturer_usi_without_data() {
        let p = capture(DIAG_USI_DISAPPEARS);
        assert_eq!(seqs(&p), (4, 3));
        let n = p.notification().unwrap();
        assert_eq!(n.alarm_type, AlarmType::DiagnosisDisappears);
        assert_eq!(n.specifier, spec(5));
        assert_eq!(
            n.item,
            Some(AlarmItem::Other {
                usi: 0x1234,
                data: vec![]
            })
        );
        assert_eq!(n.diagnosis(), None);
    }

    #[test]
    fn err_rtas() {
        for (hex, seq, code, text) in [
            (
                ERR_RTA_DEV,
                (6, 5),
                AbortCode::Unspecified,
                "abort: unspecified (0x00)",
            ),
            (
                ERR_RTA_CPU,
                (5, 5),
                AbortCode::AlarmIndicationError,
                "abort: AR alarm.ind(err) (0x0b)",
            ),
            (
                ERR_RTA_CPU_REMOVED,
                (0xfffe, 0xfffe),
                AbortCode::ArRemoved,
                "abort: AR removed (0x11)",
            ),
            (
                ERR_RTA_DEV_REMOVED_REPLY,
                (0xffff, 0xfffe),
                AbortCode::ArRemoved,
                "abort: AR removed (0x11)",
            ),
        ] {
            let p = capture(hex);
            assert_eq!(p.priority, Priority::Low);
            assert_eq!(seqs(&p), seq);
            assert_eq!(p.header.var_part_len, 4);
            assert!(!p.header.tack);
            let RtaBody::Err(e) = &p.body else {
                panic!("not an ERR-RTA: {p:?}");
            };
            assert_eq!(e.status.to_bytes()[..3], [0xcf, 0x81, 0xfd]);
            assert!(e.vendor_data.is_empty());
            assert_eq!(e.abort_code(), Some(code));
            assert_eq!(e, &ErrRta::abort(code));
            assert_eq!(e.to_string(), text);
            assert_eq!(
                p,
                RtaPdu::err(Priority::Low, 0, 0, seq.0, seq.1, ErrRta::abort(code))
            );
        }
        assert_eq!(AbortCode::from(0x99).to_string(), "abort code 0x99");
        assert_eq!(
            AbortCode::PdevCheckFailed.to_string(),
            "PDEV check failed (0x24)"
        );
    }

    #[test]
    fn sequence_numbers() {
        assert_eq!(next_seq(0xffff), 0);
        assert_eq!(next_seq(0xfffe), 0xffff);
        assert_eq!(next_seq(0), 1);
        assert_eq!(next_seq(0x7ffe), 0x7fff);
        assert_eq!(next_seq(0x7fff), 0);

        // The low channel of the capture, from both ends.
        let mut dev = RtaSequence::new();
        let mut cpu = RtaSequence::new();
        // p-net's first diagnosis DATA.
        let notif = capture(DIAG_NOTIF);
        assert_eq!(seqs(&notif), (dev.send_seq(), dev.last_received()));
        assert_eq!(cpu.receive(notif.header.send_seq), Received::New);
        // The CPU's ACK-RTA confirms it.
        let ack = capture(ACK_RTA_LOW_CPU);
        assert_eq!(seqs(&ack), (cpu.last_sent(), cpu.last_received()));
        assert!(dev.confirms(ack.header.ack_seq));
        dev.confirm();
        // The CPU's AlarmAck DATA, and p-net's ACK-RTA for it.
        let data = capture(DIAG_ACK_CPU);
        assert_eq!(seqs(&data), (cpu.send_seq(), cpu.last_received()));
        assert_eq!(dev.receive(data.header.send_seq), Received::New);
        assert_eq!(dev.classify(data.header.send_seq), Received::Duplicate);
        let ack = capture(ACK_RTA_LOW_DEV);
        assert_eq!(seqs(&ack), (dev.last_sent(), dev.last_received()));
        assert!(cpu.confirms(ack.header.ack_seq));
        cpu.confirm();
        // p-net's next DATA, then (after the CPU's next AlarmAck) the one after it.
        let next = capture(DIAG_UPDATE_APPEARS);
        assert_eq!(seqs(&next), (dev.send_seq(), dev.last_received()));
        assert_eq!(cpu.receive(next.header.send_seq), Received::New);
        dev.confirm();
        assert_eq!(dev.receive(cpu.send_seq()), Received::New);
        cpu.confirm();
        let next = capture(DIAG_UPDATE_OTHERS_REMAIN);
        assert_eq!(seqs(&next), (dev.send_seq(), dev.last_received()));
        assert_eq!(cpu.receive(5), Received::OutOfOrder);
        assert_eq!(cpu.receive(0), Received::Duplicate);
        assert_eq!(cpu.receive(1), Received::New);
    }

    /// AINFO examples of the Siemens manual (records-diagnosis.md TV10, TV11): channel
    /// diagnosis 0x8000, and a MaintenanceItem followed by extended channel diagnosis.
    #[test]
    fn manual_examples() {
        let tv10 = hex(concat!(
            "0002001e0100000100000000001000010000",
            "8ad800000000a854800000002805",
            "0006"
        ));
        let n = AlarmNotification::parse(&tv10).unwrap();
        assert_eq!(n.alarm_type, AlarmType::Diagnosis);
        assert_eq!((n.slot, n.subslot, n.module_ident), (0x10, 1, 0x8ad8));
        assert_eq!(n.specifier.sequence_number, 84);
        assert_eq!(n.specifier, spec(84));
        let d = n.diagnosis().unwrap();
        assert_eq!(d.format, DiagnosisFormat::Channel);
        assert_eq!(
            d.entries,
            vec![ChannelDiagnosis::new(0, ChannelProperties(0x2805), 6)]
        );
        assert_eq!(d.entries[0].channel_properties.data_type(), 5);
        let mut out = vec![0u8; n.buffer_len()];
        n.emit(&mut out).unwrap();
        assert_eq!(out, tv10);

        let tv11 = hex(concat!(
            "000200320100000e0000000000008001",
            "000003630000000100048100",
            "0f0000080100000000000001",
            "800280000a008007800000000010",
        ));
        let n = AlarmNotification::parse(&tv11).unwrap();
        assert_eq!(n.alarm_type, AlarmType::PortDataChange);
        assert_eq!((n.slot, n.subslot), (0, 0x8001));
        assert_eq!(n.specifier, AlarmSpecifier::from_u16(4));
        let m = n.maintenance.unwrap();
        assert!(m.maintenance_required() && !m.maintenance_demanded());
        let d = n.diagnosis().unwrap();
        assert_eq!(d.format, DiagnosisFormat::Extended);
        let e = d.entries[0];
        assert_eq!(e.channel_number, CHANNEL_NUMBER_SUBMODULE);
        assert!(e.channel_properties.maintenance_required());
        assert_eq!(e.channel_properties.specifier(), ChannelSpecifier::Appears);
        assert_eq!(
            (
                e.channel_error_type,
                e.ext_channel_error_type,
                e.ext_channel_add_value
            ),
            (0x8007, 0x8000, 16)
        );
        let mut out = vec![0u8; n.buffer_len()];
        n.emit(&mut out).unwrap();
        assert_eq!(out, tv11);
    }

    #[test]
    fn qualified_diagnosis_round_trip() {
        let entry = ChannelDiagnosis {
            channel_number: 3,
            channel_properties: ChannelProperties(0x4801),
            channel_error_type: 6,
            ext_channel_error_type: 0x8001,
            ext_channel_add_value: 0x0102_0304,
            qualifier: 1 << 27,
        };
        let n = AlarmNotification {
            priority: Priority::Low,
            alarm_type: AlarmType::Diagnosis,
            api: 0,
            slot: 2,
            subslot: 1,
            module_ident: 7,
            submodule_ident: 8,
            specifier: spec(9),
            maintenance: None,
            item: Some(AlarmItem::Diagnosis(Diagnosis {
                format: DiagnosisFormat::Qualified,
                entries: vec![entry, entry],
            })),
        };
        assert_eq!(n.buffer_len(), 6 + 20 + 2 + 32);
        let mut out = vec![0u8; n.buffer_len()];
        n.emit(&mut out).unwrap();
        assert_eq!(&out[26..28], &[0x80, 0x03]);
        assert_eq!(AlarmNotification::parse(&out).unwrap(), n);
        // A diagnosis USI with a partial entry stays raw.
        assert_eq!(
            AlarmItem::parse(USI_CHANNEL_DIAGNOSIS, &[0, 1, 2]),
            AlarmItem::Other {
                usi: USI_CHANNEL_DIAGNOSIS,
                data: vec![0, 1, 2]
            }
        );
    }

    #[test]
    fn malformed() {
        let ok = hex(ACK_RTA_HIGH_DEV);
        let pdu = &ok[18..];
        // Truncated headers.
        for n in 0..HEADER_LEN {
            assert_eq!(RtaPdu::parse(&Packet::new_unchecked(&pdu[..n])), Err(Error));
        }
        // Not an alarm FrameID.
        let mut b = pdu.to_vec();
        b[0..2].copy_from_slice(&0xfefeu16.to_be_bytes());
        assert_eq!(RtaPdu::parse(&Packet::new_unchecked(&b[..])), Err(Error));
        // Unknown PDU type.
        let mut b = pdu.to_vec();
        b[6] = 0x15;
        assert_eq!(RtaPdu::parse(&Packet::new_unchecked(&b[..])), Err(Error));
        // ACK with a VarPart; VarPartLen past the buffer.
        let mut b = pdu.to_vec();
        b[13] = 2;
        assert_eq!(RtaPdu::parse(&Packet::new_unchecked(&b[..])), Err(Error));
        b.extend_from_slice(&[0, 0]);
        assert_eq!(RtaPdu::parse(&Packet::new_unchecked(&b[..])), Err(Error));
        // ERR shorter than its status.
        let err = hex(ERR_RTA_DEV);
        let mut b = err[18..].to_vec();
        b[13] = 3;
        assert_eq!(RtaPdu::parse(&Packet::new_unchecked(&b[..])), Err(Error));
        // DATA whose block runs past VarPartLen.
        let data = hex(PROCESS_NOTIF);
        let mut b = data[18..].to_vec();
        b[13] -= 1;
        assert_eq!(RtaPdu::parse(&Packet::new_unchecked(&b[..])), Err(Error));
        // A notification with one stray byte after the specifier.
        let mut n = hex("0001001701000002000000000001000100000030000001300000ff");
        assert_eq!(AlarmNotification::parse(&n), Err(Error));
        n[3] = 0x16;
        assert!(AlarmNotification::parse(&n).is_ok());
        // An AlarmAck of the wrong length.
        let mut a = hex(ACK_HIGH_CPU)[32..54].to_vec();
        assert!(AlarmAck::parse(&a).is_ok());
        a[3] = 0x11;
        assert_eq!(AlarmAck::parse(&a), Err(Error));
        // Emit into short buffers.
        let p = capture(PROCESS_NOTIF);
        let mut buf = vec![0u8; p.buffer_len() - 1];
        let short = p.emit(&mut buf).unwrap_err();
        assert_eq!(
            short,
            EmitError::BufferTooShort {
                what: "RTA PDU",
                needed: buf.len() + 1,
                len: buf.len()
            }
        );
        assert_eq!(
            short.to_string(),
            format!(
                "buffer of {} bytes, the RTA PDU needs {}",
                buf.len(),
                buf.len() + 1
            )
        );
        assert_eq!(RtaHeader::parse(&[0; 11]), Err(Error));
        assert!(matches!(
            p.header.emit(&mut [0; 11]),
            Err(EmitError::BufferTooShort { needed: 12, .. })
        ));
    }

    fn header() -> impl Strategy<Value = RtaHeader> {
        (
            any::<(u16, u16, u16, u16, u16)>(),
            0u8..16,
            0u8..16,
            0u8..16,
            any::<bool>(),
        )
            .prop_map(|((dst, src, send, ack, len), ty, version, window, tack)| {
                RtaHeader {
                    dst_endpoint: dst,
                    src_endpoint: src,
                    pdu_type: PduType::from(ty),
                    version,
                    window_size: window,
                    tack,
                    send_seq: send,
                    ack_seq: ack,
                    var_part_len: len,
                }
            })
    }

    fn priority() -> impl Strategy<Value = Priority> {
        prop_oneof![Just(Priority::High), Just(Priority::Low)]
    }

    fn alarm_ack() -> impl Strategy<Value = AlarmAck> {
        (
            priority(),
            any::<(u16, u32, u16, u16, u32)>(),
            0u16..0x800,
            any::<u16>(),
        )
            .prop_map(|(priority, (ty, api, slot, subslot, status), seq, flags)| {
                AlarmAck {
                    priority,
                    alarm_type: AlarmType::from(ty),
                    api,
                    slot,
                    subslot,
                    specifier: AlarmSpecifier::from_u16((flags & 0xb800) | seq),
                    status: PnioStatus::from_u32(status),
                }
            })
    }

    fn entry(format: DiagnosisFormat) -> impl Strategy<Value = ChannelDiagnosis> {
        any::<(u16, u16, u16, u16, u32, u32)>().prop_map(move |(ch, props, err, ext, add, q)| {
            let mut e = ChannelDiagnosis::new(ch, ChannelProperties(props), err);
            if format != DiagnosisFormat::Channel {
                e.ext_channel_error_type = ext;
                e.ext_channel_add_value = add;
            }
            if format == DiagnosisFormat::Qualified {
                e.qualifier = q;
            }
            e
        })
    }

    fn item() -> impl Strategy<Value = AlarmItem> {
        let format = prop_oneof![
            Just(DiagnosisFormat::Channel),
            Just(DiagnosisFormat::Extended),
            Just(DiagnosisFormat::Qualified),
        ];
        prop_oneof![
            format.prop_flat_map(|format| {
                proptest::collection::vec(entry(format), 0..5)
                    .prop_map(move |entries| AlarmItem::Diagnosis(Diagnosis { format, entries }))
            }),
            (0u16..0x8000, proptest::collection::vec(any::<u8>(), 0..40))
                .prop_map(|(usi, data)| AlarmItem::Other { usi, data }),
        ]
    }

    fn notification() -> impl Strategy<Value = AlarmNotification> {
        (
            priority(),
            any::<(u16, u32, u16, u16, u32, u32)>(),
            0u16..0x800,
            any::<u16>(),
            proptest::option::of(any::<u32>()),
            proptest::option::of(item()),
        )
            .prop_map(
                |(priority, (ty, api, slot, subslot, module, submodule), seq, flags, m, item)| {
                    AlarmNotification {
                        priority,
                        alarm_type: AlarmType::from(ty),
                        api,
                        slot,
                        subslot,
                        module_ident: module,
                        submodule_ident: submodule,
                        specifier: AlarmSpecifier::from_u16((flags & 0xb800) | seq),
                        maintenance: m.map(|status| MaintenanceItem { status }),
                        item,
                    }
                },
            )
    }

    fn pdu() -> impl Strategy<Value = RtaPdu> {
        let block = prop_oneof![
            notification().prop_map(AlarmBlock::Notification),
            alarm_ack().prop_map(AlarmBlock::Ack),
        ];
        let body = prop_oneof![
            proptest::collection::vec(block, 0..3).prop_map(RtaBody::Data),
            Just(RtaBody::Ack),
            Just(RtaBody::Nack),
            (any::<u32>(), proptest::collection::vec(any::<u8>(), 0..8)).prop_map(
                |(s, vendor_data)| RtaBody::Err(ErrRta {
                    status: PnioStatus::from_u32(s),
                    vendor_data
                })
            ),
        ];
        (priority(), any::<(u16, u16, u16, u16)>(), body).prop_map(
            |(priority, (dst, src, send, ack), body)| {
                RtaPdu::new(priority, dst, src, send, ack, body)
            },
        )
    }

    proptest! {
        #[test]
        fn parse_never_panics(bytes in proptest::collection::vec(any::<u8>(), 0..300)) {
            let p = Packet::new_unchecked(&bytes[..]);
            if let Ok(r) = RtaPdu::parse(&p) {
                // What parses emits again, to the same length (reserved bits and block
                // versions are normalised).
                let v = r.to_vec().unwrap();
                prop_assert_eq!(v.len(), HEADER_LEN + usize::from(p.var_part_len()));
            }
            let _ = p.to_string();
            let _ = RtaHeader::parse(&bytes);
            let _ = AlarmNotification::parse(&bytes);
            let _ = AlarmAck::parse(&bytes);
            let _ = AlarmBlock::parse(&bytes);
            let _ = ErrRta::parse(&bytes);
        }

        #[test]
        fn parse_never_panics_on_plausible_pdus(
            frame_id in prop_oneof![Just(FRAME_ID_ALARM_HIGH), Just(FRAME_ID_ALARM_LOW)],
            pdu_type in 0u8..6,
            block_type in prop_oneof![Just(1u16), Just(2u16), Just(0x8001u16), Just(0x8002u16)],
            body in proptest::collection::vec(any::<u8>(), 0..80),
        ) {
            let mut b = frame_id.to_be_bytes().to_vec();
            b.extend_from_slice(&[0, 0, 0, 0, 0x10 | pdu_type, 0x11, 0, 0, 0, 0]);
            let var_len = body.len() + 4;
            b.extend_from_slice(&(var_len as u16).to_be_bytes());
            b.extend_from_slice(&block_type.to_be_bytes());
            b.extend_from_slice(&(body.len() as u16).to_be_bytes());
            b.extend_from_slice(&body);
            if let Ok(r) = RtaPdu::parse(&Packet::new_unchecked(&b[..])) {
                prop_assert_eq!(r.to_vec().unwrap().len(), b.len());
            }
        }

        #[test]
        fn diagnosis_decoding_never_panics(
            usi in 0x7ffeu16..0x8005,
            data in proptest::collection::vec(any::<u8>(), 0..64),
        ) {
            let item = AlarmItem::parse(usi, &data);
            prop_assert_eq!(item.buffer_len(), data.len() + 2);
        }

        #[test]
        fn rta_header_round_trip(h in header()) {
            let mut buf = [0u8; RTA_HEADER_LEN];
            h.emit(&mut buf).unwrap();
            prop_assert_eq!(RtaHeader::parse(&buf).unwrap(), h);
            // The view reads the same fields.
            let mut full = [0u8; HEADER_LEN];
            full[2..].copy_from_slice(&buf);
            let p = Packet::new_unchecked(&full[..]);
            prop_assert_eq!(
                (p.dst_endpoint(), p.src_endpoint(), p.pdu_type(), p.version()),
                (h.dst_endpoint, h.src_endpoint, h.pdu_type, h.version)
            );
            prop_assert_eq!(
                (p.window_size(), p.tack(), p.send_seq(), p.ack_seq(), p.var_part_len()),
                (h.window_size, h.tack, h.send_seq, h.ack_seq, h.var_part_len)
            );
            // And the setters write them.
            let mut other = [0u8; HEADER_LEN];
            let mut q = Packet::new_unchecked(&mut other[..]);
            q.set_dst_endpoint(h.dst_endpoint);
            q.set_src_endpoint(h.src_endpoint);
            q.set_pdu_type(h.pdu_type, h.version);
            q.set_add_flags(h.window_size, h.tack);
            q.set_send_seq(h.send_seq);
            q.set_ack_seq(h.ack_seq);
            q.set_var_part_len(h.var_part_len);
            prop_assert_eq!(&other[2..], &buf[..]);
        }

        #[test]
        fn alarm_ack_round_trip(a in alarm_ack()) {
            let mut buf = [0u8; AlarmAck::LEN];
            a.emit(&mut buf).unwrap();
            prop_assert_eq!(AlarmAck::parse(&buf).unwrap(), a);
        }

        #[test]
        fn notification_round_trip(n in notification()) {
            let mut buf = vec![0u8; n.buffer_len()];
            n.emit(&mut buf).unwrap();
            prop_assert_eq!(AlarmNotification::parse(&buf).unwrap(), n);
        }

        #[test]
        fn pdu_round_trip(p in pdu()) {
            let bytes = p.to_vec().unwrap();
            prop_assert_eq!(bytes.len(), p.buffer_len());
            let back = RtaPdu::parse(&Packet::new_checked(&bytes[..]).unwrap()).unwrap();
            prop_assert_eq!(back, p);
        }

        #[test]
        fn sequence_numbers_stay_in_range(n in any::<u16>()) {
            let m = next_seq(n);
            prop_assert!(m <= SEQ_MAX || (n == SEQ_INITIAL_LAST && m == SEQ_INITIAL));
        }
    }
}
