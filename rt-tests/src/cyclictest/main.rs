// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg-cyclictest`: the wake-up latency of a thread set up exactly like procimgd's cycle
//! thread (same pinning, SCHED_FIFO, memory locking, stack pre-faulting and absolute
//! `clock_nanosleep` on CLOCK_MONOTONIC — the very functions procimgd calls), printed in
//! cyclictest's summary format so the two can be run side by side:
//!
//! ```text
//! T: 0 ( 1234) P:80 I:1000 C:   5000 Min:     19 Act:     22 Avg:     30 Max:     663
//! ```
//!
//! Latencies are in µs: the time the thread woke minus the time it asked to wake.

use clap::Parser;
use hdrhistogram::Histogram;
use procimg_runtime::sys::clock::{now_ns, sleep_until_ns};
use procimg_runtime::sys::rt::{hold_cpu_dma_latency_zero, lock_memory, setup_current_thread};

/// Wake-up latency of a procimgd-style cycle thread (cyclictest conventions).
#[derive(Parser)]
#[command(version, about)]
struct Args {
    /// SCHED_FIFO priority.
    #[arg(short = 'p', long = "priority", default_value_t = 80)]
    priority: u8,
    /// Interval in µs.
    #[arg(short = 'i', long = "interval", default_value_t = 1000)]
    interval_us: u64,
    /// Number of loops (0: until --duration or interrupted).
    #[arg(short = 'l', long = "loops", default_value_t = 0)]
    loops: u64,
    /// Run time, e.g. 10s, 2m (cyclictest's -D).
    #[arg(short = 'D', long = "duration")]
    duration: Option<String>,
    /// Pin to this CPU.
    #[arg(short = 'a', long = "affinity")]
    cpu: Option<usize>,
    /// Lock memory (mlockall).
    #[arg(short = 'm', long = "mlockall")]
    mlock: bool,
    /// Print only the summary at the end.
    #[arg(short = 'q', long = "quiet")]
    quiet: bool,
}

fn parse_duration(s: &str) -> Result<u64, String> {
    let (num, unit) = s.split_at(s.find(|c: char| !c.is_ascii_digit()).unwrap_or(s.len()));
    let n: u64 = num
        .parse()
        .map_err(|_| format!("{s:?} is not a duration such as 10s or 2m"))?;
    let secs = match unit {
        "" | "s" => n,
        "m" => n * 60,
        "h" => n * 3600,
        "d" => n * 86400,
        _ => return Err(format!("{s:?}: unit must be s, m, h or d")),
    };
    Ok(secs * 1_000_000_000)
}

fn summary(tid: i32, args: &Args, h: &Histogram<u64>, act: u64) -> String {
    let us = |ns: u64| ns / 1000;
    format!(
        "T: 0 ({tid:>5}) P:{} I:{} C:{:>7} Min:{:>7} Act:{:>7} Avg:{:>7} Max:{:>7}",
        args.priority,
        args.interval_us,
        h.len(),
        us(h.min()),
        us(act),
        us(h.mean() as u64),
        us(h.max())
    )
}

fn main() {
    let args = Args::parse();
    let limit_ns = match args.duration.as_deref().map(parse_duration).transpose() {
        Ok(d) => d,
        Err(e) => {
            eprintln!("procimg-cyclictest: {e}");
            std::process::exit(2);
        }
    };
    if args.mlock
        && let Err(w) = lock_memory()
    {
        eprintln!("warning: {w}");
    }
    // As cyclictest (and procimgd) do: keep CPUs out of deep idle states while measuring.
    let _dma_latency = match hold_cpu_dma_latency_zero() {
        Ok(f) => Some(f),
        Err(w) => {
            eprintln!("warning: {w}");
            None
        }
    };
    let setup = setup_current_thread(args.cpu, args.priority);
    for w in &setup.warnings {
        eprintln!("warning: {w}");
    }
    // SAFETY: gettid has no preconditions.
    let tid = unsafe { libc::gettid() };
    let mut h = Histogram::<u64>::new_with_bounds(1, 10_000_000_000, 3).expect("valid bounds");
    let interval = args.interval_us * 1000;
    let start = now_ns();
    let mut next = start + interval;
    let mut act;
    let mut last_print = start;
    loop {
        sleep_until_ns(next);
        let woke = now_ns();
        act = woke.saturating_sub(next);
        h.saturating_record(act.max(1));
        next += interval;
        if woke > next {
            // Overran a whole interval: resume at the next one ahead, as procimgd does.
            next += (woke - next) / interval * interval + interval;
        }
        if args.loops > 0 && h.len() >= args.loops {
            break;
        }
        if limit_ns.is_some_and(|l| woke - start >= l) {
            break;
        }
        if !args.quiet && woke - last_print >= 100_000_000 {
            last_print = woke;
            eprint!("{}\r", summary(tid, &args, &h, act));
        }
    }
    println!("{}", summary(tid, &args, &h, act));
}
