// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg-opcua-load`: what an OPC UA server costs the cycle. procimgd runs the demo
//! (1 ms cycle); its cycle thread's wake-up latency is measured over equal windows, one per
//! condition, in one run:
//!
//! 1. procimgd alone (the baseline every ratio is to);
//! 2. procimg-opcua serving it, no client;
//! 3. an asyncua (PyPI) client monitoring `--items` PNIO items at `--sampling` (default
//!    1000 at 100 ms, published every 100 ms);
//! 4. the same items sampled as fast as the server allows (every image), published every
//!    10 ms: the updates per second the server sustains.
//!
//! Per window it prints the wake-up p50/p99/max, overruns, the CPU procimg-opcua and the
//! client took, and the updates the client received per second; with `--rounds N` the
//! median of N runs.
//!
//! ```text
//! procimg-opcua-load [--items 1000] [--sampling 100] [--window 20s] [--rounds 3]
//!                    [--cpu N] [--python PATH] [--out DIR]
//! ```
//!
//! With `--cpu N` the demo's cycle thread is pinned to CPU N (its `[cycle_thread] cpu`) and
//! procimg-opcua and the client run on the other CPUs (`taskset`), as a production machine
//! keeps them apart.
//!
//! Needs procimgd and procimg-opcua beside it (`cargo build --release --bins`) and asyncua
//! in a virtual environment (`--python`, default `target/asyncua-venv/bin/python`, which
//! `.ci/run` makes). Root makes the cycle thread real-time, as in production.

use anyhow::{Context as _, bail};
use clap::Parser;
use procimg_client::ControlHandle;
use procimg_control::Bucket;
use procimg_rt_tests::report::{buckets_between, histogram_from_buckets};
use std::io::{BufRead as _, BufReader};
use std::net::{Ipv4Addr, TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdout, Command, Stdio};
use std::time::{Duration, Instant};

#[derive(Parser)]
#[command(
    version,
    about = "The cost of procimg-opcua and its monitored items to the cycle"
)]
struct Args {
    /// Monitored items of the load.
    #[arg(long, default_value_t = 1000)]
    items: u32,
    /// Their sampling interval in ms.
    #[arg(long, default_value_t = 100.0)]
    sampling: f64,
    /// Length of each measured window.
    #[arg(long, default_value = "20s", value_parser = humantime::parse_duration)]
    window: Duration,
    /// Runs; each figure is the median.
    #[arg(long, default_value_t = 1)]
    rounds: usize,
    /// The Python interpreter with asyncua.
    #[arg(long)]
    python: Option<PathBuf>,
    /// Where the logs go (a fresh temporary directory by default).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Pin procimgd's cycle thread to this CPU and procimg-opcua and the client to the
    /// others, as a production machine keeps them apart (default: nothing pinned).
    #[arg(long, value_name = "N")]
    cpu: Option<usize>,
}

/// The figures of one window.
#[derive(Clone, Copy, Debug, Default)]
struct Window {
    wake_p50_us: f64,
    wake_p99_us: f64,
    wake_max_us: f64,
    overruns: u64,
    cycles: u64,
    /// CPU time of procimg-opcua over the window, as a share of one CPU.
    server_cpu: f64,
    /// CPU time of the load client, as a share of one CPU.
    client_cpu: f64,
    /// Notifications the client received per second.
    updates_per_s: f64,
}

/// A child process, ended when dropped: SIGTERM (procimgd then removes its shared memory),
/// SIGKILL after 5 s.
struct Ended(Child);

impl Drop for Ended {
    fn drop(&mut self) {
        procimg_netns::signal::stop(&mut self.0, libc::SIGTERM, Duration::from_secs(5));
    }
}

/// A sibling binary of this program.
fn sibling(name: &str) -> anyhow::Result<PathBuf> {
    let me = std::env::current_exe().context("cannot find this program's path")?;
    let path = me.with_file_name(name);
    if !path.is_file() {
        bail!(
            "{} is missing: build it with `cargo build --release --bins`",
            path.display()
        );
    }
    Ok(path)
}

