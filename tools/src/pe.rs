// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg pe`: PROFIenergy commands to a submodule of an IO device (record 0x80A0, the
//! answer polled until it is ready, at most 10 s), as IO-Base's `PNIO_pe_cmd_req` sends them.

use crate::services::{device_index, open, parse_u16};
use anyhow::Context;
use clap::Subcommand;
use procimg_client::RecordTarget;
use procimg_client::pe::{PeAnswer, PeCommand};

#[derive(clap::Args)]
pub struct PeArgs {
    /// The device's station name.
    device: String,
    /// Slot of the PE entity (its head module: 0).
    #[arg(long, default_value_t = 0)]
    slot: u16,
    /// Subslot (decimal or 0x hex).
    #[arg(long, default_value = "1", value_parser = parse_u16)]
    subslot: u16,
    /// API.
    #[arg(long, default_value_t = 0)]
    api: u32,
    /// JSON instead of text.
    #[arg(long)]
    json: bool,
    #[command(subcommand)]
    command: PeCommandArg,
}

#[derive(Subcommand)]
enum PeCommandArg {
    /// Start_Pause: pause for MS milliseconds.
    StartPause {
        /// The pause expected, ms.
        ms: u32,
    },
    /// End_Pause: back to operation.
    EndPause,
    /// Query_Modes: the energy-saving modes.
    Modes,
    /// Query_Modes: one mode's times and energies.
    Mode {
        /// PE_Mode_ID (0xFF: ready to operate).
        #[arg(value_parser = parse_u16)]
        mode: u16,
    },
    /// PEM_Status: where the device is.
    Status,
    /// PE_Identify: the PE services it offers.
    Identify,
    /// Query_Version.
    Version,
    /// Query_Measurement: the measurements it offers.
    Measurements,
    /// Query_Measurement: values.
    Values {
        /// Measurement_IDs.
        ids: Vec<u16>,
    },
}

pub fn run(instance: &str, args: PeArgs) -> anyhow::Result<()> {
    let mut s = open(instance, "procimg-pe", false)?;
    let target = RecordTarget {
        device: device_index(&s, &args.device)?,
        api: args.api,
        slot: args.slot,
        subslot: args.subslot,
        index: 0x80a0,
    };
    let command = match args.command {
        PeCommandArg::StartPause { ms } => PeCommand::StartPause { pause_ms: ms },
        PeCommandArg::EndPause => PeCommand::EndPause,
        PeCommandArg::Modes => PeCommand::ListModes,
        PeCommandArg::Mode { mode } => PeCommand::GetMode {
            mode: u8::try_from(mode).context("a PE_Mode_ID is 0..255")?,
        },
        PeCommandArg::Status => PeCommand::PemStatus,
        PeCommandArg::Identify => PeCommand::Identify,
        PeCommandArg::Version => PeCommand::QueryVersion,
        PeCommandArg::Measurements => PeCommand::MeasurementList,
        PeCommandArg::Values { ids } => PeCommand::MeasurementValues { ids },
    };
    let answer = s
        .pe(target, command)
        .with_context(|| format!("PROFIenergy command to {:?}", args.device))?;
    if args.json {
        println!("{}", serde_json::to_string(&answer)?);
    } else {
        println!("{}", describe(&answer));
    }
    Ok(())
}

/// A PE_Mode_ID in words.
fn mode(m: u8) -> String {
    match m {
        0x00 => "0x00 (power off)".into(),
        0xff => "0xFF (ready to operate)".into(),
        0xf0 => "0xF0 (operate)".into(),
        m => format!("{m:#04x}"),
    }
}

fn describe(a: &PeAnswer) -> String {
    match a {
        PeAnswer::StartPause { mode: m } => format!("pausing: mode {}", mode(*m)),
        PeAnswer::EndPause { time_to_operate } => {
            format!("ending the pause: ready to operate in {time_to_operate} ms")
        }
        PeAnswer::ModeList { modes } => format!(
            "modes: {}",
            modes
                .iter()
                .map(|m| mode(*m))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        PeAnswer::Mode(m) => format!(
            "mode {}: pause at least {} ms, to pause {} ms, to operate {} ms, stay {}..{} ms, \
             {} kW, {} kWh to pause, {} kWh to operate",
            mode(m.mode),
            m.time_min_pause,
            m.time_to_pause,
            m.time_to_operate,
            m.time_min_length_of_stay,
            m.time_max_length_of_stay,
            m.power_kw,
            m.energy_to_pause_kwh,
            m.energy_to_operate_kwh
        ),
        PeAnswer::PemStatus(s) => format!(
            "mode {} going to {}, {} ms to operate, {} ms to destination, {} kW",
            mode(s.source),
            mode(s.destination),
            s.time_to_operate,
            s.remaining_time_to_destination,
            s.power_kw
        ),
        PeAnswer::Identify { services } => format!(
            "PE services: {}",
            services
                .iter()
                .map(|s| format!("{s:#04x}"))
                .collect::<Vec<_>>()
                .join(" ")
        ),
        PeAnswer::Version { major, minor } => format!("PROFIenergy {major}.{minor}"),
        PeAnswer::MeasurementList { items } if items.is_empty() => "no measurements".into(),
        PeAnswer::MeasurementList { items } => items
            .iter()
            .map(|m| format!("measurement {} (range {})", m.id, m.range))
            .collect::<Vec<_>>()
            .join("\n"),
        PeAnswer::MeasurementValues { values } => values
            .iter()
            .map(|v| format!("measurement {}: {} (status {})", v.id, v.value, v.status))
            .collect::<Vec<_>>()
            .join("\n"),
        PeAnswer::Error { code } => format!(
            "refused by the device: PE error {code:#04x} ({})",
            error_text(*code)
        ),
        PeAnswer::Other {
            status,
            structure,
            data,
        } => format!(
            "status {status}, structure {structure}, {} bytes",
            data.len()
        ),
    }
}

/// The profile's name of a PE Error_Code.
fn error_text(code: u8) -> &'static str {
    match code {
        0x01 => "invalid Service_Request_ID",
        0x02 => "bad Request_Reference",
        0x03 => "invalid Modifier",
        0x04 => "invalid Data_Structure_Identifier_RQ",
        0x06 => "no PE energy-saving mode supported",
        0x08 => "invalid block header",
        0x50 => "no suitable energy-saving mode available",
        0x51 => "time not supported",
        0x52 => "impermissible PE_Mode_ID",
        0x53 => "no switch to energy saving because of state operate",
        0x54 => "service or function temporarily not available",
        _ => "see the PROFIenergy profile",
    }
}
