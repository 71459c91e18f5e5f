// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg io read|write|watch` and `procimg layout`.

use anyhow::{Context, bail};
use clap::Subcommand;
use procimg_client::{AttachOptions, Client, Ioxs, Space};
use std::time::Duration;

#[derive(Subcommand)]
pub enum IoCommand {
    /// Read inputs (or, with --output, the outputs as last sent) at a logical address.
    Read {
        /// Logical address (decimal or 0x hex).
        #[arg(value_parser = parse_u32)]
        address: u32,
        /// Bytes to read (default: to the end of the submodule).
        length: Option<usize>,
        /// Read the output (Q) space instead of the input (I) space.
        #[arg(long)]
        output: bool,
    },
    /// Write outputs at a logical address: claims the submodule for the write, then releases it.
    Write {
        /// Logical address (decimal or 0x hex).
        #[arg(value_parser = parse_u32)]
        address: u32,
        /// Bytes in hex, e.g. 01ff or "01 ff".
        bytes: String,
        /// Send the outputs with local status BAD.
        #[arg(long)]
        bad: bool,
    },
    /// Print the inputs at an address whenever they change.
    Watch {
        /// Logical address (decimal or 0x hex).
        #[arg(value_parser = parse_u32)]
        address: u32,
        /// Bytes to show (default: to the end of the submodule).
        length: Option<usize>,
        /// Watch the output (Q) space.
        #[arg(long)]
        output: bool,
        /// Stop after this many changes.
        #[arg(long)]
        count: Option<u64>,
    },
}

pub(crate) fn parse_u32(s: &str) -> Result<u32, String> {
    let r = match s.strip_prefix("0x").or_else(|| s.strip_prefix("0X")) {
        Some(hex) => u32::from_str_radix(hex, 16),
        None => s.parse(),
    };
    r.map_err(|e| format!("{s:?} is not an address: {e}"))
}

pub(crate) fn parse_hex(s: &str) -> anyhow::Result<Vec<u8>> {
    let digits: String = s
        .chars()
        .filter(|c| !c.is_whitespace() && *c != ':')
        .collect();
    if digits.is_empty() || !digits.len().is_multiple_of(2) {
        bail!("{s:?}: give whole bytes in hex, e.g. 01ff");
    }
    (0..digits.len())
        .step_by(2)
        .map(|i| {
            u8::from_str_radix(&digits[i..i + 2], 16).with_context(|| format!("{s:?} is not hex"))
        })
        .collect()
}

pub(crate) fn hex(b: &[u8]) -> String {
    b.iter()
        .map(|x| format!("{x:02x}"))
        .collect::<Vec<_>>()
        .join(" ")
}

fn attach(instance: &str) -> anyhow::Result<Client> {
    Ok(Client::attach(
        instance,
        AttachOptions::asynchronous("procimg-io"),
    )?)
}

/// Reads `length` bytes (or to the end of the submodule) at `address`.
fn read(
    client: &mut Client,
    address: u32,
    length: Option<usize>,
    output: bool,
) -> anyhow::Result<(Vec<u8>, String)> {
    let space = if output { Space::Output } else { Space::Input };
    let s = procimg_client::access::find(&client.layout().submodules, space, address)
        .with_context(|| format!("no submodule has {space} address {address}"))?;
    let e = client.layout().submodules[s];
    let (start, len) = if output {
        (e.output_address, e.output_length)
    } else {
        (e.input_address, e.input_length)
    };
    let n = length.unwrap_or((start + len as u32 - address) as usize);
    let mut buf = vec![0u8; n];
    let status = if output {
        let r = client.output_data_read(address, &mut buf)?;
        buf.truncate(r.len.min(n));
        format!("local {:?} remote {:?}", r.local, r.remote)
    } else {
        let r = client.data_read(address, &mut buf, Ioxs::Good)?;
        buf.truncate(r.len.min(n));
        format!("remote {:?}", r.remote)
    };
    Ok((buf, status))
}

pub fn run(instance: &str, op: IoCommand) -> anyhow::Result<()> {
    let mut client = attach(instance)?;
    wait_for_image(&mut client)?;
    match op {
        IoCommand::Read {
            address,
            length,
            output,
        } => {
            let (bytes, status) = read(&mut client, address, length, output)?;
            println!("{}  ({status})", hex(&bytes));
        }
        IoCommand::Write {
            address,
            bytes,
            bad,
        } => {
            let data = parse_hex(&bytes)?;
            let s =
                procimg_client::access::find(&client.layout().submodules, Space::Output, address)
                    .with_context(|| format!("no submodule has Q address {address}"))?;
            client.claim(&[s])?;
            let local = if bad { Ioxs::Bad } else { Ioxs::Good };
            let remote = client.data_write(address, &data, local)?;
            // Stay one more cycle so the write is applied while the claim is held.
            std::thread::sleep(Duration::from_nanos(client.layout().header.cycle_ns * 3));
            client.release(&[s])?;
            println!(
                "written {} at Q {address} (remote status {remote:?})",
                hex(&data)
            );
        }
        IoCommand::Watch {
            address,
            length,
            output,
            count,
        } => {
            let mut last = None;
            let mut changes = 0;
            loop {
                let (bytes, status) = read(&mut client, address, length, output)?;
                if last.as_ref() != Some(&bytes) {
                    let cycle = client.cycle_info().map_or(0, |c| c.cycle_number);
                    println!("cycle {cycle:>9}  {}  ({status})", hex(&bytes));
                    last = Some(bytes);
                    changes += 1;
                    if count.is_some_and(|c| changes >= c) {
                        return Ok(());
                    }
                }
                std::thread::sleep(Duration::from_millis(10));
            }
        }
    }
    Ok(())
}

fn wait_for_image(client: &mut Client) -> anyhow::Result<()> {
    for _ in 0..200 {
        if client.cycle_info().is_some() {
            return Ok(());
        }
        let mut b = [0u8; 0];
        let _ = client.data_read(u32::MAX, &mut b, Ioxs::Good);
        std::thread::sleep(Duration::from_millis(5));
    }
    bail!(
        "no process image from instance \"{}\" within 1 s",
        client.instance()
    )
}

pub fn layout(instance: &str) -> anyhow::Result<()> {
    let client = attach(instance)?;
    let l = client.layout();
    println!(
        "{} devices, {} submodules, {} input and {} output bytes, layout hash {:016x}",
        l.devices.len(),
        l.submodules.len(),
        l.header.input_size,
        l.header.output_size,
        l.hash()
    );
    println!(
        "{:<4} {:<20} {:>5} {:>7} {:>10} {:>10} {:>12} {:>12}",
        "#", "device", "slot", "subslot", "module", "submodule", "I", "Q"
    );
    for (i, s) in l.submodules.iter().enumerate() {
        println!(
            "{:<4} {:<20} {:>5} {:>7} {:>#10x} {:>#10x} {:>12} {:>12}",
            i,
            l.device_name(s.device as usize),
            s.slot,
            s.subslot,
            s.module_ident,
            s.submodule_ident,
            s.address_text(false),
            s.address_text(true)
        );
    }
    Ok(())
}
