// SPDX-License-Identifier: MIT OR Apache-2.0
//! Everything the simulated PROFINET device emits in a full bring-up must decode in
//! Wireshark's dissectors without malformed packets or error-level expert items: DCP
//! answers, RPC responses (positive, negative, with a ModuleDiffBlock, reject, no-call,
//! FACK), the ApplicationReady request, cyclic input frames, alarm frames and the LLDP
//! announcements (at start-up, after the Set IP and after the PDInterfaceAdjust).
//!
//! The controller's side is the S7-1515's captured requests where there are some (test data
//! of the `pnio` crate 0.1.0, MIT OR Apache-2.0) and requests built with our codecs.

use procimg_profinet::dcp_client;
use procimg_profinet::device::{ArState, Device, DeviceAction, DeviceSetup, PluggedSubmodule};
use procimg_profinet::wire::alarm::{AlarmAck, AlarmBlock, Priority};
use procimg_profinet::wire::connect::ConnectRequest;
use procimg_profinet::wire::control::ControlBlock;
use procimg_profinet::wire::dcp;
use procimg_profinet::wire::record::{Im0, IodHeader};
use procimg_profinet::wire::rpc::{self, Header, PacketType, Pdu, flags1, opnum};
use procimg_profinet::wire::rta_pdu::RtaPdu;
use procimg_profinet::wire::{MacAddress, PnioStatus, ethernet};
use procimg_runtime::config::SimBehaviour;
use procimg_runtime::roles::controller::sim_behaviour::DemoApplication;
use procimg_runtime::roles::controller::sim_plant::DemoDevice;
use procimg_testkit::fixtures::profinet_capture as capture;
use procimg_testkit::udp::udp_frame;
use std::net::{Ipv4Addr, SocketAddrV4};

const S7_MAC: MacAddress = MacAddress([0xec, 0x1c, 0x5d, 0x61, 0xe7, 0x3f]);
const DEVICE_MAC: MacAddress = MacAddress([0x8c, 0xf3, 0x19, 0xcd, 0x19, 0xf8]);
const S7_IP: Ipv4Addr = Ipv4Addr::new(172, 16, 2, 100);
const DEVICE_IP: [u8; 4] = [172, 16, 2, 10];
const S7_CLIENT: SocketAddrV4 = SocketAddrV4::new(S7_IP, 54766);
const MS: u64 = 1_000_000;

/// The captured RPC PDU of a frame (bytes 42.. after Ethernet, IPv4 and UDP).
fn rpc_capture(name: &str) -> Vec<u8> {
    capture(name)[42..].to_vec()
}

/// The p-net sample device of the captures: what the S7's Connect expects is plugged.
fn device(drop_slot: Option<u16>) -> DemoDevice {
    let payload = rpc_capture("cm/connect_req");
    let req = ConnectRequest::parse(Pdu::parse(&payload).unwrap().blocks).unwrap();
    let submodules = req
        .expected
        .iter()
        .flat_map(|b| b.modules.iter())
        .filter(|m| Some(m.slot) != drop_slot)
        .flat_map(|m| {
            m.submodules.iter().map(|s| PluggedSubmodule {
                api: m.api,
                slot: m.slot,
                subslot: s.subslot,
                module_ident: m.module_ident,
                submodule_ident: s.submodule_ident,
                input_length: s.input_length(),
                output_length: s.output_length(),
            })
        })
        .collect();
    let im0 = {
        let res = rpc_capture("alarm/im0_read_res");
        let (_, data, _) = IodHeader::split(Pdu::parse(&res).unwrap().blocks).unwrap();
        Im0::parse(data).unwrap()
    };
    Device::new(DeviceSetup {
        name: "rt-labs-dev".into(),
        mac: DEVICE_MAC,
        ip: None,
        vendor_id: 0x0493,
        device_id: 0x0002,
        instance: 1,
        submodules,
        application: DemoApplication(SimBehaviour::Echo),
        im0,
    })
}

/// Collects what the device emits, as Ethernet frames.
struct Wire {
    frames: Vec<Vec<u8>>,
}

