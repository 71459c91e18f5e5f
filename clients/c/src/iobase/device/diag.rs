// SPDX-License-Identifier: MIT OR Apache-2.0
//! The program's diagnosis (`PNIO_diag_channel_add`, `PNIO_diag_ext_channel_add`,
//! `PNIO_diag_generic_add` and their `_remove`, `PNIO_build_channel_properties`).
//!
//! An entry goes into procimgd's diagnosis store of the submodule at once, without an
//! alarm: the PLC reads it in the diagnosis records and sees it in the submodule's state;
//! the alarm is the program's `PNIO_diag_alarm_send`, as the manual's sequence has it.
//! The library keeps the DiagTag of each entry; procimgd keys entries by channel, direction
//! and error (a manufacturer entry by its USI), so two tags with the same such key are one
//! entry there, which goes when the last of its tags is removed. A remove of an unknown
//! DiagTag is no error; DiagTag 0 removes all the submodule's entries of the function's
//! kind.

use super::Pos;
pub(crate) use super::held::DiagFn;
use super::held::Entries;
use super::state::{Device, Life};
use crate::iobase::device_types::*;
use crate::iobase::errors::*;
use crate::iobase::sync::lock;
use procimg_client::{
    DiagnosisDirection, DiagnosisEntry, DiagnosisKind, DiagnosisSeverity, StationDiagnosisChange,
};

/// `PNIO_build_channel_properties`: Type in bits 0–7, Specifier in bits 11–12, Direction in
/// bits 13–15 (IEC 61158-6 ChannelProperties).
pub(crate) fn channel_properties(kind: u16, spec: u16, dir: u16) -> u16 {
    (kind & 0xff) | ((spec & 0x3) << 11) | ((dir & 0x7) << 13)
}

/// The entry of a channel (`ext`: with ExtChannelErrorType and ExtChannelAddValue) from the
/// manual's arguments.
pub(crate) fn channel_entry(
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
        severity: if u32::from(properties) & PNIO_CHAN_PROP_MAINT_DEMANDED_BIT != 0 {
            DiagnosisSeverity::MaintenanceDemanded
        } else if u32::from(properties) & PNIO_CHAN_PROP_MAINT_REQUIRED_BIT != 0 {
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
pub(crate) fn generic_entry(usi: u16, data: &[u8]) -> DiagnosisEntry {
    DiagnosisEntry {
        kind: DiagnosisKind::Manufacturer,
        usi,
        data: data.to_vec(),
        ..DiagnosisEntry::default()
    }
}

/// Where the program's submodule at `at` is, checked that the device may take diagnosis.
fn submodule(f: &str, dev: &Device, at: Pos) -> Result<(), u32> {
    let c = lock(&dev.config);
    if matches!(c.life, Life::Stopping | Life::Stopped) {
        return Err(fail(
            f,
            PNIO_ERR_SEQUENCE,
            format_args!("the device is {}", c.life.name()),
        ));
    }
    if !c.subs.contains_key(&at) {
        return Err(fail(
            f,
            PNIO_ERR_PRM_ADD,
            format_args!(
                "the program has no submodule plugged at API {} slot {} subslot {:#06x}",
                at.0, at.1, at.2
            ),
        ));
    }
    Ok(())
}

/// Adds the program's entry with `tag` to the submodule at `at`.
pub(crate) fn add(
    f: &str,
    dev: &Device,
    at: Pos,
    tag: u16,
    kind: DiagFn,
    entry: DiagnosisEntry,
) -> u32 {
    if tag == 0 {
        return fail(
            f,
            PNIO_ERR_PRM_INVALIDARG,
            "DiagTag 0 is not a tag: give 1 to 0xFFFF",
        );
    }
    if let Err(code) = submodule(f, dev, at) {
        return code;
    }
    let change = StationDiagnosisChange::Add {
        api: at.0,
        slot: at.1,
        subslot: at.2,
        entry: entry.clone(),
    };
    let mut entries = lock(&dev.diag);
    // A tag given again replaces its entry.
    if let Some((_, old)) = entries.get(&(at, tag)).cloned()
        && let Err(code) = forget(f, dev, &mut entries, at, tag, &old)
    {
        return code;
    }
    match lock(&dev.services).keep_diagnosis(change) {
        Ok(()) => {
            entries.insert((at, tag), (kind, entry));
            PNIO_OK
        }
        Err(e) => fail(f, PNIO_ERR_PRM_ADD, format_args!("{e}")),
    }
}

/// Removes the program's entry with `tag` (0: all of `kind`) from the submodule at `at`.
pub(crate) fn remove(f: &str, dev: &Device, at: Pos, tag: u16, kind: DiagFn) -> u32 {
    if let Err(code) = submodule(f, dev, at) {
        return code;
    }
    let mut entries = lock(&dev.diag);
    let tags: Vec<(u16, DiagnosisEntry)> = entries
        .iter()
        .filter(|((p, t), (k, _))| *p == at && *k == kind && (tag == 0 || *t == tag))
        .map(|((_, t), (_, e))| (*t, e.clone()))
        .collect();
    for (t, e) in tags {
        if let Err(code) = forget(f, dev, &mut entries, at, t, &e) {
            return code;
        }
    }
    PNIO_OK
}

/// Drops tag `tag`'s entry `entry`; procimgd removes it when no other tag holds it.
fn forget(
    f: &str,
    dev: &Device,
    entries: &mut Entries,
    at: Pos,
    tag: u16,
    entry: &DiagnosisEntry,
) -> Result<(), u32> {
    entries.remove(&(at, tag));
    if entries
        .iter()
        .any(|((p, _), (_, e))| *p == at && e == entry)
    {
        return Ok(());
    }
    let change = StationDiagnosisChange::Remove {
        api: at.0,
        slot: at.1,
        subslot: at.2,
        entry: entry.clone(),
    };
    lock(&dev.services)
        .keep_diagnosis(change)
        .map_err(|e| fail(f, PNIO_ERR_INTERNAL, format_args!("{e}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn channel_properties_are_packed_as_the_standard_says() {
        let p = channel_properties(
            PNIO_DIAG_CHANPROP_TYPE_SUBMOD as u16,
            PNIO_DIAG_CHAN_SPEC_ERROR_APPEARS as u16,
            PNIO_DIAG_CHAN_DIRECTION_MANUFACTURE as u16,
        );
        assert_eq!(p, 0x0800);
        let p = channel_properties(
            PNIO_DIAG_CHANPROP_TYPE_BYTE as u16,
            PNIO_DIAG_CHAN_SPEC_ERROR_DISAPP_FREE as u16,
            PNIO_DIAG_CHAN_DIRECTION_OUTPUT as u16,
        );
        assert_eq!(p, 0x04 | (2 << 11) | (2 << 13));
        let e = channel_entry(3, p | PNIO_CHAN_PROP_MAINT_REQUIRED_BIT as u16, 6, None);
        assert_eq!((e.channel, e.error_type, e.data_type), (3, 6, 4));
        assert_eq!(e.direction, DiagnosisDirection::Output);
        assert_eq!(e.severity, DiagnosisSeverity::MaintenanceRequired);
        assert_eq!(
            channel_entry(1, 0, 1, Some((2, 3))).kind,
            DiagnosisKind::Extended
        );
    }
}