/// CPU time of process `pid` so far (all its threads), from the scheduler's statistics.
fn cpu_time(pid: u32) -> Duration {
    let tasks = std::fs::read_dir(format!("/proc/{pid}/task"))
        .into_iter()
        .flatten();
    let ns: u64 = tasks
        .flatten()
        .filter_map(|t| std::fs::read_to_string(t.path().join("schedstat")).ok())
        .filter_map(|s| s.split_whitespace().next()?.parse::<u64>().ok())
        .sum();
    Duration::from_nanos(ns)
}

/// Wake-up percentiles (µs) of the buckets recorded between two snapshots.
fn percentiles(earlier: &[Bucket], later: &[Bucket]) -> (f64, f64, f64) {
    let h = histogram_from_buckets(&buckets_between(earlier, later));
    if h.is_empty() {
        return (0.0, 0.0, 0.0);
    }
    let us = |ns: u64| ns as f64 / 1e3;
    (
        us(h.value_at_quantile(0.5)),
        us(h.value_at_quantile(0.99)),
        us(h.max()),
    )
}

/// Measures one window of `length`, with procimg-opcua `server` and the load client
/// `client` (their CPU time taken over the same window) when there are.
fn window(
    control: &ControlHandle,
    length: Duration,
    server: Option<u32>,
    client: Option<u32>,
) -> anyhow::Result<Window> {
    let cpu = |pid: Option<u32>| pid.map_or(Duration::ZERO, cpu_time);
    let (s0, c0) = (cpu(server), cpu(client));
    let h0 = control.histograms().context("procimgd's histograms")?;
    let o0 = control.status().context("procimgd's status")?.overruns;
    let t0 = Instant::now();
    std::thread::sleep(length);
    let h1 = control.histograms().context("procimgd's histograms")?;
    let o1 = control.status().context("procimgd's status")?.overruns;
    let took = t0.elapsed().as_secs_f64();
    let (s1, c1) = (cpu(server), cpu(client));
    let (p50, p99, max) = percentiles(&h0.wakeup, &h1.wakeup);
    Ok(Window {
        wake_p50_us: p50,
        wake_p99_us: p99,
        wake_max_us: max,
        overruns: o1.saturating_sub(o0),
        cycles: h1.cycles.saturating_sub(h0.cycles),
        server_cpu: (s1 - s0).as_secs_f64() / took,
        client_cpu: (c1 - c0).as_secs_f64() / took,
        updates_per_s: 0.0,
    })
}

/// A command for `program`, on every CPU but `cpu` when one is given (`taskset`).
fn others(cpu: Option<usize>, program: &Path) -> Command {
    let cpus = std::thread::available_parallelism().map_or(2, |n| n.get());
    match cpu {
        Some(cpu) if cpus > 1 => {
            let list: Vec<String> = (0..cpus)
                .filter(|c| *c != cpu)
                .map(|c| c.to_string())
                .collect();
            let mut c = Command::new("taskset");
            c.args(["-c", &list.join(",")]).arg(program);
            c
        }
        _ => Command::new(program),
    }
}

/// A port nobody listens on now.
fn free_port() -> anyhow::Result<u16> {
    Ok(TcpListener::bind((Ipv4Addr::LOCALHOST, 0))?
        .local_addr()?
        .port())
}

/// The load client, started: it has said "ready".
struct Load {
    child: Ended,
    stdout: BufReader<ChildStdout>,
}

