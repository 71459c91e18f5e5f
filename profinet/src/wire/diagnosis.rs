// SPDX-License-Identifier: MIT OR Apache-2.0
//! Diagnosis items, shared by alarms and records: the UserStructureIdentifier (USI) and the
//! data after it, ChannelProperties with its fields, and the channel diagnosis entries of
//! USIs 0x8000, 0x8002 and 0x8003.
//!
//! An AlarmNotification carries one such item after its AlarmSpecifier (see
//! [`super::alarm`]); a DiagnosisData record block carries one after its ChannelNumber and
//! ChannelProperties (see [`super::record::DiagnosisData`]). The coding of the item is the
//! same in both. Everything is big-endian.

use super::cursor::{Reader, Writer};
use super::{EmitResult, Result};

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

/// What a ChannelErrorType means (IEC 61158-6-10, table "ChannelErrorType"): the common
/// values; `None` for reserved, profile and manufacturer-specific ones.
pub const fn channel_error_text(error_type: u16) -> Option<&'static str> {
    Some(match error_type {
        0x0001 => "short circuit",
        0x0002 => "undervoltage",
        0x0003 => "overvoltage",
        0x0004 => "overload",
        0x0005 => "overtemperature",
        0x0006 => "wire break",
        0x0007 => "upper limit exceeded",
        0x0008 => "lower limit exceeded",
        0x0009 => "error",
        0x0010 => "parameter assignment error",
        0x0011 => "power supply fault",
        0x0012 => "fuse blown",
        0x0014 => "ground fault",
        0x0015 => "reference point lost",
        0x0016 => "sampling error",
        0x0017 => "threshold exceeded",
        0x0018 => "output disabled",
        0x0019 => "safety-related fault",
        0x001A => "external fault",
        0x8000 => "data transmission impossible",
        0x8001 => "remote mismatch",
        0x8002 => "media redundancy mismatch",
        0x8003 => "sync mismatch",
        0x8004 => "isochronous mode mismatch",
        0x8005 => "multicast CR mismatch",
        0x8007 => "fibre optic mismatch",
        0x8008 => "network component function mismatch",
        _ => return None,
    })
}

/// `1 << n` if `b`, else 0.
pub(crate) const fn bit(b: bool, n: u16) -> u16 {
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

coded_enum! {
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

    /// The same properties with another specifier.
    pub const fn with_specifier(self, specifier: ChannelSpecifier) -> ChannelProperties {
        ChannelProperties((self.0 & !(3 << 11)) | (specifier.bits() << 11))
    }

    /// The same properties with other maintenance bits (both set: qualified diagnosis, both
    /// clear: a fault).
    pub const fn with_maintenance(self, required: bool, demanded: bool) -> ChannelProperties {
        ChannelProperties((self.0 & !(3 << 9)) | bit(required, 9) | bit(demanded, 10))
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

    pub(crate) fn emit(&self, w: &mut Writer<'_>) -> EmitResult<()> {
        w.u16(self.usi())?;
        match self {
            AlarmItem::Diagnosis(d) => d.emit_data(w),
            AlarmItem::Other { data, .. } => w.put(data),
        }
    }
}
