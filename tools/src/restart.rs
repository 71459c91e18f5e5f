// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg config load`, `procimg reset` and `procimg type-of-station`: a new configuration
//! taken into use under a running procimgd, a restart with the one it runs, and the type of
//! station its own station reports from the next start on. Programs attached are asked to
//! stop (IO-Base's CP_STOP_REQ) and waited for. And `procimg config import`: TIA Portal's PN
//! Driver configuration written as procimgd's own.

use crate::services::open;
use anyhow::Context;
use clap::Subcommand;
use procimg_client::RestartClients;
use std::path::PathBuf;
use std::time::Duration;

/// Long enough for the programs asked to stop, and for the new server's start.
const RESTART_TIMEOUT: Duration =
    Duration::from_millis(procimg_control::services::RESTART_WAIT_MS + 20_000);

#[derive(Subcommand)]
pub enum ConfigCommand {
    /// Take FILE into use: checked first, then the programs attached are asked to stop and
    /// procimgd starts anew with it (a procimgd started with -c FILE keeps it in its file).
    Load {
        /// The configuration file.
        file: PathBuf,
        /// Restart even if a program stays attached after it was asked to stop.
        #[arg(long)]
        force: bool,
    },
    /// Print TIA Portal's PN Driver configuration (…PNDriverConfiguration.xml) as procimgd's
    /// own TOML configuration, commented with the project's objects and lines. procimgd,
    /// `config load` and SERV_CP_startup take the XML itself too.
    Import {
        /// The PN Driver configuration (XML).
        file: PathBuf,
        /// The network interface procimgd is to drive (the project names none: a PN
        /// Driver program chooses its adapter); without it, procimgd needs --adapter.
        #[arg(long, value_name = "INTERFACE")]
        network: Option<String>,
    },
}

/// What `procimg reset` does with attached programs.
#[derive(Clone, Copy, clap::ValueEnum)]
pub enum ResetKind {
    /// Refused while a program is attached (IO-Base's PNIO_CP_RESET_SAFE).
    Safe,
    /// Programs are asked to stop; the restart waits for them (default).
    Ask,
    /// Programs are asked to stop; the restart comes after the wait whoever stays
    /// (PNIO_CP_RESET_FORCE).
    Force,
}

pub fn config(instance: &str, op: ConfigCommand) -> anyhow::Result<()> {
    let (file, force) = match op {
        ConfigCommand::Load { file, force } => (file, force),
        ConfigCommand::Import { file, network } => return import(&file, network.as_deref()),
    };
    let text = std::fs::read_to_string(&file)
        .with_context(|| format!("cannot read {}", file.display()))?;
    let clients = if force {
        RestartClients::Force
    } else {
        RestartClients::Ask
    };
    restart(instance, Some(text), clients)
}

/// Prints the PN Driver configuration in `file` as procimgd's, checked as procimgd checks
/// it (but for the interface, which need not be this machine's).
fn import(file: &std::path::Path, network: Option<&str>) -> anyhow::Result<()> {
    let text =
        std::fs::read_to_string(file).with_context(|| format!("cannot read {}", file.display()))?;
    let origin = file.display().to_string();
    let toml = procimg_config::pn_driver::import(&text, &origin, network)
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    procimg_config::parse(&toml, &format!("{origin} (imported)"))
        .map_err(|e| anyhow::anyhow!("{e}\n{toml}"))?;
    print!("{toml}");
    Ok(())
}

pub fn reset(instance: &str, kind: ResetKind) -> anyhow::Result<()> {
    let clients = match kind {
        ResetKind::Safe => RestartClients::Refuse,
        ResetKind::Ask => RestartClients::Ask,
        ResetKind::Force => RestartClients::Force,
    };
    restart(instance, None, clients)
}

fn restart(
    instance: &str,
    configuration: Option<String>,
    clients: RestartClients,
) -> anyhow::Result<()> {
    let mut s = open(instance, "procimg-restart", false)?;
    let message = s.restart_and_wait(configuration, clients, RESTART_TIMEOUT)?;
    println!("{message}");
    Ok(())
}

pub fn type_of_station(instance: &str, text: &str) -> anyhow::Result<()> {
    let s = open(instance, "procimg-type-of-station", false)?;
    s.set_type_of_station(text)?;
    println!("type of station {text:?} from procimgd's next start on (procimg reset)");
    Ok(())
}
