// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg-soak`: procimgd as IO controller of an independent device (`pnio-interop-device`,
//! the `pnio` stack) in two network namespaces, with a synchronous client, for a given time;
//! the client, the device and procimgd are killed and started again at random moments. At the
//! end it prints one table: cycles, overruns, OPFAULTs, watchdog expiries, reconnect times,
//! malformed frames (Wireshark's verdict on every frame on the wire), data errors, records and
//! alarms lost, beside cyclictest's late wake-ups in the same run.
//!
//! ```text
//! procimg-soak [--duration 1h] [--cycle 1ms] [--mean-gap 20s] [--seed N] [--out DIR]
//! ```
//!
//! Needs root (namespaces, raw sockets, real-time scheduling), the binaries of this workspace
//! beside it (`cargo build --release --bins`), and tshark and cyclictest in PATH (without them
//! those rows say "not checked" / "not run"). Exit status 1 when a figure that must be 0 is
//! not.

mod baseline;
mod capture;
mod client;
mod monitor;
mod process;
mod rig;
mod supervisor;
mod tally;

use anyhow::Context as _;
use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::time::Duration;

#[derive(Parser)]
#[command(
    version,
    about = "Soak procimgd against an independent PROFINET device, with faults"
)]
struct Args {
    #[command(subcommand)]
    role: Option<Role>,
    /// How long to run (e.g. 60s, 1h).
    #[arg(long, default_value = "1h", value_parser = humantime::parse_duration)]
    duration: Duration,
    /// procimgd's cycle, the send clock of the device's IOCRs.
    #[arg(long, default_value = "1ms", value_parser = humantime::parse_duration)]
    cycle: Duration,
    /// DataHoldFactor of both IOCRs: the watchdog time is this many cycles.
    #[arg(long, default_value_t = 20)]
    watchdog_factor: u32,
    /// Mean time between two faults (each gap is drawn between half and one and a half of it).
    #[arg(long, default_value = "20s", value_parser = humantime::parse_duration)]
    mean_gap: Duration,
    /// Seed of the fault schedule (default: from the clock; printed, to repeat a run).
    #[arg(long)]
    seed: Option<u64>,
    /// Where logs, the configuration and `soak.json` go.
    #[arg(long, default_value = "target/procimg-soak")]
    out: PathBuf,
    /// Do not record and check the frames with tshark.
    #[arg(long)]
    no_capture: bool,
}

#[derive(Subcommand)]
enum Role {
    /// The synchronous client (started by the soak itself).
    #[command(hide = true)]
    Client {
        /// procimgd's instance.
        #[arg(long)]
        instance: String,
        /// The device whose outputs it writes.
        #[arg(long)]
        device: String,
    },
}

fn main() -> std::process::ExitCode {
    let args = Args::parse();
    let result = match &args.role {
        Some(Role::Client { instance, device }) => client::run(instance, device),
        None => soak(&args),
    };
    match result {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("procimg-soak: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}

fn soak(args: &Args) -> anyhow::Result<()> {
    if !procimg_netns::signal::is_root() {
        anyhow::bail!(
            "procimg-soak needs root: it makes network namespaces and runs procimgd on a raw socket"
        );
    }
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let seed = args.seed.unwrap_or_else(|| {
        std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map(|d| d.as_nanos() as u64)
            .unwrap_or(1)
    });
    let settings = supervisor::Settings {
        duration: args.duration,
        cycle: args.cycle,
        watchdog_factor: args.watchdog_factor,
        mean_gap: args.mean_gap,
        seed,
        out: args.out.clone(),
        capture: !args.no_capture,
    };
    eprintln!(
        "procimg-soak: {:?} at a cycle of {:?}, a fault every {:?} on average, seed {seed}; \
         logs in {}",
        args.duration,
        args.cycle,
        args.mean_gap,
        args.out.display()
    );
    let tally = supervisor::run(&settings)?;
    let json = args.out.join("soak.json");
    std::fs::write(&json, serde_json::to_string_pretty(&tally)?)
        .with_context(|| format!("writing {}", json.display()))?;
    println!("{}", tally.table());
    let failures = tally.failures();
    if failures.is_empty() {
        println!(
            "soak passed: every figure that must be 0 is 0 ({})",
            json.display()
        );
        Ok(())
    } else {
        anyhow::bail!("soak failed: {}", failures.join(", "))
    }
}
