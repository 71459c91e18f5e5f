// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg-baseline`: the limits every procimg figure is a ratio to, measured on this
//! machine the way procimg would meet them.
//!
//! - `spin`: two processes ping-pong a sequence number over two cache lines of shared memory,
//!   busy-polling: the hardware limit of a busy-polling handshake;
//! - `futex`: the same, each side sleeping in FUTEX_WAIT: the OS limit of a sleeping one;
//! - `eventfd`, `socket`: the same over eventfds and a unix datagram socket pair, closer to
//!   what iceoryx2's events cost (its default is unix datagram sockets);
//! - `memcpy`: one copy of N bytes between hot, pre-faulted buffers: the copy limit;
//! - `page-writes`: one write per period (`--period-us`, default 1000) rotating over N
//!   pages: what a write to a page costs once it has lain unwritten for N periods (on a VM,
//!   the host may make it fault).
//!
//! With `--period-us P` a ping-pong starts one round trip every P µs instead of back to
//! back: both processes sleep between round trips, as procimgd's cycle thread and a
//! synchronous client do, and each round trip wakes CPUs that were idle for most of a
//! period.
//!
//! Output: one line per measurement (µs), `--report` (procimg latency report, JSON) and
//! `--hdr-log` (HdrHistogram log).

// The baselines are raw system calls (futex, eventfd, fork, mmap, sched_setaffinity) on
// purpose: they measure the primitives themselves.
#![allow(unsafe_code)]

mod mechanism;
mod memcpy;
mod page_writes;
mod pingpong;
mod sched;
mod shared;

use anyhow::{Context, Result, bail};
use clap::{Parser, Subcommand};
use mechanism::{Channel, EventFd, Futex, Socket, Spin};
use procimg_rt_tests::report::{Measurement, Report, table_header};
use std::path::PathBuf;

/// Measures the machine's limits that procimg's figures are judged by: a two-process
/// ping-pong (spin, futex, eventfd, socket) and memcpy.
#[derive(Parser)]
#[command(version)]
struct Args {
    #[command(subcommand)]
    what: What,
    /// Measured round trips (memcpy: copies per size, at most about 1 GiB copied per size).
    #[arg(short = 'l', long = "loops", default_value_t = 100_000, global = true)]
    loops: u64,
    /// CPUs of the two processes, e.g. 0,1 (default: the first two this process may use).
    #[arg(short = 'a', long = "affinity", value_delimiter = ',', global = true)]
    cpus: Option<Vec<usize>>,
    /// SCHED_FIFO priority of both processes (0: normal scheduling). Without the privilege
    /// the tool warns and measures at normal priority.
    #[arg(short = 'p', long = "priority", default_value_t = 80, global = true,
          value_parser = clap::value_parser!(u8).range(0..=99))]
    priority: u8,
    /// Ping-pongs: start a round trip every this many µs (0: back to back), to measure the
    /// round trip of sides that sleep through most of a cycle.
    #[arg(
        long = "period-us",
        value_name = "µs",
        default_value_t = 0,
        global = true
    )]
    period_us: u64,
    /// Write the figures as a procimg latency report (JSON).
    #[arg(long, value_name = "FILE", global = true)]
    report: Option<PathBuf>,
    /// Write the histograms as an HdrHistogram log.
    #[arg(long, value_name = "FILE", global = true)]
    hdr_log: Option<PathBuf>,
}

#[derive(Subcommand, Clone)]
enum What {
    /// Busy-polling ping-pong over two cache lines (needs two CPUs).
    Spin,
    /// Ping-pong sleeping on a shared (non-private) futex.
    Futex,
    /// Ping-pong blocking on two eventfds.
    Eventfd,
    /// Ping-pong over a unix datagram socket pair.
    Socket,
    /// Time one copy of N bytes, for each size given.
    Memcpy {
        /// Sizes, e.g. 64,4KiB,64KiB,1MiB.
        #[arg(long, value_delimiter = ',', value_parser = memcpy::parse_size,
              default_value = "64,4KiB,64KiB,1MiB")]
        bytes: Vec<usize>,
    },
    /// Time one write per period (--period-us, default 1000), rotating over N pages, for
    /// each N given.
    PageWrites {
        /// Page counts, e.g. 1,16,256,2048.
        #[arg(long, value_delimiter = ',', default_value = "1,16,256,2048")]
        pages: Vec<usize>,
    },
}

impl What {
    fn name(&self) -> &'static str {
        match self {
            What::Spin => "spin",
            What::Futex => "futex",
            What::Eventfd => "eventfd",
            What::Socket => "socket",
            What::Memcpy { .. } => "memcpy",
            What::PageWrites { .. } => "page-writes",
        }
    }
}

fn main() {
    let args = Args::parse();
    if let Err(e) = run(&args) {
        eprintln!("procimg-baseline: {e:#}");
        std::process::exit(1);
    }
}

fn run(args: &Args) -> Result<()> {
    let mut report = Report::new("procimg-baseline");
    report.setting("mechanism", args.what.name());
    // As cyclictest and procimgd do: with idle CPUs in deep C-states every wake-up would
    // measure the C-state exit too, and the limit would not be the one procimgd meets.
    let dma_latency = procimg_runtime::sys::rt::hold_cpu_dma_latency_zero();
    if let Err(w) = &dma_latency {
        eprintln!("procimg-baseline: warning: {w}");
    }
    report.setting("cpu_dma_latency_zero", dma_latency.is_ok());
    match &args.what {
        What::Memcpy { bytes } => memcpy_sizes(args, bytes, &mut report),
        What::PageWrites { pages } => page_write_counts(args, pages, &mut report),
        What::Spin => ping_pong(args, &Spin::new()?, &mut report),
        What::Futex => ping_pong(args, &Futex::new()?, &mut report),
        What::Eventfd => ping_pong(args, &EventFd::new()?, &mut report),
        What::Socket => ping_pong(args, &Socket::new()?, &mut report),
    }?;
    print_table(&report);
    report.save(args.report.as_deref(), args.hdr_log.as_deref())?;
    Ok(())
}

