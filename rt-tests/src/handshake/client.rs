// SPDX-License-Identifier: MIT OR Apache-2.0
//! One measuring client, a process of its own (`procimg-handshake client …`): a synchronous
//! procimg client that owns every `clients`-th device's outputs and, each cycle, takes the
//! STARTOP, notes how long after the image was complete it woke, writes its outputs and
//! sends OPDONE, counting the allocations of its measured cycles ([`crate::alloc_count`]).
//! It talks to the coordinating process in lines: `ready` after its warm-up, then it waits
//! for `go`, measures, writes its report and says `done`, then waits for its stdin to close
//! before it detaches (so that leaving does not disturb the others). With no devices (the
//! demo) it claims nothing and only does the handshake.

use crate::alloc_count;
use crate::plant::device_name;
use anyhow::{Context, Result, bail};
use procimg_client::{AttachOptions, Client, now_ns};
use procimg_rt_tests::report::{Measurement, Report, new_histogram};
use std::io::Write;
use std::path::Path;
use std::time::Duration;

/// The client report's setting: allocations in its measured cycles (goal 0).
pub const CYCLE_ALLOCATIONS: &str = "cycle_allocations";

/// What one client does.
pub struct ClientArgs<'a> {
    /// Server instance.
    pub instance: &'a str,
    /// This client's index, 0-based.
    pub index: usize,
    /// Clients in all.
    pub clients: usize,
    /// Devices in the layout.
    pub devices: usize,
    /// Poll for STARTOP instead of sleeping.
    pub busy_poll: bool,
    /// Cycles to measure.
    pub cycles: u64,
    /// Cycles before `ready`, not measured.
    pub warmup: u64,
    /// SCHED_FIFO priority (0: stay normal).
    pub priority: u8,
    /// CPU to pin to.
    pub cpu: Option<usize>,
    /// Where the report goes.
    pub report: &'a Path,
}

/// Runs the client; errors end the process with a message the coordinator shows.
pub fn run(a: &ClientArgs<'_>) -> Result<()> {
    let name = format!("handshake-{}", a.index);
    let mut client = Client::attach(
        a.instance,
        AttachOptions::synchronous(&name).busy_poll(a.busy_poll),
    )
    .with_context(|| format!("client {} cannot attach to {}", a.index, a.instance))?;
    let mut owned = Vec::new();
    for d in (a.index..a.devices).step_by(a.clients.max(1)) {
        owned.extend(
            client
                .claim_device(&device_name(d))
                .with_context(|| format!("client {} cannot claim {}", a.index, device_name(d)))?,
        );
    }
    // The coordinator's lines, read by a thread started before this one turns real-time
    // (a thread inherits its creator's policy and CPU, and a spinning SCHED_FIFO thread
    // would never let it run).
    let (lines_tx, lines) = std::sync::mpsc::channel::<String>();
    std::thread::spawn(move || {
        let mut line = String::new();
        while std::io::stdin().read_line(&mut line).is_ok_and(|n| n > 0) {
            if lines_tx.send(line.trim().to_string()).is_err() {
                return;
            }
            line.clear();
        }
    });
    let setup = procimg_runtime::sys::rt::setup_current_thread(a.cpu, a.priority);
    procimg_client::rt_alloc::mark_current_thread_realtime();
    for w in &setup.warnings {
        eprintln!("client {}: warning: {w}", a.index);
    }
    let mut startop = new_histogram();
    let (mut said_ready, mut measuring, mut said_done) = (false, false, false);
    let (mut n, mut measured) = (0u64, 0u64);
    loop {
        // Only the measured cycles (after the warm-up and `go`) count their allocations:
        // from the wait for STARTOP to OPDONE sent, and the recording of the figure.
        let counted = measuring && measured < a.cycles;
        alloc_count::counting(counted, || -> Result<()> {
            let mut cycle = client
                .wait_startop(Duration::from_secs(2))
                .with_context(|| format!("client {}: no STARTOP", a.index))?;
            let woke = now_ns();
            let info = cycle.info();
            // Every output byte written, as a PLC program writes its Q area each cycle.
            for &s in &owned {
                if let Ok(out) = cycle.output_overwrite(s) {
                    out.fill(info.cycle_number as u8);
                }
            }
            cycle
                .set_opdone()
                .with_context(|| format!("client {}: OPDONE not sent", a.index))?;
            if counted {
                startop.saturating_record(woke.saturating_sub(info.clock_ns).max(1));
                measured += 1;
            }
            Ok(())
        })?;
        n += 1;
        if !said_ready && n >= a.warmup {
            println!("ready");
            std::io::stdout().flush()?;
            said_ready = true;
        }
        if measured == a.cycles && !said_done {
            let mut report = Report::new("procimg-handshake client");
            report
                .setting("client", a.index)
                .setting(CYCLE_ALLOCATIONS, alloc_count::allocations());
            report
                .measurements
                .push(Measurement::from_histogram("startop one way", &startop));
            report.write_json(a.report)?;
            println!("done");
            std::io::stdout().flush()?;
            said_done = true;
        }
        // Keeps answering (unmeasured) until the coordinator closes stdin, so that the
        // server sees no client stop before it has taken its figures.
        match lines.try_recv() {
            Ok(l) if l == "go" => measuring = true,
            Ok(_) => {}
            Err(std::sync::mpsc::TryRecvError::Empty) => {}
            Err(std::sync::mpsc::TryRecvError::Disconnected) => {
                if said_done {
                    return Ok(());
                }
                bail!("client {}: the coordinator went away", a.index);
            }
        }
    }
}
