// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg-handshake`: how fast the STARTOP / OPDONE handshake is between a real procimgd
//! and real client processes.
//!
//! It starts procimgd with an image of the size asked for (devices that nobody answers, so
//! the cycle does the handshake and nothing else), then N client processes, each a
//! synchronous procimg client that sleeps on the STARTOP event or busy-polls for the image.
//! After a warm-up it measures, per cycle:
//!
//! - **startop one way**: image complete in the server (the clock stamped into the cycle
//!   info, right before STARTOP) → the client running (client side);
//! - **opdone one way**: the client sends its OPDONE → the cycle thread has its outputs
//!   (server side, from the send time in the output sample);
//! - **round trip**: STARTOP (the image's stamp, from which a client may see it) → OPDONE
//!   received, per client (server side), which is what bounds the OPDONE deadline.
//!
//! and prints p50 / p99 / p99.9 / max, with `--report` (JSON) and `--hdr-log` files, and
//! beside them procimgd's overruns, OPFAULTs and cycle allocations and the clients' cycle
//! allocations over the measured cycles.
//!
//! `--demo` runs procimgd's built-in demo (simulated devices that answer) at the cycle
//! given instead of the generated image: how short a cycle procimgd holds with real work.
//! `procimg-handshake startup` times procimgd's start and a client's attach, and reads how
//! much memory procimgd locks. `procimg-handshake attach-load` counts the overruns that clients
//! attaching and detaching cause, against an idle stretch as long.

mod alloc_count;
mod attach_load;
mod client;
mod plant;
mod server;
mod startup;

/// procimg's real-time allocator: the clients' marked cycle threads take iceoryx2's small
/// per-sample allocations from its pool, and their heap allocations are counted.
#[global_allocator]
static ALLOCATOR: procimg_client::rt_alloc::RtAllocator = procimg_client::rt_alloc::RtAllocator;

use anyhow::{Context, Result, bail};
use clap::{Parser, Subcommand, ValueEnum};
use plant::{MAX_IMAGE_BYTES, Plant};
use procimg_rt_tests::report::{
    Measurement, Report, buckets_between, histogram_from_buckets, new_histogram, table_header,
};
use server::Server;
use std::io::{BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};

/// Measures the STARTOP / OPDONE handshake latency (one way and round trip) between a real
/// procimgd and N client processes.
#[derive(Parser)]
#[command(version, args_conflicts_with_subcommands = true)]
struct Args {
    /// Client processes.
    #[arg(short = 'c', long, default_value_t = 1)]
    clients: usize,
    /// How clients (and the server, for OPDONE) wait: sleeping on events, or busy-polling
    /// (each busy client needs a CPU of its own beside the server's).
    #[arg(short = 'w', long, value_enum, default_value_t = Wait::Sleep)]
    wait: Wait,
    /// Bytes of input data in the image, and as many of output data (64 … 368128; suffixes
    /// KiB and MiB are accepted).
    #[arg(short = 'b', long, default_value = "64", value_parser = parse_bytes)]
    image_bytes: usize,
    /// Cycle time in µs, a multiple of 31.25 (procimgd's cycle unit): 1000, 250, 187.5, 125.
    #[arg(short = 'i', long = "interval", default_value = "1000", value_parser = parse_interval)]
    interval_ns: u64,
    /// Run procimgd's built-in demo (simulated devices that answer) at this cycle instead of
    /// the generated image; the clients claim nothing and only do the handshake
    /// (--image-bytes does not apply).
    #[arg(long)]
    demo: bool,
    /// Measured cycles per client.
    #[arg(short = 'l', long = "loops", default_value_t = 10_000)]
    loops: u64,
    /// SCHED_FIFO priority of the server's cycle thread; clients run 10 below.
    #[arg(short = 'p', long = "priority", default_value_t = 80)]
    priority: u8,
    /// CPUs: the server's cycle thread, then the clients' (one each, or one for all).
    /// Default: not pinned when sleeping; busy-polling: server on 0, clients on 1, 2, …
    #[arg(short = 'a', long = "affinity", value_delimiter = ',')]
    cpus: Vec<usize>,
    /// Write the figures as a procimg latency report (JSON).
    #[arg(long, value_name = "FILE")]
    report: Option<PathBuf>,
    /// Write the histograms as an HdrHistogram log.
    #[arg(long, value_name = "FILE")]
    hdr_log: Option<PathBuf>,
    /// Print only the figures.
    #[arg(short = 'q', long)]
    quiet: bool,
    #[command(subcommand)]
    role: Option<Role>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Wait {
    /// Sleep on the STARTOP / OPDONE events.
    Sleep,
    /// Poll without sleeping.
    Busy,
}

#[derive(Subcommand)]
enum Role {
    /// One measuring client (started by the coordinating process).
    #[command(hide = true)]
    Client {
        #[arg(long)]
        instance: String,
        #[arg(long)]
        index: usize,
        #[arg(long)]
        clients: usize,
        #[arg(long)]
        devices: usize,
        #[arg(long)]
        busy: bool,
        #[arg(long)]
        cycles: u64,
        #[arg(long)]
        warmup: u64,
        #[arg(long)]
        priority: u8,
        #[arg(long)]
        cpu: Option<usize>,
        #[arg(long)]
        report: PathBuf,
    },
    /// Times procimgd's start (spawn to its first cycle) and a synchronous client's attach,
    /// and reads procimgd's locked and resident memory (Locked, VmLck, VmRSS) while it runs.
    Startup {
        /// Bytes of input data in the image, and as many of output data.
        #[arg(short = 'b', long, default_value = "368128", value_parser = parse_bytes)]
        image_bytes: usize,
        /// Attaches to time, one after the other.
        #[arg(short = 'n', long, default_value_t = 20,
              value_parser = clap::value_parser!(u32).range(1..=1000))]
        attaches: u32,
        /// Write the figures as a procimg latency report (JSON).
        #[arg(long, value_name = "FILE")]
        report: Option<PathBuf>,
    },
    /// Counts procimgd's overruns while synchronous clients attach and detach one after the
    /// other, and while nothing happens for as long (the demo, or the generated image).
    AttachLoad {
        /// The generated image with this many bytes each way instead of the demo.
        #[arg(short = 'b', long, value_parser = parse_bytes)]
        image_bytes: Option<usize>,
        /// Attaches per round.
        #[arg(short = 'n', long, default_value_t = 1000)]
        attaches: u32,
        /// Rounds, each an attaching window and an idle window as long.
        #[arg(short = 'r', long, default_value_t = 1)]
        rounds: u32,
        /// Milliseconds between a client's detach and the next attach.
        #[arg(long, default_value_t = 5)]
        pause_ms: u64,
        /// Write the overruns of both windows as a procimg report (JSON).
        #[arg(long, value_name = "FILE")]
        report: Option<PathBuf>,
    },
}

