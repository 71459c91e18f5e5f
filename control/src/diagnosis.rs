// SPDX-License-Identifier: MIT OR Apache-2.0
//! The station's diagnosis as a client of the IO device role changes it.

use serde::{Deserialize, Serialize};

/// A change of the station's diagnosis (device role): on one submodule, by API, slot and
/// subslot.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(tag = "op", rename_all = "snake_case")]
pub enum StationDiagnosisChange {
    /// An entry appears (or an entry of the same channel and error changes its severity).
    Add {
        /// API.
        api: u32,
        /// Slot.
        slot: u16,
        /// Subslot.
        subslot: u16,
        /// The entry.
        entry: DiagnosisEntry,
    },
    /// The entry of the same channel and error (or USI) disappears.
    Remove {
        /// API.
        api: u32,
        /// Slot.
        slot: u16,
        /// Subslot.
        subslot: u16,
        /// The entry (its channel, direction, accumulative flag and errors, or its USI).
        entry: DiagnosisEntry,
    },
    /// Every entry of the submodule disappears.
    Clear {
        /// API.
        api: u32,
        /// Slot.
        slot: u16,
        /// Subslot.
        subslot: u16,
    },
}

impl StationDiagnosisChange {
    /// The submodule changed: (API, slot, subslot).
    pub const fn submodule(&self) -> (u32, u16, u16) {
        match *self {
            StationDiagnosisChange::Add {
                api, slot, subslot, ..
            }
            | StationDiagnosisChange::Remove {
                api, slot, subslot, ..
            }
            | StationDiagnosisChange::Clear { api, slot, subslot } => (api, slot, subslot),
        }
    }
}

/// A pending entry of the station's diagnosis (device role), as the status report has it:
/// what the PLC reads in its diagnosis records (0x800A and the others).
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct StationDiagnosis {
    /// API.
    pub api: u32,
    /// Slot.
    pub slot: u16,
    /// Subslot.
    pub subslot: u16,
    /// The entry.
    pub entry: DiagnosisEntry,
}

/// The format of a diagnosis entry.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DiagnosisKind {
    /// Channel diagnosis (USI 0x8000).
    #[default]
    Channel,
    /// Extended channel diagnosis (USI 0x8002).
    Extended,
    /// Qualified channel diagnosis (USI 0x8003).
    Qualified,
    /// Manufacturer-specific diagnosis: a USI 0x0000–0x7FFF and its data.
    Manufacturer,
}

/// ChannelProperties.Direction of a channel diagnosis.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DiagnosisDirection {
    /// Manufacturer specific (the default).
    #[default]
    Manufacturer,
    /// An input channel.
    Input,
    /// An output channel.
    Output,
    /// An input/output channel.
    InputOutput,
}

/// How severe a channel diagnosis is.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum DiagnosisSeverity {
    /// A fault (the station problem indicator goes on).
    #[default]
    Fault,
    /// Maintenance required.
    MaintenanceRequired,
    /// Maintenance demanded.
    MaintenanceDemanded,
}

/// One diagnosis entry as a client gives it. Fields that do not apply to its `kind` are
/// left at their defaults.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default)]
pub struct DiagnosisEntry {
    /// Its format.
    pub kind: DiagnosisKind,
    /// ChannelNumber: 0 to 0x7FFF, or 0x8000 (the default) for the whole submodule.
    pub channel: u16,
    /// ChannelErrorType (e.g. 1 short circuit, 6 wire break).
    pub error_type: u16,
    /// ExtChannelErrorType (extended and qualified).
    pub ext_error_type: u16,
    /// ExtChannelAddValue (extended and qualified).
    pub ext_add_value: u32,
    /// QualifiedChannelQualifier (qualified): one of bits 3 to 31.
    pub qualifier: u32,
    /// The channel's direction.
    pub direction: DiagnosisDirection,
    /// Fault or maintenance (channel and extended).
    pub severity: DiagnosisSeverity,
    /// ChannelProperties.Type: the channel's data width (0 for the whole submodule).
    pub data_type: u8,
    /// ChannelProperties.Accumulative: a group message for several channels.
    pub accumulative: bool,
    /// UserStructureIdentifier of a manufacturer entry, 0 to 0x7FFF.
    pub usi: u16,
    /// The data of a manufacturer entry.
    pub data: Vec<u8>,
}

impl Default for DiagnosisEntry {
    fn default() -> Self {
        DiagnosisEntry {
            kind: DiagnosisKind::Channel,
            channel: 0x8000,
            error_type: 0,
            ext_error_type: 0,
            ext_add_value: 0,
            qualifier: 0,
            direction: DiagnosisDirection::Manufacturer,
            severity: DiagnosisSeverity::Fault,
            data_type: 0,
            accumulative: false,
            usi: 0,
            data: Vec::new(),
        }
    }
}
