// SPDX-License-Identifier: MIT OR Apache-2.0
//! A synchronous, PLC-style client: every cycle it waits for STARTOP, reads the demo's echo
//! module, writes a new pattern to its outputs and signals OPDONE. It checks that the echo's
//! inputs carry a pattern written at most `--max-delay` cycles earlier, counts OPFAULTs, and
//! prints a summary. Exit status 1 if fewer than `--min-in-time` percent of the OPDONEs came
//! in time or the echo is wrong.
//!
//! Run against `procimgd --demo`:
//!   cargo run --release --example plc_loop -- --cycles 10000

use anyhow::{Context, bail};
use clap::Parser;
use procimg_client::{AttachOptions, Client, Event};
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
    /// Percentage of OPDONEs that must be in time.
    #[arg(long, default_value_t = 99.9)]
    min_in_time: f64,
}

/// The pattern of cycle k: k little-endian, then its complement, repeated. A torn write or
/// read shows up as a half that does not match.
fn pattern(k: u64, len: usize) -> Vec<u8> {
    let mut block = k.to_le_bytes().to_vec();
    block.extend_from_slice(&(!k).to_le_bytes());
    block.iter().copied().cycle().take(len).collect()
}

fn main() -> anyhow::Result<()> {
    let args = Args::parse();
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
    let (mut done, mut opfaults, mut checked, mut echo_errors) = (0u64, 0u64, 0u64, 0u64);
    let mut delays: BTreeMap<u64, u64> = BTreeMap::new();
    let mut first = None;
    let mut late: Vec<u64> = Vec::new();
    while done < args.cycles {
        let mut cycle = client
            .wait_startop(Duration::from_millis(500))
            .context("waiting for STARTOP")?;
        let k = cycle.number();
        let start = *first.get_or_insert(k);
        let input = cycle.input(sub).unwrap_or(&[]).to_vec();
        cycle.output_mut(sub)?.copy_from_slice(&pattern(k, len));
        cycle.set_opdone()?;
        let seq = done;
        written.insert(seq, pattern(k, len));
        // From a few cycles in, the echo must show something we wrote recently.
        if seq >= args.max_delay {
            checked += 1;
            match written
                .range(seq.saturating_sub(args.max_delay)..seq)
                .rev()
                .find(|(_, p)| **p == input)
            {
                Some((j, _)) => *delays.entry(seq - j).or_default() += 1,
                None => echo_errors += 1,
            }
        }
        while written.len() as u64 > args.max_delay + 2 {
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
         errors {echo_errors}  delays (cycles: count) {delays:?}"
    );
    if !late.is_empty() {
        println!("OPFAULT in cycles (from the first): {late:?}");
    }
    if in_time < args.min_in_time {
        bail!(
            "only {in_time:.3} % of OPDONEs in time (wanted {} %)",
            args.min_in_time
        );
    }
    if echo_errors > 0 {
        bail!(
            "{echo_errors} echo inputs were not a pattern written within {} cycles",
            args.max_delay
        );
    }
    Ok(())
}