impl Wire {
    fn take(&mut self, out: &mut Vec<DeviceAction>) -> Vec<DeviceAction> {
        for a in out.iter() {
            match a {
                DeviceAction::Frame(f) => self.frames.push(f.clone()),
                DeviceAction::Datagram {
                    to,
                    from_port,
                    payload,
                } => self.frames.push(udp_frame(
                    DEVICE_IP,
                    to.ip().octets(),
                    *from_port,
                    to.port(),
                    payload,
                )),
                // This device runs its own cyclic exchange.
                DeviceAction::StartCyclic(_)
                | DeviceAction::StopCyclic { .. }
                | DeviceAction::Record(_)
                | DeviceAction::ArCheck(_)
                | DeviceAction::DcpSetCheck(_) => {}
            }
        }
        std::mem::take(out)
    }
}

fn datagram(actions: &[DeviceAction]) -> (SocketAddrV4, Vec<u8>) {
    actions
        .iter()
        .find_map(|a| match a {
            DeviceAction::Datagram { to, payload, .. } => Some((*to, payload.clone())),
            _ => None,
        })
        .expect("a datagram")
}

fn frame_of(dst: MacAddress, tci: u16, pdu: &[u8]) -> Vec<u8> {
    let eth = ethernet::Repr {
        dst,
        src: S7_MAC,
        vlan: Some(ethernet::VlanTag::from_tci(tci)),
        ethertype: ethernet::ETHERTYPE_PROFINET,
    };
    let mut f = vec![0u8; eth.buffer_len()];
    eth.emit(&mut f).unwrap();
    f.extend_from_slice(pdu);
    f.resize(f.len().max(60), 0);
    f
}

