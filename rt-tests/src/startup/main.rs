// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg-startup`: what a procimgd costs before it does any work, for an image of a given
//! size: its locked and resident memory, the time from its start to its first cycle, and how
//! long a client takes to attach (and what each attached client adds to the server's memory).
//!
//! It starts procimgd with the configuration `procimg-handshake` uses (devices nobody
//! answers), reads `VmLck` and `VmRSS` from `/proc/<pid>/status`, then attaches clients one
//! after the other in this process, each one's `Client::attach` timed. The first cycle's
//! start is the cycle epoch the images carry (`cycle_start_ns - k·cycle_ns`), so the figure
//! does not depend on how often this tool looks.

#[path = "../handshake/plant.rs"]
mod plant;
// Shared with procimg-handshake, whose histogram calls this tool does not make.
#[allow(dead_code)]
#[path = "../handshake/server.rs"]
mod server;

use anyhow::{Context, Result, bail};
use clap::Parser;
use plant::{MAX_IMAGE_BYTES, Plant};
use procimg_client::{AttachOptions, Client};
use procimg_shm_layout::os::monotonic_ns;
use server::Server;
use std::path::PathBuf;
use std::time::{Duration, Instant};

/// Measures procimgd's memory and start-up, and the clients' attach time, for one image size.
#[derive(Parser)]
#[command(version)]
struct Args {
    /// Bytes of input data in the image, and as many of output data (1 … 368128).
    #[arg(short = 'b', long, default_value_t = 64)]
    image_bytes: usize,
    /// Asynchronous clients attached one after the other (each timed).
    #[arg(short = 'c', long, default_value_t = 4)]
    clients: usize,
    /// Lock this process's memory first (`mlockall`), as a real-time client does: its
    /// attach then pays for populating every page it maps.
    #[arg(long)]
    mlock: bool,
    /// Instance name (default: procimg-startup-<pid>).
    #[arg(long)]
    instance: Option<String>,
}

fn main() {
    if let Err(e) = run(&Args::parse()) {
        eprintln!("procimg-startup: {e:#}");
        std::process::exit(1);
    }
}

/// `VmLck` and `VmRSS` of `pid`, in KiB.
fn memory_kib(pid: u32) -> Result<(u64, u64)> {
    let path = format!("/proc/{pid}/status");
    let text = std::fs::read_to_string(&path).with_context(|| format!("cannot read {path}"))?;
    let field = |name: &str| {
        text.lines()
            .find_map(|l| l.strip_prefix(name))
            .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<u64>().ok())
            .unwrap_or(0)
    };
    Ok((field("VmLck:"), field("VmRSS:")))
}

fn mib(kib: u64) -> String {
    format!("{:.1} MiB", kib as f64 / 1024.0)
}

fn run(args: &Args) -> Result<()> {
    if args.image_bytes == 0 || args.image_bytes > MAX_IMAGE_BYTES {
        bail!("--image-bytes must be 1 to {MAX_IMAGE_BYTES}");
    }
    if args.mlock {
        procimg_client::realtime::make_current_thread_realtime(1)
            .context("--mlock needs CAP_SYS_NICE and CAP_IPC_LOCK (run as root)")?;
    }
    let instance = args
        .instance
        .clone()
        .unwrap_or_else(|| format!("procimg-startup-{}", std::process::id()));
    let plant = Plant {
        instance: instance.clone(),
        image_bytes: args.image_bytes,
        interval_us: 1000,
        priority: 80,
        cpu: None,
        busy_poll: false,
    };
    let dir = std::env::temp_dir().join(format!("procimg-startup-{}", std::process::id()));
    std::fs::create_dir_all(&dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let _cleanup = RemoveOnDrop(dir.clone());
    let config = dir.join("procimgd.toml");
    std::fs::write(&config, plant.toml())
        .with_context(|| format!("cannot write {}", config.display()))?;

    let spawned_ns = monotonic_ns();
    let server = Server::start(&config, &instance, &dir.join("procimgd.log"))?;
    let (lck0, rss0) = memory_kib(server.pid())?;

    let mut clients = Vec::new();
    let mut attach = Vec::new();
    let mut epoch_ns = None;
    for i in 0..args.clients.max(1) {
        let t = Instant::now();
        let client = Client::attach(
            &instance,
            AttachOptions::asynchronous(&format!("startup-{i}")),
        )
        .with_context(|| format!("client {i} could not attach"))?;
        attach.push(t.elapsed());
        if epoch_ns.is_none() {
            epoch_ns = client
                .cycle_info()
                .map(|c| c.cycle_start_ns - c.cycle_number * 1_000_000);
        }
        clients.push(client);
    }
    // Let the server's cycle connect to every client before looking at its memory.
    std::thread::sleep(Duration::from_millis(200));
    let (lck1, rss1) = memory_kib(server.pid())?;
    let (own_lck, own_rss) = memory_kib(std::process::id())?;
    drop(clients);
    drop(server);

    let first_cycle = epoch_ns
        .map(|e| format!("{:.1} ms", e.saturating_sub(spawned_ns) as f64 / 1e6))
        .unwrap_or_else(|| "no image seen".into());
    let mut sorted = attach.clone();
    sorted.sort();
    let ms = |d: Duration| format!("{:.2} ms", d.as_secs_f64() * 1e3);
    let n = args.clients.max(1) as u64;
    println!("image bytes each way          {}", args.image_bytes);
    println!("procimgd start → first cycle  {first_cycle}");
    println!(
        "procimgd, no client           VmLck {}  VmRSS {}",
        mib(lck0),
        mib(rss0)
    );
    println!(
        "procimgd, {n} clients          VmLck {}  VmRSS {}  (+{} locked per client)",
        mib(lck1),
        mib(rss1),
        mib(lck1.saturating_sub(lck0) / n)
    );
    println!(
        "Client::attach                first {}  median {}  max {}",
        ms(attach[0]),
        ms(sorted[sorted.len() / 2]),
        ms(sorted[sorted.len() - 1])
    );
    println!(
        "this process ({n} clients{})    VmLck {}  VmRSS {}",
        if args.mlock { ", mlockall" } else { "" },
        mib(own_lck),
        mib(own_rss)
    );
    Ok(())
}

/// Removes the run's temporary directory, whatever happens.
struct RemoveOnDrop(PathBuf);

impl Drop for RemoveOnDrop {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}
