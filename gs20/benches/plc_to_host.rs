// SPDX-License-Identifier: MIT OR Apache-2.0
//! How long a PLC's write takes to reach a GS20-PN host as Adapter Data (0x31): prints the
//! figures, asserts nothing. As root (network namespaces, veth, AF_PACKET):
//!
//! ```text
//! cargo bench -p procimg-gs20 --bench plc_to_host [-- SAMPLES]   # 1000 by default
//! ```
//!
//! The plant of the veth acceptance test ([`host::plant`]), release builds: procimg's
//! controller as the PLC, procimgd's station, the bridge, the host on a pty. The PLC's
//! program writes a new value into item 3032's outputs every 10 cycles and notes when it
//! handed the cycle back (OPDONE). Two readers note when the value first reaches them:
//!
//! - the baseline, a synchronous client of the station: the write's path through the two
//!   cycle threads and the wire, which any program on the station has;
//! - the host: the same path, then the bridge and its 0x31 frame on the pty.
//!
//! The difference is the bridge's own share. A pty has no bit rate: a real UART adds the
//! frame's transmission time, printed beside the figures (11 bits a byte at 8E1).

#[path = "../tests/host/mod.rs"]
mod host;

use host::Got;
use host::plant::{OUTPUT_LEN, Plant, STATION_NAME};
use procimg_client::{AttachOptions, Client, Event};
use procimg_gs20::catalogue::ITEM_SUBSLOT;
use procimg_testkit::exchange::at;
use procimg_testkit::{pattern, pattern_value};
use std::collections::HashMap;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Cycles between two writes: long enough that each value reaches both readers before the
/// next one is written, at the bridge's worst (a whole 0x31 frame's pace on a 115200 line
/// is not modelled on the pty).
const EVERY: u64 = 10;

/// Cycles before the first write: the readers attach meanwhile.
const WARM_UP: u64 = 1_000;

/// The host's input image of the plant: zeros (the PLC's inputs are not measured here).
const HOST_IMAGE: [u8; 36] = [0; 36];

/// The bit rate of the module's UART.
const BAUD: f64 = 115_200.0;

fn main() {
    // `cargo bench` passes `--bench`; the first number is the sample count; `--test` (CI's
    // smoke run) takes a few.
    let args: Vec<String> = std::env::args().skip(1).collect();
    let samples: usize = match args.iter().find_map(|a| a.parse().ok()) {
        Some(n) => n,
        None if args.iter().any(|a| a == "--test") => 50,
        None => 1_000,
    };
    if !procimg_testkit::signal::is_root() {
        eprintln!("plc_to_host needs root (network namespaces, veth, AF_PACKET)");
        std::process::exit(1);
    }
    let mut plant = Plant::start("gl", false, &HOST_IMAGE);
    let done = Arc::new(AtomicBool::new(false));
    let writes = plc_writes(plant.plc.instance.clone(), samples as u64, done.clone());
    let station = station_reader(plant.station.instance.clone(), done.clone());

    // The host: the first Adapter Data of each value, and when it was read.
    let from = plant.host.mark();
    let mut at_host = HashMap::new();
    let mut looked = from;
    while !done.load(Ordering::Acquire) {
        plant.host.read(Duration::from_millis(50));
        for i in looked..plant.host.got.len() {
            if let Got::Data(d) = &plant.host.got[i]
                && let Some(k) = pattern_value(d)
            {
                at_host.entry(k).or_insert(plant.host.arrived[i]);
            }
        }
        looked = plant.host.got.len();
    }
    let Written {
        values: writes,
        opfaults,
    } = writes.join().expect("the PLC's program");
    let at_station = station.join().expect("the station's reader");

    let mut to_station = Vec::new();
    let mut to_host = Vec::new();
    let mut bridge = Vec::new();
    for (k, written) in &writes {
        let (Some(s), Some(h)) = (at_station.get(k), at_host.get(k)) else {
            continue;
        };
        to_station.push(s.saturating_duration_since(*written));
        to_host.push(h.saturating_duration_since(*written));
        bridge.push(h.saturating_duration_since(*s));
    }
    let frame = OUTPUT_LEN + 4;
    let uart = Duration::from_secs_f64(frame as f64 * 11.0 / BAUD);
    let reached =
        |seen: &HashMap<u64, Instant>| writes.iter().filter(|(k, _)| seen.contains_key(k)).count();
    println!(
        "plc_to_host: {} writes, {} reached the station's client, {} the host; cycle 1 ms, \
         item 3032 (32 bytes)",
        writes.len(),
        reached(&at_station),
        reached(&at_host),
    );
    println!("the PLC's OPDONE came too late (OPFAULT) in {opfaults} cycles");
    print_row(
        "PLC write → station client (baseline)",
        &mut to_station,
        None,
    );
    let baseline = median(&to_station);
    print_row("PLC write → 0x31 at the host (pty)", &mut to_host, baseline);
    print_row("station client → 0x31 (the bridge)", &mut bridge, None);
    println!(
        "a {frame}-byte 0x31 frame on a UART at 115200 8E1 adds {:.2} ms",
        uart.as_secs_f64() * 1e3
    );
    drop(plant);
}

