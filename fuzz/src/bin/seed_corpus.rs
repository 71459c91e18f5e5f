// SPDX-License-Identifier: MIT OR Apache-2.0
//! Writes the seed corpus of every fuzz target, `fuzz/seeds/<target>/` (or below the folder
//! given as the only argument), from the captured frames in
//! `profinet/tests/fixtures/captures`, the configuration and GSDML files of the repository,
//! and a bring-up recorded on the simulated network:
//!
//! ```text
//! cargo run --manifest-path fuzz/Cargo.toml --bin seed_corpus
//! ```
//!
//! Each target gets the part of a frame it parses: whole frames (`frame`), the PROFINET PDU
//! behind the EtherType (`dcp`, `alarm`), the UDP payload (`rpc`), the PNIO blocks after the
//! RPC and NDR headers (`connect`, `control`, `record`), operation sequences (`controller`,
//! `device`, `rta_channel`), text (`config`, `gsdml`), GS20-PN host link frames and UART
//! streams (`gs20`, from the reference's examples), LLDPDUs and the physical device's records
//! (`topology`). Run it again when the captures,
//! the operation formats in `src/world.rs` or the fuzz network change. The output is the same
//! every time except for the ARUUIDs and activity UUIDs the controller draws at random, which
//! appear in the `device` bring-up seed.

use procimg_fuzz::captures::{self, Captured, profinet_pdu, rpc_blocks, udp_payload};
use procimg_fuzz::ops::Writer;
use procimg_fuzz::world::{self, device_ops, ops};
use procimg_profinet::wire::alarm;
use procimg_profinet::wire::record::IodHeader;
use procimg_profinet::wire::rpc::{self, opnum};
use procimg_profinet::wire::rt::FrameIdClass;
use procimg_profinet::wire::rta_pdu::{self, RtaPdu};
use procimg_runtime::config::DEMO_TOML;
use procimg_runtime::roles::controller::sim_plant;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Seeds by target, then by file name.
type Seeds = BTreeMap<&'static str, BTreeMap<String, Vec<u8>>>;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let fuzz_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = std::env::args_os()
        .nth(1)
        .map_or_else(|| fuzz_dir.join("seeds"), PathBuf::from);
    let caps = captures::load(&captures::default_dir())?;
    let mut seeds = Seeds::new();
    frames(&caps, &mut seeds);
    sessions(&caps, &mut seeds);
    rta_channel(&caps, &mut seeds);
    text(fuzz_dir, &mut seeds)?;
    gs20(&mut seeds)?;
    topology(&mut seeds)?;
    let mut total = 0;
    for (target, files) in &seeds {
        let dir = out.join(target);
        if dir.exists() {
            std::fs::remove_dir_all(&dir)?;
        }
        std::fs::create_dir_all(&dir)?;
        for (name, bytes) in files {
            std::fs::write(dir.join(name), bytes)?;
            total += bytes.len();
        }
        println!("{target}: {} seeds", files.len());
    }
    println!("{} bytes in {}", total, out.display());
    Ok(())
}

fn add(seeds: &mut Seeds, target: &'static str, name: &str, bytes: &[u8]) {
    seeds
        .entry(target)
        .or_default()
        .insert(name.replace('/', "_"), bytes.to_vec());
}

/// The opnum of an unfragmented RPC request or response.
fn rpc_opnum(frame: &[u8]) -> Option<u16> {
    rpc::Pdu::parse(udp_payload(frame)?)
        .ok()
        .map(|p| p.header.opnum)
}

