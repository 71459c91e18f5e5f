// SPDX-License-Identifier: MIT OR Apache-2.0
//! The program's diagnosis entries by DiagTag, as IO-Base's `PNIO_diag_channel_add`,
//! `PNIO_diag_ext_channel_add`, `PNIO_diag_generic_add` and their removes have them.
//!
//! An entry goes into procimgd's diagnosis store of the submodule at once, without an
//! alarm: the PLC reads it in the diagnosis records and sees it in the submodule's state;
//! the alarm is the program's to send, as the manual's sequence has it. procimgd keys
//! entries by channel, direction and error (a manufacturer entry by its USI), so two tags
//! with the same such key are one entry there, which goes when the last of its tags is
//! removed. A tag given again replaces its entry. A remove of an unknown DiagTag is no
//! error; DiagTag 0 removes all the submodule's entries of the add function's kind.

use crate::error::ControlError;
use crate::services::Services;
use procimg_control::{
    DiagnosisDirection, DiagnosisEntry, DiagnosisKind, DiagnosisSeverity, StationDiagnosisChange,
};
use std::collections::BTreeMap;

/// API, slot, subslot.
pub type Position = (u32, u16, u16);

/// ChannelProperties' bit of a maintenance-required entry.
pub const CHAN_PROP_MAINT_REQUIRED: u16 = 0x0200;
/// ChannelProperties' bit of a maintenance-demanded entry.
pub const CHAN_PROP_MAINT_DEMANDED: u16 = 0x0400;

/// The kinds of entries, one per add function; a remove with DiagTag 0 takes one kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DiagTagKind {
    /// `PNIO_diag_channel_add`.
    Channel,
    /// `PNIO_diag_ext_channel_add`.
    ExtChannel,
    /// `PNIO_diag_generic_add`.
    Generic,
}

/// Why a diagnosis call failed.
#[derive(Debug, thiserror::Error)]
pub enum DiagTagError {
    /// DiagTag 0 names no entry on an add.
    #[error("DiagTag 0 is not a tag: give 1 to 0xFFFF")]
    TagZero,
    /// procimgd did not take the entry.
    #[error("procimgd did not take the diagnosis entry: {0}")]
    Refused(ControlError),
    /// procimgd did not remove the entry.
    #[error("procimgd did not remove the diagnosis entry: {0}")]
    NotRemoved(ControlError),
}

/// ChannelProperties (IEC 61158-6): Type in bits 0–7, Specifier in bits 11–12, Direction in
/// bits 13–15 (`PNIO_build_channel_properties`).
pub fn channel_properties(kind: u16, specifier: u16, direction: u16) -> u16 {
    (kind & 0xff) | ((specifier & 0x3) << 11) | ((direction & 0x7) << 13)
}

/// The entry of a channel (`ext`: with ExtChannelErrorType and ExtChannelAddValue) from
/// the manual's arguments.
pub fn channel_entry(
    channel: u16,
    properties: u16,
    error_type: u16,
    ext: Option<(u16, u32)>,
) -> DiagnosisEntry {
    let (ext_error_type, ext_add_value) = ext.unwrap_or((0, 0));
    DiagnosisEntry {
        kind: if ext.is_some() {
            DiagnosisKind::Extended
        } else {
            DiagnosisKind::Channel
        },
        channel,
        error_type,
        ext_error_type,
        ext_add_value,
        direction: match properties >> 13 {
            1 => DiagnosisDirection::Input,
            2 => DiagnosisDirection::Output,
            3 => DiagnosisDirection::InputOutput,
            _ => DiagnosisDirection::Manufacturer,
        },
        severity: if properties & CHAN_PROP_MAINT_DEMANDED != 0 {
            DiagnosisSeverity::MaintenanceDemanded
        } else if properties & CHAN_PROP_MAINT_REQUIRED != 0 {
            DiagnosisSeverity::MaintenanceRequired
        } else {
            DiagnosisSeverity::Fault
        },
        data_type: (properties & 0xff) as u8,
        accumulative: properties & 0x0100 != 0,
        ..DiagnosisEntry::default()
    }
}

/// The entry of a manufacturer diagnosis.
pub fn generic_entry(usi: u16, data: &[u8]) -> DiagnosisEntry {
    DiagnosisEntry {
        kind: DiagnosisKind::Manufacturer,
        usi,
        data: data.to_vec(),
        ..DiagnosisEntry::default()
    }
}

