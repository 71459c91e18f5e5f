// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg-handshake startup`: what procimgd costs before the first cycle and what a client
//! waits to attach, for an image of the size asked for (the generated plant, nobody
//! answering):
//!
//! - **start to first cycle**: from spawning procimgd until its status first shows a cycle
//!   run (polled every [`START_POLL`], so good to about that);
//! - **Locked, VmLck, VmRSS** of procimgd after the attaches (the larger of that and the
//!   reading at the start): `Locked` from `/proc/<pid>/smaps_rollup` is the memory locked and
//!   resident, the RAM procimgd pins; `VmLck` from `/proc/<pid>/status` counts whole mappings
//!   flagged locked, also the pages of those locked on fault that were never faulted in (see
//!   `procimg_runtime::shm::reserve`);
//! - **client attach**: `Client::attach` of a synchronous client, timed call by call, each
//!   client dropped (detached) before the next;
//! - **control request**: a status request over the control service and its answer, timed
//!   one after the other ([`REQUESTS`] of them, [`REQUEST_PAUSE`] apart, so that each finds
//!   the control thread asleep, as a program's occasional request does).

use crate::plant::Plant;
use crate::server::{START_POLL, Server};
use anyhow::{Context, Result};
use procimg_client::{AttachOptions, Client, ControlHandle};
use procimg_rt_tests::names::{ATTACH, FIRST_CYCLE, LOCKED_KIB, REQUEST, VMLCK_KIB, VMRSS_KIB};
use procimg_rt_tests::report::{Measurement, Report, new_histogram};
use std::path::Path;
use std::time::{Duration, Instant};

/// Control requests timed.
const REQUESTS: u32 = 200;
/// Between two timed requests.
const REQUEST_PAUSE: Duration = Duration::from_millis(5);

/// Runs the measurement and prints and writes its report.
pub fn run(image_bytes: usize, attaches: u32, report_path: Option<&Path>) -> Result<()> {
    let instance = format!("startup-{}", std::process::id());
    let plant = Plant::at_one_ms(&instance, image_bytes);
    let dir = std::env::temp_dir().join(format!("procimg-startup-{}", std::process::id()));
    std::fs::create_dir_all(&dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let _cleanup = crate::RemoveOnDrop(dir.clone());
    let config = dir.join("procimgd.toml");
    std::fs::write(&config, plant.toml())
        .with_context(|| format!("cannot write {}", config.display()))?;
    let server = Server::start(&config, &instance, &dir.join("procimgd.log"))?;
    let first_cycle = server.first_cycle();
    let at_start = memory(server.pid())?;

    let mut attach = new_histogram();
    for i in 0..attaches {
        let name = format!("startup-{i}");
        let t = Instant::now();
        let client = Client::attach(&instance, AttachOptions::synchronous(&name))
            .with_context(|| format!("attach {i} to {instance} failed"))?;
        attach.saturating_record(duration_ns(t.elapsed()));
        drop(client);
        // Let the server take the connection down before the next one comes.
        std::thread::sleep(Duration::from_millis(20));
    }
    let mut request = new_histogram();
    let control = ControlHandle::open(&instance, "startup-requests")
        .with_context(|| format!("cannot open the control service of {instance}"))?;
    for i in 0..REQUESTS {
        std::thread::sleep(REQUEST_PAUSE);
        let t = Instant::now();
        control
            .status()
            .with_context(|| format!("status request {i} to {instance} failed"))?;
        request.saturating_record(duration_ns(t.elapsed()));
    }
    drop(control);
    let after = memory(server.pid())?;
    let (vmlck, vmrss, locked) = (
        at_start.0.max(after.0),
        at_start.1.max(after.1),
        at_start.2.max(after.2),
    );
    drop(server);

    let mut first = new_histogram();
    first.saturating_record(duration_ns(first_cycle));
    let mut report = Report::new("procimg-handshake startup");
    report
        .setting("image_bytes", image_bytes)
        .setting("devices", plant.device_sizes().len())
        .setting("max_clients", procimg_shm_layout::MAX_CLIENTS)
        .setting("attaches", attaches)
        .setting("attach_role", "synchronous")
        .setting("start_poll_ms", START_POLL.as_millis())
        .setting(LOCKED_KIB, locked)
        .setting(VMLCK_KIB, vmlck)
        .setting(VMRSS_KIB, vmrss);
    report.measurements = vec![
        Measurement::from_histogram(FIRST_CYCLE, &first),
        Measurement::from_histogram(ATTACH, &attach),
        Measurement::from_histogram(REQUEST, &request),
    ];
    println!(
        "# procimgd, {image_bytes} B each way, {} clients allowed: Locked {locked} KiB, VmLck \
         {vmlck} KiB, VmRSS {vmrss} KiB; start to first cycle {:.1} ms; attach (synchronous) p50 {:.2} ms, max \
         {:.2} ms over {attaches}; control request p50 {:.3} ms, max {:.3} ms over {REQUESTS}",
        procimg_shm_layout::MAX_CLIENTS,
        first_cycle.as_secs_f64() * 1000.0,
        attach.value_at_quantile(0.5) as f64 / 1e6,
        attach.max() as f64 / 1e6,
        request.value_at_quantile(0.5) as f64 / 1e6,
        request.max() as f64 / 1e6,
    );
    report.save(report_path, None)?;
    Ok(())
}

fn duration_ns(d: Duration) -> u64 {
    u64::try_from(d.as_nanos()).unwrap_or(u64::MAX).max(1)
}

/// (VmLck, VmRSS, Locked) of process `pid` in KiB.
fn memory(pid: u32) -> Result<(u64, u64, u64)> {
    let rollup = format!("/proc/{pid}/smaps_rollup");
    let rolled =
        std::fs::read_to_string(&rollup).with_context(|| format!("cannot read {rollup}"))?;
    let locked = status_kib(&rolled, "Locked")
        .with_context(|| format!("{rollup} has no Locked line (Linux 4.14 or later has it)"))?;
    let path = format!("/proc/{pid}/status");
    let text = std::fs::read_to_string(&path).with_context(|| format!("cannot read {path}"))?;
    let field = |name: &str| {
        status_kib(&text, name)
            .with_context(|| format!("{path} has no {name} line (is procfs mounted?)"))
    };
    Ok((field("VmLck")?, field("VmRSS")?, locked))
}

/// The value in KiB of the line `name:` of a `/proc/<pid>/status` text.
pub fn status_kib(text: &str, name: &str) -> Option<u64> {
    text.lines()
        .find_map(|l| l.strip_prefix(name)?.strip_prefix(':'))
        .and_then(procimg_shm_layout::maps::kib)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn proc_status_lines_are_read_in_kib() {
        let text = "Name:\tprocimgd\nVmLck:\t   23456 kB\nVmRSS:\t    7890 kB\nVmLckX:\t1 kB\n";
        assert_eq!(status_kib(text, "VmLck"), Some(23_456));
        assert_eq!(status_kib(text, "VmRSS"), Some(7_890));
        assert_eq!(status_kib(text, "VmSwap"), None);
    }
}
