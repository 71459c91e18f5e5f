// SPDX-License-Identifier: MIT OR Apache-2.0
//! An asynchronous monitor: reads the newest consistent image whenever it likes (no
//! handshake), prints every device's inputs with their status once a period, and reports
//! mode changes as they happen.
//!
//!   cargo run --release --example monitor -- --period-ms 500

use clap::Parser;
use procimg_client::{AttachOptions, Client, Event};
use std::fmt::Write as _;
use std::time::{Duration, Instant};

#[derive(Parser)]
struct Args {
    /// Instance to attach to.
    #[arg(long, default_value = "procimg")]
    instance: String,
    /// Print period in ms.
    #[arg(long, default_value_t = 1000)]
    period_ms: u64,
    /// Stop after this many lines (default: run until interrupted).
    #[arg(long)]
    lines: Option<u64>,
}

fn main() {
    // An expected error (no server, say) is a message that says what to do, not a backtrace.
    if let Err(e) = run(Args::parse()) {
        eprintln!("monitor: {e:#}");
        std::process::exit(1);
    }
}

fn run(args: Args) -> anyhow::Result<()> {
    let mut client = Client::attach(&args.instance, AttachOptions::asynchronous("monitor"))?;
    let period = Duration::from_millis(args.period_ms);
    let mut next = Instant::now();
    let mut printed = 0;
    while args.lines.is_none_or(|n| printed < n) {
        // Any cycle will do: waiting for one just keeps the image fresh and the loop calm.
        if let Ok(cycle) = client.wait_startop(Duration::from_millis(100))
            && Instant::now() >= next
        {
            next += period;
            let mut line = format!("cycle {:>9} {:<8}", cycle.number(), cycle.mode().name());
            let layout = cycle.layout();
            for d in 0..layout.devices.len() {
                let _ = write!(line, " | {}", layout.device_name(d));
                for s in layout.submodules_of(d) {
                    let (Some(input), Some(st)) = (cycle.input(s), cycle.status(s)) else {
                        continue;
                    };
                    if input.is_empty() {
                        continue;
                    }
                    let _ = write!(line, " ");
                    for b in input.iter().take(8) {
                        let _ = write!(line, "{b:02x}");
                    }
                    if st.input_remote != procimg_client::Ioxs::Good {
                        line.push_str("(BAD)");
                    }
                }
            }
            println!("{line}");
            printed += 1;
        }
        for e in client.events() {
            match e {
                Event::Mode(m) => println!("mode {m}"),
                Event::ServerShutdown => println!("server stopping"),
                Event::Reattached { generation } => {
                    println!("re-attached to the restarted server (generation {generation:016x})")
                }
                _ => {}
            }
        }
    }
    Ok(())
}