/// Adds `entry` to procimgd's store of the submodule at `at`, or removes it.
fn keep(
    services: &Services,
    add: bool,
    at: Position,
    entry: &DiagnosisEntry,
) -> Result<(), ControlError> {
    let (api, slot, subslot, entry) = (at.0, at.1, at.2, entry.clone());
    services.keep_diagnosis(if add {
        StationDiagnosisChange::Add {
            api,
            slot,
            subslot,
            entry,
        }
    } else {
        StationDiagnosisChange::Remove {
            api,
            slot,
            subslot,
            entry,
        }
    })
}

/// The program's entries: (submodule, DiagTag) → their kind and the entry.
#[derive(Debug, Default)]
pub struct DiagTags {
    entries: BTreeMap<(Position, u16), (DiagTagKind, DiagnosisEntry)>,
}

impl DiagTags {
    /// Adds the entry with `tag` to the submodule at `at` in procimgd's store.
    pub fn add(
        &mut self,
        services: &Services,
        at: Position,
        tag: u16,
        kind: DiagTagKind,
        entry: DiagnosisEntry,
    ) -> Result<(), DiagTagError> {
        if tag == 0 {
            return Err(DiagTagError::TagZero);
        }
        if let Some((_, old)) = self.entries.get(&(at, tag)).cloned() {
            self.forget(services, at, tag, &old)?;
        }
        keep(services, true, at, &entry).map_err(DiagTagError::Refused)?;
        self.entries.insert((at, tag), (kind, entry));
        Ok(())
    }

    /// Removes the entry with `tag` (0: every entry of `kind`) from the submodule at `at`.
    pub fn remove(
        &mut self,
        services: &Services,
        at: Position,
        tag: u16,
        kind: DiagTagKind,
    ) -> Result<(), DiagTagError> {
        let tags: Vec<(u16, DiagnosisEntry)> = self
            .entries
            .iter()
            .filter(|((p, t), (k, _))| *p == at && *k == kind && (tag == 0 || *t == tag))
            .map(|((_, t), (_, e))| (*t, e.clone()))
            .collect();
        for (t, e) in tags {
            self.forget(services, at, t, &e)?;
        }
        Ok(())
    }

    /// The tags the submodule at `at` has entries under.
    pub fn tags(&self, at: Position) -> impl Iterator<Item = u16> + '_ {
        self.entries
            .keys()
            .filter(move |(p, _)| *p == at)
            .map(|(_, t)| *t)
    }

    /// Drops `tag`'s entry; procimgd removes it when no other tag holds it.
    fn forget(
        &mut self,
        services: &Services,
        at: Position,
        tag: u16,
        entry: &DiagnosisEntry,
    ) -> Result<(), DiagTagError> {
        self.entries.remove(&(at, tag));
        if self.held(at, entry) {
            return Ok(());
        }
        keep(services, false, at, entry).map_err(DiagTagError::NotRemoved)
    }

    /// Whether another tag holds `entry` at `at`.
    fn held(&self, at: Position, entry: &DiagnosisEntry) -> bool {
        self.entries
            .iter()
            .any(|((p, _), (_, e))| *p == at && e == entry)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn channel_properties_are_packed_as_the_standard_says() {
        // Submodule type, error appears, manufacturer direction.
        assert_eq!(channel_properties(0, 1, 0), 0x0800);
        // Byte, disappears (error free), output.
        let p = channel_properties(4, 2, 2);
        assert_eq!(p, 0x04 | (2 << 11) | (2 << 13));
        let e = channel_entry(3, p | CHAN_PROP_MAINT_REQUIRED, 6, None);
        assert_eq!((e.channel, e.error_type, e.data_type), (3, 6, 4));
        assert_eq!(e.direction, DiagnosisDirection::Output);
        assert_eq!(e.severity, DiagnosisSeverity::MaintenanceRequired);
        assert_eq!(
            channel_entry(1, 0, 1, Some((2, 3))).kind,
            DiagnosisKind::Extended
        );
        assert_eq!(generic_entry(0x10, &[1]).kind, DiagnosisKind::Manufacturer);
    }

    #[test]
    fn an_entry_two_tags_hold_is_held_until_the_last_goes() {
        let mut d = DiagTags::default();
        let at = (0, 1, 1);
        let e = channel_entry(0, 0, 6, None);
        d.entries.insert((at, 1), (DiagTagKind::Channel, e.clone()));
        d.entries.insert((at, 2), (DiagTagKind::Channel, e.clone()));
        d.entries.remove(&(at, 1));
        assert!(d.held(at, &e));
        assert!(
            !d.held((0, 2, 1), &e),
            "another submodule's entry is its own"
        );
        assert_eq!(d.tags(at).collect::<Vec<_>>(), [2]);
    }
}