/// What the PLC's program wrote: each value and the moment it was first handed over; the
/// cycles whose OPDONE came too late (OPFAULT: their outputs were not used, and the next
/// cycle's carry the value again, as a PLC program writes its outputs every cycle).
struct Written {
    values: Vec<(u64, Instant)>,
    opfaults: usize,
}

/// The PLC's program: a new value every [`EVERY`] cycles, `samples` of them, written every
/// cycle. Sets `done` when the last value has had a second to arrive.
fn plc_writes(
    instance: String,
    samples: u64,
    done: Arc<AtomicBool>,
) -> std::thread::JoinHandle<Written> {
    std::thread::spawn(move || {
        let _ = procimg_client::realtime::make_current_thread_realtime(60);
        let mut client = Client::attach(&instance, AttachOptions::synchronous("gs20-bench-plc"))
            .expect("attach to the controller");
        client
            .claim_device(STATION_NAME)
            .expect("claim the outputs");
        let item = at(&client, 1, ITEM_SUBSLOT);
        let mut written = Written {
            values: Vec::with_capacity(samples as usize),
            opfaults: 0,
        };
        let mut value = 1;
        // A second of cycles after the last value, for it to arrive.
        for n in 1..=WARM_UP + samples * EVERY + 1_000 {
            let mut cycle = client
                .wait_startop(Duration::from_secs(5))
                .expect("STARTOP");
            let new =
                n > WARM_UP && written.values.len() < samples as usize && n.is_multiple_of(EVERY);
            value += u64::from(new);
            cycle
                .output_mut(item)
                .expect("outputs")
                .copy_from_slice(&pattern(value, OUTPUT_LEN));
            cycle.set_opdone().expect("OPDONE");
            if new {
                written.values.push((value, Instant::now()));
            }
            written.opfaults += client
                .events()
                .iter()
                .filter(|e| matches!(e, Event::OpFault { .. }))
                .count();
        }
        done.store(true, Ordering::Release);
        written
    })
}

/// A synchronous client of the station: when each value first shows in item 3032's Q data.
fn station_reader(
    instance: String,
    done: Arc<AtomicBool>,
) -> std::thread::JoinHandle<HashMap<u64, Instant>> {
    std::thread::spawn(move || {
        let _ = procimg_client::realtime::make_current_thread_realtime(60);
        let mut client =
            Client::attach(&instance, AttachOptions::synchronous("gs20-bench-station"))
                .expect("attach to the station");
        let item = at(&client, 1, ITEM_SUBSLOT);
        let mut seen = HashMap::new();
        while !done.load(Ordering::Acquire) {
            let Ok(cycle) = client.wait_startop(Duration::from_secs(5)) else {
                break;
            };
            let now = Instant::now();
            if let Some(k) = cycle.q_data(item).ok().and_then(pattern_value) {
                seen.entry(k).or_insert(now);
            }
            if cycle.set_opdone().is_err() {
                break;
            }
        }
        seen
    })
}

fn median(d: &[Duration]) -> Option<Duration> {
    let mut d = d.to_vec();
    d.sort();
    d.get(d.len() / 2).copied()
}

/// One line: median, 90th and 99th percentile, maximum in ms; with a baseline, the median's
/// ratio to it.
fn print_row(what: &str, d: &mut [Duration], baseline: Option<Duration>) {
    if d.is_empty() {
        println!("{what}: no samples");
        return;
    }
    d.sort();
    let q = |p: f64| d[((d.len() - 1) as f64 * p).round() as usize].as_secs_f64() * 1e3;
    let ratio = baseline
        .map(|b| {
            format!(
                ", median ×{:.2} the baseline",
                d[d.len() / 2].as_secs_f64() / b.as_secs_f64()
            )
        })
        .unwrap_or_default();
    println!(
        "{what}: median {:.2} ms, p90 {:.2}, p99 {:.2}, max {:.2} ms{ratio}",
        q(0.5),
        q(0.9),
        q(0.99),
        q(1.0)
    );
}
