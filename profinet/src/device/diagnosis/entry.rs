// SPDX-License-Identifier: MIT OR Apache-2.0
//! The entries of the diagnosis store: where they are, how severe, what they say, what
//! identifies them, and the checks they pass before the store takes them.

use crate::wire::alarm::MaintenanceItem;
use crate::wire::diagnosis::{
    CHANNEL_NUMBER_SUBMODULE, ChannelDiagnosis, ChannelDirection, ChannelProperties,
    ChannelSpecifier, DiagnosisFormat,
};
/// Entries one submodule may hold: a bound against an application that adds without end.
pub const MAX_ENTRIES_PER_SUBMODULE: usize = 64;
/// The most data a manufacturer-specific entry may carry (the IO-Base limit).
pub const MAX_GENERIC_DATA: usize = 1404;

/// Where a submodule is.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct SubslotAddr {
    /// API.
    pub api: u32,
    /// SlotNumber.
    pub slot: u16,
    /// SubslotNumber.
    pub subslot: u16,
}

impl SubslotAddr {
    /// From its parts.
    pub const fn new(api: u32, slot: u16, subslot: u16) -> SubslotAddr {
        SubslotAddr { api, slot, subslot }
    }
}

/// "API 0 slot 1 subslot 0x0001", as engineering tools name a position.
impl core::fmt::Display for SubslotAddr {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(
            f,
            "API {} slot {} subslot {:#06x}",
            self.api, self.slot, self.subslot
        )
    }
}

/// QualifiedChannelQualifier bits of each severity (bits 0–2 are reserved).
const QUALIFIER_ADVICE: u32 = 0x0000_0078;
const QUALIFIER_REQUIRED: u32 = 0x0001_ff80;
const QUALIFIER_DEMANDED: u32 = 0x07fe_0000;
const QUALIFIER_FAULT: u32 = 0xf800_0000;

/// How severe an entry is: ChannelProperties.Maintenance (bits 9–10), with the qualifier of a
/// qualified one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Severity {
    /// A fault (maintenance bits 00, "diagnosis" in older texts).
    Fault,
    /// Maintenance required (bit 9).
    MaintenanceRequired,
    /// Maintenance demanded (bit 10).
    MaintenanceDemanded,
    /// Qualified (both bits): QualifiedChannelQualifier says how severe, with exactly one of
    /// its bits 3–31 set: 3–6 advice, 7–16 maintenance required, 17–26 maintenance
    /// demanded, 27–31 fault. Only for qualified channel diagnosis (USI 0x8003).
    Qualified(u32),
}

impl Severity {
    /// The (MaintenanceRequired, MaintenanceDemanded) bits of ChannelProperties.
    const fn maintenance_bits(self) -> (bool, bool) {
        match self {
            Severity::Fault => (false, false),
            Severity::MaintenanceRequired => (true, false),
            Severity::MaintenanceDemanded => (false, true),
            Severity::Qualified(_) => (true, true),
        }
    }

    /// Whether it is a fault (the station problem, SubmoduleDiagnosisState, DiagInfo).
    pub const fn is_fault(self) -> bool {
        match self {
            Severity::Fault => true,
            Severity::Qualified(q) => q & QUALIFIER_FAULT != 0,
            _ => false,
        }
    }

    /// Whether it requires maintenance.
    pub const fn requires_maintenance(self) -> bool {
        match self {
            Severity::MaintenanceRequired => true,
            Severity::Qualified(q) => q & QUALIFIER_REQUIRED != 0,
            _ => false,
        }
    }

    /// Whether it demands maintenance.
    pub const fn demands_maintenance(self) -> bool {
        match self {
            Severity::MaintenanceDemanded => true,
            Severity::Qualified(q) => q & QUALIFIER_DEMANDED != 0,
            _ => false,
        }
    }