/// The parser targets: each capture cut to what the target parses.
fn frames(caps: &[Captured], seeds: &mut Seeds) {
    for c in caps {
        add(seeds, "frame", &c.name, &c.frame);
        if let Some(pdu) = profinet_pdu(&c.frame) {
            let id = pdu.get(..2).map_or(0, |b| u16::from_be_bytes([b[0], b[1]]));
            match FrameIdClass::of(id) {
                FrameIdClass::Dcp => add(seeds, "dcp", &c.name, pdu),
                FrameIdClass::AlarmHigh | FrameIdClass::AlarmLow => {
                    add(seeds, "alarm", &c.name, pdu)
                }
                _ => {}
            }
        }
        if let Some(udp) = udp_payload(&c.frame) {
            add(seeds, "rpc", &c.name, udp);
        }
        let (Some(blocks), Some(op)) = (rpc_blocks(&c.frame), rpc_opnum(&c.frame)) else {
            continue;
        };
        match op {
            opnum::CONNECT => add(seeds, "connect", &c.name, blocks),
            opnum::CONTROL | opnum::RELEASE => add(seeds, "control", &c.name, blocks),
            opnum::READ | opnum::WRITE | opnum::READ_IMPLICIT => {
                add(seeds, "record", &c.name, blocks);
                // The record data alone, e.g. the I&M0 block of a read response.
                if let Ok((_, data, _)) = IodHeader::split(blocks)
                    && !data.is_empty()
                {
                    add(seeds, "record", &format!("{}-data", c.name), data);
                }
            }
            _ => {}
        }
    }
    // Every block of the Connect exchange on its own, too.
    let split: Vec<(String, Vec<u8>)> = seeds
        .get("connect")
        .into_iter()
        .flatten()
        .flat_map(|(name, b)| {
            procimg_profinet::wire::common::blocks(b)
                .map_while(Result::ok)
                .enumerate()
                .map(move |(i, (_, block))| (format!("{name}-block{i}"), block.to_vec()))
        })
        .collect();
    for (name, b) in split {
        add(seeds, "connect", &name, &b);
    }
}

