// SPDX-License-Identifier: MIT OR Apache-2.0
//! The soak's synchronous client (`procimg-soak client`, started by the soak itself): a
//! PLC-style loop on the device's outputs and inputs, in a process of its own so that the
//! soak can kill it.
//!
//! Every cycle it waits for STARTOP, checks the device's inputs and writes the next value to
//! its outputs, then signals OPDONE. The value of the k-th handled cycle carries k, and the
//! device answers every output byte plus one, so valid inputs name the output they answer:
//! an answer to no value this client wrote is a data error (torn or foreign data); an answer
//! to a value more than [`HISTORY`] handled cycles old is stale (its outputs were held while
//! OPDONE came late, or the device's application lagged), counted apart. It survives a
//! restart of procimgd (the client library re-attaches) and takes its claim again when it
//! was lost.
//!
//! Standard output, one line per event: `ATTACHED`, `ECHO` (the first answer after
//! attaching or re-attaching), `REATTACHED`, and every second
//! `COUNT cycles=N opfaults=N wrong=N stale=N oldest=N` (`oldest`: the largest age of an
//! answer, in handled cycles).

use anyhow::{Context as _, bail};
use procimg_client::{AttachOptions, Client, Event, Ioxs, WaitError};
use std::io::Write as _;
use std::time::{Duration, Instant};

/// Bytes of the device's input and output submodules.
const IO_LEN: usize = 8;
/// Answers up to this many handled cycles old are in time: the device answers in its own
/// cycle, a few cycles after the value went out, more when OPDONE came late.
const HISTORY: u64 = 64;
/// How long the client keeps trying to attach when procimgd is not there yet.
const ATTACH_TIMEOUT: Duration = Duration::from_secs(60);
/// SCHED_FIFO priority of the loop: below procimgd's cycle thread (80).
const PRIORITY: u8 = 70;

fn emit(line: &str) {
    let mut out = std::io::stdout().lock();
    let _ = writeln!(out, "{line}");
    let _ = out.flush();
}

/// The value written in the `k`-th handled cycle.
fn value(k: u64) -> [u8; IO_LEN] {
    let mut v = k.to_le_bytes();
    // Never all zero: zero inputs are what the device publishes before its first answer.
    v[IO_LEN - 1] |= 0x80;
    v
}

/// The handled cycle whose value `answer` answers (every byte is the value's plus one), if it
/// is one of this client's values at all.
fn answered(answer: &[u8; IO_LEN]) -> Option<u64> {
    let mut v = answer.map(|b| b.wrapping_sub(1));
    if v[IO_LEN - 1] & 0x80 == 0 {
        return None;
    }
    v[IO_LEN - 1] &= 0x7f;
    Some(u64::from_le_bytes(v))
}

/// The device's output and input submodule in the layout.
fn submodules(client: &Client, device: &str) -> anyhow::Result<(usize, usize)> {
    let layout = client.layout();
    let d = layout
        .device(device)
        .with_context(|| format!("no device {device:?} in procimgd's layout"))?;
    let find = |output: bool| {
        layout.submodules_of(d).find(|&s| {
            let e = &layout.submodules[s];
            let len = if output {
                e.output_length
            } else {
                e.input_length
            };
            len as usize == IO_LEN
        })
    };
    let output = find(true).context("the device has no 8-byte output submodule")?;
    let input = find(false).context("the device has no 8-byte input submodule")?;
    Ok((output, input))
}

fn attach(instance: &str) -> anyhow::Result<Client> {
    let until = Instant::now() + ATTACH_TIMEOUT;
    loop {
        match Client::attach(instance, AttachOptions::synchronous("soak-client")) {
            Ok(c) => return Ok(c),
            Err(e) if Instant::now() >= until => {
                return Err(e).with_context(|| format!("attaching to {instance:?}"));
            }
            Err(_) => std::thread::sleep(Duration::from_millis(50)),
        }
    }
}

/// The client loop; runs until killed.
pub fn run(instance: &str, device: &str) -> anyhow::Result<()> {
    if let Err(e) = procimg_client::realtime::make_current_thread_realtime(PRIORITY) {
        eprintln!("soak client: at normal priority ({e})");
    }
    let mut client = attach(instance)?;
    let (output, input) = submodules(&client, device)?;
    client
        .claim(&[output])
        .with_context(|| format!("claiming the outputs of {device:?}"))?;
    emit("ATTACHED");

    let (mut k, mut opfaults, mut wrong, mut stale, mut oldest) = (0u64, 0u64, 0u64, 0u64, 0u64);
    let mut echoed = false;
    let mut next_count = Instant::now() + Duration::from_secs(1);
    loop {
        match client.wait_startop(Duration::from_secs(1)) {
            Ok(mut cycle) => {
                let mut seen = [0u8; IO_LEN];
                if let Some(i) = cycle.input(input) {
                    let n = i.len().min(IO_LEN);
                    seen[..n].copy_from_slice(&i[..n]);
                }
                let good = cycle
                    .status(input)
                    .is_some_and(|s| s.input_remote == Ioxs::Good);
                if good && seen != [0; IO_LEN] {
                    // Before the first answer after (re-)attaching, the inputs may still
                    // answer a predecessor's outputs, which procimgd held.
                    match answered(&seen).filter(|&j| j < k) {
                        Some(_) if !echoed => {
                            echoed = true;
                            emit("ECHO");
                        }
                        Some(j) => {
                            oldest = oldest.max(k - j);
                            if k - j > HISTORY {
                                stale += 1;
                            }
                        }
                        None if echoed => {
                            wrong += 1;
                            eprintln!("soak client: inputs {seen:02x?} answer no value it wrote");
                        }
                        None => {}
                    }
                }
                if let Ok(out) = cycle.output_mut(output) {
                    out.copy_from_slice(&value(k));
                    k += 1;
                }
                let _ = cycle.set_opdone();
            }
            Err(WaitError::ServerGone { .. } | WaitError::Timeout(_)) => {}
            Err(e) => bail!("waiting for STARTOP: {e}"),
        }
        for event in client.events() {
            match event {
                Event::OpFault { .. } => opfaults += 1,
                Event::Reattached { .. } => {
                    echoed = false;
                    emit("REATTACHED");
                }
                Event::ClaimLost { .. } => {
                    let _ = client.claim(&[output]);
                }
                _ => {}
            }
        }
        if Instant::now() >= next_count {
            next_count += Duration::from_secs(1);
            emit(&format!(
                "COUNT cycles={k} opfaults={opfaults} wrong={wrong} stale={stale} oldest={oldest}"
            ));
        }
    }
}
