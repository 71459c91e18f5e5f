// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg io read|write|watch` and `procimg layout`.

use crate::text::{hex, space_words};
use anyhow::bail;
use clap::Subcommand;
use procimg_client::access::{resolve_read, resolve_write};
use procimg_client::{AttachOptions, Client, ControlHandle, Ioxs, Space};
use procimg_control::StatusReport;
use procimg_shm_layout::SubmoduleEntry;
use std::time::{Duration, Instant};

#[derive(Subcommand)]
pub enum IoCommand {
    /// Read inputs (or, with --output, the outputs as last sent) at a logical address. In the
    /// device role: the Q data the PLC writes (or, with --output, the I data it reads), at
    /// the addresses `procimg layout` gives in its Q (or I) column.
    Read {
        /// Logical address (decimal or 0x hex).
        #[arg(value_parser = parse_u32)]
        address: u32,
        /// Bytes to read (default: to the end of the submodule).
        length: Option<usize>,
        /// Read the output (Q) space instead of the input (I) space; in the device role the I
        /// data the station sends to the PLC.
        #[arg(long)]
        output: bool,
    },
    /// Write outputs (in the device role: the I data the PLC reads) at a logical address and hold them: the command claims the submodule,
    /// writes, and keeps the claim (so the outputs keep going out) until Ctrl-C or --seconds;
    /// then the outputs go out invalid again. `io force` keeps values without a command running.
    Write {
        /// Logical address (decimal or 0x hex).
        #[arg(value_parser = parse_u32)]
        address: u32,
        /// Bytes in hex, e.g. 01ff or "01 ff".
        bytes: String,
        /// Send the outputs (in the device role: the I data) with IOPS BAD.
        #[arg(long)]
        bad: bool,
        /// Hold the outputs this long, then release them (default: until Ctrl-C).
        #[arg(long)]
        seconds: Option<f64>,
    },
    /// Force bytes, as a PLC's force table: the server holds them at these values every cycle
    /// (outputs over what clients write, sent valid in OPERATE; inputs, with --input, over what
    /// the devices deliver) until `io unforce` or the server's end. Shown by status, layout and
    /// io read.
    Force {
        /// Logical address (decimal or 0x hex).
        #[arg(value_parser = parse_u32)]
        address: u32,
        /// Bytes in hex, e.g. 01ff or "01 ff"; they must lie in one submodule.
        bytes: String,
        /// Force inputs (I) instead of outputs (Q).
        #[arg(long)]
        input: bool,
    },
    /// End forcing at a logical address (the rest of its submodule, or LEN bytes), or all.
    Unforce {
        /// Logical address (decimal or 0x hex).
        #[arg(value_parser = parse_u32, required_unless_present = "all")]
        address: Option<u32>,
        /// Bytes to unforce (default: to the end of the submodule).
        length: Option<u32>,
        /// Unforce inputs (I) instead of outputs (Q).
        #[arg(long)]
        input: bool,
        /// Unforce everything, inputs and outputs.
        #[arg(long, conflicts_with_all = ["address", "length", "input"])]
        all: bool,
    },
    /// Print the inputs at an address whenever they, their IOPS/IOCS, a force on them or
    /// their device's state change: a line with the time and the cycle number each. In the
    /// device role: the Q data from the PLC (with --output, the I data to it), and the AR's
    /// state.
    Watch {
        /// Logical address (decimal or 0x hex).
        #[arg(value_parser = parse_u32)]
        address: u32,
        /// Bytes to show (default: to the end of the submodule).
        length: Option<usize>,
        /// Watch the output (Q) space; in the device role the I data the PLC reads.
        #[arg(long)]
        output: bool,
        /// Stop after this many lines.
        #[arg(long)]
        count: Option<u64>,
        /// One JSON object per line (time, cycle, space, address, data, iops, iocs,
        /// device, state, forced).
        #[arg(long)]
        json: bool,
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
    if digits.is_empty() {
        bail!("{s:?}: give the bytes in hex, e.g. 01ff or \"01 ff\"");
    }
    hex::decode(&digits)
        .map_err(|e| anyhow::anyhow!("{s:?} is not whole bytes in hex ({e}); e.g. 01ff"))
}

/// Addresses for people: `0..15`, or `7` for one byte.
pub(crate) fn range(first: u32, len: usize) -> String {
    match len {
        0 | 1 => first.to_string(),
        n => format!("{first}..{}", first as usize + n - 1),
    }
}

fn attach(instance: &str) -> anyhow::Result<Client> {
    Ok(Client::attach(
        instance,
        AttachOptions::asynchronous("procimg-io"),
    )?)
}

/// Reads `length` bytes (or to the end of the submodule) at `address`, with the status and
/// whether a force covers the bytes.
fn read(
    client: &mut Client,
    status: Option<&StatusReport>,
    address: u32,
    length: Option<usize>,
    output: bool,
) -> anyhow::Result<(Vec<u8>, String)> {
    let space = if output { Space::Output } else { Space::Input };
    let at = resolve_read(
        &client.layout().submodules,
        space,
        address,
        usize::MAX,
        true,
    )?;
    let n = length.unwrap_or(at.data_len);
    let mut buf = vec![0u8; n];
    let device = client.is_device();
    let mut text = if output {
        let r = client.output_data_read(address, &mut buf)?;
        buf.truncate(r.len.min(n));
        if device {
            format!(
                "{}: this station's IOPS {:?}, the PLC's IOCS {:?}",
                space_words(true, space),
                r.local,
                r.remote
            )
        } else {
            format!("local {:?} remote {:?}", r.local, r.remote)
        }
    } else {
        let r = client.data_read(address, &mut buf, Ioxs::Good)?;
        buf.truncate(r.len.min(n));
        if device {
            format!(
                "{}: the PLC's IOPS {:?}",
                space_words(true, space),
                r.remote
            )
        } else {
            format!("remote {:?}", r.remote)
        }
    };
    if let Some(st) = status
        && st
            .forces_in(space, address, buf.len() as u32)
            .next()
            .is_some()
    {
        text.push_str(", FORCED");
    }
    Ok((buf, text))
}

/// The server's status, for its force table.
fn forces(client: &Client) -> Option<StatusReport> {
    client.control().status().ok()
}

/// Waits for Ctrl-C (SIGINT), SIGTERM, the server's end or `seconds`.
fn hold(client: &mut Client, seconds: Option<f64>) -> anyhow::Result<()> {
    let stop = crate::interrupt::flag()?;
    let until = seconds.map(|x| Instant::now() + Duration::from_secs_f64(x));
    while !stop.load(std::sync::atomic::Ordering::Acquire)
        && until.is_none_or(|u| Instant::now() < u)
    {
        for e in client.events() {
            match e {
                procimg_client::Event::ServerShutdown => bail!(
                    "instance \"{}\" stopped: the outputs are no longer held",
                    client.instance()
                ),
                procimg_client::Event::ClaimLost { .. } => bail!(
                    "the claim was lost (the server restarted or dropped this command): the \
                     outputs are no longer held"
                ),
                _ => {}
            }
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    Ok(())
}

fn force(instance: &str, op: IoCommand) -> anyhow::Result<()> {
    // What the user typed is checked before the server is asked.
    let data = match &op {
        IoCommand::Force { bytes, .. } => parse_hex(bytes)?,
        _ => Vec::new(),
    };
    let control = ControlHandle::open(instance, "procimg-force")?;
    match op {
        IoCommand::Force { address, input, .. } => {
            let space = if input { Space::Input } else { Space::Output };
            control.force(space, address, &data)?;
            println!(
                "forced {space} {} to {} until `procimg io unforce{} {address}`",
                range(address, data.len()),
                hex(&data),
                if input { " --input" } else { "" }
            );
        }
        IoCommand::Unforce { all: true, .. } => {
            control.unforce_all()?;
            println!("nothing forced");
        }
        IoCommand::Unforce {
            address: Some(address),
            length,
            input,
            ..
        } => {
            let space = if input { Space::Input } else { Space::Output };
            control.unforce(space, address, length)?;
            let left = control.status()?.forces.len();
            println!("{space} {address} no longer forced ({left} forces left)");
        }
        _ => unreachable!("only force and unforce come here"),
    }
    Ok(())
}

pub fn run(instance: &str, op: IoCommand) -> anyhow::Result<()> {
    if matches!(op, IoCommand::Force { .. } | IoCommand::Unforce { .. }) {
        return force(instance, op);
    }
    let mut client = attach(instance)?;
    wait_for_image(&mut client)?;
    match op {
        IoCommand::Read {
            address,
            length,
            output,
        } => {
            let status = forces(&client);
            let (bytes, status) = read(&mut client, status.as_ref(), address, length, output)?;
            println!("{}  ({status})", hex(&bytes));
        }
        IoCommand::Write {
            address,
            bytes,
            bad,
            seconds,
        } => {
            let data = parse_hex(&bytes)?;
            let at = resolve_write(&client.layout().submodules, address, data.len(), true)?;
            client.claim(&[at.submodule])?;
            let local = if bad { Ioxs::Bad } else { Ioxs::Good };
            let remote = client.data_write(address, &data, local)?;
            let span = range(address, data.len());
            // In the device role the bytes are I data: the PLC reads them.
            let (at_text, remote_text, what) = if client.is_device() {
                ("I data to the PLC at", "the PLC's IOCS", "the I data goes")
            } else {
                ("at Q", "remote status", "the outputs go")
            };
            match seconds {
                Some(s) => println!(
                    "written {} {at_text} {span} ({remote_text} {remote:?}); held for {s} s",
                    hex(&data)
                ),
                None => println!(
                    "written {} {at_text} {span} ({remote_text} {remote:?}); held until \
                     Ctrl-C, then {what} out invalid (`procimg io force` keeps them \
                     without a running command)",
                    hex(&data)
                ),
            }
            hold(&mut client, seconds)?;
            client.release(&[at.submodule])?;
        }
        IoCommand::Watch {
            address,
            length,
            output,
            count,
            json,
        } => crate::watch::watch(
            &mut client,
            &crate::watch::Watch {
                address,
                length,
                output,
                count,
                json,
            },
        )?,
        IoCommand::Force { .. } | IoCommand::Unforce { .. } => {}
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
    let status = forces(&client);
    let l = client.layout();
    // In the device role the image keeps its two directions: what the PLC writes (its Q
    // data) is in the server-written space, the I data the PLC reads in the client-written
    // one. The columns name them as the PLC does.
    let device = l.is_device();
    if device {
        println!(
            "station, {} submodules, {} bytes of I data (the PLC reads them; `io write`, `io \
             read --output`) and {} of Q data (the PLC writes them; `io read`), layout hash \
             {:016x}",
            l.submodules.len(),
            l.header.output_size,
            l.header.input_size,
            l.hash()
        );
    } else {
        println!(
            "{} devices, {} submodules, {} input and {} output bytes, layout hash {:016x}",
            l.devices.len(),
            l.submodules.len(),
            l.header.input_size,
            l.header.output_size,
            l.hash()
        );
    }
    println!(
        "{:<4} {:<20} {:>5} {:>7} {:>10} {:>10} {:>12} {:>12}",
        "#", "device", "slot", "subslot", "module", "submodule", "I", "Q"
    );
    for (i, s) in l.submodules.iter().enumerate() {
        let column = |space: Space| {
            let text = s.address_text(space == Space::Output);
            marked(text, forced(status.as_ref(), s, space))
        };
        // A submodule without data keeps its diagnostic address in the I column.
        let (i_space, q_space) = if device && s.diagnostic_address().is_none() {
            (Space::Output, Space::Input)
        } else {
            (Space::Input, Space::Output)
        };
        println!(
            "{:<4} {:<20} {:>5} {:>7} {:>#10x} {:>#10x} {:>12} {:>12}",
            i,
            l.device_name(s.device as usize),
            s.slot,
            s.subslot,
            s.module_ident,
            s.submodule_ident,
            column(i_space),
            column(q_space)
        );
    }
    if status.as_ref().is_some_and(|s| !s.forces.is_empty()) {
        println!("F: forced bytes in the range (`procimg status` lists them)");
    }
    Ok(())
}

/// Whether a force covers some of submodule `e`'s bytes in `space`.
fn forced(status: Option<&StatusReport>, e: &SubmoduleEntry, space: Space) -> bool {
    let (first, len) = match space {
        Space::Input => (e.input_address, e.input_length),
        Space::Output => (e.output_address, e.output_length),
    };
    len > 0 && status.is_some_and(|st| st.forces_in(space, first, len as u32).next().is_some())
}

fn marked(text: String, forced: bool) -> String {
    if forced { format!("F {text}") } else { text }
}

#[cfg(test)]
mod tests {
    use super::parse_hex;

    #[test]
    fn hex_input_is_parsed_or_refused_with_the_reason_never_a_panic() {
        assert_eq!(parse_hex("01ff").unwrap(), [0x01, 0xff]);
        assert_eq!(parse_hex("01 FF:10").unwrap(), [0x01, 0xff, 0x10]);
        for bad in ["", "0", "0g", "ü1", "1ü", "€€"] {
            let e = parse_hex(bad).unwrap_err().to_string();
            assert!(e.contains("hex"), "{bad:?}: {e}");
        }
    }
}