    /// Its part of a MaintenanceStatus: bit 0 required, bit 1 demanded, and a qualified
    /// entry's qualifier bit where the qualifier has it.
    pub(super) const fn maintenance_status(self) -> u32 {
        let q = match self {
            Severity::Qualified(q) => {
                q & (QUALIFIER_ADVICE | QUALIFIER_REQUIRED | QUALIFIER_DEMANDED | QUALIFIER_FAULT)
            }
            _ => 0,
        };
        let r = if self.requires_maintenance() {
            MaintenanceItem::REQUIRED
        } else {
            0
        };
        let d = if self.demands_maintenance() {
            MaintenanceItem::DEMANDED
        } else {
            0
        };
        q | r | d
    }
}

/// A channel diagnosis entry: USI 0x8000, 0x8002 or 0x8003 on the wire.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ChannelDiag {
    /// Which USI: channel (no extended fields), extended, or qualified (severity
    /// [`Severity::Qualified`]).
    pub format: DiagnosisFormat,
    /// ChannelNumber: 0..=0x7FFF, or 0x8000 for the whole submodule.
    pub channel_number: u16,
    /// ChannelProperties.Type: the channel's data width (0 for the whole submodule, 1 = 1 bit
    /// … 7 = 64 bit).
    pub data_type: u8,
    /// ChannelProperties.Accumulative: a group message for several channels.
    pub accumulative: bool,
    /// ChannelProperties.Direction.
    pub direction: ChannelDirection,
    /// How severe.
    pub severity: Severity,
    /// ChannelErrorType.
    pub error_type: u16,
    /// ExtChannelErrorType (extended and qualified; 0 otherwise).
    pub ext_error_type: u16,
    /// ExtChannelAddValue (extended and qualified; 0 otherwise).
    pub ext_add_value: u32,
}

impl ChannelDiag {
    /// A fault on a channel (USI 0x8000), direction manufacturer specific, type 0; the
    /// `with_*` methods change the rest.
    pub const fn new(channel_number: u16, error_type: u16) -> ChannelDiag {
        ChannelDiag {
            format: DiagnosisFormat::Channel,
            channel_number,
            data_type: 0,
            accumulative: false,
            direction: ChannelDirection::Manufacturer,
            severity: Severity::Fault,
            error_type,
            ext_error_type: 0,
            ext_add_value: 0,
        }
    }

    /// An extended channel fault (USI 0x8002).
    pub const fn extended(
        channel_number: u16,
        error_type: u16,
        ext_error_type: u16,
        ext_add_value: u32,
    ) -> ChannelDiag {
        ChannelDiag {
            format: DiagnosisFormat::Extended,
            ext_error_type,
            ext_add_value,
            ..ChannelDiag::new(channel_number, error_type)
        }
    }

    /// A qualified channel diagnosis (USI 0x8003) with its QualifiedChannelQualifier.
    pub const fn qualified(
        channel_number: u16,
        error_type: u16,
        ext_error_type: u16,
        ext_add_value: u32,
        qualifier: u32,
    ) -> ChannelDiag {
        ChannelDiag {
            format: DiagnosisFormat::Qualified,
            severity: Severity::Qualified(qualifier),
            ..ChannelDiag::extended(channel_number, error_type, ext_error_type, ext_add_value)
        }
    }

    /// With another direction.
    pub const fn with_direction(self, direction: ChannelDirection) -> ChannelDiag {
        ChannelDiag { direction, ..self }
    }

    /// With another data width (ChannelProperties.Type).
    pub const fn with_data_type(self, data_type: u8) -> ChannelDiag {
        ChannelDiag { data_type, ..self }
    }

    /// With another severity.
    pub const fn with_severity(self, severity: Severity) -> ChannelDiag {
        ChannelDiag { severity, ..self }
    }

    /// As a group message for several channels, or not.
    pub const fn with_accumulative(self, accumulative: bool) -> ChannelDiag {
        ChannelDiag {
            accumulative,
            ..self
        }
    }

    /// Its ChannelProperties while pending (specifier Appears).
    pub const fn properties(&self) -> ChannelProperties {
        let (required, demanded) = self.severity.maintenance_bits();
        ChannelProperties::new(
            self.data_type,
            self.accumulative,
            required,
            demanded,
            ChannelSpecifier::Appears,
            self.direction,
        )
    }