#[test]
fn everything_the_sim_device_emits_in_a_bring_up_dissects_clean() {
    let mut dev = device(None);
    let mut wire = Wire { frames: Vec::new() };
    let mut out = Vec::new();
    // The first LLDP announcement, at once; the next is 5 s away, after this bring-up.
    assert_eq!(dev.next_deadline_ns(), Some(0));
    dev.poll(0, &mut out);
    assert_eq!(wire.take(&mut out).len(), 1);

    // DCP: Identify by name (at once), Identify All (after its delay), Get, Set IP (the
    // captured request), Signal.
    let ident = dcp::Repr::identify_by_name(0x0300_012c, 1, "rt-labs-dev");
    dev.on_frame(
        &dcp_client::frame(MacAddress::DCP_IDENTIFY, S7_MAC, &ident).unwrap(),
        0,
        &mut out,
    );
    let all = dcp::Repr::identify_all(2, 0x80);
    dev.on_frame(
        &dcp_client::frame(MacAddress::DCP_IDENTIFY, S7_MAC, &all).unwrap(),
        0,
        &mut out,
    );
    let delay = dev.next_deadline_ns().unwrap();
    dev.poll(delay, &mut out);
    let get = dcp::Repr::get(
        3,
        &[
            dcp::code::MAC_ADDRESS,
            dcp::code::FULL_IP_SUITE,
            (0x02, 0x09),
        ],
    );
    dev.on_frame(
        &dcp_client::frame(DEVICE_MAC, S7_MAC, &get).unwrap(),
        0,
        &mut out,
    );
    dev.on_frame(&capture("cm/dcp_set_req"), 0, &mut out);
    let signal = dcp::Repr::signal(4);
    dev.on_frame(
        &dcp_client::frame(DEVICE_MAC, S7_MAC, &signal).unwrap(),
        0,
        &mut out,
    );
    assert_eq!(wire.take(&mut out).len(), 5);
    assert_eq!(dev.station().ip(), DEVICE_IP);
    // The new address is announced by LLDP at once.
    assert_eq!(dev.next_deadline_ns(), Some(0));
    dev.poll(0, &mut out);
    assert_eq!(wire.take(&mut out).len(), 1);

    // A refused Connect (input CR FrameID out of its range), then the real one.
    let mut bad = rpc_capture("cm/connect_req");
    bad[100 + 95 + 18..100 + 95 + 20].copy_from_slice(&[0x00, 0x01]);
    bad[55] ^= 0xff; // another activity: not a duplicate of the real Connect
    dev.on_datagram(S7_CLIENT, rpc::RPC_PORT, &bad, 0, &mut out);
    dev.on_datagram(
        S7_CLIENT,
        rpc::RPC_PORT,
        &rpc_capture("cm/connect_req"),
        0,
        &mut out,
    );
    dev.on_datagram(
        S7_CLIENT,
        rpc::RPC_PORT,
        &rpc_capture("cm/write_req"),
        MS,
        &mut out,
    );
    let ar_uuid = dev.ar().ar_uuid().unwrap();
    let mut im0 = rpc_capture("alarm/im0_read_req");
    im0[108..124].copy_from_slice(&ar_uuid.0);
    let im0_client = SocketAddrV4::new(S7_IP, 56789);
    dev.on_datagram(im0_client, rpc::RPC_PORT, &im0, MS, &mut out);
    // A ping for an unknown call and a request on an unknown interface.
    let connect_header =
        Header::parse(&rpc::Packet::new_checked(&rpc_capture("cm/connect_req")[..]).unwrap())
            .unwrap();
    let ping = Header {
        packet_type: PacketType::Ping,
        sequence_number: 40,
        body_len: 0,
        ..connect_header
    };
    let mut ping_pdu = vec![0u8; 80];
    ping.emit(&mut ping_pdu).unwrap();
    dev.on_datagram(S7_CLIENT, rpc::RPC_PORT, &ping_pdu, MS, &mut out);
    let mut unknown = rpc_capture("cm/prmend_req");
    unknown[24] ^= 0x55;
    unknown[64] = 50;
    let other_client = SocketAddrV4::new(S7_IP, 50000);
    dev.on_datagram(other_client, rpc::RPC_PORT, &unknown, MS, &mut out);
    // A Write in two fragments on another activity: a FACK, then the response.
    let write = {
        let h = IodHeader::write_request(1, ar_uuid, 0, 3, 1, 123, 4);
        let mut b = h.to_bytes().to_vec();
        b.extend_from_slice(&[0, 0, 0, 1]);
        let mut activity = connect_header.activity;
        activity.0[0] ^= 0xff;
        let h = Header {
            activity,
            sequence_number: 0,
            opnum: opnum::WRITE,
            ..connect_header
        };
        rpc::emit_request(&h, 1340, &b).unwrap()
    };
    let header = Header::parse(&rpc::Packet::new_checked(&write[..]).unwrap()).unwrap();
    for (n, part) in write[80..].chunks(48).enumerate() {
        let last = 80 + (n + 1) * 48 >= write.len();
        let h = Header {
            flags1: flags1::IDEMPOTENT
                | flags1::FRAGMENT
                | if last { flags1::LAST_FRAGMENT } else { 0 },
            fragment_number: n as u16,
            body_len: part.len() as u16,
            ..header
        };
        let mut pdu = vec![0u8; 80];
        h.emit(&mut pdu).unwrap();
        pdu.extend_from_slice(part);
        dev.on_datagram(other_client, rpc::RPC_PORT, &pdu, MS, &mut out);
    }
    dev.on_datagram(
        S7_CLIENT,
        rpc::RPC_PORT,
        &rpc_capture("cm/prmend_req"),
        2 * MS,
        &mut out,
    );
    let n = wire.take(&mut out).len();
    assert!(n >= 9, "{n}");
    // The PDInterfaceAdjust of the captured write asks for the NameOfStation in the LLDP
    // port ID: announced at once.
    assert_eq!(dev.next_deadline_ns(), Some(0));
    dev.poll(0, &mut out);
    assert_eq!(wire.take(&mut out).len(), 1);

    // The ApplicationReady; the first input frames (status BAD); the S7's confirmation.
    let t = dev.next_deadline_ns().unwrap();
    dev.poll(t, &mut out);
    let t = dev.next_deadline_ns().unwrap();
    dev.poll(t, &mut out);
    let actions = wire.take(&mut out);
    let (to, app_ready) = datagram(&actions);
    assert_eq!(to, SocketAddrV4::new(S7_IP, rpc::RPC_PORT));
    let app = Pdu::parse(&app_ready).unwrap();
    let res = rpc::emit_response(
        &app.header.reply(0),
        PnioStatus::OK,
        app.ndr.maximum_count(),
        &ControlBlock::application_ready_done(ar_uuid, 2).to_bytes(),
    )
    .unwrap();
    dev.on_datagram(SocketAddrV4::new(S7_IP, 56424), 0xc001, &res, t, &mut out);
    assert_eq!(dev.ar().state(), ArState::Data);

    // Data exchange: the S7's output frames, our input frames; a process alarm, the S7's
    // transport ACK and AlarmAck, our ACK.
    let mut now = t;
    for (i, name) in ["rt/rtc_cpu_8001", "rt/echo_cpu_8001"].iter().enumerate() {
        now += 16 * MS;
        dev.on_frame(&capture(name), now, &mut out);
        now = dev.next_deadline_ns().unwrap();
        dev.poll(now, &mut out);
        assert!(!out.is_empty(), "frame {i}");
    }
    assert!(dev.raise_process_alarm(0, 1, 1, 0x0010, &[1], now, &mut out));
    let actions = wire.take(&mut out);
    let notif = actions
        .iter()
        .find_map(|a| match a {
            DeviceAction::Frame(f) if f[18..20] == [0xfc, 0x01] => Some(f.clone()),
            _ => None,
        })
        .unwrap();
    let notif =
        RtaPdu::parse(&procimg_profinet::wire::rta_pdu::Packet::new_checked(&notif[18..]).unwrap())
            .unwrap();
    let h = notif.header;
    let ack = RtaPdu::first_ack_of(Priority::High, &h);
    dev.on_frame(
        &frame_of(DEVICE_MAC, 0xc000, &ack.to_vec().unwrap()),
        now,
        &mut out,
    );
    let alarm_ack = AlarmAck::for_notification(notif.notification().unwrap(), PnioStatus::OK);
    let data = RtaPdu::first_reply_to(Priority::High, &h, vec![AlarmBlock::Ack(alarm_ack)]);
    dev.on_frame(
        &frame_of(DEVICE_MAC, 0xc000, &data.to_vec().unwrap()),
        now,
        &mut out,
    );
    assert_eq!(dev.alarm_acks().list().len(), 1);

    // Release.
    let release = ControlBlock::release(ar_uuid, 2).to_bytes();
    let h = Header {
        sequence_number: 3,
        opnum: opnum::RELEASE,
        ..connect_header
    };
    dev.on_datagram(
        S7_CLIENT,
        rpc::RPC_PORT,
        &rpc::emit_request(&h, 32, &release).unwrap(),
        now,
        &mut out,
    );
    assert_eq!(dev.ar().state(), ArState::Idle);
    wire.take(&mut out);

    // Another device with slot 3 missing: a Connect response with a ModuleDiffBlock, its
    // ApplicationReady with the ModuleDiffBlock, and the ERR-RTA of its data hold watchdog.
    let mut short = device(Some(3));
    short.on_frame(&capture("cm/dcp_set_req"), 0, &mut out);
    out.clear();
    short.on_datagram(
        S7_CLIENT,
        rpc::RPC_PORT,
        &rpc_capture("cm/connect_req"),
        0,
        &mut out,
    );
    short.on_datagram(
        S7_CLIENT,
        rpc::RPC_PORT,
        &rpc_capture("cm/prmend_req"),
        0,
        &mut out,
    );
    short.on_frame(&capture("rt/rtc_cpu_8001"), 0, &mut out);
    let mut t = 0;
    while short.ar().state() != ArState::Idle {
        t = short.next_deadline_ns().unwrap();
        short.poll(t, &mut out);
    }
    assert!(t < 200 * MS, "the watchdog ended the AR");
    let frames_before = wire.frames.len();
    wire.take(&mut out);
    assert!(wire.frames.len() > frames_before + 3);

    let d = procimg_testkit::tshark::dissect_clean("sim-device", &wire.frames);
    let protocols: std::collections::BTreeSet<&str> =
        d.iter().map(|f| f.protocol.as_str()).collect();
    assert!(
        d.iter().all(|f| f.protocol.starts_with("PN")
            || f.protocol == "DCERPC"
            || f.protocol == "LLDP"),
        "{d:#?}"
    );
    for p in ["PN-DCP", "PNIO-CM", "PNIO", "PNIO-AL", "LLDP"] {
        assert!(protocols.contains(p), "no {p} among {protocols:?}");
    }
    let info: Vec<&str> = d.iter().map(|f| f.info.as_str()).collect();
    for needle in [
        "Connect response",
        "ModuleDiffBlock",
        "Application Ready",
        "Prm End",
        "Release",
    ] {
        assert!(
            info.iter().any(|i| i.contains(needle)),
            "no {needle:?} in {info:#?}"
        );
    }
}

