// SPDX-License-Identifier: MIT OR Apache-2.0
//! `procimg status`.

use procimg_client::ControlHandle;
use procimg_control::{ArState, Percentiles, StationReport};

pub fn run(instance: &str, json: bool) -> anyhow::Result<()> {
    let control = ControlHandle::open(instance, "procimg-status")?;
    let s = control.status()?;
    if json {
        println!("{}", serde_json::to_string(&s)?);
        return Ok(());
    }
    println!(
        "instance {} (pid {}, generation {:016x}, layout {:016x})",
        s.instance, s.pid, s.generation, s.layout_hash
    );
    println!(
        "mode {}  cycle {} µs  OPDONE deadline {} µs  real-time {}",
        s.mode,
        s.cycle_ns as f64 / 1000.0,
        s.opdone_deadline_ns as f64 / 1000.0,
        if s.realtime { "yes" } else { "no" }
    );
    println!(
        "cycles {}  overruns {}  OPFAULTs {}",
        s.cycle_count, s.overruns, s.opfaults
    );
    println!(
        "heap allocations in the cycle {} (must stay 0{}); in client connection set-up {}",
        s.rt_heap_allocations,
        if s.rt_heap_allocations == 0 {
            ""
        } else {
            ": the real-time path allocated, see docs/ARCHITECTURE.md"
        },
        s.rt_setup_allocations
    );
    println!(
        "input images locked {} KiB; loans beyond them {}",
        s.input_images_locked_bytes / 1024,
        s.unready_image_loans
    );
    println!(
        "busy clients' outputs taken in place {}; writes rejected {}",
        s.outputs_in_place, s.rejected_writes
    );
    line("wake-up latency", &s.wakeup_latency);
    line("STARTOP→OPDONE", &s.handshake_round_trip);
    line("OPDONE one way", &s.opdone_one_way);
    line("cycle work", &s.cycle_work);
    match &s.station {
        // The device role: procimgd is the station, its PLC's AR is what there is.
        Some(st) => station(st),
        None => {
            let devices: Vec<String> = s
                .devices
                .iter()
                .map(|d| format!("{} {}", d.name, d.state))
                .collect();
            println!("devices: {}", devices.join(", "));
            if let Some(c) = &s.controller {
                println!(
                    "controller station \"{}\" ({}) on {}  IP {}/{}",
                    c.station_name, c.type_of_station, c.interface, c.ip, c.netmask
                );
                if let Some(n) = &c.counters {
                    println!(
                        "interface frames: {} sent ({} errors, {} collisions), {} received \
                         ({} errors, {} dropped)",
                        n.frames_sent,
                        n.send_errors,
                        n.send_collisions,
                        n.frames_received,
                        n.receive_errors,
                        n.received_dropped
                    );
                }
            }
        }
    }
    let n = &s.network;
    println!(
        "network: {} cyclic frames in; {} out ({} from the image, {} written first); dropped: \
         {} malformed, {} unknown, {} stale, {} no buffer; {} send errors, {} watchdog expiries",
        n.cyclic_frames,
        n.sent_in_place + n.sent_copied,
        n.sent_in_place,
        n.sent_copied,
        n.malformed,
        n.unknown,
        n.stale,
        n.dropped,
        n.send_errors,
        n.watchdog_expiries
    );
    println!(
        "RPC datagrams dropped: {} malformed, {} unexpected",
        n.malformed_datagrams, n.unexpected_datagrams
    );
    if s.forces.is_empty() {
        println!("no forces");
    } else {
        println!("FORCED (`procimg io unforce ADDR` or `--all` ends them):");
        for f in &s.forces {
            println!(
                "  {} {}  {}  ({} slot {} subslot {})",
                f.space,
                crate::io::range(f.address, f.data.len()),
                crate::text::hex(&f.data),
                f.device,
                f.slot,
                f.subslot
            );
        }
    }
    if s.clients.is_empty() {
        println!("no clients");
    } else {
        println!(
            "{:<5} {:<20} {:>8} {:<13} {:>8}  claims",
            "slot", "client", "pid", "role", "OPFAULTs"
        );
        for c in &s.clients {
            let claims: Vec<String> = c
                .claims
                .iter()
                .map(|k| {
                    format!(
                        "{} {}/{} Q{}..{}",
                        k.device,
                        k.slot,
                        k.subslot,
                        k.output_address,
                        k.output_address + k.output_length as u32 - 1
                    )
                })
                .collect();
            println!(
                "{:<5} {:<20} {:>8} {:<13} {:>8}  {}",
                c.slot,
                c.name,
                c.pid,
                format!("{:?}", c.role).to_lowercase(),
                c.opfaults,
                if claims.is_empty() {
                    "-".into()
                } else {
                    claims.join(", ")
                }
            );
        }
    }
    Ok(())
}

