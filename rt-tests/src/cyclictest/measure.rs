// SPDX-License-Identifier: MIT OR Apache-2.0
//! The measuring threads: set up like procimgd's cycle thread, then the same absolute sleeps
//! and the same overrun rule as its loop (`procimg_runtime::cycle::thread::run`), recording
//! each wake-up without allocating and without locks.

use crate::args::ThreadPlan;
use crate::stats::ThreadStats;
use procimg_runtime::sys::clock::{now_ns, sleep_until_ns};
use procimg_runtime::sys::rt::{RtSetup, pin_to, prefault_stack, setup_current_thread};
use procimg_runtime::sys::rt_alloc;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU32, AtomicU64, Ordering};
use std::thread::JoinHandle;

/// What the main thread may read of a measuring thread while it runs (the live lines): plain
/// atomics written with relaxed stores, so the measuring thread never waits for a reader.
#[derive(Debug, Default)]
pub struct Live {
    /// Kernel thread id, once the thread runs.
    pub tid: AtomicU32,
    /// Wake-ups so far.
    pub cycles: AtomicU64,
    /// Smallest latency so far, µs.
    pub min_us: AtomicU64,
    /// Latest latency, µs.
    pub act_us: AtomicU64,
    /// Sum of latencies, µs.
    pub sum_us: AtomicU64,
    /// Largest latency so far, µs.
    pub max_us: AtomicU64,
    /// The thread got SCHED_FIFO.
    pub realtime: AtomicBool,
    /// The thread has finished.
    pub done: AtomicBool,
}

/// A started measuring thread.
pub struct Running {
    /// Its plan.
    pub plan: ThreadPlan,
    /// Its live figures.
    pub live: Arc<Live>,
    /// Its results, when it ends.
    pub handle: JoinHandle<ThreadStats>,
}

/// Why a measuring thread could not be started.
#[derive(Debug, thiserror::Error)]
#[error(
    "cannot start measuring thread {index}: {source}; lower -t or raise the thread limit (ulimit -u)"
)]
pub struct SpawnError {
    /// The thread number.
    pub index: usize,
    /// The OS error.
    pub source: std::io::Error,
}

/// The calling thread's kernel id, from /proc/thread-self (a link to `<pid>/task/<tid>`).
pub fn current_tid() -> u32 {
    std::fs::read_link("/proc/thread-self")
        .ok()
        .and_then(|p| p.file_name()?.to_str()?.parse().ok())
        .unwrap_or(0)
}

/// The CPU the calling thread last ran on (field 39 of /proc/thread-self/stat).
pub fn current_cpu() -> Option<usize> {
    let stat = std::fs::read_to_string("/proc/thread-self/stat").ok()?;
    stat_field(&stat, 39)?.parse().ok()
}

/// Field `n` (1-based, as in proc(5)) of a /proc/…/stat line; the command name in field 2
/// may hold spaces and parentheses, so fields are counted after its closing parenthesis.
pub fn stat_field(stat: &str, n: usize) -> Option<&str> {
    let rest = &stat[stat.rfind(')')? + 1..];
    rest.split_whitespace().nth(n.checked_sub(3)?)
}

/// procimgd's set-up for `plan`; priority 0 keeps normal scheduling (cyclictest without -p).
fn set_up(plan: &ThreadPlan) -> RtSetup {
    if plan.priority > 0 {
        return setup_current_thread(plan.cpu, plan.priority);
    }
    let mut setup = RtSetup::default();
    if let Some(cpu) = plan.cpu {
        match pin_to(cpu) {
            Ok(()) => setup.pinned_cpu = Some(cpu),
            Err(w) => setup.warnings.push(w),
        }
    }
    prefault_stack();
    setup
}

/// Starts the measuring thread for `plan`. It ends after `loops` wake-ups (0: no limit), or
/// when it finds `stop` set after a wake-up.
pub fn spawn(
    plan: ThreadPlan,
    loops: u64,
    hist_us: usize,
    stop: Arc<AtomicBool>,
) -> Result<Running, SpawnError> {
    let live = Arc::new(Live::default());
    let thread_live = live.clone();
    let thread_plan = plan.clone();
    let handle = std::thread::Builder::new()
        .name(format!("procimg-ct{}", plan.index))
        .spawn(move || measure(&thread_plan, loops, hist_us, &stop, &thread_live))
        .map_err(|source| SpawnError {
            index: plan.index,
            source,
        })?;
    Ok(Running { plan, live, handle })
}

fn measure(
    plan: &ThreadPlan,
    loops: u64,
    hist_us: usize,
    stop: &AtomicBool,
    live: &Live,
) -> ThreadStats {
    let setup = set_up(plan);
    for w in &setup.warnings {
        eprintln!("warning: T:{}: {w}", plan.index);
    }
    live.realtime.store(setup.realtime, Ordering::Relaxed);
    // The line shows the priority the thread really runs at: 0 if SCHED_FIFO was refused.
    let priority = if setup.realtime { plan.priority } else { 0 };
    let mut stats = ThreadStats::new(plan.index, priority, plan.interval_us, hist_us);
    stats.tid = current_tid();
    live.tid.store(stats.tid, Ordering::Relaxed);

    // From here to the end of the loop the thread must not touch the heap; procimgd's
    // allocator counts it if it does (see `allocations_while_measuring`).
    rt_alloc::mark_current_thread_realtime();
    let period = plan.interval_us * 1000;
    let epoch = now_ns();
    let mut k: u64 = 1;
    loop {
        let t0 = epoch + k * period;
        sleep_until_ns(t0);
        let woke = now_ns();
        if stop.load(Ordering::Relaxed) {
            break;
        }
        stats.record(woke.saturating_sub(t0));
        live.cycles.store(stats.cycles, Ordering::Relaxed);
        live.min_us.store(stats.min_us, Ordering::Relaxed);
        live.act_us.store(stats.act_us, Ordering::Relaxed);
        live.sum_us.store(stats.sum_us, Ordering::Relaxed);
        live.max_us.store(stats.max_us, Ordering::Relaxed);
        if loops > 0 && stats.cycles >= loops {
            // The main thread ends the others when it sees this one done (within its tick,
            // as cyclictest does), so threads at the same interval all finish their loops.
            break;
        }
        // procimgd's rule: a cycle still running when the next should start is an overrun,
        // and the loop resumes at the next period still ahead.
        let now = now_ns();
        if now >= epoch + (k + 1) * period {
            stats.overruns += 1;
            k = (now - epoch) / period + 1;
        } else {
            k += 1;
        }
    }
    rt_alloc::clear_current_thread_realtime();
    stats.cpu = current_cpu();
    live.done.store(true, Ordering::Release);
    stats
}

/// Allocations made by measuring threads while they were marked real-time (0 when the loop
/// is allocation-free as it must be).
pub fn allocations_while_measuring() -> u64 {
    rt_alloc::rt_heap_allocations() + rt_alloc::pool_allocations()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stat_fields_are_counted_after_the_command_name() {
        let stat = "123 (a (b) c) S 1 2 3";
        assert_eq!(stat_field(stat, 3), Some("S"));
        assert_eq!(stat_field(stat, 6), Some("3"));
        assert_eq!(stat_field(stat, 7), None);
    }

    #[test]
    fn tid_and_cpu_are_found() {
        assert!(current_tid() > 0);
        assert!(current_cpu().is_some());
    }
}