/// Parses a cycle time in µs, whole or decimal ("250", "187.5"), into ns; procimgd takes
/// multiples of 31.25 µs only.
fn parse_interval(s: &str) -> Result<u64, String> {
    let us: f64 = s
        .trim()
        .parse()
        .map_err(|_| format!("{s:?} is not a cycle time in µs such as 1000, 250 or 187.5"))?;
    let ns = (us * 1000.0).round();
    let unit = procimg_shm_layout::CYCLE_COUNT_UNIT_NS as f64;
    if !(unit..=512_000_000.0).contains(&ns) || ns % unit != 0.0 {
        return Err(format!(
            "{s} µs: procimgd's cycle is a multiple of 31.25 µs up to 512 ms, e.g. 1000, 250, \
             218.75, 187.5, 156.25, 125 or 93.75"
        ));
    }
    Ok(ns as u64)
}

fn parse_bytes(s: &str) -> Result<usize, String> {
    let t = s.trim();
    let (num, mul) = if let Some(n) = t.strip_suffix("MiB").or(t.strip_suffix('M')) {
        (n, 1 << 20)
    } else if let Some(n) = t.strip_suffix("KiB").or(t.strip_suffix('K')) {
        (n, 1 << 10)
    } else {
        (t.strip_suffix('B').unwrap_or(t), 1)
    };
    let n: usize = num
        .trim()
        .parse()
        .map_err(|_| format!("{s:?} is not a size such as 64, 4KiB or 1MiB"))?;
    let bytes = n * mul;
    if bytes == 0 || bytes > MAX_IMAGE_BYTES {
        return Err(format!(
            "{bytes} bytes: an image holds 1 to {MAX_IMAGE_BYTES} bytes per direction \
             (256 devices of 1438 bytes: the most one procimgd serves and one PROFINET frame carries with its status bytes)"
        ));
    }
    Ok(bytes)
}

fn main() {
    let args = Args::parse();
    let result = match &args.role {
        Some(Role::Client {
            instance,
            index,
            clients,
            devices,
            busy,
            cycles,
            warmup,
            priority,
            cpu,
            report,
        }) => client::run(&client::ClientArgs {
            instance,
            index: *index,
            clients: *clients,
            devices: *devices,
            busy_poll: *busy,
            cycles: *cycles,
            warmup: *warmup,
            priority: *priority,
            cpu: *cpu,
            report,
        }),
        Some(Role::Startup {
            image_bytes,
            attaches,
            report,
        }) => startup::run(*image_bytes, *attaches, report.as_deref()),
        Some(Role::AttachLoad {
            image_bytes,
            attaches,
            rounds,
            pause_ms,
            report,
        }) => attach_load::run(&attach_load::Args {
            image_bytes: *image_bytes,
            attaches: *attaches,
            rounds: *rounds,
            pause: std::time::Duration::from_millis(*pause_ms),
            report: report.as_deref(),
        }),
        None => coordinate(&args),
    };
    if let Err(e) = result {
        eprintln!("procimg-handshake: {e:#}");
        std::process::exit(1);
    }
}

