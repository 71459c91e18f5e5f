// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg-gs20 gsdml`: the item catalogue's GSDML file ([`procimg_gs20::catalogue`]) to
//! standard output, to a file or into a directory under its standard name.

use std::path::PathBuf;
use std::time::SystemTime;

use anyhow::anyhow;
use clap::Args;
use procimg_config::gsdml::export::Destination;
use procimg_gs20::catalogue::{
    CatalogueIdentity, DEFAULT_DEVICE_ID, DEFAULT_VENDOR_ID, GsdmlDate, catalogue_gsdml,
};

#[derive(Args)]
pub struct GsdmlArgs {
    /// Write the file here (atomically) instead of to standard output, and print its path.
    #[arg(short, long, conflicts_with = "dir")]
    output: Option<PathBuf>,
    /// Write the file into this directory under its standard name
    /// (GSDML-V2.4-procimg-GS20_PN-<date>.xml) and print its path.
    #[arg(short, long)]
    dir: Option<PathBuf>,
    /// The PROFINET VendorID, 0x.... or decimal (default 0x0493: another vendor's,
    /// borrowed as procimg's demo does; a product needs its own from PROFIBUS & PROFINET
    /// International).
    #[arg(long, value_parser = parse_id)]
    vendor_id: Option<u16>,
    /// The PROFINET DeviceID, 0x.... or decimal (default 0x0200).
    #[arg(long, value_parser = parse_id)]
    device_id: Option<u16>,
    /// The file's date, YYYYMMDD or YYYY-MM-DD (default: today, UTC).
    #[arg(long)]
    date: Option<GsdmlDate>,
    /// The cycle_time of procimgd's configuration: the PLC's IO cycles the file offers are
    /// whole multiples of it.
    #[arg(long, value_parser = parse_cycle, default_value = "1ms")]
    cycle_time: u64,
}

/// "0x0493" or "1171".
fn parse_id(text: &str) -> Result<u16, String> {
    let parsed = match text.strip_prefix("0x").or_else(|| text.strip_prefix("0X")) {
        Some(hex) => u16::from_str_radix(hex, 16),
        None => text.parse(),
    };
    parsed.map_err(|_| "give a number from 0 to 0xFFFF, in hex as 0x0493 or in decimal".to_owned())
}

fn parse_cycle(text: &str) -> Result<u64, String> {
    procimg_config::parse_duration(text).map_err(|e| format!("{text:?} {e}"))
}

pub fn run(args: GsdmlArgs) -> anyhow::Result<()> {
    let identity = CatalogueIdentity {
        vendor_id: args.vendor_id.unwrap_or(DEFAULT_VENDOR_ID),
        device_id: args.device_id.unwrap_or(DEFAULT_DEVICE_ID),
    };
    let date = match args.date {
        Some(date) => date,
        None => GsdmlDate::of(SystemTime::now()).ok_or_else(|| {
            anyhow!("the system clock is not between 1970 and 9999; give the date with --date")
        })?,
    };
    let gsdml = catalogue_gsdml(&identity, args.cycle_time, date)?;
    if let Some(path) = gsdml.deliver(Destination::of(args.output, args.dir))? {
        println!("{}", path.display());
    }
    Ok(())
}