impl Load {
    fn start(
        cpu: Option<usize>,
        python: &Path,
        script: &Path,
        url: &str,
        (items, sampling, publishing): (u32, f64, f64),
        seconds: f64,
    ) -> anyhow::Result<Load> {
        let mut child = others(cpu, python)
            .arg(script)
            .args([url, &items.to_string(), &sampling.to_string()])
            .args([&publishing.to_string(), &seconds.to_string()])
            .stdout(Stdio::piped())
            .spawn()
            .with_context(|| format!("cannot run {}", python.display()))?;
        let stdout = child.stdout.take().context("the load's standard output")?;
        let mut load = Load {
            child: Ended(child),
            stdout: BufReader::new(stdout),
        };
        let line = load.line()?;
        if line.trim() != "ready" {
            bail!("the load client did not start: {line}");
        }
        Ok(load)
    }

    fn line(&mut self) -> anyhow::Result<String> {
        let mut line = String::new();
        self.stdout.read_line(&mut line)?;
        Ok(line)
    }

    /// The updates per second it counted.
    fn updates_per_s(mut self) -> anyhow::Result<f64> {
        let line = self.line()?;
        let mut words = line.split_whitespace();
        match (words.next(), words.next(), words.next()) {
            (Some("updates"), Some(n), Some(s)) => {
                let n: f64 = n.parse()?;
                let s: f64 = s.parse()?;
                Ok(n / s.max(1e-3))
            }
            _ => bail!("the load client said: {line}"),
        }
    }
}

