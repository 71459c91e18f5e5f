// SPDX-License-Identifier: MIT OR Apache-2.0
//! The diagnosis records: which submodules an index covers (its first hex digit), which
//! entries it selects (its last two), and the DiagnosisData blocks that carry them.
//!
//! | suffix | selects |
//! |---|---|
//! | `0A` | channel, extended and qualified entries that are faults |
//! | `0B` | the same and manufacturer-specific faults |
//! | `0C`, `F80C` | every entry (diagnosis, maintenance, qualified and status) |
//! | `10` / `11` | channel entries requiring / demanding maintenance |
//! | `12` / `13` | the same and manufacturer-specific ones |
//!
//! A qualified entry has both maintenance bits set, so only `0C` (and `F80C`) selects it.
//! Per submodule the record holds one block per channel format (0x8000, 0x8002, 0x8003, in
//! that order) with the selected entries oldest first, then one block per selected
//! manufacturer entry; all in BlockVersion 1.1. Nothing selected: no block, and a record with
//! no block is empty (length 0).

use super::{DiagEntry, DiagnosisStore, Severity, SubslotAddr};
use crate::wire::EmitResult;
use crate::wire::diagnosis::{
    AlarmItem, CHANNEL_NUMBER_SUBMODULE, ChannelProperties, ChannelSpecifier, Diagnosis,
    DiagnosisFormat,
};
use crate::wire::record::{DiagnosisData, INDEX_DEVICE_DIAGNOSIS, RecordVersion};

/// Which submodules a diagnosis record covers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DiagnosisScope {
    /// 0x80xx: the addressed subslot.
    Subslot,
    /// 0xC0xx: the subslots of the addressed slot.
    Slot,
    /// 0xE0xx: the submodules of the AR.
    Ar,
    /// 0xF0xx: the submodules of the addressed API.
    Api,
    /// 0xF80C: every submodule of the device.
    Device,
}

/// Which entries a diagnosis record selects.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Selection {
    /// xx0A: faults in channel coding.
    ChannelFaults,
    /// xx0B: faults in all codings.
    AllFaults,
    /// xx0C: diagnosis, maintenance, qualified and status: everything.
    Everything,
    /// xx10: maintenance required in channel coding.
    ChannelRequired,
    /// xx11: maintenance demanded in channel coding.
    ChannelDemanded,
    /// xx12: maintenance required in all codings.
    AllRequired,
    /// xx13: maintenance demanded in all codings.
    AllDemanded,
}

impl Selection {
    /// Whether the record selects `entry`. The severity must match exactly (the
    /// ChannelProperties.Maintenance coding): a qualified entry is neither a fault nor
    /// maintenance here, whatever its qualifier.
    pub fn selects(self, entry: &DiagEntry) -> bool {
        let channel = matches!(entry, DiagEntry::Channel(_));
        let sev = entry.severity();
        match self {
            Selection::ChannelFaults => channel && sev == Severity::Fault,
            Selection::AllFaults => sev == Severity::Fault,
            Selection::Everything => true,
            Selection::ChannelRequired => channel && sev == Severity::MaintenanceRequired,
            Selection::ChannelDemanded => channel && sev == Severity::MaintenanceDemanded,
            Selection::AllRequired => sev == Severity::MaintenanceRequired,
            Selection::AllDemanded => sev == Severity::MaintenanceDemanded,
        }
    }
}

/// The scope and selection of a diagnosis record index; `None` for other indices.
pub const fn diagnosis_index(index: u16) -> Option<(DiagnosisScope, Selection)> {
    if index == INDEX_DEVICE_DIAGNOSIS {
        return Some((DiagnosisScope::Device, Selection::Everything));
    }
    let scope = match index >> 8 {
        0x80 => DiagnosisScope::Subslot,
        0xc0 => DiagnosisScope::Slot,
        0xe0 => DiagnosisScope::Ar,
        0xf0 => DiagnosisScope::Api,
        _ => return None,
    };
    let selection = match index & 0xff {
        0x0a => Selection::ChannelFaults,
        0x0b => Selection::AllFaults,
        0x0c => Selection::Everything,
        0x10 => Selection::ChannelRequired,
        0x11 => Selection::ChannelDemanded,
        0x12 => Selection::AllRequired,
        0x13 => Selection::AllDemanded,
        _ => return None,
    };
    Some((scope, selection))
}

impl DiagnosisStore {
    /// The blocks of a diagnosis record over the submodules `scope` lists, in its order.
    pub fn record_blocks(
        &self,
        selection: Selection,
        scope: impl IntoIterator<Item = SubslotAddr>,
    ) -> Vec<DiagnosisData> {
        let mut blocks = Vec::new();
        for at in scope {
            let selected: Vec<&DiagEntry> = self
                .entries(at)
                .iter()
                .filter(|e| selection.selects(e))
                .collect();
            let block = |channel_number, channel_properties, item| DiagnosisData {
                version: RecordVersion::V1_1,
                api: at.api,
                slot: at.slot,
                subslot: at.subslot,
                channel_number,
                channel_properties,
                item,
            };
            for format in [
                DiagnosisFormat::Channel,
                DiagnosisFormat::Extended,
                DiagnosisFormat::Qualified,
            ] {
                let of_format: Vec<_> = selected
                    .iter()
                    .filter_map(|e| match e {
                        DiagEntry::Channel(c) if c.format == format => Some(c),
                        _ => None,
                    })
                    .collect();
                if of_format.is_empty() {
                    continue;
                }
                // The block's own properties: type, direction and maintenance 0, the
                // specifier Appears when a fault appears among the entries.
                let fault = of_format.iter().any(|c| c.severity == Severity::Fault);
                let specifier = if fault {
                    ChannelSpecifier::Appears
                } else {
                    ChannelSpecifier::Disappears
                };
                let properties = ChannelProperties(0).with_specifier(specifier);
                let entries = of_format.iter().map(|c| c.wire(c.properties())).collect();
                let item = AlarmItem::Diagnosis(Diagnosis { format, entries });
                blocks.push(block(CHANNEL_NUMBER_SUBMODULE, properties, item));
            }
            for e in &selected {
                if let DiagEntry::Generic(g) = e {
                    let item = AlarmItem::Other {
                        usi: g.usi,
                        data: g.data.clone(),
                    };
                    blocks.push(block(g.channel_number, g.properties(), item));
                }
            }
        }
        blocks
    }

    /// The bytes of a diagnosis record over the submodules `scope` lists (empty when nothing
    /// is selected).
    pub fn record(
        &self,
        selection: Selection,
        scope: impl IntoIterator<Item = SubslotAddr>,
    ) -> EmitResult<Vec<u8>> {
        DiagnosisData::record_to_vec(&self.record_blocks(selection, scope))
    }
}
