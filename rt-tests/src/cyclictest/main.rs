// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg-cyclictest`: the wake-up latency of threads set up exactly like procimgd's cycle
//! thread (same pinning, SCHED_FIFO, memory locking, stack pre-faulting, absolute
//! `clock_nanosleep` on CLOCK_MONOTONIC and overrun rule — the very functions procimgd
//! calls), with cyclictest's options and output formats so the two can be run side by side:
//!
//! ```text
//! T: 0 ( 1234) P:80 I:1000 C:   5000 Min:     19 Act:   22 Avg:   30 Max:     663
//! ```
//!
//! With `--procimgd INSTANCE` it measures nothing itself and reports a running server's own
//! cycle thread instead, from the histogram the server keeps.
//!
//! Files: `args` (the command line), `measure` (the measuring threads), `stats` (one
//! thread's results), `procimgd` (the server mode), `text` (summary, live and histogram
//! formats), `json` (cyclictest's --json), `files` (procimg's --report / --hdr-log),
//! `signal` (Ctrl-C).

mod args;
mod files;
mod json;
mod measure;
mod procimgd;
mod signal;
mod stats;
mod text;

use anyhow::{Context, Result};
use args::{Args, thread_plans};
use clap::Parser;
use procimg_runtime::sys::rt::{hold_cpu_dma_latency_zero, lock_memory};
use procimg_runtime::sys::rt_alloc::RtAllocator;
use stats::ThreadStats;
use std::io::Write as _;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant, SystemTime};
use text::Line;

// procimgd's allocator: it tells whether a measuring loop ever allocated.
#[global_allocator]
static ALLOCATOR: RtAllocator = RtAllocator;

/// How often the live lines are redrawn (cyclictest: every 10 ms; this is gentler on the
/// CPUs being measured).
const LIVE_EVERY: Duration = Duration::from_millis(100);
/// How often the main thread looks at the clock, Ctrl-C and the threads.
const TICK: Duration = Duration::from_millis(10);

