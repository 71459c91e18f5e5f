// SPDX-License-Identifier: MIT OR Apache-2.0
//! Diagnosis from clients: the control protocol's [`StationDiagnosisChange`] in the device
//! engine's terms, and carried out on it (the store changes, the PLC gets the alarm).

use procimg_control::{
    DiagnosisDirection, DiagnosisEntry, DiagnosisKind, DiagnosisSeverity, StationDiagnosisChange,
};
use procimg_profinet::device::{
    Application, ChannelDiag, Device, DeviceAction, DiagEntry, DiagnosisEdit, GenericDiag,
    Severity, SubslotAddr,
};
use procimg_profinet::wire::alarm::{ChannelDirection, DiagnosisFormat};

/// `entry` as the engine takes it.
pub fn entry(e: &DiagnosisEntry) -> Result<DiagEntry, String> {
    if e.kind == DiagnosisKind::Manufacturer {
        if e.usi > 0x7FFF {
            return Err(format!(
                "USI {:#06x} is not manufacturer specific; give 0x0000 to 0x7FFF",
                e.usi
            ));
        }
        return Ok(DiagEntry::Generic(GenericDiag::new(e.usi, &e.data)));
    }
    let base = ChannelDiag::new(e.channel, e.error_type);
    let channel = match e.kind {
        DiagnosisKind::Extended => {
            ChannelDiag::extended(e.channel, e.error_type, e.ext_error_type, e.ext_add_value)
        }
        DiagnosisKind::Qualified => ChannelDiag::qualified(
            e.channel,
            e.error_type,
            e.ext_error_type,
            e.ext_add_value,
            e.qualifier,
        ),
        _ => base,
    };
    let direction = match e.direction {
        DiagnosisDirection::Manufacturer => ChannelDirection::Manufacturer,
        DiagnosisDirection::Input => ChannelDirection::Input,
        DiagnosisDirection::Output => ChannelDirection::Output,
        DiagnosisDirection::InputOutput => ChannelDirection::InputOutput,
    };
    let mut channel = channel
        .with_direction(direction)
        .with_data_type(e.data_type)
        .with_accumulative(e.accumulative);
    if channel.format != DiagnosisFormat::Qualified {
        channel = channel.with_severity(match e.severity {
            DiagnosisSeverity::Fault => Severity::Fault,
            DiagnosisSeverity::MaintenanceRequired => Severity::MaintenanceRequired,
            DiagnosisSeverity::MaintenanceDemanded => Severity::MaintenanceDemanded,
        });
    }
    Ok(DiagEntry::Channel(channel))
}

/// `e` as clients give it and the status report shows it: [`entry`]'s inverse.
pub fn reported(e: &DiagEntry) -> DiagnosisEntry {
    let direction = |d: ChannelDirection| match d {
        ChannelDirection::Input => DiagnosisDirection::Input,
        ChannelDirection::Output => DiagnosisDirection::Output,
        ChannelDirection::InputOutput => DiagnosisDirection::InputOutput,
        _ => DiagnosisDirection::Manufacturer,
    };
    match e {
        DiagEntry::Generic(g) => DiagnosisEntry {
            kind: DiagnosisKind::Manufacturer,
            usi: g.usi,
            data: g.data.clone(),
            channel: g.channel_number,
            direction: direction(g.direction),
            ..DiagnosisEntry::default()
        },
        DiagEntry::Channel(c) => {
            let (severity, qualifier) = match c.severity {
                Severity::Fault => (DiagnosisSeverity::Fault, 0),
                Severity::MaintenanceRequired => (DiagnosisSeverity::MaintenanceRequired, 0),
                Severity::MaintenanceDemanded => (DiagnosisSeverity::MaintenanceDemanded, 0),
                Severity::Qualified(q) => (DiagnosisSeverity::Fault, q),
            };
            DiagnosisEntry {
                kind: match c.format {
                    DiagnosisFormat::Extended => DiagnosisKind::Extended,
                    DiagnosisFormat::Qualified => DiagnosisKind::Qualified,
                    DiagnosisFormat::Channel => DiagnosisKind::Channel,
                },
                channel: c.channel_number,
                error_type: c.error_type,
                ext_error_type: c.ext_error_type,
                ext_add_value: c.ext_add_value,
                qualifier,
                direction: direction(c.direction),
                severity,
                data_type: c.data_type,
                accumulative: c.accumulative,
                usi: 0,
                data: Vec::new(),
            }
        }
    }
}

