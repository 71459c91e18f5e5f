// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg-handshake attach-load`: what clients attaching and detaching cost a running
//! cycle, as overruns against an idle stretch of the same length.
//!
//! procimgd runs the demo (simulated devices that answer) or, with `--image-bytes`, the
//! generated image that nobody answers. Each round has two windows:
//!
//! - **attaching**: N synchronous clients attach one after the other, each dropped (detached)
//!   before the next, [`Args::pause`] apart;
//! - **idle**: nothing attaches, for as long as the attaching window took.
//!
//! Per window it prints procimgd's cycles, overruns and OPFAULTs (an attached client that
//! never answers STARTOP may get one), and at the end the overruns of all attaching windows
//! against those of all idle windows. Attaching sets up iceoryx2 ports in procimgd; the
//! cycle thread should not pay for that.

use crate::plant::{self, Plant};
use crate::server::{Counters, Server};
use anyhow::{Context, Result};
use procimg_client::{AttachOptions, Client};
use procimg_rt_tests::names::{ATTACHES, OVERRUNS_ATTACHING, OVERRUNS_IDLE, overrun_ratio};
use procimg_rt_tests::report::Report;
use std::path::Path;
use std::time::{Duration, Instant};

/// What to run.
pub struct Args<'a> {
    /// The generated image of this size instead of the demo.
    pub image_bytes: Option<usize>,
    /// Attaches per attaching window.
    pub attaches: u32,
    /// Rounds (an attaching and an idle window each).
    pub rounds: u32,
    /// Between one client's detach and the next attach.
    pub pause: Duration,
    /// Where the report goes, if anywhere.
    pub report: Option<&'a Path>,
}

/// One window's counters and length.
struct Window {
    counters: Counters,
    length: Duration,
}

/// Runs the benchmark and prints its figures.
pub fn run(args: &Args<'_>) -> Result<()> {
    let instance = format!("attach-load-{}", std::process::id());
    let dir = std::env::temp_dir().join(format!("procimg-attach-load-{}", std::process::id()));
    std::fs::create_dir_all(&dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let _cleanup = crate::RemoveOnDrop(dir.clone());
    let (toml, what) = match args.image_bytes {
        Some(image_bytes) => (
            Plant::at_one_ms(&instance, image_bytes).toml(),
            format!("{image_bytes} B each way, nobody answering"),
        ),
        None => (
            plant::demo_toml(&instance, 1_000_000).map_err(anyhow::Error::msg)?,
            "the demo".to_string(),
        ),
    };
    let config = dir.join("procimgd.toml");
    std::fs::write(&config, toml).with_context(|| format!("cannot write {}", config.display()))?;
    let server = Server::start(&config, &instance, &dir.join("procimgd.log"))?;
    println!(
        "# procimgd with {what}, 1 ms cycle; {} rounds of {} attaches ({} ms apart), each \
         against an idle window of the same length",
        args.rounds,
        args.attaches,
        args.pause.as_millis()
    );
    // Let the start's own work (devices coming up) pass before anything is counted.
    std::thread::sleep(Duration::from_secs(2));

    let mut attaching = Vec::new();
    let mut idle = Vec::new();
    println!("round  window     seconds    cycles  overruns  opfaults");
    for round in 1..=args.rounds {
        let before = server.counters()?;
        let t = Instant::now();
        for i in 0..args.attaches {
            let name = format!("attach-load-{i}");
            let client = Client::attach(&instance, AttachOptions::synchronous(&name))
                .with_context(|| format!("attach {i} of round {round} to {instance} failed"))?;
            drop(client);
            std::thread::sleep(args.pause);
        }
        let length = t.elapsed();
        let after = server.counters()?;
        let a = Window {
            counters: after.since(before),
            length,
        };
        print_window(round, "attaching", &a);
        attaching.push(a);

        std::thread::sleep(length);
        let later = server.counters()?;
        let b = Window {
            counters: later.since(after),
            length: t.elapsed() - length,
        };
        print_window(round, "idle", &b);
        idle.push(b);
    }
    drop(server);

    let total = |w: &[Window]| w.iter().map(|w| w.counters.overruns).sum::<u64>();
    let (with, without) = (total(&attaching), total(&idle));
    let ratio = match (with, without) {
        (0, 0) => "1.00 (none in either)".to_string(),
        (_, 0) => "infinite (none while idle)".to_string(),
        _ => format!("{:.2}", overrun_ratio(with, without)),
    };
    let attaches = u64::from(args.attaches) * u64::from(args.rounds);
    println!(
        "# overruns with {attaches} attaches: {with}; idle for as long: {without}; ratio {ratio}"
    );
    let mut report = Report::new("procimg-handshake attach-load");
    report
        .setting(
            "image_bytes",
            args.image_bytes
                .map_or("demo".to_string(), |b| b.to_string()),
        )
        .setting("pause_ms", args.pause.as_millis())
        .setting(ATTACHES, attaches)
        .setting(OVERRUNS_ATTACHING, with)
        .setting(OVERRUNS_IDLE, without);
    report.save(args.report, None)?;
    Ok(())
}

fn print_window(round: u32, name: &str, w: &Window) {
    println!(
        "{round:>5}  {name:<9} {:>8.1} {:>9} {:>9} {:>9}",
        w.length.as_secs_f64(),
        w.counters.cycles,
        w.counters.overruns,
        w.counters.opfaults
    );
}
