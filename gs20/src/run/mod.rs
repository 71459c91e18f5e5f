// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg-gs20 run`: the GS20-PN host link on a serial port, with procimgd's station as
//! the module's PROFINET side.

mod baskets;
mod bridge;
mod definition;
mod image;
mod network;
mod pacer;
mod procimgd;
mod serial;
mod sockets;

use anyhow::Context;
use procimg_gs20::link::Link;
use std::path::PathBuf;
use std::time::Duration;
use tracing::{info, warn};

/// The parity of the serial line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum ParityArg {
    /// Even parity: the module's 8E1.
    Even,
    /// No parity (8N1), for a host that cannot send a parity bit.
    None,
}

/// `procimg-gs20 run`.
#[derive(Debug, clap::Args)]
pub struct RunArgs {
    /// The serial port the host is on, e.g. /dev/ttyUSB0.
    #[arg(long)]
    port: String,
    /// procimgd's instance: a station its program defines (role = "device", [station]
    /// gsdml = "FILE").
    #[arg(long, default_value = "procimg", env = "PROCIMG_INSTANCE")]
    instance: String,
    /// Bit rate of the serial line (the module's is fixed at 115200).
    #[arg(long, default_value_t = 115_200)]
    baud: u32,
    /// Parity of the serial line (8 data bits and 1 stop bit either way).
    #[arg(long, value_enum, default_value_t = ParityArg::Even)]
    parity: ParityArg,
    /// Adapter Data goes to the host when the PLC's outputs change, and again after this
    /// many milliseconds without a change (0: only on changes).
    #[arg(long, default_value_t = 100)]
    min_period_ms: u64,
    /// The baskets Add Basket selects from, a TOML file (see the README); without it Add
    /// Basket is refused (error bit 1).
    #[arg(long)]
    baskets: Option<PathBuf>,
    /// SCHED_FIFO priority of the bridge, 1 to 99 (0: normal scheduling). The default, 40,
    /// is above the machine's normal work and below procimgd's cycle thread (80), so that
    /// a busy machine does not hold back the host's Adapter Data.
    #[arg(long, default_value_t = 40, value_parser = clap::value_parser!(u8).range(0..=99))]
    priority: u8,
}

/// Runs the bridge until the serial port fails.
pub fn run(args: RunArgs) -> anyhow::Result<()> {
    let baskets = match &args.baskets {
        Some(path) => baskets::load(path)?,
        None => Default::default(),
    };
    let parity = match args.parity {
        ParityArg::Even => serialport::Parity::Even,
        ParityArg::None => serialport::Parity::None,
    };
    let serial = serial::Serial::open(&args.port, args.baud, parity)?;
    if args.priority > 0
        && let Err(e) = procimg_client::realtime::make_current_thread_realtime(args.priority)
    {
        warn!(
            "cannot run at SCHED_FIFO priority {} with its memory locked ({e}): a busy \
             machine may delay the host's frames; run it as \
             root or with CAP_SYS_NICE and CAP_IPC_LOCK, or pass --priority 0 to silence this",
            args.priority
        );
    }
    let procimgd = procimgd::Procimgd::attach(&args.instance)?;
    let period = (args.min_period_ms > 0).then(|| Duration::from_millis(args.min_period_ms));
    info!(
        "the GS20-PN host link on {} ({} bit/s, 8{}1) for procimgd instance \"{}\": waiting \
         for the host's Request Status",
        serial.name(),
        args.baud,
        if parity == serialport::Parity::Even {
            "E"
        } else {
            "N"
        },
        args.instance
    );
    bridge::Bridge::new(
        serial,
        procimgd,
        Link::new(baskets),
        pacer::Pacer::new(period),
    )
    .run()
    .context("the host link stopped")
}