/// Carries out `change` on `device`: what it sends goes to `out`; `Err` says why the change
/// was refused.
pub fn apply<A: Application>(
    device: &mut Device<A>,
    change: &StationDiagnosisChange,
    now_ns: u64,
    out: &mut Vec<DeviceAction>,
) -> Result<(), String> {
    let result = match change {
        StationDiagnosisChange::Add {
            api,
            slot,
            subslot,
            entry: e,
        } => device.add_diagnosis(*api, *slot, *subslot, entry(e)?, now_ns, out),
        StationDiagnosisChange::Remove {
            api,
            slot,
            subslot,
            entry: e,
        } => device.remove_diagnosis(*api, *slot, *subslot, &entry(e)?.key(), now_ns, out),
        StationDiagnosisChange::Clear { api, slot, subslot } => {
            device.clear_diagnosis(*api, *slot, *subslot, now_ns, out)
        }
    };
    match result {
        Ok(c) if c.alarms_too_long > 0 => Err(format!(
            "the diagnosis changed, but {} alarm(s) were longer than the AR allows and not \
             sent; shorten the manufacturer data",
            c.alarms_too_long
        )),
        Ok(_) => Ok(()),
        Err(e) => Err(e.to_string()),
    }
}

/// Carries out `change` on `device`'s store only, without an alarm (the client sends its
/// own); `Err` says why the change was refused.
pub fn keep<A: Application>(
    device: &mut Device<A>,
    change: &StationDiagnosisChange,
) -> Result<(), String> {
    let (api, slot, subslot) = change.submodule();
    let edit = match change {
        StationDiagnosisChange::Add { entry: e, .. } => DiagnosisEdit::Add(entry(e)?),
        StationDiagnosisChange::Remove { entry: e, .. } => DiagnosisEdit::Remove(entry(e)?.key()),
        StationDiagnosisChange::Clear { .. } => DiagnosisEdit::Clear,
    };
    let at = SubslotAddr::new(api, slot, subslot);
    device
        .keep_diagnosis(at, edit)
        .map(|_| ())
        .map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn entries_in_the_engines_terms() {
        let e = DiagnosisEntry {
            channel: 3,
            error_type: 6,
            direction: DiagnosisDirection::Output,
            severity: DiagnosisSeverity::MaintenanceRequired,
            ..DiagnosisEntry::default()
        };
        let DiagEntry::Channel(c) = entry(&e).unwrap() else {
            panic!("a channel entry");
        };
        assert_eq!((c.channel_number, c.error_type), (3, 6));
        assert_eq!(c.direction, ChannelDirection::Output);
        assert_eq!(c.severity, Severity::MaintenanceRequired);
        assert_eq!(c.format, DiagnosisFormat::Channel);
        let m = DiagnosisEntry {
            kind: DiagnosisKind::Manufacturer,
            usi: 0x8000,
            ..DiagnosisEntry::default()
        };
        assert!(entry(&m).is_err());
    }

    #[test]
    fn a_reported_entry_is_the_entry_that_was_given() {
        let given = [
            DiagnosisEntry {
                channel: 1,
                error_type: 6,
                direction: DiagnosisDirection::Input,
                data_type: 1,
                ..DiagnosisEntry::default()
            },
            DiagnosisEntry {
                kind: DiagnosisKind::Extended,
                channel: 0x8000,
                error_type: 2,
                ext_error_type: 0x8000,
                ext_add_value: 7,
                severity: DiagnosisSeverity::MaintenanceDemanded,
                accumulative: true,
                ..DiagnosisEntry::default()
            },
            DiagnosisEntry {
                kind: DiagnosisKind::Qualified,
                channel: 4,
                error_type: 9,
                qualifier: 1 << 27,
                direction: DiagnosisDirection::InputOutput,
                ..DiagnosisEntry::default()
            },
            DiagnosisEntry {
                kind: DiagnosisKind::Manufacturer,
                usi: 0x1234,
                data: vec![1, 2, 3],
                ..DiagnosisEntry::default()
            },
        ];
        for e in given {
            assert_eq!(reported(&entry(&e).unwrap()), e);
        }
    }
}