/// A request of `opnum` with `blocks` on a fresh activity (`n` tells the calls apart).
fn call(connect_header: &Header, n: u8, opnum: u16, blocks: &[u8]) -> Vec<u8> {
    let mut activity = connect_header.activity;
    activity.0[15] ^= n;
    activity.0[14] ^= 0xa5;
    let h = Header {
        activity,
        sequence_number: 0,
        opnum,
        ..*connect_header
    };
    rpc::emit_request(&h, 4096, blocks).unwrap()
}

/// The record data of a positive Read response among `actions`.
fn record_of(actions: &[DeviceAction]) -> Vec<u8> {
    let (_, res) = datagram(actions);
    let pdu = Pdu::parse(&res).unwrap();
    assert_eq!(
        pdu.ndr.status(),
        Some(PnioStatus::OK),
        "{:02x?}",
        pdu.blocks
    );
    let (_, data, rest) = IodHeader::split(pdu.blocks).unwrap();
    assert!(rest.is_empty());
    data.to_vec()
}

#[test]
fn the_physical_device_the_ar_records_and_a_device_access_ar_dissect_clean() {
    use procimg_profinet::port::lldp::{Announcer, LldpStation};
    use procimg_profinet::wire::connect::{ArBlockReq, ar_properties};
    use procimg_profinet::wire::record::{
        ArData, LogBookData, MultipleBlockHeader, PdInterfaceDataReal, PdPortDataReal,
    };
    use procimg_profinet::wire::{BlockHeader, Uuid};

    let mut dev = device(None);
    let mut wire = Wire { frames: Vec::new() };
    let mut out = Vec::new();
    dev.on_frame(&capture("cm/dcp_set_req"), 0, &mut out);
    // The S7's port announces itself: the device's neighbour.
    let mut s7 = Announcer::new(LldpStation::new(
        "plc",
        S7_MAC,
        S7_MAC,
        Some(S7_IP.octets()),
        1,
    ));
    let lldp = s7.poll(0).expect("an announcement");
    dev.on_frame(&lldp, 0, &mut out);
    assert_eq!(dev.station().alias_name(), Some("port-001.plc"));
    // The IO AR, parameterized (its PDInterfaceAdjust written).
    for (name, t) in [
        ("cm/connect_req", 0),
        ("cm/write_req", MS),
        ("cm/prmend_req", MS),
    ] {
        dev.on_datagram(S7_CLIENT, rpc::RPC_PORT, &rpc_capture(name), t, &mut out);
    }
    let ar_uuid = dev.ar().ar_uuid().unwrap();
    wire.take(&mut out);
    let connect_header =
        Header::parse(&rpc::Packet::new_checked(&rpc_capture("cm/connect_req")[..]).unwrap())
            .unwrap();
    let client = SocketAddrV4::new(S7_IP, 50001);
    let read = |dev: &mut DemoDevice, wire: &mut Wire, n: u8, ar: Uuid, slot, subslot, index| {
        let implicit = ar == Uuid([0; 16]);
        let h = IodHeader::read_request(n.into(), ar, 0, slot, subslot, index, 4096);
        let op = if implicit {
            opnum::READ_IMPLICIT
        } else {
            opnum::READ
        };
        let mut o = Vec::new();
        dev.on_datagram(
            client,
            rpc::RPC_PORT,
            &call(&connect_header, n, op, &h.to_bytes()),
            2 * MS,
            &mut o,
        );
        let data = record_of(&o);
        wire.take(&mut o);
        data
    };
    let nil = Uuid([0; 16]);

    let real = read(&mut dev, &mut wire, 1, nil, 0, 0, 0xf841);
    let interface = MultipleBlockHeader::parse(&real).unwrap();
    assert_eq!((interface.slot, interface.subslot), (0, 0x8000));
    let i = PdInterfaceDataReal::parse(&interface.blocks).unwrap();
    assert_eq!(
        (i.chassis_id.as_str(), i.mac, i.ip),
        ("rt-labs-dev", DEVICE_MAC, DEVICE_IP)
    );
    let port = MultipleBlockHeader::parse(&real[interface.buffer_len()..]).unwrap();
    assert_eq!(port.subslot, 0x8001);
    let p = PdPortDataReal::parse(&port.blocks).unwrap();
    assert_eq!(p.peers.len(), 1);
    assert_eq!(
        (
            p.peers[0].chassis_id.as_str(),
            p.peers[0].port_id.as_str(),
            p.peers[0].mac
        ),
        ("plc", "port-001", S7_MAC)
    );
    assert_eq!(
        PdInterfaceDataReal::parse(&read(&mut dev, &mut wire, 2, nil, 0, 0x8000, 0x8080)).unwrap(),
        i
    );
    assert_eq!(
        PdPortDataReal::parse(&read(&mut dev, &mut wire, 3, nil, 0, 0x8001, 0x802a)).unwrap(),
        p
    );
    let statistic = read(&mut dev, &mut wire, 4, nil, 0, 0x8001, 0x8072);
    assert_eq!(
        BlockHeader::parse(&statistic).unwrap().block_type.raw(),
        0x0251
    );
    let ars = ArData::parse(&read(&mut dev, &mut wire, 5, nil, 0, 0, 0xf820)).unwrap();
    assert_eq!(ars.ars.len(), 1);
    assert_eq!(ars.ars[0].ar_uuid, ar_uuid);
    assert_eq!(ars.ars[0].iocrs.len(), 2);
    read(&mut dev, &mut wire, 6, nil, 0, 0, 0xf821);
    let log = LogBookData::parse(&read(&mut dev, &mut wire, 7, nil, 0, 0, 0xf830)).unwrap();
    assert!(log.entries.iter().any(|e| e.ar_uuid == ar_uuid), "{log:?}");
    // PDExpectedData in the AR: the PDInterfaceAdjust it wrote.
    let expected = read(&mut dev, &mut wire, 8, ar_uuid, 0, 0, 0xf842);
    let m = MultipleBlockHeader::parse(&expected).unwrap();
    assert_eq!((m.subslot, &m.blocks[..2]), (0x8000, &[0x02, 0x50][..]));

    // An engineering tool's device access AR beside the IO AR: Connect, a read of I&M0, a
    // write of I&M1, ARData with both ARs, Release.
    let tool = Uuid([0x7a; 16]);
    let ar = ArBlockReq {
        ar_type: 0x0006,
        ar_properties: ar_properties::STATE_ACTIVE
            | ar_properties::PARAMETERIZATION_SERVER_CM_INITIATOR
            | ar_properties::DEVICE_ACCESS,
        ..ArBlockReq::io_controller(
            tool,
            1,
            MacAddress([0x02, 0, 0, 0, 0, 0x7a]),
            rpc::object_uuid(1, 0x0001, 0x002a),
            "engineering-tool".into(),
        )
    };
    let mut o = Vec::new();
    dev.on_datagram(
        client,
        rpc::RPC_PORT,
        &call(&connect_header, 20, opnum::CONNECT, &ar.to_vec().unwrap()),
        2 * MS,
        &mut o,
    );
    let (_, res) = datagram(&o);
    assert_eq!(Pdu::parse(&res).unwrap().ndr.status(), Some(PnioStatus::OK));
    wire.take(&mut o);
    assert_eq!(dev.ar().access().map(|a| a.ar_uuid()), Some(tool));
    assert_eq!(dev.ar().ar_uuid(), Some(ar_uuid), "the IO AR is untouched");
    read(&mut dev, &mut wire, 21, tool, 0, 1, 0xaff0);
    let im1 = {
        let mut d = vec![0x00, 0x21, 0x00, 0x38, 0x01, 0x00];
        d.extend_from_slice(&[b' '; 32]);
        d.extend_from_slice(b"hall-3                ");
        d
    };
    let h = IodHeader::write_request(22, tool, 0, 1, 1, 0xaff1, im1.len() as u32);
    let mut w = h.to_bytes().to_vec();
    w.extend_from_slice(&im1);
    dev.on_datagram(
        client,
        rpc::RPC_PORT,
        &call(&connect_header, 22, opnum::WRITE, &w),
        2 * MS,
        &mut o,
    );
    let (_, res) = datagram(&o);
    assert_eq!(Pdu::parse(&res).unwrap().ndr.status(), Some(PnioStatus::OK));
    wire.take(&mut o);
    let ars = ArData::parse(&read(&mut dev, &mut wire, 23, tool, 0, 0, 0xf820)).unwrap();
    assert_eq!(
        ars.ars
            .iter()
            .map(|a| (a.ar_type, a.initiator_station_name.as_str()))
            .collect::<Vec<_>>(),
        [
            (1, ars.ars[0].initiator_station_name.as_str()),
            (6, "engineering-tool")
        ]
    );
    let release = ControlBlock::release(tool, 1).to_bytes();
    dev.on_datagram(
        client,
        rpc::RPC_PORT,
        &call(&connect_header, 24, opnum::RELEASE, &release),
        2 * MS,
        &mut o,
    );
    assert!(dev.ar().access().is_none());
    assert_eq!(dev.ar().ar_uuid(), Some(ar_uuid));
    wire.take(&mut o);

    let d = procimg_testkit::tshark::dissect_clean("sim-device-pdev", &wire.frames);
    let info: Vec<&str> = d.iter().map(|f| f.info.as_str()).collect();
    assert!(
        info.iter().any(|i| i.contains("Read response")),
        "{info:#?}"
    );
}