/// The station of the device role and its AR, as the PLC sees them.
fn station(st: &StationReport) {
    println!(
        "station \"{}\"  IP {}  MAC {}  VendorID {:#06x}  DeviceID {:#06x}",
        st.name, st.ip, st.mac, st.vendor_id, st.device_id
    );
    if let Some(p) = &st.program {
        match &p.defined_by {
            Some(who) => println!("tree defined by its program {who} from {}", p.gsdml),
            None => println!(
                "tree: waits for its program to define it from {} (off the wire until then)",
                p.gsdml
            ),
        }
    }
    match &st.ar {
        Some(ar) => {
            let plc = match ar.plc_running {
                Some(true) => "RUN",
                Some(false) => "STOP",
                None => "no frame yet",
            };
            let state = ar_words(ar.state);
            println!(
                "AR {state}  with PLC \"{}\" {} ({plc})  ARUUID {}",
                ar.controller_name, ar.controller_mac, ar.ar_uuid
            );
        }
        None => println!("AR none (no PLC connected)"),
    }
    if let Some(a) = &st.access_ar {
        println!(
            "device access AR of tool \"{}\" {}  ARUUID {}",
            a.tool_name, a.tool_mac, a.ar_uuid
        );
    }
    println!(
        "ARs aborted {}{}  alarms acknowledged by the PLC {}",
        st.aborted_ars,
        st.last_abort
            .as_deref()
            .map(|w| format!(" (last: {w})"))
            .unwrap_or_default(),
        st.alarms_acknowledged
    );
    neighbours(st);
}

/// The station port's LLDP neighbours and the alias name they give it.
fn neighbours(st: &StationReport) {
    if st.neighbours.is_empty() {
        println!("port-001 neighbour none (no LLDP received)");
    }
    for n in &st.neighbours {
        let who = match (&n.station, &n.port) {
            (Some(s), Some(p)) => format!("\"{s}\" {p}"),
            _ => format!("chassis {} port {}", n.chassis_id, n.port_id),
        };
        println!(
            "port-001 neighbour {who}  MAC {}{}{}  (forgotten in {} s without LLDP)",
            n.mac,
            n.ip.as_deref()
                .map(|ip| format!("  IP {ip}"))
                .unwrap_or_default(),
            n.mau_type
                .map(|m| format!("  MAU type {m}"))
                .unwrap_or_default(),
            n.ttl_left_s
        );
    }
    if let Some(alias) = &st.alias_name {
        println!("alias name {alias:?} (DCP Identify answers to it)");
    }
}

fn line(what: &str, p: &Percentiles) {
    if p.count == 0 {
        println!("{what:<16} no samples");
        return;
    }
    let us = |ns: u64| ns as f64 / 1000.0;
    println!(
        "{what:<16} min {:>7.1}  p50 {:>7.1}  p99 {:>7.1}  p99.9 {:>7.1}  max {:>8.1} µs  ({} samples)",
        us(p.min_ns),
        us(p.p50_ns),
        us(p.p99_ns),
        us(p.p999_ns),
        us(p.max_ns),
        p.count
    );
}

/// Where an AR of the device role stands, in words.
pub fn ar_words(state: ArState) -> &'static str {
    match state {
        ArState::Connected => "connected, the PLC writes its parameters",
        ArState::Parameterized => "parameterized, the ApplicationReady waits",
        ArState::WaitingForApplicationReadyConfirm => "ApplicationReady sent",
        ArState::Data => "in data exchange",
        ArState::Unknown => "in a state this tool does not know",
    }
}