/// One run of the four windows.
fn round(args: &Args, python: &Path, out: &Path, n: usize) -> anyhow::Result<[Window; 4]> {
    let instance = format!("opcua-load-{}-{n}", std::process::id());
    let log = |name: &str| std::fs::File::create(out.join(format!("{name}-{n}.log")));
    let mut procimgd = Command::new(sibling("procimgd")?);
    match args.cpu {
        Some(cpu) => {
            // The demo's configuration with its cycle thread pinned.
            let demo = Command::new(sibling("procimgd")?)
                .arg("--print-demo-config")
                .output()
                .context("procimgd --print-demo-config")?;
            let text =
                String::from_utf8_lossy(&demo.stdout).replace("# cpu = 3", &format!("cpu = {cpu}"));
            let config = out.join(format!("demo-cpu{cpu}.toml"));
            std::fs::write(&config, text)?;
            procimgd.arg("-c").arg(config);
        }
        None => {
            procimgd.arg("--demo");
        }
    }
    let procimgd = Ended(
        procimgd
            .args(["--instance", &instance])
            .stdout(Stdio::null())
            .stderr(log("procimgd")?)
            .spawn()
            .context("cannot start procimgd")?,
    );
    let until = Instant::now() + Duration::from_secs(60);
    let control = loop {
        let ready = ControlHandle::open(&instance, "procimg-opcua-load")
            .ok()
            .filter(|c| {
                c.status().is_ok_and(|s| {
                    !s.devices.is_empty()
                        && s.devices
                            .iter()
                            .all(|d| d.state == procimg_client::DeviceState::Running)
                })
            });
        if let Some(c) = ready {
            break c;
        }
        if Instant::now() > until {
            bail!("procimgd's demo devices are not running after 60 s");
        }
        std::thread::sleep(Duration::from_millis(100));
    };
    let alone = window(&control, args.window, None, None)?;
    let port = free_port()?;
    let url = format!("opc.tcp://127.0.0.1:{port}/");
    let server = Ended(
        others(args.cpu, &sibling("procimg-opcua")?)
            .args(["--instance", &instance, "--insecure"])
            .args(["--endpoint", &format!("opc.tcp://127.0.0.1:{port}")])
            .arg("--pki")
            .arg(out.join("pki"))
            .stdout(Stdio::null())
            .stderr(log("procimg-opcua")?)
            .spawn()
            .context("cannot start procimg-opcua")?,
    );
    let until = Instant::now() + Duration::from_secs(60);
    while TcpStream::connect((Ipv4Addr::LOCALHOST, port)).is_err() {
        if Instant::now() > until {
            bail!("procimg-opcua does not listen on {url}");
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    let server_pid = server.0.id();
    let serving = window(&control, args.window, Some(server_pid), None)?;
    let script = out.join("load.py");
    std::fs::write(&script, include_str!("load.py"))?;
    let seconds = args.window.as_secs_f64();
    let mut loaded = Vec::new();
    for (sampling, publishing) in [(args.sampling, 100.0), (0.0, 10.0)] {
        let load = Load::start(
            args.cpu,
            python,
            &script,
            &url,
            (args.items, sampling, publishing),
            seconds,
        )?;
        let pid = load.child.0.id();
        let mut w = window(&control, args.window, Some(server_pid), Some(pid))?;
        w.updates_per_s = load.updates_per_s()?;
        loaded.push(w);
    }
    drop(server);
    drop(procimgd);
    Ok([alone, serving, loaded[0], loaded[1]])
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(0.0)
}

fn main() -> anyhow::Result<()> {
    let args = Args::parse();
    let python = args.python.clone().unwrap_or_else(|| {
        std::env::current_exe()
            .ok()
            .and_then(|me| Some(me.parent()?.parent()?.join("asyncua-venv/bin/python")))
            .unwrap_or_else(|| PathBuf::from("target/asyncua-venv/bin/python"))
    });
    if !python.is_file() {
        bail!(
            "no Python with asyncua at {}: python3 -m venv target/asyncua-venv && \
             target/asyncua-venv/bin/pip install asyncua==2.1.0, or give --python",
            python.display()
        );
    }
    let temp;
    let out = match &args.out {
        Some(dir) => {
            std::fs::create_dir_all(dir)?;
            dir.clone()
        }
        None => {
            temp = std::env::temp_dir().join(format!("procimg-opcua-load-{}", std::process::id()));
            std::fs::create_dir_all(&temp)?;
            temp
        }
    };
    let mut rounds = Vec::new();
    for n in 0..args.rounds.max(1) {
        rounds.push(round(&args, &python, &out, n)?);
        eprintln!("round {} of {} done", n + 1, args.rounds.max(1));
    }
    let names = [
        "procimgd alone (baseline)".to_owned(),
        "procimg-opcua serving, no client".to_owned(),
        format!(
            "{} items at {} ms, published 100 ms",
            args.items, args.sampling
        ),
        format!("{} items every image, published 10 ms", args.items),
    ];
    let pinned = args.cpu.map_or_else(
        || "nothing pinned".to_owned(),
        |c| format!("cycle thread on CPU {c}, the others elsewhere"),
    );
    println!(
        "procimgd --demo (1 ms cycle), {pinned}, windows of {:?}, median of {} round(s); logs in {}",
        args.window,
        rounds.len(),
        out.display()
    );
    println!(
        "{:<44} {:>8} {:>8} {:>8} {:>6} {:>9} {:>8} {:>8} {:>10}",
        "condition",
        "p50 µs",
        "p99 µs",
        "max µs",
        "p99 ×",
        "overruns",
        "srv CPU",
        "cli CPU",
        "updates/s"
    );
    let fig = |i: usize, f: fn(&Window) -> f64| median(rounds.iter().map(|r| f(&r[i])).collect());
    let base = fig(0, |w| w.wake_p99_us).max(1e-3);
    for (i, name) in names.iter().enumerate() {
        println!(
            "{:<44} {:>8.1} {:>8.1} {:>8.1} {:>6.2} {:>9} {:>7.1}% {:>7.1}% {:>10.0}",
            name,
            fig(i, |w| w.wake_p50_us),
            fig(i, |w| w.wake_p99_us),
            fig(i, |w| w.wake_max_us),
            fig(i, |w| w.wake_p99_us) / base,
            fig(i, |w| w.overruns as f64),
            fig(i, |w| w.server_cpu * 100.0),
            fig(i, |w| w.client_cpu * 100.0),
            fig(i, |w| w.updates_per_s),
        );
    }
    let cycles = fig(0, |w| w.cycles as f64);
    println!("(about {cycles:.0} cycles per window)");
    Ok(())
}
