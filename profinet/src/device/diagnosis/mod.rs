// SPDX-License-Identifier: MIT OR Apache-2.0
//! The device's diagnosis: per submodule, the pending entries (channel, extended channel,
//! qualified channel and manufacturer-specific), what each change means as a diagnosis
//! alarm, the records that read them back ([`records`]) and the states derived from them.
//!
//! The store holds only what is pending ("appears"). Adding an entry that is already there
//! with other values (severity, ExtChannelAddValue, manufacturer data) updates it; removing
//! one, or clearing a submodule, makes it disappear. Every change yields the alarms that
//! announce it, which the device sends on the AR's low-priority alarm channel, as p-net does:
//!
//! - an entry appears: AlarmType Diagnosis, its item with specifier Appears;
//! - a channel entry is updated: Diagnosis with the new entry (Appears), then Diagnosis with
//!   the old one (DisappearsOthersRemain: the new one remains);
//! - a channel entry is removed: Diagnosis with the entry and specifier
//!   DisappearsOthersRemain when other entries of its channel remain, AllDisappear (with the
//!   maintenance bits cleared, as that specifier requires) when the submodule has none left,
//!   Disappears otherwise;
//! - a manufacturer entry is removed: DiagnosisDisappears with its USI and no data (its data
//!   has no specifier to say it disappears, so the alarm type says it);
//! - a submodule is cleared: one DiagnosisDisappears without an item, which the standard
//!   allows to say that everything disappeared.
//!
//! The AlarmSpecifier describes the submodule after the change: ChannelDiagnosis when a
//! channel entry is pending, ManufacturerSpecificDiagnosis when a manufacturer entry is,
//! SubmoduleDiagnosisState when a fault is; ARDiagnosisState (a fault on any submodule of the
//! AR) is the device's to set. A maintenance or qualified entry's alarm carries a
//! MaintenanceItem with the submodule's maintenance status after the change. The captured
//! p-net alarms (tests) come out byte for byte.

mod entry;
pub mod records;
#[cfg(test)]
mod tests;

pub use entry::{
    ChannelDiag, DiagEntry, DiagKey, DiagnosisError, GenericDiag, MAX_ENTRIES_PER_SUBMODULE,
    MAX_GENERIC_DATA, Severity, SubslotAddr,
};

use crate::wire::alarm::{AlarmNotification, AlarmSpecifier, AlarmType, MaintenanceItem, Priority};
use crate::wire::connect::SubmoduleState;
use crate::wire::diagnosis::{AlarmItem, ChannelSpecifier, Diagnosis};
use std::collections::BTreeMap;

/// A diagnosis alarm to send: everything of its AlarmNotification but what the device adds
/// (the idents, the sequence number and ARDiagnosisState).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct DiagnosisAlarm {
    /// The submodule.
    pub at: SubslotAddr,
    /// Diagnosis or DiagnosisDisappears.
    pub alarm_type: AlarmType,
    /// The submodule's state after the change (sequence number 0, ARDiagnosisState clear).
    pub specifier: AlarmSpecifier,
    /// The maintenance status, for a maintenance or qualified entry.
    pub maintenance: Option<MaintenanceItem>,
    /// The entry (none when a whole submodule was cleared).
    pub item: Option<AlarmItem>,
}

impl DiagnosisAlarm {
    /// The AlarmNotification (low priority, as diagnosis alarms go).
    pub fn notification(
        &self,
        module_ident: u32,
        submodule_ident: u32,
        sequence_number: u16,
        ar_diagnosis: bool,
    ) -> AlarmNotification {
        AlarmNotification {
            priority: Priority::Low,
            alarm_type: self.alarm_type,
            api: self.at.api,
            slot: self.at.slot,
            subslot: self.at.subslot,
            module_ident,
            submodule_ident,
            specifier: AlarmSpecifier {
                sequence_number,
                ar_diagnosis,
                ..self.specifier
            },
            maintenance: self.maintenance,
            item: self.item.clone(),
        }
    }
}

/// The pending diagnosis of every submodule.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct DiagnosisStore {
    subslots: BTreeMap<SubslotAddr, Vec<DiagEntry>>,
}

