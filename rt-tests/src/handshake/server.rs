// SPDX-License-Identifier: MIT OR Apache-2.0
//! The procimgd under measurement: started from the binary next to this one, with the
//! generated configuration, stopped (SIGINT, then SIGKILL) whatever happens.

use anyhow::{Context, Result, bail};
use procimg_client::ControlHandle;
use procimg_control::HistogramsReport;
use procimg_runtime::stats::HANDOFF_CYCLES;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// A running procimgd; stopped on drop.
pub struct Server {
    child: Child,
    control: ControlHandle,
    first_cycle: Duration,
}

/// procimgd's counters that the tools take differences of.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    /// Cycles run.
    pub cycles: u64,
    /// Cycles that overran.
    pub overruns: u64,
    /// OPFAULTs given.
    pub opfaults: u64,
    /// System-allocator calls of the cycle thread in its cycles (outside connection set-up).
    pub heap_allocations: u64,
}

impl Counters {
    /// `self − earlier`, counter by counter.
    pub fn since(self, earlier: Counters) -> Counters {
        Counters {
            cycles: self.cycles.saturating_sub(earlier.cycles),
            overruns: self.overruns.saturating_sub(earlier.overruns),
            opfaults: self.opfaults.saturating_sub(earlier.opfaults),
            heap_allocations: self
                .heap_allocations
                .saturating_sub(earlier.heap_allocations),
        }
    }
}

/// How often the start is polled.
pub const START_POLL: Duration = Duration::from_millis(1);

/// The procimgd binary: beside this tool (both are built into the same target directory).
pub fn procimgd_path() -> Result<PathBuf> {
    let me = std::env::current_exe().context("cannot find this program's path")?;
    let path = me.with_file_name("procimgd");
    if !path.exists() {
        bail!(
            "{} is missing: build it with `cargo build --release --bins` (procimg-handshake \
             starts the procimgd beside it)",
            path.display()
        );
    }
    Ok(path)
}

impl Server {
    /// Starts procimgd with `config` and waits until it answers on `instance`; its log goes
    /// to `log`.
    pub fn start(config: &Path, instance: &str, log: &Path) -> Result<Server> {
        let log_file = std::fs::File::create(log)
            .with_context(|| format!("cannot create {}", log.display()))?;
        let mut child = Command::new(procimgd_path()?)
            .arg("--config")
            .arg(config)
            .arg("--quiet")
            .stdin(Stdio::null())
            .stdout(log_file.try_clone()?)
            .stderr(log_file)
            .spawn()
            .context("cannot start procimgd")?;
        let spawned = Instant::now();
        // Generous: with a large image, mlockall makes procimgd populate every sample slot of
        // the image service (one per subscriber it may have) before it cycles.
        let until = spawned + Duration::from_secs(60);
        let mut control = None;
        let mut first_cycle = None;
        loop {
            if let Some(status) = child.try_wait()? {
                bail!(
                    "procimgd ended at start ({status}); its log, {}:\n{}",
                    log.display(),
                    std::fs::read_to_string(log).unwrap_or_default()
                );
            }
            // The control service exists once procimgd is up; it answers once it cycles.
            if control.is_none() {
                control = ControlHandle::open(instance, "procimg-handshake").ok();
            }
            if let Some(s) = control.as_ref().and_then(|c| c.status().ok()) {
                if s.cycle_count > 0 && first_cycle.is_none() {
                    first_cycle = Some(spawned.elapsed());
                }
                if s.cycle_count > 10
                    && let Some(control) = control.take()
                {
                    return Ok(Server {
                        child,
                        control,
                        first_cycle: first_cycle.unwrap_or_else(|| spawned.elapsed()),
                    });
                }
            }
            if Instant::now() > until {
                let _ = child.kill();
                let _ = child.wait();
                bail!(
                    "procimgd on instance {instance} did not answer within 60 s; its log: {}",
                    log.display()
                );
            }
            // Often enough to time the start to the first cycle to about a millisecond.
            std::thread::sleep(START_POLL);
        }
    }

    /// From spawning procimgd until `procimg status` first showed a cycle run (polled every
    /// [`START_POLL`]).
    pub fn first_cycle(&self) -> Duration {
        self.first_cycle
    }

    /// The server's histograms since it started.
    pub fn histograms(&self) -> Result<HistogramsReport> {
        self.control
            .histograms()
            .context("procimgd did not answer the histogram request")
    }

    /// The histograms once every cycle run so far has been handed over: the cycle thread
    /// hands its figures over every [`HANDOFF_CYCLES`] cycles, so an answer taken right
    /// after the clients' last measured cycle lacks up to that many. The clients keep
    /// answering meanwhile, so the extra cycles are handshakes like the measured ones.
    pub fn histograms_after_handover(&self) -> Result<HistogramsReport> {
        let first = self.histograms()?;
        let until = Instant::now() + Duration::from_secs(10);
        loop {
            let now = self.histograms()?;
            if now.cycles >= first.cycles + 2 * HANDOFF_CYCLES {
                return Ok(now);
            }
            if Instant::now() > until {
                bail!(
                    "procimgd ran only {} cycles in 10 s; its histograms stay incomplete",
                    now.cycles - first.cycles
                );
            }
            std::thread::sleep(Duration::from_millis(5));
        }
    }

    /// The counters so far.
    pub fn counters(&self) -> Result<Counters> {
        let s = self.control.status().context("procimgd did not answer")?;
        Ok(Counters {
            cycles: s.cycle_count,
            overruns: s.overruns,
            opfaults: s.opfaults,
            heap_allocations: s.rt_heap_allocations,
        })
    }

    /// The server's process id.
    pub fn pid(&self) -> u32 {
        self.child.id()
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        procimg_netns::signal::stop(&mut self.child, libc::SIGINT, Duration::from_secs(5));
    }
}