/// The controller and simulated device targets: a recorded bring-up, and variations that
/// reach records, alarms, release and the S7's own requests.
fn sessions(caps: &[Captured], seeds: &mut Seeds) {
    let (bringup, sent) = world::record_bringup();
    add(seeds, "controller", "bringup", &bringup);

    let with = |tail: &dyn Fn(&mut Writer)| {
        let mut w = Writer::new();
        let mut seed = bringup.clone();
        tail(&mut w);
        seed.extend(w.finish());
        seed
    };
    add(
        seeds,
        "controller",
        "bringup-outputs",
        &with(&|w| {
            w.u8(ops::OUTPUTS).u8(0).u8(1).bytes(&[0x5a; 16]);
            w.u8(ops::STEP).u8(10);
        }),
    );
    add(
        seeds,
        "controller",
        "bringup-alarm",
        &with(&|w| {
            w.u8(ops::RAISE_ALARM).u8(0).u16(0x0010).bytes(&[1, 2]);
            w.u8(ops::STEP)
                .u8(5)
                .u8(ops::ACK_ALARMS)
                .u8(ops::STEP)
                .u8(5);
        }),
    );
    add(
        seeds,
        "controller",
        "bringup-records",
        &with(&|w| {
            // I&M0 of the IO submodule, then a write of a user record.
            w.u8(ops::RECORD)
                .u8(0)
                .u16(1)
                .u16(1)
                .u16(0xaff0)
                .u16(256)
                .u8(0);
            w.bytes(&[]);
            w.u8(ops::STEP).u8(5);
            w.u8(ops::RECORD)
                .u8(0)
                .u16(1)
                .u16(1)
                .u16(0x0100)
                .u16(0)
                .u8(1);
            w.bytes(&[9, 8, 7]);
            w.u8(ops::STEP).u8(5);
        }),
    );
    add(
        seeds,
        "controller",
        "bringup-offline",
        &with(&|w| {
            w.u8(ops::ONLINE).u8(0).u8(ops::STEP).u8(20);
            w.u8(ops::ACTIVATE)
                .u8(1)
                .u8(0)
                .u8(ops::ONLINE)
                .u8(1)
                .u8(ops::STEP)
                .u8(50);
        }),
    );
    add(
        seeds,
        "controller",
        "bringup-lost-frames",
        &with(&|w| {
            // Drop a cyclic frame of a device, then let its watchdog run out.
            w.u8(ops::TAMPER).u8(3).u8(0).u8(2).u16(0).u8(0);
            w.u8(ops::STEP).u8(2);
            w.u8(ops::WATCHDOG)
                .u8(0)
                .u32(1)
                .u8(ops::SKIP)
                .u16(600)
                .u8(ops::STEP)
                .u8(30);
        }),
    );
    // A corrupted Connect response: the first datagram a device sends.
    let mut w = Writer::new();
    w.u8(ops::TAMPER).u8(1).u8(0).u8(0).u16(120).u8(0x40);
    let mut seed = w.finish();
    seed.extend(&bringup);
    add(seeds, "controller", "corrupt-connect-response", &seed);
    // The captured frames and datagrams, handed to a running controller.
    add(
        seeds,
        "controller",
        "bringup-captures",
        &with(&|w| {
            for c in caps {
                if let Some(udp) = udp_payload(&c.frame) {
                    w.u8(ops::DATAGRAM).u8(0).u16(rpc::RPC_PORT).bytes(udp);
                } else {
                    w.u8(ops::FRAME).bytes(&c.frame);
                    w.u8(ops::WIRE).bytes(&c.frame);
                }
            }
            w.u8(ops::STEP).u8(10);
        }),
    );

    // The simulated device: what the controller sent it, and the S7's side of the captured
    // session, addressed to the simulated device.
    add(seeds, "device", "bringup", &world::device_seed(&sent));
    // The same with the application's part: slots 0 and 1 give their records to it, the
    // ApplicationReady held, new ARs checked; afterwards the check accepted, jobs answered
    // (one with an error) and the hold released.
    let mut w = Writer::new();
    for (what, arg, len) in [(0, 1, 0), (0, 3, 0), (2, 1, 0), (4, 1, 0)] {
        w.u8(device_ops::APPLICATION).u8(what).u8(arg).u8(len);
    }
    let mut application = w.finish();
    application.extend_from_slice(&world::device_seed(&sent));
    let mut w = Writer::new();
    for (what, arg, len) in [(5, 0, 0), (1, 0, 4), (1, 1, 255), (1, 0, 0), (3, 0, 0)] {
        w.u8(device_ops::APPLICATION).u8(what).u8(arg).u8(len);
    }
    w.u8(device_ops::STEP).u8(50);
    application.extend_from_slice(&w.finish());
    add(seeds, "device", "bringup-application", &application);
    // The same bring-up, then slot 1 pulled, plugged again as it was, pulled, plugged with
    // other ident numbers, and the return of slot 2 announced.
    let mut plugging = world::device_seed(&sent);
    let mut w = Writer::new();
    for (what, arg, len) in [(6, 1, 0), (6, 1, 0), (6, 1, 0), (6, 1, 1), (7, 2, 0)] {
        w.u8(device_ops::APPLICATION).u8(what).u8(arg).u8(len);
        w.u8(device_ops::STEP).u8(5);
    }
    plugging.extend_from_slice(&w.finish());
    add(seeds, "device", "bringup-plugging", &plugging);
    let by_name = |name: &str| caps.iter().find(|c| c.name == name);
    let s7 = [
        "cm/dcp_set_req",
        "cm/connect_req",
        "cm/write_req",
        "cm/prmend_req",
        "cm/appready_res",
        "rt/rtc_cpu_8001",
        "rt/echo_cpu_8001",
        "alarm/alarm_ack_rta_high_cpu",
        "alarm/alarm_ack_high_cpu",
        "alarm/alarm_ack_rta_low_cpu",
        "alarm/alarm_diag_ack_cpu",
        "alarm/im0_read_req",
        "alarm/im0_read_req_if",
        "alarm/alarm_err_rta_cpu",
    ];
    let session = device_messages(s7.iter().filter_map(|n| by_name(n)));
    add(seeds, "device", "s7-session", &session);
    add(
        seeds,
        "device",
        "every-capture",
        &device_messages(caps.iter()),
    );
}

