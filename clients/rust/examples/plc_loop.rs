// SPDX-License-Identifier: MIT OR Apache-2.0
//! A synchronous, PLC-style client: every cycle it waits for STARTOP, reads the demo's echo
//! module, writes a new pattern to its outputs and signals OPDONE. It checks that the echo's
//! valid inputs carry a pattern it wrote (within `--max-delay` cycles, or later when the
//! machine held it back), counts OPFAULTs, and prints a summary. Exit status 1 if an echo
//! input was not a pattern it wrote (torn or foreign data), or, with `--require PERCENT`, if
//! fewer OPDONEs than that came in time (how many do depends on the machine's load and on
//! the loop's priority: the figure is reported, and judged only when asked).
//!
//! Run against `procimgd --demo`:
//!   cargo run --release --example plc_loop -- --cycles 10000

use anyhow::{Context, bail};
use clap::Parser;
use procimg_client::{AttachOptions, Client, Event, Ioxs};
use std::collections::BTreeMap;
use std::time::Duration;

#[derive(Parser)]
struct Args {
    /// Instance to attach to.
    #[arg(long, default_value = "procimg")]
    instance: String,
    /// Cycles to run.
    #[arg(long, default_value_t = 10_000)]
    cycles: u64,
    /// Station name of the echo device.
    #[arg(long, default_value = "echo")]
    device: String,
    /// Largest accepted delay, in cycles this client handled, between writing a pattern and
    /// reading it back. It is 1 when every OPDONE is in time; each OPFAULT in a row adds one
    /// (the late outputs are not used, the previous ones are held). Cycles the server skipped
    /// (overruns) do not count.
    #[arg(long, default_value_t = 8)]
    max_delay: u64,
    /// SCHED_FIFO priority of the loop (0: stay at normal priority).
    #[arg(long, default_value_t = 70)]
    priority: u8,
    /// Exit with status 1 if fewer than this percentage of OPDONEs came in time (e.g. 99.9).
    #[arg(long, alias = "min-in-time")]
    require: Option<f64>,
}

/// Patterns remembered, to tell a late echo (a pattern written long ago) from a wrong one.
const HISTORY: u64 = 4096;

/// The pattern of cycle k: k little-endian, then its complement, repeated. A torn write or
/// read shows up as a half that does not match.
fn pattern(k: u64, len: usize) -> Vec<u8> {
    let mut block = k.to_le_bytes().to_vec();
    block.extend_from_slice(&(!k).to_le_bytes());
    block.iter().copied().cycle().take(len).collect()
}

fn main() {
    // An expected error (no server, a failed check) is a message, not a backtrace.
    if let Err(e) = run(Args::parse()) {
        eprintln!("plc_loop: {e:#}");
        std::process::exit(1);
    }
}

fn run(args: Args) -> anyhow::Result<()> {
    if args.priority > 0
        && let Err(e) = procimg_client::realtime::make_current_thread_realtime(args.priority)
    {
        eprintln!(
            "warning: cannot run SCHED_FIFO at priority {} ({e}); OPDONE may miss the \
             deadline under load",
            args.priority
        );
    }
    let mut client = Client::attach(&args.instance, AttachOptions::synchronous("plc_loop"))
        .context("attaching")?;
    let echo = client
        .layout()
        .device(&args.device)
        .context("no such device in the layout")?;
    let subs = client
        .claim_device(&args.device)
        .context("claiming the echo outputs")?;
    let sub = *subs.first().context("the echo device has no outputs")?;
    let len = client.layout().submodules[sub].output_length as usize;
    let _ = echo;

    // Patterns by the sequence number of the handled cycle (not the cycle number: a stall of
    // the machine skips cycle numbers without delaying the echo).
    let mut written: BTreeMap<u64, Vec<u8>> = BTreeMap::new();
    let (mut done, mut opfaults, mut checked) = (0u64, 0u64, 0u64);
    let (mut wrong, mut late_echoes, mut invalid) = (0u64, 0u64, 0u64);
    let mut delays: BTreeMap<u64, u64> = BTreeMap::new();
    let mut first = None;
    let mut late: Vec<u64> = Vec::new();
    while done < args.cycles {
        let mut cycle = client
            .wait_startop(Duration::from_secs(5))
            .context("waiting for STARTOP")?;
        let k = cycle.number();
        let start = *first.get_or_insert(k);
        let input = cycle.input(sub).unwrap_or(&[]).to_vec();
        let valid = cycle
            .status(sub)
            .is_some_and(|s| s.input_remote == Ioxs::Good);
        cycle.output_mut(sub)?.copy_from_slice(&pattern(k, len));
        cycle.set_opdone()?;
        let seq = done;
        written.insert(seq, pattern(k, len));
        // From a few cycles in, a valid echo must show something we wrote; inputs the device
        // marks invalid (it is not in data exchange, e.g. starved on a loaded machine) carry
        // no data to check.
        if seq >= args.max_delay && !valid {
            invalid += 1;
        } else if seq >= args.max_delay {
            checked += 1;
            match written.range(..seq).rev().find(|(_, p)| **p == input) {
                Some((j, _)) if seq - j <= args.max_delay => {
                    *delays.entry(seq - j).or_default() += 1
                }
                Some(_) => late_echoes += 1,
                None => wrong += 1,
            }
        }
        while written.len() as u64 > HISTORY {
            written.pop_first();
        }
        for e in client.events() {
            if let Event::OpFault { cycle } = e {
                opfaults += 1;
                if late.len() < 10 {
                    late.push(cycle.saturating_sub(start));
                }
            }
        }
        done += 1;
    }
    let in_time = 100.0 * (done - opfaults.min(done)) as f64 / done as f64;
    println!(
        "cycles {done}  OPDONE in time {in_time:.3} %  OPFAULTs {opfaults}  echo checked {checked} \
         wrong {wrong}  later than {} cycles {late_echoes}  invalid {invalid}  delays (cycles: \
         count) {delays:?}",
        args.max_delay
    );
    if !late.is_empty() {
        println!("OPFAULT in cycles (from the first): {late:?}");
    }
    if wrong > 0 {
        bail!(
            "{wrong} valid echo inputs were not a pattern this loop wrote (torn or foreign data)"
        );
    }
    if checked == 0 {
        bail!(
            "the echo device's inputs were never valid: is it in data exchange? \
             `procimg status` shows the devices and the mode (`procimg mode operate`)"
        );
    }
    if let Some(required) = args.require
        && in_time < required
    {
        bail!(
            "only {in_time:.3} % of OPDONEs in time, {required} % required (--require); run \
             the loop at a real-time priority (--priority, as root) on a less loaded machine"
        );
    }
    Ok(())
}
