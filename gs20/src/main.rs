// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg-gs20`: procimgd's IO device role as a GS20-PN module for a host microcontroller
//! written for that module.
//!
//! - `procimg-gs20 gsdml -o FILE`: the GSDML file of the item catalogue, for the PLC's
//!   engineering tool and for procimgd's `[station] gsdml`.
//! - `procimg-gs20 run --port /dev/ttyUSB0`: the host link on a serial port, bridged to a
//!   procimgd whose station its program defines (`[station] gsdml = "FILE"`): the host's
//!   items become the station's modules at Request Start, its input bytes the station's
//!   I data, the PLC's Q data comes back as Adapter Data, the station's AR as Adapter
//!   Events.
//!
//! The protocol and the catalogue are the library's ([`procimg_gs20::link`],
//! [`procimg_gs20::catalogue`]); each subcommand is a module of its own.
#![forbid(unsafe_code)]

mod gsdml;
mod run;

use clap::{Parser, Subcommand};
use std::io::IsTerminal;

/// procimgd as a GS20-PN PROFINET IO module for a host on a serial port.
#[derive(Parser)]
#[command(name = "procimg-gs20", version)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Write the GSDML file of the item catalogue: every item ID as a module, for the PLC's
    /// project and for procimgd's configuration ([station] gsdml = "FILE").
    Gsdml(gsdml::GsdmlArgs),
    /// Speak the GS20-PN host protocol on a serial port, with procimgd's station as the
    /// module's PROFINET side.
    Run(run::RunArgs),
}

fn main() {
    tracing_subscriber::fmt()
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env()
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("info")),
        )
        .with_writer(std::io::stderr)
        .with_ansi(colour_on_stderr())
        // A log line that cannot be written is lost, not a reason to stop the bridge.
        .log_internal_errors(false)
        .init();
    let result = match Cli::parse().command {
        Command::Gsdml(args) => gsdml::run(args),
        Command::Run(args) => run::run(args),
    };
    if let Err(e) = result {
        // Said plainly, as a command line tool says why it stops; the log lines before it
        // have told what happened until then.
        eprintln!("procimg-gs20: {e:#}");
        std::process::exit(1);
    }
}

/// Colour only on a terminal, and not with `NO_COLOR` set (to anything but ""), as procimgd.
fn colour_on_stderr() -> bool {
    std::io::stderr().is_terminal() && std::env::var_os("NO_COLOR").is_none_or(|v| v.is_empty())
}