/// `device` operations delivering captured frames and datagrams to the simulated device:
/// frames re-addressed to its MAC, RPC requests to its port 34964, other RPC PDUs (answers to
/// its own calls) to another port, 2 ms apart.
fn device_messages<'a>(caps: impl Iterator<Item = &'a Captured>) -> Vec<u8> {
    let mac = sim_plant::device_mac(0);
    let mut w = Writer::new();
    for c in caps {
        match udp_payload(&c.frame) {
            Some(udp) => {
                let request = rpc::Packet::new_checked(udp)
                    .is_ok_and(|p| p.packet_type() == rpc::PacketType::Request);
                // Calls come from the S7's client port to 34964; answers to the device's own
                // calls (ApplicationReady) go the other way.
                let (from, to) = if request {
                    (0xc001, rpc::RPC_PORT)
                } else {
                    (rpc::RPC_PORT, 0xc001)
                };
                w.u8(device_ops::DATAGRAM).u16(from).u16(to).bytes(udp);
            }
            None => {
                let mut frame = c.frame.clone();
                if frame.len() >= 6 {
                    frame[..6].copy_from_slice(&mac.0);
                }
                w.u8(device_ops::FRAME).bytes(&frame);
            }
        }
        w.u8(device_ops::STEP).u8(2);
    }
    w.finish()
}

/// The RTA channel target: a channel with the captured session's endpoints, fed the captured
/// PDUs, asked to send the captured notification blocks, given time.
fn rta_channel(caps: &[Captured], seeds: &mut Seeds) {
    let pdus: Vec<(&str, &[u8], RtaPdu)> = caps
        .iter()
        .filter_map(|c| {
            let pdu = profinet_pdu(&c.frame)?;
            let parsed = RtaPdu::parse(&rta_pdu::Packet::new_checked(pdu).ok()?).ok()?;
            Some((c.name.as_str(), pdu, parsed))
        })
        .collect();
    for (name, pdu, parsed) in &pdus {
        let h = parsed.header;
        let mut w = Writer::new();
        let priority = u8::from(parsed.priority == alarm::Priority::Low);
        w.u8(priority)
            .u16(h.dst_endpoint)
            .u16(h.src_endpoint)
            .u16(1)
            .u16(3)
            .u8(0);
        // Receive it, send its blocks back, wait for the retransmission, receive again.
        w.u8(0).bytes(pdu);
        w.u8(2).bytes(pdu.get(rta_pdu::HEADER_LEN..).unwrap_or(&[]));
        w.u8(3).u16(150).u8(0).bytes(pdu).u8(3).u16(500);
        add(seeds, "rta_channel", name, &w.finish());
    }
    // The window logic from sequence numbers: DATA 0xFFFF, its duplicate, an ACK, and one out
    // of order.
    let mut w = Writer::new();
    w.u8(0).u16(1).u16(2).u16(1).u16(3).u8(0);
    w.u8(1).u8(0).u16(0xffff).u16(0xfffe);
    w.u8(1).u8(0).u16(0xffff).u16(0xfffe);
    w.u8(2).bytes(&[]).u8(1).u8(1).u16(0xfffe).u16(0xffff);
    w.u8(1).u8(0).u16(0x0005).u16(0x0000).u8(3).u16(100);
    add(seeds, "rta_channel", "sequence", &w.finish());
}