impl DiagnosisStore {
    /// An empty store.
    pub fn new() -> DiagnosisStore {
        DiagnosisStore::default()
    }

    /// The pending entries of a submodule, oldest first.
    pub fn entries(&self, at: SubslotAddr) -> &[DiagEntry] {
        self.subslots.get(&at).map_or(&[], Vec::as_slice)
    }

    /// Every submodule with pending entries, in (API, slot, subslot) order.
    pub fn iter(&self) -> impl Iterator<Item = (SubslotAddr, &[DiagEntry])> {
        self.subslots.iter().map(|(a, e)| (*a, e.as_slice()))
    }

    /// Whether nothing is pending anywhere.
    pub fn is_empty(&self) -> bool {
        self.subslots.is_empty()
    }

    /// Adds an entry, or updates the one with the same [`key`](DiagEntry::key): the alarms
    /// that announce the change, in order (none when the same entry was pending already).
    pub fn add(
        &mut self,
        at: SubslotAddr,
        entry: DiagEntry,
    ) -> Result<Vec<DiagnosisAlarm>, DiagnosisError> {
        entry.validate()?;
        let key = entry.key();
        let list = self.subslots.entry(at).or_default();
        let old = match list.iter().position(|e| e.key() == key) {
            Some(i) if list[i] == entry => return Ok(Vec::new()),
            Some(i) => Some(core::mem::replace(&mut list[i], entry.clone())),
            None if list.len() >= MAX_ENTRIES_PER_SUBMODULE => {
                return Err(DiagnosisError::TooManyEntries(at));
            }
            None => {
                list.push(entry.clone());
                None
            }
        };
        let mut alarms = vec![self.alarm(at, &entry, ChannelSpecifier::Appears)];
        // The old values of a channel entry disappear while the new ones remain; a
        // manufacturer entry's new data simply replaces the old (p-net does the same).
        if let Some(DiagEntry::Channel(c)) = old {
            let item = Some(channel_item(&c, ChannelSpecifier::DisappearsOthersRemain));
            alarms.push(self.alarm_with(at, AlarmType::Diagnosis, c.severity, item));
        }
        Ok(alarms)
    }

    /// Removes the entry with `key`: the alarm that announces it, none when no such entry is
    /// pending.
    pub fn remove(&mut self, at: SubslotAddr, key: &DiagKey) -> Vec<DiagnosisAlarm> {
        let Some(list) = self.subslots.get_mut(&at) else {
            return Vec::new();
        };
        let Some(i) = list.iter().position(|e| e.key() == *key) else {
            return Vec::new();
        };
        let old = list.remove(i);
        if list.is_empty() {
            self.subslots.remove(&at);
        }
        let remaining = self.entries(at);
        let alarm = match &old {
            DiagEntry::Channel(c) => {
                let same_channel = remaining.iter().any(|e| match e {
                    DiagEntry::Channel(o) => {
                        (o.channel_number, o.direction) == (c.channel_number, c.direction)
                    }
                    DiagEntry::Generic(_) => false,
                });
                let specifier = if same_channel {
                    ChannelSpecifier::DisappearsOthersRemain
                } else if remaining.is_empty() {
                    ChannelSpecifier::AllDisappear
                } else {
                    ChannelSpecifier::Disappears
                };
                self.alarm(at, &old, specifier)
            }
            DiagEntry::Generic(g) => {
                let item = Some(AlarmItem::Other {
                    usi: g.usi,
                    data: Vec::new(),
                });
                self.alarm_with(at, AlarmType::DiagnosisDisappears, g.severity, item)
            }
        };
        vec![alarm]
    }

    /// Removes every entry of a submodule: one DiagnosisDisappears without an item, none when
    /// nothing was pending.
    pub fn clear(&mut self, at: SubslotAddr) -> Vec<DiagnosisAlarm> {
        if self.subslots.remove(&at).is_none() {
            return Vec::new();
        }
        vec![DiagnosisAlarm {
            at,
            alarm_type: AlarmType::DiagnosisDisappears,
            specifier: AlarmSpecifier::default(),
            maintenance: None,
            item: None,
        }]
    }

