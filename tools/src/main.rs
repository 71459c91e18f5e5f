// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg`: look at and poke a running procimgd.

mod capture;
mod dcp;
mod gsdml;
mod interface;
mod interrupt;
mod io;
mod pe;
mod restart;
mod services;
mod station_diag;
mod status;
mod text;
mod watch;

use clap::{Parser, Subcommand};
use procimg_client::{ControlHandle, Mode};

/// The command line of the procimg process-image server: status, the image by logical
/// address (read, write, watch, force), mode, layout, records, events, devices, diagnosis,
/// DCP, capture, and the GSDML file of a device-role configuration.
#[derive(Parser)]
#[command(name = "procimg", version)]
struct Cli {
    /// Server instance.
    #[arg(
        long,
        short,
        global = true,
        default_value = "procimg",
        env = "PROCIMG_INSTANCE"
    )]
    instance: String,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Mode, cycle, timing percentiles, clients and their claims.
    Status {
        /// One JSON object instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Read, write or watch the image by logical address.
    Io {
        #[command(subcommand)]
        op: io::IoCommand,
    },
    /// Ask for a mode change (offline, clear, operate) and wait for its confirmation.
    Mode {
        /// The mode.
        mode: Mode,
    },
    /// The devices and submodules with their logical addresses.
    Layout,
    /// Read or write a record of a device (asynchronous job, waited for).
    Record {
        #[command(subcommand)]
        op: services::RecordCommand,
    },
    /// Print device events, alarms and confirmations as they come (of a device-role server:
    /// the station's AR, the PLC's RUN/STOP, DCP).
    Events {
        /// One JSON object per line.
        #[arg(long)]
        json: bool,
        /// Take part in alarm acknowledgement: the device's alarm is acknowledged once it
        /// was printed.
        #[arg(long)]
        ack: bool,
        /// Stop after this many.
        #[arg(long)]
        count: Option<u64>,
        /// Stop after this many seconds.
        #[arg(long)]
        seconds: Option<f64>,
    },
    /// Activate or deactivate a device and wait for the confirmation.
    Device {
        #[command(subcommand)]
        op: DeviceCommand,
    },
    /// A PROFIenergy command to a submodule of an IO device (record 0x80A0).
    Pe(pe::PeArgs),
    /// Take a new configuration into use under the running procimgd.
    Config {
        #[command(subcommand)]
        op: restart::ConfigCommand,
    },
    /// Start procimgd's instance anew with its configuration (programs are asked to stop).
    Reset {
        /// What happens while programs are attached.
        #[arg(long, value_enum, default_value = "ask")]
        kind: restart::ResetKind,
    },
    /// The type of station procimgd's own station reports by DCP, from its next start on.
    TypeOfStation {
        /// The text (engineering tools show 19 characters).
        text: String,
    },
    /// The controller's own interface: its records, its station's name and address.
    Interface {
        #[command(subcommand)]
        op: interface::InterfaceCommand,
    },
    /// The state of every device: state, activation, last error, module differences; of a
    /// device-role server, the station's own diagnosis as the PLC reads it (its diagnosis
    /// records) and the station problem indicator.
    Diag {
        /// JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Find PROFINET devices (DCP) and set their name or address. Needs root or CAP_NET_RAW.
    Dcp {
        /// The network interface.
        #[arg(long)]
        iface: String,
        /// Hides the global --instance: dcp talks to the network, not to a procimgd.
        #[arg(long, short, hide = true, value_parser = dcp::no_instance("dcp"))]
        instance: Option<String>,
        #[command(subcommand)]
        op: dcp::DcpCommand,
    },
    /// Record the PROFINET frames on a network interface (both directions) into a pcap file
    /// that Wireshark opens. Needs root or CAP_NET_RAW.
    Capture {
        /// The network interface.
        #[arg(long)]
        iface: String,
        /// Hides the global --instance: capture reads the network, not a procimgd.
        #[arg(long, short, hide = true, value_parser = dcp::no_instance("capture"))]
        instance: Option<String>,
        /// The pcap file to write.
        #[arg(short, long)]
        output: std::path::PathBuf,
        /// Stop after this many frames.
        #[arg(long)]
        count: Option<u64>,
        /// Stop after this many seconds.
        #[arg(long)]
        seconds: Option<f64>,
    },
    /// Write the GSDML file of procimgd as an IO device (a configuration with
    /// role = "device"), for the PLC's engineering tool.
    Gsdml(gsdml::GsdmlArgs),
}

#[derive(Subcommand)]
enum DeviceCommand {
    /// Connect the device again (not in OFFLINE).
    Activate {
        /// Station name.
        name: String,
    },
    /// Release the device's connection and leave it alone.
    Deactivate {
        /// Station name.
        name: String,
    },
    /// Tailor the IO system to the machine as built: every device down, then the mandatory
    /// devices and the optional ones named up, each joined port checking its neighbour
    /// (IO-Base's PNIO_iosystem_reconfig TAILOR).
    Tailor {
        /// The optional devices the machine has (station names).
        #[arg(value_name = "DEVICE")]
        present: Vec<String>,
        /// Two ports joined: NAME:SUBSLOT=NAME:SUBSLOT (a port submodule of slot 0, e.g.
        /// conveyor:0x8002=labeller:0x8001); repeat for more.
        #[arg(long = "link", value_name = "PORT=PORT")]
        links: Vec<String>,
    },
    /// Deactivate every device (IO-Base's PNIO_iosystem_reconfig DEACT).
    DeactivateAll,
}

fn main() {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Status { json } => status::run(&cli.instance, json),
        Command::Io { op } => io::run(&cli.instance, op),
        Command::Mode { mode } => set_mode(&cli.instance, mode),
        Command::Layout => io::layout(&cli.instance),
        Command::Record { op } => services::record(&cli.instance, op),
        Command::Events {
            json,
            ack,
            count,
            seconds,
        } => services::events(&cli.instance, json, ack, count, seconds),
        Command::Device { op } => match op {
            DeviceCommand::Activate { name } => services::activate(&cli.instance, &name, true),
            DeviceCommand::Deactivate { name } => services::activate(&cli.instance, &name, false),
            DeviceCommand::Tailor { present, links } => {
                services::tailor(&cli.instance, Some((&present, &links)))
            }
            DeviceCommand::DeactivateAll => services::tailor(&cli.instance, None),
        },
        Command::Interface { op } => interface::run(&cli.instance, op),
        Command::Pe(args) => pe::run(&cli.instance, args),
        Command::Config { op } => restart::config(&cli.instance, op),
        Command::Reset { kind } => restart::reset(&cli.instance, kind),
        Command::TypeOfStation { text } => restart::type_of_station(&cli.instance, &text),
        Command::Diag { json } => services::diag(&cli.instance, json),
        Command::Dcp { iface, op, .. } => dcp::run(&iface, op),
        Command::Capture {
            iface,
            output,
            count,
            seconds,
            ..
        } => capture::run(&iface, &output, count, seconds),
        Command::Gsdml(args) => gsdml::run(args),
    };
    if let Err(e) = result {
        eprintln!("procimg: {e:#}");
        std::process::exit(1);
    }
}

fn set_mode(instance: &str, mode: Mode) -> anyhow::Result<()> {
    let control = ControlHandle::open(instance, "procimg-mode")?;
    control.set_mode(mode)?;
    let until = std::time::Instant::now() + std::time::Duration::from_secs(5);
    loop {
        let now = control.status()?.mode;
        if now == mode {
            println!("{now}");
            return Ok(());
        }
        if std::time::Instant::now() > until {
            anyhow::bail!("instance \"{instance}\" is still in {now} after 5 s");
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
}