/// The configuration and GSDML targets: the repository's own files.
fn text(fuzz_dir: &Path, seeds: &mut Seeds) -> std::io::Result<()> {
    add(seeds, "config", "demo.toml", DEMO_TOML.as_bytes());
    add(
        seeds,
        "config",
        "fuzz-network.toml",
        world::CONFIG.as_bytes(),
    );
    let root = fuzz_dir.join("..");
    for dir in ["config/gsdml", "config/tests/fixtures/gsdml"] {
        let mut files: Vec<PathBuf> = std::fs::read_dir(root.join(dir))?
            .map(|e| e.map(|e| e.path()))
            .collect::<Result<_, _>>()?;
        files.sort();
        for f in files {
            if f.extension().is_some_and(|e| e == "xml") {
                let name = f.file_name().unwrap_or_default().to_string_lossy();
                add(seeds, "gsdml", &name, &std::fs::read(&f)?);
            }
        }
    }
    Ok(())
}

/// The GS20-PN host link: the reference's example frames (§1.4) one by one, and UART streams
/// of a host's session and of a module in Run, with garbage and a damaged frame in the first.
fn gs20(seeds: &mut Seeds) -> Result<(), procimg_gs20::frame::EmitError> {
    use procimg_gs20::messages::*;
    use std::net::{Ipv4Addr, SocketAddrV4};

    let add_item = AddItem {
        item_id: 3008,
        position: 1,
    }
    .to_vec()?;
    let response = AdapterResponse::new(
        Mode::Config,
        StatusFlags::empty(),
        ErrorBits::NO_NETWORK_CONFIG,
    )
    .to_vec()?;
    let status = RequestStatus.to_vec()?;
    let start = RequestStart.to_vec()?;
    add(seeds, "gs20", "add-item-3008-slot-1", &add_item);
    add(seeds, "gs20", "adapter-response-no-network", &response);
    add(seeds, "gs20", "request-status", &status);
    add(seeds, "gs20", "request-reset", &RequestReset.to_vec()?);
    add(seeds, "gs20", "request-start", &start);

    let network = SetNetworkConfig::static_ip(
        Ipv4Addr::new(192, 168, 0, 50),
        Ipv4Addr::new(255, 255, 255, 0),
        b"gs20-host",
    )
    .to_vec()?;
    let mut damaged = add_item.clone();
    damaged[5] ^= 0x01;
    let host = [
        &status[..],
        &AddDevice { device_id: 1 }.to_vec()?,
        &add_item,
        &AddItem {
            item_id: 1002,
            position: 2,
        }
        .to_vec()?,
        &[0x00, 0x55, 0xFF],
        &damaged,
        &network,
        &SetSerialNumber { serial: 42 }.to_vec()?,
        &start,
        &SetBusData { data: &[1; 10] }.to_vec()?,
        &OpenSocket {
            role: SocketRole::Client,
            protocol: SocketProtocol::Udp,
            port: 5000,
            ip: Ipv4Addr::new(192, 168, 0, 9),
        }
        .to_vec()?,
        &SendSocketData {
            handle: 1,
            data: b"ping",
        }
        .to_vec()?,
    ]
    .concat();
    add(seeds, "gs20", "host-session", &host);

    let remote = SocketAddrV4::new(Ipv4Addr::new(192, 168, 0, 9), 5000);
    let module = [
        &AdapterResponse::new(Mode::Run, StatusFlags::PLC_CONNECTED, ErrorBits::empty())
            .to_vec()?[..],
        &AdapterEvent {
            mode: Mode::Run,
            event: Event::PlcConnected,
        }
        .to_vec()?,
        &AdapterData { data: &[2; 8] }.to_vec()?,
        &SocketResponse {
            handle: 1,
            status: SocketStatus::LISTENING,
            errors: SocketErrors::empty(),
        }
        .to_vec()?,
        &SocketEvent {
            handle: 1,
            status: SocketStatus::CONNECTED,
            event: SocketEventKind::Connected { remote },
        }
        .to_vec()?,
        &AdapterSocketData {
            handle: 1,
            data: b"pong",
        }
        .to_vec()?,
    ]
    .concat();
    add(seeds, "gs20", "module-run", &module);
    Ok(())
}