    /// The entry on the wire, with `properties`.
    pub(super) fn wire(&self, properties: ChannelProperties) -> ChannelDiagnosis {
        ChannelDiagnosis {
            channel_number: self.channel_number,
            channel_properties: properties,
            channel_error_type: self.error_type,
            ext_channel_error_type: self.ext_error_type,
            ext_channel_add_value: self.ext_add_value,
            qualifier: match self.severity {
                Severity::Qualified(q) => q,
                _ => 0,
            },
        }
    }

    fn validate(&self) -> Result<(), DiagnosisError> {
        let invalid = |why| Err(DiagnosisError::InvalidEntry(why));
        if self.channel_number > CHANNEL_NUMBER_SUBMODULE {
            return invalid("ChannelNumber above 0x8000 is reserved");
        }
        if self.data_type > 7 {
            return invalid("ChannelProperties.Type above 7 is reserved");
        }
        if self.channel_number == CHANNEL_NUMBER_SUBMODULE && self.data_type != 0 {
            return invalid("the whole submodule (channel 0x8000) has ChannelProperties.Type 0");
        }
        if let ChannelDirection::Unknown(_) = self.direction {
            return invalid("ChannelProperties.Direction 4..=7 is reserved");
        }
        let qualified = matches!(self.severity, Severity::Qualified(_));
        match self.format {
            DiagnosisFormat::Channel if self.ext_error_type != 0 || self.ext_add_value != 0 => {
                invalid("channel diagnosis (USI 0x8000) has no extended fields")
            }
            DiagnosisFormat::Qualified if !qualified => {
                invalid("qualified diagnosis (USI 0x8003) has the qualified severity")
            }
            DiagnosisFormat::Channel | DiagnosisFormat::Extended if qualified => {
                invalid("the qualified severity is for qualified diagnosis (USI 0x8003) only")
            }
            _ => match self.severity {
                Severity::Qualified(q) if q.count_ones() != 1 || q & 0x7 != 0 => {
                    invalid("QualifiedChannelQualifier has exactly one of bits 3 to 31 set")
                }
                _ => Ok(()),
            },
        }
    }
}

/// A manufacturer-specific entry: USI 0x0000–0x7FFF and its data.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct GenericDiag {
    /// UserStructureIdentifier, 0..=0x7FFF.
    pub usi: u16,
    /// ChannelNumber of its record block: 0..=0x7FFF, or 0x8000 for the whole submodule.
    pub channel_number: u16,
    /// ChannelProperties.Direction of its record block.
    pub direction: ChannelDirection,
    /// How severe (a manufacturer entry cannot be qualified).
    pub severity: Severity,
    /// The data, big-endian as the device manual defines it (at most
    /// [`MAX_GENERIC_DATA`] bytes).
    pub data: Vec<u8>,
}

impl GenericDiag {
    /// A fault of the whole submodule with `usi` and `data`.
    pub fn new(usi: u16, data: &[u8]) -> GenericDiag {
        GenericDiag {
            usi,
            channel_number: CHANNEL_NUMBER_SUBMODULE,
            direction: ChannelDirection::Manufacturer,
            severity: Severity::Fault,
            data: data.to_vec(),
        }
    }

    /// Its ChannelProperties while pending (type 0, specifier Appears).
    pub const fn properties(&self) -> ChannelProperties {
        let (required, demanded) = self.severity.maintenance_bits();
        ChannelProperties::new(
            0,
            false,
            required,
            demanded,
            ChannelSpecifier::Appears,
            self.direction,
        )
    }