    /// Removes the entries of submodules `keep` says no to (pulled ones), without alarms.
    pub fn retain(&mut self, mut keep: impl FnMut(SubslotAddr) -> bool) {
        self.subslots.retain(|a, _| keep(*a));
    }

    /// The alarm announcing `entry` with `specifier` (its channel entry's specifier; a
    /// manufacturer entry appears).
    fn alarm(
        &self,
        at: SubslotAddr,
        entry: &DiagEntry,
        specifier: ChannelSpecifier,
    ) -> DiagnosisAlarm {
        let item = match entry {
            DiagEntry::Channel(c) => channel_item(c, specifier),
            DiagEntry::Generic(g) => AlarmItem::Other {
                usi: g.usi,
                data: g.data.clone(),
            },
        };
        self.alarm_with(at, AlarmType::Diagnosis, entry.severity(), Some(item))
    }

    fn alarm_with(
        &self,
        at: SubslotAddr,
        alarm_type: AlarmType,
        severity: Severity,
        item: Option<AlarmItem>,
    ) -> DiagnosisAlarm {
        let maintenance = (severity != Severity::Fault).then(|| MaintenanceItem {
            status: self.maintenance_status(at),
        });
        DiagnosisAlarm {
            at,
            alarm_type,
            specifier: self.specifier(at),
            maintenance,
            item,
        }
    }

    /// The AlarmSpecifier flags of a submodule's state (sequence number 0, ARDiagnosisState
    /// clear).
    pub fn specifier(&self, at: SubslotAddr) -> AlarmSpecifier {
        let entries = self.entries(at);
        AlarmSpecifier {
            sequence_number: 0,
            channel_diagnosis: entries.iter().any(|e| matches!(e, DiagEntry::Channel(_))),
            manufacturer_diagnosis: entries.iter().any(|e| matches!(e, DiagEntry::Generic(_))),
            submodule_diagnosis: self.has_fault_at(at),
            ar_diagnosis: false,
        }
    }

    /// The MaintenanceStatus of a submodule: bit 0 maintenance required, bit 1 demanded, and
    /// the qualifier bits of its qualified entries.
    pub fn maintenance_status(&self, at: SubslotAddr) -> u32 {
        self.entries(at)
            .iter()
            .fold(0, |s, e| s | e.severity().maintenance_status())
    }

    /// The diagnosis bits of a submodule's SubmoduleState: QualifiedInfo (bit 3),
    /// MaintenanceRequired (4), MaintenanceDemanded (5), DiagInfo (6, a fault).
    pub fn submodule_state(&self, at: SubslotAddr) -> u16 {
        self.entries(at).iter().fold(0, |s, e| {
            let sev = e.severity();
            let bit = |set: bool, b: u16| if set { b } else { 0 };
            s | bit(
                matches!(sev, Severity::Qualified(_)),
                SubmoduleState::QUALIFIED_INFO,
            ) | bit(
                sev.requires_maintenance(),
                SubmoduleState::MAINTENANCE_REQUIRED,
            ) | bit(
                sev.demands_maintenance(),
                SubmoduleState::MAINTENANCE_DEMANDED,
            ) | bit(sev.is_fault(), SubmoduleState::DIAG_INFO)
        })
    }

    /// Whether a fault is pending on a submodule.
    pub fn has_fault_at(&self, at: SubslotAddr) -> bool {
        self.entries(at).iter().any(|e| e.severity().is_fault())
    }

    /// Whether a fault is pending anywhere: the station problem of the DataStatus.
    pub fn has_fault(&self) -> bool {
        self.subslots
            .values()
            .flatten()
            .any(|e| e.severity().is_fault())
    }
}

/// The alarm item of a channel entry with `specifier`: AllDisappear goes with the maintenance
/// bits clear, as the standard's combinations of ChannelProperties require.
fn channel_item(c: &ChannelDiag, specifier: ChannelSpecifier) -> AlarmItem {
    let mut properties = c.properties().with_specifier(specifier);
    if specifier == ChannelSpecifier::AllDisappear {
        properties = properties.with_maintenance(false, false);
    }
    AlarmItem::Diagnosis(Diagnosis {
        format: c.format,
        entries: vec![c.wire(properties)],
    })
}