/// The topology: an S7-like port's LLDPDUs as a length-prefixed stream (announced, again,
/// withdrawn), and the physical device's blocks one by one.
fn topology(seeds: &mut Seeds) -> Result<(), procimg_profinet::wire::EmitError> {
    use procimg_profinet::port::lldp::{Announcer, LldpStation};
    use procimg_profinet::wire::MacAddress;
    use procimg_profinet::wire::record::*;

    let plc = MacAddress([0x28, 0x63, 0x36, 0x8a, 0x1b, 0x01]);
    let mut port = Announcer::new(LldpStation::new("plc", plc, plc, Some([192, 168, 0, 1]), 1));
    let frame = port.poll(0).expect("an announcement");
    let pdu = &frame[14..];
    let mut withdrawn = pdu.to_vec();
    // The TTL TLV follows Chassis ID and Port ID: set it to 0.
    let ttl_at = 2 + usize::from(pdu[1]) + 2 + usize::from(pdu[2 + usize::from(pdu[1]) + 1]);
    withdrawn[ttl_at + 2..ttl_at + 4].copy_from_slice(&[0, 0]);
    let mut stream = Vec::new();
    for p in [pdu, pdu, &withdrawn[..]] {
        stream.extend_from_slice(&(p.len() as u16).to_be_bytes());
        stream.extend_from_slice(p);
    }
    add(seeds, "topology", "lldp-announced-again-withdrawn", &stream);
    let peer = PeerReal {
        port_id: "port-001".into(),
        chassis_id: "plc".into(),
        line_delay: 0,
        mac: plc,
    };
    let real = PdPortDataReal {
        slot: 0,
        subslot: 0x8001,
        own_port_id: "port-001".into(),
        peers: vec![peer],
        mau_type: 0x10,
        domain_boundary: 0,
        multicast_boundary: 0,
        port_state: PORT_STATE_UNKNOWN,
        link: LINK_UP,
        media_type: MEDIA_COPPER,
    };
    add(seeds, "topology", "pd-port-data-real", &real.to_vec()?);
    let interface = PdInterfaceDataReal {
        chassis_id: "io-device".into(),
        mac: plc,
        ip: [192, 168, 0, 10],
        mask: [255, 255, 255, 0],
        gateway: [0; 4],
    };
    add(
        seeds,
        "topology",
        "pd-interface-data-real",
        &interface.to_vec()?,
    );
    let mut blocks = interface.to_vec()?;
    blocks.extend(PdPortStatistic::default().to_vec()?);
    let mbh = MultipleBlockHeader {
        api: 0,
        slot: 0,
        subslot: 0x8000,
        blocks,
    };
    add(seeds, "topology", "multiple-block-header", &mbh.to_vec()?);
    let check = PdPortDataCheck {
        slot: 0,
        subslot: 0x8001,
        checks: vec![
            PortCheck::Peers(vec![CheckedPeer {
                port_id: "port-002".into(),
                chassis_id: "switch".into(),
            }]),
            PortCheck::MauType(0x10),
        ],
    };
    add(seeds, "topology", "pd-port-data-check", &check.to_vec()?);
    let adjust = PdPortDataAdjust {
        slot: 0,
        subslot: 0x8001,
        adjusts: vec![
            PortAdjust::PeerToPeerBoundary {
                boundary: PEER_TO_PEER_NO_LLDP,
                properties: 0,
            },
            PortAdjust::DcpBoundary {
                boundary: DCP_BOUNDARY_IDENTIFY,
                properties: 0,
            },
        ],
    };
    add(seeds, "topology", "pd-port-data-adjust", &adjust.to_vec()?);
    add(
        seeds,
        "topology",
        "log-book-empty",
        &LogBookData::default().to_vec()?,
    );
    add(
        seeds,
        "topology",
        "api-data",
        &ApiData { apis: vec![0] }.to_vec()?,
    );
    Ok(())
}