    fn validate(&self) -> Result<(), DiagnosisError> {
        let invalid = |why| Err(DiagnosisError::InvalidEntry(why));
        if self.usi >= 0x8000 {
            return invalid("a manufacturer-specific USI is 0x0000..=0x7FFF");
        }
        if self.channel_number > CHANNEL_NUMBER_SUBMODULE {
            return invalid("ChannelNumber above 0x8000 is reserved");
        }
        if let ChannelDirection::Unknown(_) = self.direction {
            return invalid("ChannelProperties.Direction 4..=7 is reserved");
        }
        if let Severity::Qualified(_) = self.severity {
            return invalid("the qualified severity is for qualified diagnosis (USI 0x8003) only");
        }
        if self.data.len() > MAX_GENERIC_DATA {
            return invalid("manufacturer data longer than 1404 bytes");
        }
        Ok(())
    }
}

/// A diagnosis entry.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum DiagEntry {
    /// Channel, extended or qualified channel diagnosis.
    Channel(ChannelDiag),
    /// Manufacturer-specific diagnosis.
    Generic(GenericDiag),
}

impl From<ChannelDiag> for DiagEntry {
    fn from(d: ChannelDiag) -> DiagEntry {
        DiagEntry::Channel(d)
    }
}

impl From<GenericDiag> for DiagEntry {
    fn from(d: GenericDiag) -> DiagEntry {
        DiagEntry::Generic(d)
    }
}

impl DiagEntry {
    /// What identifies it on its submodule: a second entry with the same key updates it.
    pub fn key(&self) -> DiagKey {
        match self {
            DiagEntry::Channel(c) => DiagKey::Channel {
                channel_number: c.channel_number,
                accumulative: c.accumulative,
                direction: c.direction,
                error_type: c.error_type,
                ext_error_type: c.ext_error_type,
            },
            DiagEntry::Generic(g) => DiagKey::Generic { usi: g.usi },
        }
    }

    /// How severe.
    pub fn severity(&self) -> Severity {
        match self {
            DiagEntry::Channel(c) => c.severity,
            DiagEntry::Generic(g) => g.severity,
        }
    }

    /// Its ChannelProperties while pending.
    pub fn properties(&self) -> ChannelProperties {
        match self {
            DiagEntry::Channel(c) => c.properties(),
            DiagEntry::Generic(g) => g.properties(),
        }
    }

    pub(super) fn validate(&self) -> Result<(), DiagnosisError> {
        match self {
            DiagEntry::Channel(c) => c.validate(),
            DiagEntry::Generic(g) => g.validate(),
        }
    }
}

/// What identifies an entry on its submodule: for channel diagnosis the channel (number,
/// direction, accumulative) and the error (ChannelErrorType, ExtChannelErrorType), not the
/// severity or ExtChannelAddValue; for manufacturer diagnosis the USI.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DiagKey {
    /// A channel entry.
    Channel {
        /// ChannelNumber.
        channel_number: u16,
        /// ChannelProperties.Accumulative.
        accumulative: bool,
        /// ChannelProperties.Direction.
        direction: ChannelDirection,
        /// ChannelErrorType.
        error_type: u16,
        /// ExtChannelErrorType (0 for USI 0x8000).
        ext_error_type: u16,
    },
    /// A manufacturer entry.
    Generic {
        /// UserStructureIdentifier.
        usi: u16,
    },
}

/// Why a diagnosis was not taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DiagnosisError {
    /// No such submodule is plugged.
    UnknownSubmodule(SubslotAddr),
    /// The entry's fields contradict each other or the standard.
    InvalidEntry(&'static str),
    /// The submodule holds [`MAX_ENTRIES_PER_SUBMODULE`] entries already.
    TooManyEntries(SubslotAddr),
}

impl core::fmt::Display for DiagnosisError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            DiagnosisError::UnknownSubmodule(a) => write!(f, "no submodule is plugged at {a}"),
            DiagnosisError::InvalidEntry(why) => write!(f, "invalid diagnosis entry: {why}"),
            DiagnosisError::TooManyEntries(a) => write!(
                f,
                "slot {} subslot {:#06x} holds {MAX_ENTRIES_PER_SUBMODULE} diagnosis entries already",
                a.slot, a.subslot
            ),
        }
    }
}

impl core::error::Error for DiagnosisError {}