/// The two CPUs: given, or the first two allowed.
fn placement(args: &Args) -> Result<Option<(usize, usize)>> {
    let allowed = sched::allowed_cpus();
    let spin = matches!(args.what, What::Spin);
    match args.cpus.as_deref() {
        Some(&[a, b]) => {
            if let Some(c) = [a, b].into_iter().find(|c| !allowed.contains(c)) {
                bail!("CPU {c} is not one this process may use: choose from {allowed:?}");
            }
            if spin && a == b {
                bail!(
                    "spin needs the two processes on different CPUs: on one CPU a spinning \
                     process only hands over when the scheduler preempts it"
                );
            }
            Ok(Some((a, b)))
        }
        Some(other) => bail!("-a takes two CPUs, e.g. -a 0,1; got {other:?}"),
        None if allowed.len() >= 2 => Ok(Some((allowed[0], allowed[1]))),
        None if spin => bail!(
            "spin needs two CPUs and this process may use only {allowed:?}: on one CPU a \
             spinning process only hands over when the scheduler preempts it"
        ),
        None => Ok(None),
    }
}

fn ping_pong<C: Channel>(args: &Args, channel: &C, report: &mut Report) -> Result<()> {
    let cpus = placement(args)?;
    let plan = pingpong::Plan {
        loops: args.loops.max(1),
        cpus,
        priority: args.priority,
        period_ns: args.period_us.saturating_mul(1000),
    };
    let outcome = pingpong::run(channel, &plan).context("the ping-pong failed")?;
    for w in &outcome.warnings {
        eprintln!("procimg-baseline: warning: {w}");
    }
    let cpus = cpus.map_or("not pinned".to_string(), |(a, b)| format!("{a},{b}"));
    report
        .setting("loops", plan.loops)
        .setting("warmup", pingpong::WARMUP)
        .setting("cpus", cpus)
        .setting("priority", args.priority)
        .setting("period_us", args.period_us)
        .setting("realtime", outcome.realtime);
    report.measurements.push(Measurement::from_histogram(
        "round trip",
        &outcome.round_trips,
    ));
    Ok(())
}

/// Pins this (only) thread to the first CPU of the placement and makes it SCHED_FIFO at the
/// priority asked for; what cannot be done is a warning, and the figures are taken anyway.
fn one_thread_setup(args: &Args) -> Result<()> {
    if let Some((a, _)) = placement(args)?
        && let Err(w) = sched::pin("A", a)
    {
        eprintln!("procimg-baseline: warning: {w}");
    }
    if args.priority > 0
        && let Err(w) = sched::set_fifo(args.priority)
    {
        eprintln!("procimg-baseline: warning: {w}");
    }
    Ok(())
}

fn memcpy_sizes(args: &Args, sizes: &[usize], report: &mut Report) -> Result<()> {
    // One process is enough for a copy; pinned so that the caches stay the same.
    one_thread_setup(args)?;
    report
        .setting("loops", args.loops)
        .setting("clock_overhead_ns", memcpy::clock_overhead_ns())
        .setting(
            "sizes",
            sizes
                .iter()
                .map(|s| s.to_string())
                .collect::<Vec<_>>()
                .join(","),
        );
    for &bytes in sizes {
        let reps = memcpy::repetitions(bytes, args.loops.max(1));
        let h = memcpy::measure(bytes, reps);
        report
            .measurements
            .push(Measurement::from_histogram(&copy_name(bytes), &h));
    }
    Ok(())
}

fn page_write_counts(args: &Args, pages: &[usize], report: &mut Report) -> Result<()> {
    // One thread, pinned and real-time as procimgd's cycle thread.
    one_thread_setup(args)?;
    let period_us = if args.period_us == 0 {
        1000
    } else {
        args.period_us
    };
    report
        .setting("loops", args.loops)
        .setting("period_us", period_us);
    for &n in pages {
        let h = page_writes::measure(n, args.loops.max(1), period_us * 1000);
        report
            .measurements
            .push(Measurement::from_histogram(&page_writes::name(n), &h));
    }
    Ok(())
}

/// The measurement name of a copy of `bytes`, as procimg-compare looks it up.
fn copy_name(bytes: usize) -> String {
    format!("copy {bytes} B")
}

fn print_table(r: &Report) {
    let memcpy = r.settings.get("mechanism").is_some_and(|m| m == "memcpy");
    let width = r
        .measurements
        .iter()
        .map(|m| m.name.chars().count())
        .max()
        .unwrap_or(0)
        .max(16);
    print!("{}", table_header(width));
    if memcpy {
        print!(" {:>9} {:>10}", "p50 ns", "ns/KiB p50");
    }
    println!();
    for m in &r.measurements {
        print!("{}", m.table_row(width));
        if memcpy {
            let bytes: f64 = m
                .name
                .trim_start_matches("copy ")
                .trim_end_matches(" B")
                .parse()
                .unwrap_or(f64::NAN);
            print!(
                " {:>9} {:>10.1}",
                m.p50_ns,
                m.p50_ns as f64 * 1024.0 / bytes
            );
        }
        println!();
    }
    if let Some(ns) = r.settings.get("clock_overhead_ns") {
        println!("# every copy's time includes two clock reads: {ns} ns (p50)");
    }
    if r.settings.get("realtime").is_some_and(|v| v == "false") {
        println!("# not SCHED_FIFO: figures at normal priority");
    }
}
