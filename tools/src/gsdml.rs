// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg gsdml`: the GSDML file of procimgd's own station (`role = "device"`), for the
//! engineering tool of the PLC that connects to it.

use std::path::PathBuf;
use std::time::SystemTime;

use anyhow::{anyhow, bail};
use clap::Args;
use procimg_config::Role;
use procimg_config::gsdml::export::{Destination, GsdmlDate, station_gsdml};

#[derive(Args)]
pub struct GsdmlArgs {
    /// The configuration file, with `role = "device"` and its `[station]`.
    #[arg(short, long)]
    config: PathBuf,
    /// Write the file here (atomically) instead of to standard output.
    #[arg(short, long, conflicts_with = "dir")]
    output: Option<PathBuf>,
    /// Write the file into this directory under its standard name
    /// (`GSDML-V2.4-procimg-<device_type>-<date>.xml`) and print its path.
    #[arg(short, long)]
    dir: Option<PathBuf>,
    /// The file's date, YYYYMMDD or YYYY-MM-DD (default: today, UTC).
    #[arg(long)]
    date: Option<GsdmlDate>,
    /// Hides the global --instance: gsdml reads a configuration file, not a procimgd.
    #[arg(long, short, hide = true, value_parser = no_instance)]
    instance: Option<String>,
}

fn no_instance(_: &str) -> Result<String, String> {
    Err(
        "`procimg gsdml` reads the configuration file given with -c, not a running \
         procimgd, so it takes no --instance; leave it out"
            .to_owned(),
    )
}

pub fn run(args: GsdmlArgs) -> anyhow::Result<()> {
    // The file describes the station, not this machine: the engineering PC that makes the
    // GSDML for the PLC's project usually has no such interface, so any name is taken.
    let config =
        procimg_config::load(&args.config, &|_: &str| Ok(())).map_err(|e| anyhow!("{e}"))?;
    let Some(station) = config
        .station
        .as_ref()
        .filter(|_| config.role == Role::Device)
    else {
        bail!(
            "{}: this is a configuration of the controller role (role = \"{}\"); `procimg \
             gsdml` describes procimgd itself as an IO device, and the devices it controls come \
             with their vendors' GSDML files. Give a configuration with role = \"device\" and \
             a [station] (`procimgd --print-demo-device-config` prints a commented \
             example)",
            args.config.display(),
            config.role.as_str()
        );
    };
    let date = match args.date {
        Some(date) => date,
        None => today()?,
    };
    let gsdml = station_gsdml(station, config.cycle_ns, date)
        .map_err(|e| anyhow!("{}: {e}", args.config.display()))?;
    if let Some(path) = gsdml.deliver(Destination::of(args.output, args.dir))? {
        println!("{}", path.display());
    }
    Ok(())
}

fn today() -> anyhow::Result<GsdmlDate> {
    GsdmlDate::of(SystemTime::now()).ok_or_else(|| {
        anyhow!("the system clock is not between 1970 and 9999; give the date with --date")
    })
}
