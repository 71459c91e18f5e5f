// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg-gs20`: procimgd's IO device role as a GS20-PN module, for a host
//! microcontroller written for that module.
//!
//! - `procimg-gs20 gsdml -o FILE`: the GSDML file of the item catalogue, for the PLC's
//!   engineering tool and for procimgd's `[station] gsdml`.
//!
//! Each subcommand is a module of its own; the protocol and the catalogue are the
//! library's ([`procimg_gs20::catalogue`]).
#![forbid(unsafe_code)]

mod gsdml;

use clap::{Parser, Subcommand};

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
}

fn main() {
    let result = match Cli::parse().command {
        Command::Gsdml(args) => gsdml::run(args),
    };
    if let Err(e) = result {
        eprintln!("procimg-gs20: {e:#}");
        std::process::exit(1);
    }
}