/// A client process and its pipes.
struct ClientProcess {
    child: Child,
    stdin: Option<ChildStdin>,
    stdout: BufReader<ChildStdout>,
    report: PathBuf,
}

impl ClientProcess {
    /// Waits for the line `want`.
    fn expect(&mut self, want: &str, index: usize) -> Result<()> {
        let mut line = String::new();
        loop {
            line.clear();
            if self.stdout.read_line(&mut line)? == 0 {
                let status = self.child.wait()?;
                bail!("client {index} ended ({status}) before saying {want:?}");
            }
            if line.trim() == want {
                return Ok(());
            }
        }
    }

    fn say(&mut self, what: &str) -> Result<()> {
        if let Some(stdin) = &mut self.stdin {
            writeln!(stdin, "{what}")?;
            stdin.flush()?;
        }
        Ok(())
    }
}

impl Drop for ClientProcess {
    fn drop(&mut self) {
        // Closing stdin tells the client to leave; a stuck one is killed.
        self.stdin = None;
        for _ in 0..100 {
            if let Ok(Some(_)) = self.child.try_wait() {
                return;
            }
            std::thread::sleep(std::time::Duration::from_millis(20));
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Where the server and each client run.
fn placement(args: &Args) -> Result<(Option<usize>, Vec<Option<usize>>)> {
    let cpus = std::thread::available_parallelism().map_or(1, |n| n.get());
    let busy = args.wait == Wait::Busy;
    if busy && args.clients + 1 > cpus {
        bail!(
            "{} busy-polling clients and the server need {} CPUs, this machine has {cpus}: a \
             spinning SCHED_FIFO thread keeps its CPU; use fewer clients or --wait sleep",
            args.clients,
            args.clients + 1
        );
    }
    if let Some(&c) = args.cpus.iter().find(|&&c| c >= cpus) {
        bail!(
            "CPU {c} does not exist: this machine has CPUs 0 to {}",
            cpus - 1
        );
    }
    let server = args.cpus.first().copied().or(busy.then_some(0));
    let clients = (0..args.clients)
        .map(|i| match args.cpus.get(1..) {
            Some(rest) if !rest.is_empty() => Some(rest[i % rest.len()]),
            _ => busy.then_some((1 + i) % cpus),
        })
        .collect();
    Ok((server, clients))
}

fn coordinate(args: &Args) -> Result<()> {
    let (server_cpu, client_cpus) = placement(args)?;
    let instance = format!("handshake-{}", std::process::id());
    let busy = args.wait == Wait::Busy;
    let plant = Plant {
        instance: instance.clone(),
        image_bytes: args.image_bytes,
        interval_ns: args.interval_ns,
        priority: args.priority,
        cpu: server_cpu,
        busy_poll: busy,
    };
    let dir = std::env::temp_dir().join(format!("procimg-handshake-{}", std::process::id()));
    std::fs::create_dir_all(&dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let _cleanup = RemoveOnDrop(dir.clone());
    let config = dir.join("procimgd.toml");
    let (toml, devices) = if args.demo {
        let text = plant::demo_toml(&instance, args.interval_ns).map_err(anyhow::Error::msg)?;
        (text, 0)
    } else {
        (plant.toml(), plant.device_sizes().len())
    };
    std::fs::write(&config, toml).with_context(|| format!("cannot write {}", config.display()))?;
    if !args.quiet {
        let image = if args.demo {
            "the demo's devices".to_string()
        } else {
            format!("{} bytes each way over {devices} devices", args.image_bytes)
        };
        eprintln!(
            "procimgd: {image}, cycle {} µs; {} {} client(s)",
            us_text(args.interval_ns),
            args.clients,
            if busy { "busy-polling" } else { "sleeping" }
        );
    }
    let server = Server::start(&config, &instance, &dir.join("procimgd.log"))?;
    let warmup = 500.max(2_000_000_000 / args.interval_ns.max(1)).min(3000);
    let mut clients = Vec::new();
    for (i, cpu) in client_cpus.iter().enumerate() {
        clients.push(spawn_client(
            args, &instance, i, devices, warmup, *cpu, &dir,
        )?);
    }
    for (i, c) in clients.iter_mut().enumerate() {
        c.expect("ready", i)?;
    }
    let before = server.histograms()?;
    let counters_before = server.counters()?;
    for c in &mut clients {
        c.say("go")?;
    }
    for (i, c) in clients.iter_mut().enumerate() {
        c.expect("done", i)?;
    }
    let after = server.histograms_after_handover()?;
    let counters = server.counters()?.since(counters_before);
    let mut startop = new_histogram();
    let mut client_allocations = 0u64;
    for c in &clients {
        let r = Report::read_json(&c.report)?;
        if let Some(m) = r.get("startop one way") {
            let _ = startop.add(m.histogram());
        }
        client_allocations += r
            .settings
            .get(client::CYCLE_ALLOCATIONS)
            .and_then(|v| v.parse::<u64>().ok())
            .unwrap_or(0);
    }
    drop(clients);
    let server_pid = server.pid();
    drop(server);

    let mut report = Report::new("procimg-handshake");
    report
        .setting("clients", args.clients)
        .setting("wait", if busy { "busy" } else { "sleep" })
        .setting("plant", if args.demo { "demo" } else { "generated" })
        .setting("image_bytes", args.image_bytes)
        .setting("devices", devices)
        .setting("interval_us", us_text(args.interval_ns))
        .setting("priority", args.priority)
        .setting("cycles", counters.cycles)
        .setting("overruns", counters.overruns)
        .setting("opfaults", counters.opfaults)
        .setting(SERVER_ALLOCATIONS, counters.heap_allocations)
        .setting(CLIENT_ALLOCATIONS, client_allocations)
        .setting("procimgd_pid", server_pid);
    let between = |a: &[_], b: &[_]| histogram_from_buckets(&buckets_between(a, b));
    report.measurements = vec![
        Measurement::from_histogram("startop one way", &startop),
        Measurement::from_histogram("opdone one way", &between(&before.opdone, &after.opdone)),
        Measurement::from_histogram("round trip", &between(&before.handshake, &after.handshake)),
        Measurement::from_histogram("server wake-up", &between(&before.wakeup, &after.wakeup)),
    ];
    print_table(&report);
    report.save(args.report.as_deref(), args.hdr_log.as_deref())?;
    Ok(())
}

/// The report's setting: the cycle thread's system-allocator calls over the measured
/// cycles (procimgd's `rt_heap_allocations`; goal 0).
pub const SERVER_ALLOCATIONS: &str = "server_cycle_allocations";
/// The report's setting: every client's allocations in its measured cycles, summed (goal 0).
pub const CLIENT_ALLOCATIONS: &str = "client_cycle_allocations";

/// "250", "187.5": a cycle time in µs as people write it.
fn us_text(ns: u64) -> String {
    let us = ns as f64 / 1000.0;
    if us.fract() == 0.0 {
        format!("{us:.0}")
    } else {
        format!("{us}")
    }
}

fn spawn_client(
    args: &Args,
    instance: &str,
    index: usize,
    devices: usize,
    warmup: u64,
    cpu: Option<usize>,
    dir: &Path,
) -> Result<ClientProcess> {
    let report = dir.join(format!("client-{index}.json"));
    let mut cmd = Command::new(std::env::current_exe()?);
    cmd.arg("client")
        .args(["--instance", instance])
        .args(["--index", &index.to_string()])
        .args(["--clients", &args.clients.to_string()])
        .args(["--devices", &devices.to_string()])
        .args(["--cycles", &args.loops.to_string()])
        .args(["--warmup", &warmup.to_string()])
        .args(["--priority", &args.priority.saturating_sub(10).to_string()])
        .arg("--report")
        .arg(&report);
    if args.wait == Wait::Busy {
        cmd.arg("--busy");
    }
    if let Some(cpu) = cpu {
        cmd.args(["--cpu", &cpu.to_string()]);
    }
    let mut child = cmd
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .context("cannot start a client process")?;
    let stdin = child.stdin.take();
    let stdout = BufReader::new(child.stdout.take().context("no client stdout")?);
    Ok(ClientProcess {
        child,
        stdin,
        stdout,
        report,
    })
}

fn print_table(r: &Report) {
    let s = |k: &str| r.settings.get(k).cloned().unwrap_or_default();
    let image = if s("plant") == "demo" {
        "the demo's devices".to_string()
    } else {
        format!("{} B each way", s("image_bytes"))
    };
    println!(
        "# {} client(s) {}, {image}, cycle {} µs; {} cycles, {} overruns, {} OPFAULTs; \
         allocations in the cycles: server {}, clients {}",
        s("clients"),
        if s("wait") == "busy" {
            "busy-polling"
        } else {
            "sleeping"
        },
        s("interval_us"),
        s("cycles"),
        s("overruns"),
        s("opfaults"),
        s(SERVER_ALLOCATIONS),
        s(CLIENT_ALLOCATIONS)
    );
    println!("{}", table_header(18));
    for m in &r.measurements {
        println!("{}", m.table_row(18));
    }
}

/// Removes the run's temporary directory, whatever happens.
struct RemoveOnDrop(PathBuf);

impl Drop for RemoveOnDrop {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}