fn main() -> std::process::ExitCode {
    let args = Args::parse();
    match run(&args) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("procimg-cyclictest: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}

fn run(args: &Args) -> Result<()> {
    if let Err(w) = signal::install() {
        eprintln!("warning: {w}");
    }
    let hist_us = args.histogram_us().unwrap_or(0) as usize;
    let start = SystemTime::now();
    let (threads, mode) = match &args.procimgd {
        Some(instance) => (
            vec![read_procimgd(args, instance, hist_us)?],
            format!("procimgd {instance}"),
        ),
        None => (measure_threads(args, hist_us)?, "threads".to_string()),
    };
    let end = SystemTime::now();

    let lines: Vec<Line> = threads.iter().map(Line::of).collect();
    let mut stdout = std::io::stdout().lock();
    if !args.quiet {
        // The final state of the live block, in place of the last one drawn.
        stdout.write_all(text::live_block(policy(&threads), &lines, false).as_bytes())?;
    } else if hist_us == 0 {
        // As cyclictest: with -q and a histogram, only the histogram is printed, so the
        // scripts that plot it can take every line that does not start with '#'.
        for l in &lines {
            writeln!(stdout, "{}", text::summary_line(l))?;
        }
    }
    if hist_us > 0 {
        let dump = text::histogram_dump(&threads, args.histofall.is_some());
        match &args.histfile {
            Some(path) => std::fs::write(path, dump).with_context(|| {
                format!(
                    "cannot write the histogram to {}; check that the directory exists and is writable",
                    path.display()
                )
            })?,
            None => stdout.write_all(dump.as_bytes())?,
        }
    }
    stdout.flush()?;
    if let Some(path) = &args.json {
        json::write(path, &threads, json::RunTimes { start, end }, 0)?;
    }
    if args.report.is_some() || args.hdr_log.is_some() {
        let report = files::report(&threads, &mode, args.mlock);
        report.save(args.report.as_deref(), args.hdr_log.as_deref())?;
    }
    Ok(())
}

/// The scheduling policy for the live lines: "fifo" when every thread got SCHED_FIFO.
fn policy(threads: &[ThreadStats]) -> &'static str {
    if !threads.is_empty() && threads.iter().all(|t| t.priority > 0) {
        "fifo"
    } else {
        "other"
    }
}

/// Whether the run should end: Ctrl-C, or -D elapsed.
fn time_is_up(args: &Args, started: Instant) -> bool {
    signal::interrupted() || args.duration.is_some_and(|d| started.elapsed() >= d)
}

/// Runs the measuring threads until the first has done -l loops, -D has passed or Ctrl-C,
/// drawing the live lines meanwhile unless -q.
fn measure_threads(args: &Args, hist_us: usize) -> Result<Vec<ThreadStats>> {
    // All of it, as cyclictest's -m (mlockall(MCL_CURRENT | MCL_FUTURE)) locks.
    if args.mlock
        && let Err(w) = lock_memory(true)
    {
        eprintln!("warning: {w}");
    }
    // As cyclictest (and procimgd) do: keep CPUs out of deep idle states while measuring.
    // Said on stderr, so that stdout holds only what -q promises.
    let _dma_latency = match hold_cpu_dma_latency_zero() {
        Ok(f) => {
            eprintln!("# /dev/cpu_dma_latency set to 0us");
            Some(f)
        }
        Err(w) => {
            eprintln!("warning: {w}");
            None
        }
    };
    let allocations_before = measure::allocations_while_measuring();
    let stop = Arc::new(AtomicBool::new(false));
    let mut running = Vec::new();
    for plan in thread_plans(args) {
        match measure::spawn(plan, args.loops, hist_us, stop.clone()) {
            Ok(r) => running.push(r),
            Err(e) => {
                stop.store(true, Ordering::Relaxed);
                for r in running {
                    let _ = r.handle.join();
                }
                return Err(e.into());
            }
        }
    }
    let started = Instant::now();
    let mut last_live: Option<Instant> = None;
    let mut stdout = std::io::stdout();
    while !running.iter().all(|r| r.live.done.load(Ordering::Acquire)) {
        std::thread::sleep(TICK);
        // As cyclictest: the first thread done with its loops ends the run.
        if time_is_up(args, started) || running.iter().any(|r| r.live.done.load(Ordering::Acquire))
        {
            stop.store(true, Ordering::Relaxed);
        }
        if !args.quiet && last_live.is_none_or(|t| t.elapsed() >= LIVE_EVERY) {
            let lines: Vec<Line> = running.iter().map(live_line).collect();
            let realtime = running
                .iter()
                .all(|r| r.plan.priority > 0 && r.live.realtime.load(Ordering::Relaxed));
            let policy = if realtime { "fifo" } else { "other" };
            let block = text::live_block(policy, &lines, last_live.is_none());
            // A terminal that cannot take the lines is no reason to stop measuring.
            let _ = stdout.write_all(block.as_bytes());
            let _ = stdout.flush();
            last_live = Some(Instant::now());
        }
    }
    let mut threads = Vec::with_capacity(running.len());
    for r in running {
        let index = r.plan.index;
        let stats = r
            .handle
            .join()
            .map_err(|_| anyhow::anyhow!("measuring thread {index} failed; please report this"))?;
        threads.push(stats);
    }
    if last_live.is_none() && !args.quiet {
        // No block was drawn: the final one must not move the cursor up.
        let lines: Vec<Line> = threads.iter().map(Line::of).collect();
        let _ = stdout.write_all(text::live_block(policy(&threads), &lines, true).as_bytes());
    }
    let allocations = measure::allocations_while_measuring() - allocations_before;
    if allocations > 0 {
        eprintln!(
            "warning: the measuring loops allocated {allocations} times; the figures include \
             allocator time (please report this)"
        );
    }
    Ok(threads)
}

/// A running thread's `T:` line from its live figures.
fn live_line(r: &measure::Running) -> Line {
    let cycles = r.live.cycles.load(Ordering::Relaxed);
    Line {
        index: r.plan.index,
        tid: r.live.tid.load(Ordering::Relaxed),
        priority: if r.live.realtime.load(Ordering::Relaxed) {
            r.plan.priority
        } else {
            0
        },
        interval_us: r.plan.interval_us,
        cycles,
        min_us: r.live.min_us.load(Ordering::Relaxed),
        act_us: r.live.act_us.load(Ordering::Relaxed),
        avg_us: r
            .live
            .sum_us
            .load(Ordering::Relaxed)
            .checked_div(cycles)
            .unwrap_or(0),
        max_us: r.live.max_us.load(Ordering::Relaxed),
    }
}

/// The --procimgd mode: reads the server's wake-up histogram until it holds -l more wake-ups,
/// -D has passed or Ctrl-C.
fn read_procimgd(args: &Args, instance: &str, hist_us: usize) -> Result<ThreadStats> {
    let mut server = procimgd::Server::open(instance, hist_us)?;
    let mut first = true;
    let mut stdout = std::io::stdout();
    loop {
        std::thread::sleep(procimgd::POLL);
        let recorded = server.poll()?;
        if !args.quiet {
            let line = server.line();
            let policy = if line.priority > 0 { "fifo" } else { "other" };
            let block = text::live_block(policy, &[line], first);
            let _ = stdout.write_all(block.as_bytes());
            let _ = stdout.flush();
            first = false;
        }
        if (args.loops > 0 && recorded >= args.loops)
            || signal::interrupted()
            || args.duration.is_some_and(|d| server.elapsed() >= d)
        {
            break;
        }
    }
    let mut stats = server.stats(hist_us);
    stats.overruns = server.overruns()?;
    Ok(stats)
}
