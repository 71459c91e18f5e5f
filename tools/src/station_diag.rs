// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg diag` in the device role: the station's own diagnosis, as the PLC reads it in the
//! diagnosis records (0x800A and the others) and was told by alarms.

use crate::text::hex;
use procimg_control::{
    DiagnosisDirection, DiagnosisEntry, DiagnosisKind, DiagnosisSeverity, StationReport,
};
use procimg_profinet::wire::diagnosis::{CHANNEL_NUMBER_SUBMODULE, channel_error_text};

/// Prints the station's diagnosis, in text or JSON.
pub fn print(station: &StationReport, json: bool) -> anyhow::Result<()> {
    if json {
        let doc = serde_json::json!({
            "station": station.name,
            "ar": station.ar,
            "station_problem": station.station_problem,
            "diagnosis": station.diagnosis,
            "alarms_acknowledged": station.alarms_acknowledged,
        });
        println!("{}", serde_json::to_string_pretty(&doc)?);
        return Ok(());
    }
    let ar = match &station.ar {
        Some(ar) => format!(
            "AR {} with PLC \"{}\" ({})",
            crate::status::ar_words(ar.state),
            ar.controller_name,
            ar.controller_mac
        ),
        None => "no AR".to_owned(),
    };
    println!(
        "station \"{}\": {ar}; station problem indicator {}",
        station.name,
        if station.station_problem { "on" } else { "off" }
    );
    if station.diagnosis.is_empty() {
        println!("no diagnosis pending");
    }
    for d in &station.diagnosis {
        println!(
            "API {} slot {} subslot {:#06x}: {}",
            d.api,
            d.slot,
            d.subslot,
            entry_text(&d.entry)
        );
    }
    println!(
        "alarms acknowledged by the PLC {}",
        station.alarms_acknowledged
    );
    Ok(())
}

/// One entry in words: severity, channel and direction, the error.
pub fn entry_text(e: &DiagnosisEntry) -> String {
    let channel = if e.channel == CHANNEL_NUMBER_SUBMODULE {
        "the whole submodule".to_owned()
    } else {
        format!("channel {}", e.channel)
    };
    let direction = match e.direction {
        DiagnosisDirection::Input => " (input)",
        DiagnosisDirection::Output => " (output)",
        DiagnosisDirection::InputOutput => " (input/output)",
        DiagnosisDirection::Manufacturer => "",
    };
    if e.kind == DiagnosisKind::Manufacturer {
        return format!(
            "manufacturer diagnosis USI {:#06x}, {channel}{direction}: {}",
            e.usi,
            if e.data.is_empty() {
                "no data".to_owned()
            } else {
                hex(&e.data)
            }
        );
    }
    let severity = match (e.kind, e.severity) {
        (DiagnosisKind::Qualified, _) => format!("qualifier {:#010x}", e.qualifier),
        (_, DiagnosisSeverity::Fault) => "fault".to_owned(),
        (_, DiagnosisSeverity::MaintenanceRequired) => "maintenance required".to_owned(),
        (_, DiagnosisSeverity::MaintenanceDemanded) => "maintenance demanded".to_owned(),
    };
    let error = channel_error_text(e.error_type).map_or_else(
        || format!("ChannelErrorType {:#06x}", e.error_type),
        |t| format!("{t} (ChannelErrorType {:#06x})", e.error_type),
    );
    let extended = if e.kind == DiagnosisKind::Channel {
        String::new()
    } else {
        format!(
            ", ExtChannelErrorType {:#06x}, ExtChannelAddValue {}",
            e.ext_error_type, e.ext_add_value
        )
    };
    format!("{severity}, {channel}{direction}: {error}{extended}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_entry_says_severity_channel_and_error() {
        let e = DiagnosisEntry {
            channel: 1,
            error_type: 6,
            direction: DiagnosisDirection::Output,
            ..DiagnosisEntry::default()
        };
        assert_eq!(
            entry_text(&e),
            "fault, channel 1 (output): wire break (ChannelErrorType 0x0006)"
        );
        let m = DiagnosisEntry {
            kind: DiagnosisKind::Manufacturer,
            usi: 0x0042,
            data: vec![0xab],
            ..DiagnosisEntry::default()
        };
        assert_eq!(
            entry_text(&m),
            "manufacturer diagnosis USI 0x0042, the whole submodule: ab"
        );
        let x = DiagnosisEntry {
            kind: DiagnosisKind::Extended,
            error_type: 0x0100,
            ext_error_type: 0x8001,
            ext_add_value: 3,
            severity: DiagnosisSeverity::MaintenanceRequired,
            ..DiagnosisEntry::default()
        };
        assert_eq!(
            entry_text(&x),
            "maintenance required, the whole submodule: ChannelErrorType 0x0100, \
             ExtChannelErrorType 0x8001, ExtChannelAddValue 3"
        );
    }
}
