// SPDX-License-Identifier: MIT OR Apache-2.0
//! `--procimgd INSTANCE`: the wake-up latency of a running procimgd's own cycle thread. The
//! server keeps a histogram of it since it started; this mode takes it at the start and at
//! the end and reports the difference in the same formats as the measuring threads. The
//! server answers to 2 significant digits: the per-µs histogram is exact below about 260 µs
//! and groups 2–4 µs per bucket above.

use crate::measure::stat_field;
use crate::stats::ThreadStats;
use crate::text::Line;
use procimg_client::ControlHandle;
use procimg_control::Bucket;
use procimg_rt_tests::report::{buckets_between, histogram_from_buckets};
use std::time::{Duration, Instant};

/// How often the server's histograms are read while waiting.
pub const POLL: Duration = Duration::from_millis(100);

/// Why the server could not be read.
#[derive(Debug, thiserror::Error)]
pub enum ProcimgdError {
    /// No control service for the instance.
    #[error(
        "cannot reach procimgd instance {instance:?}: {detail}; is it running (procimg status -i {instance})?"
    )]
    Open {
        /// The instance.
        instance: String,
        /// What failed.
        detail: String,
    },
    /// A status or histograms request failed.
    #[error(
        "procimgd instance {instance:?} did not answer the {what} request: {detail}; check that it still runs and is of the same version as this tool"
    )]
    Request {
        /// The instance.
        instance: String,
        /// The request.
        what: &'static str,
        /// What failed.
        detail: String,
    },
}

/// The cycle thread of a server, as found in /proc.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CycleThread {
    /// Its kernel thread id (0 if not found).
    pub tid: u32,
    /// Its SCHED_FIFO priority (0: not real-time, or not found).
    pub priority: u8,
    /// The CPU it last ran on.
    pub cpu: Option<usize>,
}

/// Finds the thread named `procimg-cycle` of process `pid`: its tid, the real-time priority
/// (the kernel reports -1 - rtprio in field 18 of stat for SCHED_FIFO) and its CPU.
pub fn find_cycle_thread(pid: u32) -> CycleThread {
    let Ok(tasks) = std::fs::read_dir(format!("/proc/{pid}/task")) else {
        return CycleThread::default();
    };
    for task in tasks.flatten() {
        let comm = std::fs::read_to_string(task.path().join("comm")).unwrap_or_default();
        if comm.trim_end() != "procimg-cycle" {
            continue;
        }
        let stat = std::fs::read_to_string(task.path().join("stat")).unwrap_or_default();
        let prio: i64 = stat_field(&stat, 18)
            .and_then(|f| f.parse().ok())
            .unwrap_or(0);
        return CycleThread {
            tid: task
                .file_name()
                .to_str()
                .and_then(|s| s.parse().ok())
                .unwrap_or(0),
            priority: if prio < 0 {
                u8::try_from(-1 - prio).unwrap_or(0)
            } else {
                0
            },
            cpu: stat_field(&stat, 39).and_then(|f| f.parse().ok()),
        };
    }
    CycleThread::default()
}

/// An open connection to the server, and what it said at the start.
pub struct Server {
    handle: ControlHandle,
    instance: String,
    /// The wake-up histogram at the start.
    first: Vec<Bucket>,
    /// The last one read.
    last: Vec<Bucket>,
    /// Largest latency between the last two reads, µs (the `Act:` of this mode).
    act_us: u64,
    /// The line's fixed fields.
    base: ThreadStats,
    /// When the connection was opened.
    started: Instant,
    /// The server's overrun count at the start.
    overruns_at_start: u64,
}

fn total(buckets: &[Bucket]) -> u64 {
    buckets.iter().map(|b| b.count).sum()
}

impl Server {
    /// Connects to `instance` and takes its histogram as the starting point.
    pub fn open(instance: &str, hist_us: usize) -> Result<Server, ProcimgdError> {
        let handle = ControlHandle::open(instance, "procimg-cyclictest").map_err(|e| {
            ProcimgdError::Open {
                instance: instance.to_string(),
                detail: e.to_string(),
            }
        })?;
        let request = |what, detail: String| ProcimgdError::Request {
            instance: instance.to_string(),
            what,
            detail,
        };
        let status = handle
            .status()
            .map_err(|e| request("status", e.to_string()))?;
        let thread = find_cycle_thread(status.pid);
        let mut base = ThreadStats::new(0, thread.priority, status.cycle_ns / 1000, hist_us);
        base.tid = if thread.tid != 0 {
            thread.tid
        } else {
            status.pid
        };
        base.cpu = thread.cpu;
        if !status.realtime {
            base.priority = 0;
        }
        let first = handle
            .histograms()
            .map_err(|e| request("histograms", e.to_string()))?
            .wakeup;
        Ok(Server {
            handle,
            instance: instance.to_string(),
            last: first.clone(),
            first,
            act_us: 0,
            base,
            started: Instant::now(),
            overruns_at_start: status.overruns,
        })
    }

    /// Reads the histogram again. Returns the wake-ups recorded since the start.
    pub fn poll(&mut self) -> Result<u64, ProcimgdError> {
        let now = self
            .handle
            .histograms()
            .map_err(|e| ProcimgdError::Request {
                instance: self.instance.clone(),
                what: "histograms",
                detail: e.to_string(),
            })?
            .wakeup;
        let recent = buckets_between(&self.last, &now);
        if let Some(b) = recent.last() {
            self.act_us = b.ns / 1000;
        }
        self.last = now;
        Ok(total(&self.last).saturating_sub(total(&self.first)))
    }

    /// How long this mode has been reading.
    pub fn elapsed(&self) -> Duration {
        self.started.elapsed()
    }

    /// The results so far: the difference between the last read and the first.
    pub fn stats(&self, hist_us: usize) -> ThreadStats {
        let h = histogram_from_buckets(&buckets_between(&self.first, &self.last));
        let mut s = self.base.clone();
        s.fill_from_histogram(&h, hist_us);
        s.act_us = self.act_us;
        s
    }

    /// The server's overruns since the start (asks the server).
    pub fn overruns(&self) -> Result<u64, ProcimgdError> {
        let status = self.handle.status().map_err(|e| ProcimgdError::Request {
            instance: self.instance.clone(),
            what: "status",
            detail: e.to_string(),
        })?;
        Ok(status.overruns.saturating_sub(self.overruns_at_start))
    }

    /// The live line so far.
    pub fn line(&self) -> Line {
        Line::of(&self.stats(0))
    }
}
