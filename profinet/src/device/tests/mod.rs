// SPDX-License-Identifier: MIT OR Apache-2.0
//! The simulated device driven by what an S7-1515 sent to the p-net sample device (the
//! captures in profinet/tests/fixtures/captures, test data of the `pnio` crate 0.1.0, MIT OR
//! Apache-2.0), compared with what p-net answered, and by requests built with our codecs.

use super::cm::pnio;
use super::connect::refuse;
use super::*;
use crate::cyclic::CrTiming;
use crate::cyclic::trial::TrialSetup;
use crate::dcp_client;
use crate::iocr_layout::{IocrLayout, SubmoduleIo};
use crate::test_fixtures::capture;
use crate::wire::PnioStatus;
use crate::wire::alarm::{AlarmAck, AlarmBlock, Priority};
use crate::wire::connect::{
    AlarmCrBlockReq, ArBlockReq, ConnectRequest, ConnectResponse, ExpectedModule,
    ExpectedSubmodule, ExpectedSubmoduleBlockReq, IdentInfo, IocrBlockReq, ModuleState,
};
use crate::wire::dcp::{self as wire_dcp, BlockRepr};
use crate::wire::record::{IodHeader, IodKind, split_write_multiple_response};
use crate::wire::rpc::{
    CONTROLLER_INTERFACE, DEVICE_INTERFACE, NdrRequest, Pdu, RPC_PORT, flags1, object_uuid,
};
use crate::wire::rpc::{Ndr, opnum};
use crate::wire::rt::{self, data_status};
use crate::wire::rta_pdu::{ErrRta, RtaBody};
use crate::wire::test_captures::rpc_pdu;
use std::net::Ipv4Addr;

mod abort;
mod delegated_records;
mod diagnosis;
mod kept_identity;
mod topology;

/// The applications these tests need: inputs left alone, the echo of the submodule's own
/// outputs, or a big-endian u32 count of the frames produced.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum TestApp {
    None,
    Echo,
    Counter,
}

impl Application for TestApp {
    fn fill_inputs(&mut self, k: u64, inputs: &mut [u8], own: &[u8], _: &[u8], _: bool) {
        match self {
            TestApp::None => {}
            TestApp::Echo => {
                let n = inputs.len().min(own.len());
                inputs[..n].copy_from_slice(&own[..n]);
            }
            TestApp::Counter => {
                let word = (k as u32).to_be_bytes();
                for (i, b) in inputs.iter_mut().enumerate() {
                    *b = word[i % 4];
                }
            }
        }
    }
}

/// The S7-1515 of the captures.
pub(super) const S7_MAC: MacAddress = MacAddress([0xec, 0x1c, 0x5d, 0x61, 0xe7, 0x3f]);
/// The p-net sample device of the captures.
pub(super) const PNET_MAC: MacAddress = MacAddress([0x8c, 0xf3, 0x19, 0xcd, 0x19, 0xf8]);
const S7_IP: Ipv4Addr = Ipv4Addr::new(172, 16, 2, 100);
pub(super) const DEVICE_IP: [u8; 4] = [172, 16, 2, 10];
/// The S7's RPC client socket in the captures.
const S7_CLIENT: SocketAddrV4 = SocketAddrV4::new(S7_IP, 54766);
pub(super) const MS: u64 = 1_000_000;

/// The PNIO blocks of a captured RPC frame.
fn captured_blocks(name: &str) -> Vec<u8> {
    let payload = rpc_pdu(name);
    Pdu::parse(&payload).unwrap().blocks.to_vec()
}

/// The I&M0 p-net answered (alarm/im0_read_res).
fn pnet_im0() -> Im0 {
    let blocks = captured_blocks("alarm/im0_read_res");
    let (_, data, _) = IodHeader::split(&blocks).unwrap();
    Im0::parse(data).unwrap()
}

/// What the S7 expects in the connect capture, as what is plugged.
fn pnet_submodules() -> Vec<PluggedSubmodule> {
    let req = ConnectRequest::parse(&captured_blocks("cm/connect_req")).unwrap();
    req.expected
        .iter()
        .flat_map(|b| b.modules.iter())
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
        .collect()
}

pub(super) fn pnet_spec(behaviour: TestApp) -> DeviceSetup<TestApp> {
    DeviceSetup {
        name: "rt-labs-dev".into(),
        mac: PNET_MAC,
        ip: None,
        vendor_id: 0x0493,
        device_id: 0x0002,
        instance: 1,
        submodules: pnet_submodules(),
        application: behaviour,
        im0: pnet_im0(),
    }
}

/// A device without LLDP: these tests look at what it sends for DCP, RPC, alarms and the
/// cyclic exchange, frame by frame; its LLDP announcements have tests of their own.
fn quiet_device(spec: DeviceSetup<TestApp>) -> Device<TestApp> {
    let mut d = Device::new(spec);
    d.station_mut().set_lldp(false);
    d
}

/// The p-net sample device, with the IP the S7 gives it.
fn pnet_device(behaviour: TestApp) -> Device<TestApp> {
    let mut d = quiet_device(DeviceSetup {
        ip: Some(DEVICE_IP),
        ..pnet_spec(behaviour)
    });
    d.station_mut()
        .set_type_of_station("P-Net Sample Application");
    d
}

/// The datagrams among `out`: (to, from port, payload).
pub(super) fn datagrams(out: &[DeviceAction]) -> Vec<(SocketAddrV4, u16, Vec<u8>)> {
    out.iter()
        .filter_map(|a| match a {
            DeviceAction::Datagram {
                to,
                from_port,
                payload,
            } => Some((*to, *from_port, payload.clone())),
            _ => None,
        })
        .collect()
}

/// The frames among `out`.
pub(super) fn frames(out: &[DeviceAction]) -> Vec<Vec<u8>> {
    out.iter()
        .filter_map(|a| match a {
            DeviceAction::Frame(f) => Some(f.clone()),
            _ => None,
        })
        .collect()
}

/// The alarm notifications among `out`.
pub(super) fn alarms(out: &[DeviceAction]) -> Vec<crate::wire::alarm::AlarmNotification> {
    frames(out)
        .iter()
        .filter_map(|f| {
            let pdu = RtaPdu::parse(&rta_pdu::Packet::new_checked(f.get(18..)?).ok()?).ok()?;
            pdu.notification().cloned()
        })
        .collect()
}

/// An RPC PDU parsed into owned parts.
pub(super) struct Reply {
    pub(super) header: Header,
    pub(super) ndr: Ndr,
    pub(super) blocks: Vec<u8>,
}

pub(super) fn parse_reply(payload: &[u8]) -> Reply {
    let p = Pdu::parse(payload).unwrap_or_else(|e| panic!("{e}: {payload:02x?}"));
    Reply {
        header: p.header,
        ndr: p.ndr,
        blocks: p.blocks.to_vec(),
    }
}

/// Sends `payload` from `from` to the RPC port; the one response.
fn call_from(dev: &mut Device<TestApp>, from: SocketAddrV4, payload: &[u8], now: u64) -> Reply {
    let mut out = Vec::new();
    dev.on_datagram(from, RPC_PORT, payload, now, &mut out);
    let d = datagrams(&out);
    assert_eq!(d.len(), 1, "one response expected: {out:?}");
    assert_eq!((d[0].0, d[0].1), (from, RPC_PORT));
    parse_reply(&d[0].2)
}

pub(super) fn call(dev: &mut Device<TestApp>, payload: &[u8], now: u64) -> Reply {
    call_from(dev, S7_CLIENT, payload, now)
}

pub(super) fn status(r: &Reply) -> PnioStatus {
    r.ndr.status().expect("a response")
}

/// Polls at every deadline up to `until`; everything sent.
pub(super) fn run_until(dev: &mut Device<TestApp>, until: u64) -> Vec<(u64, DeviceAction)> {
    let mut all = Vec::new();
    while let Some(t) = dev.next_deadline_ns().filter(|t| *t <= until) {
        let mut out = Vec::new();
        dev.poll(t, &mut out);
        all.extend(out.into_iter().map(|a| (t, a)));
    }
    all
}

/// The captured S7 requests up to PrmEnd, answered; the ApplicationReady the device sends.
fn bring_up_to_app_ready(dev: &mut Device<TestApp>) -> (Reply, u64) {
    assert_eq!(
        status(&call(dev, &rpc_pdu("cm/connect_req"), 0)),
        PnioStatus::OK
    );
    assert_eq!(
        status(&call(dev, &rpc_pdu("cm/write_req"), MS)),
        PnioStatus::OK
    );
    assert_eq!(
        status(&call(dev, &rpc_pdu("cm/prmend_req"), 2 * MS)),
        PnioStatus::OK
    );
    let mut out = Vec::new();
    let t = 2 * MS + APP_READY_DELAY_NS;
    dev.poll(t, &mut out);
    let d = datagrams(&out);
    assert_eq!(d.len(), 1, "the ApplicationReady: {out:?}");
    assert_eq!(d[0].0, SocketAddrV4::new(S7_IP, RPC_PORT));
    assert_eq!(d[0].1, rpc::CLIENT_PORT);
    (parse_reply(&d[0].2), t)
}

/// The captured ApplicationReady response of the S7, re-addressed to our activity.
fn s7_app_ready_response(activity: Uuid) -> Vec<u8> {
    let mut res = rpc_pdu("cm/appready_res");
    // The S7 answers little-endian: the activity UUID's first fields are swapped.
    res[40..56].copy_from_slice(&activity.to_drep(true));
    res
}

/// The device in data exchange after the captured bring-up.
pub(super) fn pnet_in_data(behaviour: TestApp) -> (Device<TestApp>, u64) {
    let mut dev = pnet_device(behaviour);
    let (app_ready, t) = bring_up_to_app_ready(&mut dev);
    let mut out = Vec::new();
    let s7_server = SocketAddrV4::new(S7_IP, 56424);
    dev.on_datagram(
        s7_server,
        rpc::CLIENT_PORT,
        &s7_app_ready_response(app_ready.header.activity),
        t + MS,
        &mut out,
    );
    assert!(out.is_empty(), "{out:?}");
    assert_eq!(dev.ar().state(), ArState::Data);
    (dev, t + MS)
}

/// Replaces the byte at `at` of an RPC payload's blocks (offset 100 = 80 + 20).
fn patch_block(payload: &mut [u8], at: usize, bytes: &[u8]) {
    payload[100 + at..100 + at + bytes.len()].copy_from_slice(bytes);
}

#[test]
fn dcp_identify_and_set_ip_answer_like_pnet() {
    let mut dev = quiet_device(pnet_spec(TestApp::None));
    dev.station_mut()
        .set_type_of_station("P-Net Sample Application");
    let req = wire_dcp::Repr::identify_by_name(0x0300_012c, 1, "rt-labs-dev");
    let frame = dcp_client::frame(MacAddress::DCP_IDENTIFY, S7_MAC, &req).unwrap();
    let mut out = Vec::new();
    dev.on_frame(&frame, 0, &mut out);
    let f = frames(&out);
    assert_eq!(f.len(), 1, "ResponseDelayFactor 1 answers at once");
    let ours = parse_dcp(&f[0]);
    let pnet = parse_dcp(&capture("cm/ident_ok_pnet"));
    assert_eq!(&f[0][..12], &capture("cm/ident_ok_pnet")[..12], "addresses");
    for r in [&ours, &pnet] {
        assert_eq!(r.frame_id, wire_dcp::FRAME_ID_IDENTIFY_RESPONSE);
        assert_eq!(r.xid, 0x0300_012c);
        assert_eq!(r.name_of_station(), Some("rt-labs-dev"));
        assert_eq!(r.device_vendor(), Some("P-Net Sample Application"));
        assert_eq!(r.device_id(), Some((0x0493, 0x0002)));
        assert_eq!(r.ip(), Some(([0; 4], [0; 4], [0; 4])));
    }
    // Same blocks in the same order, except: DeviceRole's reserved byte (we send 0 as the
    // standard says, p-net 1), the DeviceOptions (what each of us supports) and our extra
    // DeviceInstance block.
    let codes = |r: &wire_dcp::Repr| r.blocks.iter().map(|b| b.value.code()).collect::<Vec<_>>();
    let mut expected = codes(&pnet);
    expected.push(wire_dcp::code::DEVICE_INSTANCE);
    assert_eq!(codes(&ours), expected);
    assert!(ours.blocks.contains(&wire_dcp::Block::new(
        0,
        BlockRepr::DeviceRole {
            role: 1,
            reserved: 0
        }
    )));
    assert!(ours.blocks.contains(&wire_dcp::Block::new(
        0,
        BlockRepr::DeviceInstance { high: 0, low: 1 }
    )));

    // The captured Set IP (VLAN tagged, qualifier temporary): p-net's answer byte for byte,
    // padded to the Ethernet minimum (the capture was taken before padding).
    out.clear();
    dev.on_frame(&capture("cm/dcp_set_req"), MS, &mut out);
    let f = frames(&out);
    let pnet = capture("cm/dcp_set_res");
    assert_eq!(&f[0][..pnet.len()], &pnet[..]);
    assert!(f[0][pnet.len()..].iter().all(|&b| b == 0) && f[0].len() == 60);
    assert_eq!(dev.station().ip(), DEVICE_IP);
}

fn parse_dcp(frame: &[u8]) -> wire_dcp::Repr {
    let eth = ethernet::Frame::new_checked(frame).unwrap();
    wire_dcp::Repr::parse(&wire_dcp::Packet::new_checked(eth.payload()).unwrap()).unwrap()
}

#[test]
fn dcp_filters_delay_get_set_name_and_signal() {
    let mut dev = pnet_device(TestApp::None);
    let mut out = Vec::new();
    // Another name: no answer.
    let other = wire_dcp::Repr::identify_by_name(1, 1, "someone-else");
    dev.on_frame(
        &dcp_client::frame(MacAddress::DCP_IDENTIFY, S7_MAC, &other).unwrap(),
        0,
        &mut out,
    );
    assert!(out.is_empty());
    // Identify All with factor 100: ((0x19 << 8 | 0xf8) mod 100) × 10 ms = 480 ms.
    let all = wire_dcp::Repr::identify_all(2, 100);
    dev.on_frame(
        &dcp_client::frame(MacAddress::DCP_IDENTIFY, S7_MAC, &all).unwrap(),
        0,
        &mut out,
    );
    assert!(out.is_empty());
    assert_eq!(dev.next_deadline_ns(), Some(480 * MS));
    dev.poll(479 * MS, &mut out);
    assert!(out.is_empty());
    dev.poll(480 * MS, &mut out);
    assert_eq!(parse_dcp(&frames(&out)[0]).xid, 2);
    // Not for our MAC: ignored.
    out.clear();
    let get = wire_dcp::Repr::get(3, &[wire_dcp::code::NAME_OF_STATION]);
    let stranger = MacAddress([2, 0, 0, 0, 0, 9]);
    dev.on_frame(
        &dcp_client::frame(stranger, S7_MAC, &get).unwrap(),
        0,
        &mut out,
    );
    assert!(out.is_empty());
    // Get: a value and an unsupported suboption.
    let get = wire_dcp::Repr::get(4, &[wire_dcp::code::NAME_OF_STATION, (0x02, 0x09)]);
    dev.on_frame(
        &dcp_client::frame(PNET_MAC, S7_MAC, &get).unwrap(),
        0,
        &mut out,
    );
    let r = parse_dcp(&frames(&out)[0]);
    assert_eq!(r.name_of_station(), Some("rt-labs-dev"));
    assert_eq!(
        r.set_result().collect::<Vec<_>>(),
        vec![(2, 9, wire_dcp::block_error::SUBOPTION_UNSUPPORTED)]
    );
    // Set NameOfStation, an invalid one, Signal.
    for (xid, repr, error) in [
        (5, wire_dcp::Repr::set_name(5, "new-name", true), 0),
        (
            6,
            wire_dcp::Repr::set_name(6, "Bad_Name", false),
            wire_dcp::block_error::SET_NOT_POSSIBLE,
        ),
        (7, wire_dcp::Repr::signal(7), 0),
    ] {
        out.clear();
        dev.on_frame(
            &dcp_client::frame(PNET_MAC, S7_MAC, &repr).unwrap(),
            0,
            &mut out,
        );
        let r = parse_dcp(&frames(&out)[0]);
        assert_eq!(r.xid, xid);
        assert_eq!(r.service_type, wire_dcp::ServiceType::Success);
        assert_eq!(r.set_result().next().map(|(_, _, e)| e), Some(error));
    }
    assert_eq!(dev.station().name(), "new-name");
    assert_eq!(dev.station().signal_count(), 1);
}

#[test]
fn captured_s7_bring_up_gets_pnets_answers() {
    let mut dev = quiet_device(pnet_spec(TestApp::Echo));
    dev.station_mut()
        .set_type_of_station("P-Net Sample Application");
    let mut out = Vec::new();
    // No IP yet: no RPC endpoint.
    dev.on_datagram(S7_CLIENT, RPC_PORT, &rpc_pdu("cm/connect_req"), 0, &mut out);
    assert!(out.is_empty());
    dev.on_frame(&capture("cm/dcp_set_req"), 0, &mut out);

    // Connect: p-net's blocks byte for byte. The RPC header echoes the request's UUIDs,
    // sequence and opnum like p-net's; it differs in DREP (we answer in the request's byte
    // order, LE here; p-net answers BE) and Flags1 (0x0A LastFragment|NoFack, as the S7
    // answers, p-net 0x28 Idempotent|NoFack).
    let req = rpc_pdu("cm/connect_req");
    let ours = call(&mut dev, &req, 0);
    let pnet = parse_reply(&rpc_pdu("cm/connect_res"));
    assert_eq!(status(&ours), PnioStatus::OK);
    assert_eq!(ours.blocks, pnet.blocks, "Connect response blocks");
    assert_eq!(
        ConnectResponse::parse(&ours.blocks).unwrap(),
        ConnectResponse::parse(&pnet.blocks).unwrap()
    );
    same_rpc_reply(&ours, &pnet);
    assert!(ours.header.little_endian && !pnet.header.little_endian);
    assert_eq!(
        (ours.header.flags1, pnet.header.flags1),
        (flags1::LAST_FRAGMENT | flags1::NO_FACK, 0x28)
    );
    assert_eq!(dev.ar().state(), ArState::Connected);

    // WriteMultiple: PDInterfaceAdjust and the three user records, each answered OK.
    let ours = call(&mut dev, &rpc_pdu("cm/write_req"), MS);
    let pnet = parse_reply(&rpc_pdu("cm/write_res"));
    assert_eq!(ours.blocks, pnet.blocks, "Write response blocks");
    same_rpc_reply(&ours, &pnet);
    let (outer, each) = split_write_multiple_response(&ours.blocks).unwrap();
    assert!(outer.is_write_multiple() && each.len() == 4);
    assert!(each.iter().all(|h| h.status.is_ok()));

    // PrmEnd.
    let ours = call(&mut dev, &rpc_pdu("cm/prmend_req"), 2 * MS);
    let pnet = parse_reply(&rpc_pdu("cm/prmend_res"));
    assert_eq!(ours.blocks, pnet.blocks, "PrmEnd response blocks");
    same_rpc_reply(&ours, &pnet);
    assert_eq!(dev.ar().state(), ArState::Parameterized);

    // ApplicationReady to the S7's RPC server port 34964 from 0xC001, like p-net's: the
    // same blocks and header except the activity UUID (each device makes its own).
    out.clear();
    let t = 2 * MS + APP_READY_DELAY_NS;
    dev.poll(t, &mut out);
    let d = datagrams(&out);
    assert_eq!(d.len(), 1);
    assert_eq!(
        (d[0].0, d[0].1),
        (SocketAddrV4::new(S7_IP, RPC_PORT), rpc::CLIENT_PORT)
    );
    let pnet_frame = capture("cm/appready_req");
    assert_eq!(
        u16::from_be_bytes([pnet_frame[34], pnet_frame[35]]),
        rpc::CLIENT_PORT
    );
    let ours = parse_reply(&d[0].2);
    let pnet = parse_reply(&pnet_frame[42..]);
    assert_eq!(ours.blocks, pnet.blocks, "ApplicationReady blocks");
    assert_eq!(ours.ndr, pnet.ndr);
    assert_ne!(ours.header.activity, pnet.header.activity);
    assert_eq!(
        Header {
            activity: pnet.header.activity,
            ..ours.header
        },
        pnet.header
    );
    assert_eq!(ours.header.interface, CONTROLLER_INTERFACE);
    assert_eq!(dev.ar().state(), ArState::WaitAppReadyConfirm);
    // The input CR started at PrmEnd: one frame so far, status BAD until the confirmation.
    let first = frames(&out);
    assert_eq!(first.len(), 1);
    assert!(
        input_statuses(&first[0]).iter().all(|&s| s == ar::IOXS_BAD),
        "{:02x?}",
        first[0]
    );

    // The S7's response (re-addressed to our activity) confirms it.
    out.clear();
    dev.on_datagram(
        SocketAddrV4::new(S7_IP, 56424),
        rpc::CLIENT_PORT,
        &s7_app_ready_response(ours.header.activity),
        t + MS,
        &mut out,
    );
    assert_eq!(dev.ar().state(), ArState::Data);

    // The S7's output frame with the echo values; the next input frame has p-net's layout:
    // the same addresses, tag, FrameID, DataStatus and status bytes, the echoed data at the
    // Echo submodule's offset.
    dev.on_frame(&capture("rt/echo_cpu_8001"), t + 2 * MS, &mut out);
    assert_eq!(
        dev.ar().outputs(0, 4, 1),
        Some((&[0x12, 0x34, 0x56, 0x78, 0x3f, 0xc0, 0, 0][..], true))
    );
    assert_eq!(dev.ar().outputs(0, 2, 1), Some((&[0x01][..], true)));
    out.clear();
    let next = dev.next_deadline_ns().unwrap();
    assert_eq!(next, 2 * MS + 32 * MS, "32 ms after the first frame");
    dev.poll(next, &mut out);
    let ours = frames(&out).remove(0);
    let pnet = capture("rt/rtc_dev_8000");
    assert_eq!(
        &ours[..20],
        &pnet[..20],
        "addresses, tag, EtherType, FrameID"
    );
    assert_eq!(ours.len(), pnet.len());
    assert_eq!(input_statuses(&ours), input_statuses(&pnet));
    assert!(input_statuses(&ours).iter().all(|&s| s == ar::IOXS_GOOD));
    assert_eq!(
        &ours[20 + 9..20 + 17],
        &[0x12, 0x34, 0x56, 0x78, 0x3f, 0xc0, 0, 0]
    );
    assert_eq!(ours[62], data_status::OPERATE);
    assert_eq!(ours[62], pnet[62]);

    // Release (built with our codecs, as the S7 sends it: LE, next sequence number).
    let release = ControlBlock::release(dev.ar().ar_uuid().unwrap(), 2).to_bytes();
    let req = parse_reply(&rpc_pdu("cm/prmend_req")).header;
    let h = Header {
        sequence_number: 3,
        opnum: opnum::RELEASE,
        ..req
    };
    let pdu = wire_rpc::emit_request(&h, 32, &release).unwrap();
    let r = call(&mut dev, &pdu, t + 3 * MS);
    assert_eq!(status(&r), PnioStatus::OK);
    let done = ControlBlock::parse(&r.blocks).unwrap();
    assert!(done.answers(&ControlBlock::parse(&release).unwrap()));
    assert_eq!(dev.ar().state(), ArState::Idle);
    assert_eq!(dev.ar().last_abort(), None);
    assert_eq!(dev.next_deadline_ns(), None);
}

/// The header fields a response must echo, equal in ours and p-net's; and the NDR header.
fn same_rpc_reply(ours: &Reply, pnet: &Reply) {
    let (a, b) = (&ours.header, &pnet.header);
    assert_eq!(a.packet_type, PacketType::Response);
    assert_eq!(
        (
            a.object,
            a.interface,
            a.activity,
            a.sequence_number,
            a.opnum
        ),
        (
            b.object,
            b.interface,
            b.activity,
            b.sequence_number,
            b.opnum
        )
    );
    assert_eq!(
        (a.server_boot_time, a.interface_version, a.fragment_number),
        (b.server_boot_time, b.interface_version, b.fragment_number)
    );
    assert_eq!(ours.ndr, pnet.ndr, "NDR header");
}

/// The IOPS/IOCS bytes of an input CR frame of the captured layout (offsets from the
/// Connect: IOPS 0, 1, 2, 4, 7, 17; IOCS 5, 8, 18).
fn input_statuses(frame: &[u8]) -> Vec<u8> {
    [0, 1, 2, 4, 7, 17, 5, 8, 18]
        .iter()
        .map(|&o| frame[20 + o])
        .collect()
}

#[test]
fn big_endian_connect_gets_the_same_blocks_in_big_endian() {
    let le = rpc_pdu("cm/connect_req");
    let p = Pdu::parse(&le).unwrap();
    let be = Pdu {
        header: Header {
            little_endian: false,
            ..p.header
        },
        ..p
    }
    .to_vec()
    .unwrap();
    assert_ne!(be, le);
    let mut a = pnet_device(TestApp::None);
    let mut b = pnet_device(TestApp::None);
    let ra = call(&mut a, &le, 0);
    let rb = call(&mut b, &be, 0);
    assert!(ra.header.little_endian);
    assert!(!rb.header.little_endian);
    assert_eq!(ra.blocks, rb.blocks);
    assert_eq!(ra.ndr, rb.ndr);
    assert_eq!(
        Header {
            little_endian: true,
            ..rb.header
        },
        ra.header
    );
    // And byte for byte, the BE answer is p-net's apart from Flags1.
    let mut pnet = rpc_pdu("cm/connect_res");
    let d = {
        let mut out = Vec::new();
        let mut c = pnet_device(TestApp::None);
        c.on_datagram(S7_CLIENT, RPC_PORT, &be, 0, &mut out);
        datagrams(&out).remove(0).2
    };
    pnet[2] = flags1::LAST_FRAGMENT | flags1::NO_FACK;
    assert_eq!(d, pnet[..d.len()]);
}

#[test]
fn wrong_and_missing_submodules_give_a_module_diff_block() {
    let mut spec = pnet_spec(TestApp::Echo);
    spec.ip = Some(DEVICE_IP);
    // Slot 3 empty, slot 4 with another submodule.
    spec.submodules.retain(|s| s.slot != 3);
    for s in spec.submodules.iter_mut().filter(|s| s.slot == 4) {
        s.submodule_ident = 0x141;
    }
    let mut dev = quiet_device(spec);
    let r = call(&mut dev, &rpc_pdu("cm/connect_req"), 0);
    assert_eq!(status(&r), PnioStatus::OK, "a difference is not an error");
    let res = ConnectResponse::parse(&r.blocks).unwrap();
    let diff = res.module_diff.expect("a ModuleDiffBlock");
    assert_eq!(diff.apis.len(), 1);
    let m = &diff.apis[0].modules;
    assert_eq!(m.len(), 2);
    assert_eq!(
        (m[0].slot, m[0].state, m[0].module_ident),
        (3, ModuleState::NoModule, 0)
    );
    assert!(m[0].submodules.is_empty());
    assert_eq!(
        (m[1].slot, m[1].state, m[1].module_ident),
        (4, ModuleState::ProperModule, 0x40)
    );
    assert_eq!(m[1].submodules.len(), 1);
    let s = m[1].submodules[0];
    assert_eq!((s.subslot, s.submodule_ident), (1, 0x141));
    assert_eq!(s.state.ident_info(), IdentInfo::Wrong);
    assert!(!s.state.is_usable());
    assert!(res.ar_server.is_some(), "ARServerBlock after the diff");

    // The ApplicationReady carries the same ModuleDiffBlock after the control block.
    call(&mut dev, &rpc_pdu("cm/prmend_req"), MS);
    let mut out = Vec::new();
    dev.poll(MS + APP_READY_DELAY_NS, &mut out);
    let app = parse_reply(&datagrams(&out)[0].2);
    let control_len = crate::wire::control::BLOCK_LEN;
    assert_eq!(
        crate::wire::connect::ModuleDiffBlock::parse(&app.blocks[control_len..]).unwrap(),
        diff
    );
    // In data exchange the wrong submodule's status stays BAD.
    let act = app.header.activity;
    dev.on_datagram(
        SocketAddrV4::new(S7_IP, 56424),
        rpc::CLIENT_PORT,
        &s7_app_ready_response(act),
        2 * MS,
        &mut out,
    );
    assert_eq!(dev.ar().state(), ArState::Data);
    out.clear();
    let t = dev.next_deadline_ns().unwrap();
    dev.poll(t, &mut out);
    let f = frames(&out).remove(0);
    // IOPS: DAP 0,1,2 and slot 1 (4) GOOD; slot 3 (7) and slot 4 (17) BAD; IOCS of slot 2
    // (5) GOOD, slots 3 (8) and 4 (18) BAD.
    assert_eq!(
        input_statuses(&f),
        vec![0x80, 0x80, 0x80, 0x80, 0x00, 0x00, 0x80, 0x00, 0x00]
    );
}

/// A Connect like the S7's, built from a list of submodules (slot, subslot, module ident,
/// submodule ident, in, out), with the CRs' timing given.
pub(super) fn built_connect(
    subs: &[(u16, u16, u32, u32, u16, u16)],
    ar_uuid: Uuid,
    (scf, rr, dhf): (u16, u16, u16),
) -> ConnectRequest {
    let io: Vec<SubmoduleIo> = subs
        .iter()
        .map(|&(slot, subslot, _, _, i, o)| SubmoduleIo {
            api: 0,
            slot,
            subslot,
            input_length: i,
            output_length: o,
        })
        .collect();
    let layout = IocrLayout::new(&io).unwrap();
    let timing = |mut c: IocrBlockReq| {
        c.send_clock_factor = scf;
        c.reduction_ratio = rr;
        c.data_hold_factor = dhf;
        c.watchdog_factor = dhf;
        c
    };
    let input = timing(IocrBlockReq::from_layout(1, 1, 0x8000, &layout.input, &io).unwrap());
    let output = timing(IocrBlockReq::from_layout(2, 2, 0x8001, &layout.output, &io).unwrap());
    let expected = subs
        .iter()
        .map(
            |&(slot, subslot, module, sub, i, o)| ExpectedSubmoduleBlockReq {
                modules: vec![ExpectedModule {
                    api: 0,
                    slot,
                    module_ident: module,
                    properties: 0,
                    submodules: vec![ExpectedSubmodule::with_io(subslot, sub, i, o)],
                }],
            },
        )
        .collect();
    ConnectRequest {
        ar: ArBlockReq::io_controller(
            ar_uuid,
            1,
            S7_MAC,
            object_uuid(1, 0x010e, 0x002a),
            "procimgd".into(),
        ),
        iocrs: vec![input, output],
        alarm_cr: AlarmCrBlockReq::io_controller(1),
        expected,
    }
}

/// A request PDU on the device interface.
pub(super) fn request(
    op: u16,
    activity: Uuid,
    seq: u32,
    blocks: &[u8],
    little_endian: bool,
) -> Vec<u8> {
    let h = Header {
        little_endian,
        ..Header::request(
            object_uuid(1, 0x0001, 0x0493),
            DEVICE_INTERFACE,
            activity,
            seq,
            op,
        )
    };
    wire_rpc::emit_request(&h, 1340, blocks).unwrap()
}

pub(super) const ACTIVITY: Uuid =
    Uuid::from_fields(0xaaaa_0001, 1, 0x4000, [8, 7, 6, 5, 4, 3, 2, 1]);
pub(super) const AR_UUID: Uuid =
    Uuid::from_fields(0x1234_5678, 0x9abc, 0x4def, [1, 2, 3, 4, 5, 6, 7, 8]);

/// A counter device: DAP and 4 bytes in, 2 bytes out.
pub(super) fn counter_device() -> (Device<TestApp>, ConnectRequest) {
    let subs = [
        (0, 1, 0x1, 0x1, 0, 0),
        (1, 1, 0x30, 0x1, 4, 0),
        (2, 1, 0x31, 0x1, 0, 2),
    ];
    let dev = quiet_device(DeviceSetup {
        name: "counter".into(),
        mac: PNET_MAC,
        ip: Some(DEVICE_IP),
        vendor_id: 0x0493,
        device_id: 0x0001,
        instance: 1,
        submodules: subs
            .iter()
            .map(|&(slot, subslot, m, s, i, o)| PluggedSubmodule {
                api: 0,
                slot,
                subslot,
                module_ident: m,
                submodule_ident: s,
                input_length: i,
                output_length: o,
            })
            .collect(),
        application: TestApp::Counter,
        im0: Im0::default(),
    });
    // 1 ms send clock, reduction ratio 2: a frame every 2 ms; data hold factor 3: 6 ms.
    (dev, built_connect(&subs, AR_UUID, (32, 2, 3)))
}

/// The RPC request carrying `connect` (activity [`ACTIVITY`], sequence 0), big-endian.
pub(super) fn connect_request(connect: &ConnectRequest) -> Vec<u8> {
    connect_request_in_drep(connect, false)
}

/// [`connect_request`] in the DREP byte order `little_endian` says.
pub(super) fn connect_request_in_drep(connect: &ConnectRequest, little_endian: bool) -> Vec<u8> {
    let blocks = connect.to_vec().unwrap();
    request(opnum::CONNECT, ACTIVITY, 0, &blocks, little_endian)
}

/// Connect and PrmEnd with our codecs, both answered OK, at `t0`.
pub(super) fn to_prm_end(dev: &mut Device<TestApp>, connect: &ConnectRequest, t0: u64) {
    let r = call(dev, &connect_request(connect), t0);
    assert_eq!(status(&r), PnioStatus::OK);
    let prm = ControlBlock::prm_end(AR_UUID, 1).to_bytes();
    let r = call(dev, &request(opnum::CONTROL, ACTIVITY, 1, &prm, false), t0);
    assert_eq!(status(&r), PnioStatus::OK);
}

/// Connect, PrmEnd and the ApplicationReady answered with our codecs, at `t0`.
pub(super) fn to_data(dev: &mut Device<TestApp>, connect: &ConnectRequest, t0: u64) -> u64 {
    to_prm_end(dev, connect, t0);
    let mut out = Vec::new();
    let t = t0 + APP_READY_DELAY_NS;
    dev.poll(t, &mut out);
    let d = datagrams(&out);
    let app = parse_reply(&d[0].2);
    let res = wire_rpc::emit_response(
        &app.header.reply(7),
        PnioStatus::OK,
        app.ndr.maximum_count(),
        &ControlBlock::application_ready_done(AR_UUID, 1).to_bytes(),
    )
    .unwrap();
    dev.on_datagram(d[0].0, rpc::CLIENT_PORT, &res, t, &mut out);
    assert_eq!(dev.ar().state(), ArState::Data);
    t
}

/// The controller's output frame for the counter device's layout.
fn output_frame(connect: &ConnectRequest, cycle_counter: u16, ds: u8, outputs: [u8; 2]) -> Vec<u8> {
    let cr = &connect.iocrs[1];
    let mut c_sdu = vec![0u8; usize::from(cr.data_length)];
    let api = &cr.apis[0];
    for e in &api.iocs {
        c_sdu[usize::from(e.frame_offset)] = ar::IOXS_GOOD;
    }
    let o = usize::from(api.data_objects[0].frame_offset);
    c_sdu[o..o + 2].copy_from_slice(&outputs);
    c_sdu[o + 2] = ar::IOXS_GOOD;
    let repr = rt::Repr {
        frame_id: cr.frame_id,
        data_length: c_sdu.len(),
        cycle_counter,
        data_status: ds,
        transfer_status: 0,
    };
    let mut pdu = vec![0u8; repr.buffer_len()];
    let mut p = rt::Packet::new_unchecked(&mut pdu[..], c_sdu.len());
    p.data_mut().copy_from_slice(&c_sdu);
    repr.emit(&mut p).unwrap();
    ethernet_frame(PNET_MAC, S7_MAC, Some(0xc000), &pdu)
}

#[test]
fn cyclic_frames_keep_period_offsets_and_counters_and_the_watchdog_aborts() {
    let (mut dev, connect) = counter_device();
    let t0 = 1_000 * MS;
    to_data(&mut dev, &connect, t0);
    // Frames every 2 ms from PrmEnd on, CycleCounter + 64 each, inputs at the Connect's
    // offsets: the counter (frames produced before this one, big-endian) then its IOPS.
    let input = &connect.iocrs[0];
    let data_at = 20 + usize::from(input.apis[0].data_objects[1].frame_offset);
    let iocs_at = 20 + usize::from(input.apis[0].iocs[0].frame_offset);
    // The controller sends its outputs every 2 ms, 1 ms after ours.
    let mut sent = Vec::new();
    let mut next_output = t0 + 3 * MS;
    let mut cc = 0u16;
    loop {
        let t = dev.next_deadline_ns().unwrap().min(next_output);
        if t > t0 + 20 * MS {
            break;
        }
        let mut out = Vec::new();
        if t == next_output {
            dev.on_frame(
                &output_frame(&connect, cc, data_status::OPERATE, [7, 8]),
                t,
                &mut out,
            );
            next_output += 2 * MS;
            cc = cc.wrapping_add(64);
        } else {
            dev.poll(t, &mut out);
        }
        sent.extend(out.into_iter().map(|a| (t, a)));
    }
    let fs: Vec<(u64, Vec<u8>)> = sent
        .into_iter()
        .filter_map(|(t, a)| match a {
            DeviceAction::Frame(f) => Some((t, f)),
            _ => None,
        })
        .collect();
    assert_eq!(
        fs.len(),
        10,
        "2 ms period over 20 ms, the first at PrmEnd already sent"
    );
    let mut last_cc = None;
    for (i, (at, f)) in fs.iter().enumerate() {
        assert_eq!(*at, t0 + 2 * MS * (i as u64 + 1));
        let p = rt::Packet::new_checked(&f[18..], usize::from(input.data_length)).unwrap();
        let r = rt::Repr::parse(&p).unwrap();
        assert_eq!((r.frame_id, r.data_status), (0x8000, data_status::OPERATE));
        assert_eq!(r.cycle_counter, ((at / 31_250) & 0xffff) as u16);
        if let Some(l) = last_cc {
            assert_eq!(r.cycle_counter, u16::wrapping_add(l, 64));
        }
        last_cc = Some(r.cycle_counter);
        let k = i as u32 + 1;
        assert_eq!(&f[data_at..data_at + 4], &k.to_be_bytes());
        assert_eq!(f[data_at + 4], ar::IOXS_GOOD, "IOPS after the data");
        assert_eq!(f[iocs_at], ar::IOXS_GOOD, "IOCS of the output submodule");
    }
    assert_eq!(dev.ar().inputs(0, 1, 1), Some(&10u32.to_be_bytes()[..]));

    assert_eq!(dev.ar().outputs(0, 2, 1), Some((&[7, 8][..], true)));
    // A STOP frame makes the outputs invalid.
    let mut out = Vec::new();
    let now = next_output;
    dev.on_frame(
        &output_frame(&connect, cc, data_status::CLEAR, [3, 4]),
        now,
        &mut out,
    );
    assert_eq!(dev.ar().outputs(0, 2, 1), Some((&[3, 4][..], false)));
    // A repeated CycleCounter is not fresh: ignored.
    dev.on_frame(
        &output_frame(&connect, cc, data_status::OPERATE, [5, 6]),
        now,
        &mut out,
    );
    assert_eq!(dev.ar().outputs(0, 2, 1), Some((&[3, 4][..], false)));
    assert!(out.is_empty());
    // Then silence: DataHoldFactor 3 × 2 ms after the last frame, the AR is aborted with an
    // ERR-RTA (consumer DHT expired) on the low-priority alarm channel.
    let sent = run_until(&mut dev, now + 10 * MS);
    assert_eq!(dev.ar().state(), ArState::Idle);
    assert_eq!(dev.ar().last_abort(), Some(AbortCode::ConsumerDhtExpired));
    let (at, err) = sent
        .iter()
        .find_map(|(t, a)| match a {
            DeviceAction::Frame(f) if f[18..20] == [0xfe, 0x01] => Some((*t, f.clone())),
            _ => None,
        })
        .expect("an ERR-RTA");
    assert_eq!(at, now + 6 * MS);
    let pdu = RtaPdu::parse(&rta_pdu::Packet::new_checked(&err[18..]).unwrap()).unwrap();
    assert_eq!(
        pdu.body,
        RtaBody::Err(ErrRta::abort(AbortCode::ConsumerDhtExpired))
    );
    assert_eq!((pdu.header.dst_endpoint, pdu.header.src_endpoint), (1, 0));
    assert_eq!(&err[..6], &S7_MAC.0, "to the controller");
    assert_eq!(&err[14..16], &[0xa0, 0x00], "low priority tag");
    assert_eq!(dev.next_deadline_ns(), None);
}

#[test]
fn the_engine_judges_the_consumer_trial_as_the_consumer_does() {
    let (mut dev, connect) = counter_device();
    let t0 = 1_000 * MS;
    let t = to_data(&mut dev, &connect, t0);
    let cr = &connect.iocrs[1];
    let setup = TrialSetup {
        peer: S7_MAC,
        own: PNET_MAC,
        frame_id: cr.frame_id,
        data_length: usize::from(cr.data_length),
        timing: CrTiming {
            send_clock_factor: cr.send_clock_factor,
            reduction_ratio: cr.reduction_ratio,
            every_cycles: 1,
            data_hold_factor: cr.data_hold_factor,
        },
        first_at_ns: t + MS,
        first_counter: 0x1000,
    };
    let trial = setup.trial();
    let mut out = Vec::new();
    for f in &trial.frames {
        dev.poll(f.at_ns, &mut out);
        dev.on_frame(&f.frame, f.at_ns, &mut out);
    }
    assert_eq!(dev.ar().consumer_verdicts(), Some(trial.counts));
    // The outputs are those of the last accepted frame: its data bytes, valid.
    let o = usize::from(cr.apis[0].data_objects[0].frame_offset);
    assert_eq!(
        dev.ar().outputs(0, 2, 1),
        Some((&trial.last_c_sdu[o..o + 2], true))
    );
    run_until(&mut dev, trial.expires_at_ns - 1);
    assert_eq!(
        dev.ar().state(),
        ArState::Data,
        "not before the watchdog's time"
    );
    run_until(&mut dev, trial.expires_at_ns);
    assert_eq!(dev.ar().last_abort(), Some(AbortCode::ConsumerDhtExpired));
}

#[test]
fn negative_responses_name_the_fault() {
    let connect = rpc_pdu("cm/connect_req");
    let faulty = |patch: &dyn Fn(&mut Vec<u8>)| {
        let mut dev = pnet_device(TestApp::None);
        let mut p = connect.clone();
        patch(&mut p);
        let r = call(&mut dev, &p, 0);
        assert!(r.blocks.is_empty());
        assert_eq!(dev.ar().state(), ArState::Idle);
        status(&r)
    };
    // The input IOCR's FrameID (ARBlockReq is 95 bytes; FrameID at 6 + 12 in the IOCR).
    let iocr = 95;
    assert_eq!(
        faulty(&|p| patch_block(p, iocr + 18, &[0x00, 0x01])),
        refuse(0x02, 9)
    );
    // ARType 2.
    assert_eq!(
        faulty(&|p| patch_block(p, 6, &[0x00, 0x02])),
        refuse(0x01, 4)
    );
    // DataHoldFactor 0.
    assert_eq!(
        faulty(&|p| patch_block(p, iocr + 34, &[0, 0])),
        refuse(0x02, 16)
    );
    // An NDR ArgsLength beyond the blocks.
    assert_eq!(
        faulty(&|p| p[84..88].copy_from_slice(&9999u32.to_le_bytes())),
        refuse(0x40, 0)
    );
    // An unknown block appended.
    let unknown = |p: &mut Vec<u8>| {
        let n = u32::from_le_bytes([p[84], p[85], p[86], p[87]]) + 8;
        p.extend_from_slice(&[0x01, 0x99, 0x00, 0x04, 0x01, 0x00, 0x00, 0x00]);
        let body_len = u16::from_le_bytes([p[74], p[75]]) + 8;
        p[74..76].copy_from_slice(&body_len.to_le_bytes());
        for at in [84, 96] {
            p[at..at + 4].copy_from_slice(&n.to_le_bytes());
        }
    };
    assert_eq!(faulty(&unknown), refuse(0x40, 1));

    // With an AR: another AR is refused, the same AR re-run ends it.
    let mut dev = pnet_device(TestApp::None);
    call(&mut dev, &connect, 0);
    let mut other = connect.clone();
    patch_block(&mut other, 8, &[0xff]);
    other[64] = 9; // a new sequence number, not a duplicate
    assert_eq!(status(&call(&mut dev, &other, MS)), refuse(0x40, 4));
    assert_eq!(dev.ar().state(), ArState::Connected);
    let mut rerun = connect.clone();
    rerun[64] = 10;
    let mut out = Vec::new();
    dev.on_datagram(S7_CLIENT, RPC_PORT, &rerun, 2 * MS, &mut out);
    assert_eq!(status(&parse_reply(&datagrams(&out)[0].2)), refuse(0x3d, 0));
    assert_eq!(frames(&out).len(), 1, "an ERR-RTA");
    assert_eq!(dev.ar().state(), ArState::Idle);
    assert_eq!(dev.ar().last_abort(), Some(AbortCode::RerunAbortsExisting));

    // PrmEnd with a wrong session key, and for an unknown AR.
    let mut dev = pnet_device(TestApp::None);
    call(&mut dev, &connect, 0);
    // (Each call a new sequence number: a CL server answers an old one from its cache or
    // not at all.)
    let prm_seq = |seq: u8| {
        let mut p = rpc_pdu("cm/prmend_req");
        p[64] = seq;
        p
    };
    let mut prm = prm_seq(5);
    patch_block(&mut prm, 24, &[0x00, 0x07]);
    assert_eq!(status(&call(&mut dev, &prm, MS)), pnio(0xdd, 0x14, 6));
    let mut prm = prm_seq(6);
    patch_block(&mut prm, 8, &[0xff]);
    assert_eq!(status(&call(&mut dev, &prm, MS)), pnio(0xdd, 0x40, 5));
    // The real PrmEnd, then a second one: state conflict.
    assert_eq!(status(&call(&mut dev, &prm_seq(7), MS)), PnioStatus::OK);
    let again = prm_seq(8);
    assert_eq!(status(&call(&mut dev, &again, MS)), pnio(0xdd, 0x3d, 0));

    // An unknown interface and an unknown opnum are rejected at the RPC level.
    let mut epm = prm_seq(9);
    epm[24] ^= 0x55;
    let mut out = Vec::new();
    dev.on_datagram(S7_CLIENT, RPC_PORT, &epm, MS, &mut out);
    let rej = &datagrams(&out)[0].2;
    assert_eq!(
        wire_rpc::Packet::new_checked(&rej[..])
            .unwrap()
            .packet_type(),
        PacketType::Reject
    );
    assert_eq!(&rej[80..84], &rpc::NCA_UNKNOWN_INTERFACE.to_le_bytes());
}

#[test]
fn records_read_im0_and_written_data_and_refuse_the_rest() {
    let (mut dev, _) = pnet_in_data(TestApp::None);
    let ar_uuid = dev.ar().ar_uuid().unwrap();
    // The captured I&M0 read (another AR's UUID in the capture: patched to ours). Its
    // response is p-net's byte for byte in the blocks.
    let mut req = rpc_pdu("alarm/im0_read_req");
    patch_block(&mut req, 8, &ar_uuid.0);
    let ours = call(&mut dev, &req, 10 * MS);
    let pnet = parse_reply(&rpc_pdu("alarm/im0_read_res"));
    let mut expected = pnet.blocks.clone();
    expected[8..24].copy_from_slice(&ar_uuid.0);
    assert_eq!(ours.blocks, expected);
    assert_eq!(status(&ours), PnioStatus::OK);

    let read = |dev: &mut Device<TestApp>, seq: u32, slot: u16, subslot: u16, index: u16| {
        let h = IodHeader::read_request(0, ar_uuid, 0, slot, subslot, index, 4096);
        call(
            dev,
            &request(opnum::READ, ACTIVITY, seq, &h.to_bytes(), true),
            10 * MS,
        )
    };
    // The user record the S7 wrote (index 123 of slot 3) reads back.
    let r = read(&mut dev, 1, 3, 1, 123);
    let (h, data, _) = IodHeader::split(&r.blocks).unwrap();
    assert_eq!(h.kind, IodKind::ReadRes);
    assert_eq!(data, split_write_multiple_written(123));
    // Diagnosis: empty; unknown index and slot: PNIORW errors.
    let r = read(&mut dev, 2, 0, 1, 0x800a);
    assert_eq!(status(&r), PnioStatus::OK);
    assert_eq!(IodHeader::parse(&r.blocks).unwrap().record_data_length, 0);
    assert_eq!(
        status(&read(&mut dev, 3, 0, 1, 0x4711)),
        PnioStatus::from_bytes([0xde, 0x80, 0xb0, 0x00])
    );
    assert_eq!(
        status(&read(&mut dev, 4, 9, 1, 0xaff0)),
        PnioStatus::from_bytes([0xde, 0x80, 0xb2, 0x00])
    );
    // A write to I&M0 is denied; to an unknown index refused.
    let write = |dev: &mut Device<TestApp>, seq: u32, index: u16| {
        let h = IodHeader::write_request(0, ar_uuid, 0, 0, 1, index, 2);
        let mut b = h.to_bytes().to_vec();
        b.extend_from_slice(&[1, 2]);
        let r = call(
            dev,
            &request(opnum::WRITE, ACTIVITY, seq, &b, true),
            10 * MS,
        );
        let h = IodHeader::parse(&r.blocks).unwrap();
        assert_eq!(h.status, status(&r));
        status(&r)
    };
    assert_eq!(
        write(&mut dev, 5, 0xaff0),
        PnioStatus::from_bytes([0xdf, 0x80, 0xb6, 0])
    );
    assert_eq!(
        write(&mut dev, 6, 0xb000),
        PnioStatus::from_bytes([0xdf, 0x80, 0xb0, 0])
    );
    // The records the device serves itself are read-only too.
    assert_eq!(
        write(&mut dev, 7, 0xc000),
        PnioStatus::from_bytes([0xdf, 0x80, 0xb6, 0])
    );
    assert_eq!(write(&mut dev, 8, 0x0010), PnioStatus::OK);
    // ReadImplicit of I&M0 works without naming the AR.
    let h = IodHeader::read_request(0, Uuid::NIL, 0, 0, 1, 0xaff0, 4096);
    let r = call(
        &mut dev,
        &request(opnum::READ_IMPLICIT, ACTIVITY, 9, &h.to_bytes(), true),
        10 * MS,
    );
    let (_, data, _) = IodHeader::split(&r.blocks).unwrap();
    assert_eq!(Im0::parse(data).unwrap(), pnet_im0());
}

/// The data the captured WriteMultiple wrote to `index`.
fn split_write_multiple_written(index: u16) -> Vec<u8> {
    let blocks = captured_blocks("cm/write_req");
    let (_, data, _) = IodHeader::split(&blocks).unwrap();
    crate::wire::record::split_write_multiple(data)
        .unwrap()
        .into_iter()
        .find(|(h, _)| h.index == index)
        .map(|(_, d)| d.to_vec())
        .unwrap()
}

#[test]
fn duplicates_pings_and_fragments() {
    let mut dev = pnet_device(TestApp::None);
    let connect = rpc_pdu("cm/connect_req");
    let mut out = Vec::new();
    dev.on_datagram(S7_CLIENT, RPC_PORT, &connect, 0, &mut out);
    let first = datagrams(&out);
    // The same request again (the response was lost): the same response, the AR unchanged.
    out.clear();
    dev.on_datagram(S7_CLIENT, RPC_PORT, &connect, MS, &mut out);
    assert_eq!(datagrams(&out), first);
    assert_eq!(dev.ar().state(), ArState::Connected);
    // A ping for it: the response again; for an unknown call: no-call.
    let ping = |seq: u32| {
        let h = Header {
            packet_type: PacketType::Ping,
            sequence_number: seq,
            ..parse_reply(&connect).header
        };
        rpc::pdu(&h, &[]).unwrap()
    };
    out.clear();
    dev.on_datagram(S7_CLIENT, RPC_PORT, &ping(0), MS, &mut out);
    assert_eq!(datagrams(&out), first);
    out.clear();
    dev.on_datagram(S7_CLIENT, RPC_PORT, &ping(5), MS, &mut out);
    let d = datagrams(&out);
    assert_eq!(
        wire_rpc::Packet::new_checked(&d[0].2[..])
            .unwrap()
            .packet_type(),
        PacketType::NoCall
    );

    // The Connect in two fragments: a FACK for the first, the same answer after the second.
    let mut fresh = pnet_device(TestApp::None);
    let h = parse_reply(&connect).header;
    let body = &connect[80..];
    let (a, b) = body.split_at(300);
    let frag = |n: u16, last: bool, part: &[u8]| {
        let f = Header {
            flags1: flags1::IDEMPOTENT
                | flags1::FRAGMENT
                | if last { flags1::LAST_FRAGMENT } else { 0 },
            fragment_number: n,
            ..h
        };
        rpc::pdu(&f, part).unwrap()
    };
    out.clear();
    fresh.on_datagram(S7_CLIENT, RPC_PORT, &frag(0, false, a), 0, &mut out);
    let d = datagrams(&out);
    assert_eq!(d.len(), 1);
    let fack = wire_rpc::Packet::new_checked(&d[0].2[..]).unwrap();
    assert_eq!(
        (fack.packet_type(), fack.fragment_number()),
        (PacketType::Fack, 0)
    );
    out.clear();
    fresh.on_datagram(S7_CLIENT, RPC_PORT, &frag(1, true, b), 0, &mut out);
    assert_eq!(datagrams(&out), first);
}

#[test]
fn alarms_are_acknowledged_and_err_rta_ends_the_ar() {
    let (mut dev, t) = pnet_in_data(TestApp::None);
    let mut out = Vec::new();
    // A process alarm goes out as high-priority DATA with TACK.
    assert!(dev.raise_process_alarm(0, 1, 1, 0x0010, &[1], t, &mut out));
    let f = frames(&out);
    assert_eq!(f.len(), 1);
    assert_eq!(
        &f[0][12..20],
        &[0x81, 0x00, 0xc0, 0x00, 0x88, 0x92, 0xfc, 0x01]
    );
    let notif = RtaPdu::parse(&rta_pdu::Packet::new_checked(&f[0][18..]).unwrap()).unwrap();
    let n = notif.notification().unwrap().clone();
    assert_eq!(
        (n.slot, n.subslot, n.module_ident, n.submodule_ident),
        (1, 1, 0x30, 0x130)
    );
    assert!(notif.header.tack);
    // Unanswered, it is repeated after the RTA timeout (factor 1: 100 ms).
    assert_eq!(
        dev.next_deadline_ns().map(|d| d <= t + 100 * MS),
        Some(true)
    );
    // The S7's transport ACK and its AlarmAck (DATA): the device acknowledges the DATA.
    let to_dev = |pdu: RtaPdu| {
        let tci = if pdu.priority == Priority::High {
            0xc000
        } else {
            0xa000
        };
        ethernet_frame(PNET_MAC, S7_MAC, Some(tci), &pdu.to_vec().unwrap())
    };
    out.clear();
    let h = notif.header;
    dev.on_frame(
        &to_dev(RtaPdu::first_ack_of(Priority::High, &h)),
        t + MS,
        &mut out,
    );
    assert!(out.is_empty());
    let ack = AlarmAck::for_notification(&n, PnioStatus::OK);
    dev.on_frame(
        &to_dev(RtaPdu::first_reply_to(
            Priority::High,
            &h,
            vec![AlarmBlock::Ack(ack)],
        )),
        t + 2 * MS,
        &mut out,
    );
    let f = frames(&out);
    assert_eq!(f.len(), 1);
    let tack = RtaPdu::parse(&rta_pdu::Packet::new_checked(&f[0][18..]).unwrap()).unwrap();
    assert_eq!(tack.body, RtaBody::Ack);
    assert_eq!(tack.header.ack_seq, 0xffff);
    assert_eq!(dev.alarm_acks().list(), &[ack]);
    // The S7's ERR-RTA (captured) ends the AR without an answer.
    out.clear();
    let mut err = capture("alarm/alarm_err_rta_cpu");
    err[..6].copy_from_slice(&PNET_MAC.0);
    err[6..12].copy_from_slice(&S7_MAC.0);
    dev.on_frame(&err, t + 3 * MS, &mut out);
    assert!(out.is_empty());
    assert_eq!(dev.ar().state(), ArState::Idle);
    assert_eq!(dev.ar().last_abort(), Some(AbortCode::AlarmIndicationError));
}

/// Found by the `controller` fuzz target: a process alarm with 5 000 bytes of data went out
/// as one frame of 5 302 bytes. The notification must fit the AR's MaxAlarmDataLength (200
/// here, the device's own limit).
#[test]
fn a_process_alarm_longer_than_max_alarm_data_length_is_refused() {
    let (mut dev, t) = pnet_in_data(TestApp::None);
    let mut out = Vec::new();
    // Block header 6, fixed part 20, USI 2: 172 bytes of data make 200.
    assert!(!dev.raise_process_alarm(0, 1, 1, 0x0010, &[0xa5; 5000], t, &mut out));
    assert!(!dev.raise_process_alarm(0, 1, 1, 0x0010, &[0xa5; 173], t, &mut out));
    assert!(out.is_empty());
    assert!(dev.raise_process_alarm(0, 1, 1, 0x0010, &[0xa5; 172], t, &mut out));
    let f = frames(&out);
    assert_eq!(f.len(), 1);
    let pdu = rta_pdu::Packet::new_checked(&f[0][18..]).unwrap();
    assert_eq!(pdu.var_part_len(), 200);
}

#[test]
fn an_unanswered_application_ready_is_repeated_then_the_ar_aborted() {
    let mut dev = pnet_device(TestApp::None);
    let (app, t) = bring_up_to_app_ready(&mut dev);
    let sent = run_until(&mut dev, t + 10_000 * MS);
    let repeats: Vec<u64> = sent
        .iter()
        .filter_map(|(at, a)| match a {
            DeviceAction::Datagram { payload, .. } => {
                assert_eq!(parse_reply(payload).header, app.header);
                Some(*at)
            }
            _ => None,
        })
        .collect();
    assert_eq!(repeats, vec![t + 2_000 * MS, t + 4_000 * MS]);
    assert_eq!(dev.ar().state(), ArState::Idle);
    assert_eq!(
        dev.ar().last_abort(),
        Some(AbortCode::RpcClientCallNegative)
    );
}

#[test]
fn ndr_request_helper_matches_the_s7_shape() {
    // The requests built in these tests have the shape the device checks.
    let p = request(opnum::CONTROL, ACTIVITY, 0, &[0; 32], true);
    let r = parse_reply(&p);
    let Ndr::Request(n) = r.ndr else {
        panic!("a request")
    };
    assert_eq!(n, NdrRequest::for_blocks(1340, 32));
}

#[test]
fn a_station_name_change_by_dcp_ends_the_ar() {
    let (mut dev, t) = pnet_in_data(TestApp::None);
    let mut out = Vec::new();
    let set = wire_dcp::Repr::set_name(9, "renamed", false);
    dev.on_frame(
        &dcp_client::frame(PNET_MAC, S7_MAC, &set).unwrap(),
        t,
        &mut out,
    );
    assert_eq!(dev.ar().state(), ArState::Idle);
    assert_eq!(dev.ar().last_abort(), Some(AbortCode::StationNameChanged));
    assert_eq!(frames(&out).len(), 2, "the Set response and the ERR-RTA");
}

#[test]
fn legacy_startup_with_frame_ids_left_to_the_device() {
    let (mut dev, mut connect) = counter_device();
    connect.ar.ar_properties = 0x0000_0011;
    for c in &mut connect.iocrs {
        c.iocr_properties = crate::wire::connect::iocr_properties::RT_CLASS_1;
        c.frame_id = 0xffff;
    }
    let r = call(&mut dev, &connect_request_in_drep(&connect, true), 0);
    assert_eq!(status(&r), PnioStatus::OK);
    let res = ConnectResponse::parse(&r.blocks).unwrap();
    assert_eq!(
        (res.frame_id(1), res.frame_id(2)),
        (Some(0xc000), Some(0xc001))
    );
    assert_eq!(res.ar_server, None, "no ARServerBlock in legacy startup");
    let prm = ControlBlock::prm_end(AR_UUID, 1).to_bytes();
    call(
        &mut dev,
        &request(opnum::CONTROL, ACTIVITY, 1, &prm, true),
        0,
    );
    let mut out = Vec::new();
    dev.poll(0, &mut out);
    assert_eq!(&frames(&out)[0][18..20], &[0xc0, 0x00]);
    // Advanced startup with RT class 1 FrameIDs is refused.
    connect.ar.ar_properties = 0x4000_0011;
    let mut fresh = counter_device().0;
    let r = call(&mut fresh, &connect_request_in_drep(&connect, true), 0);
    assert_eq!(status(&r), refuse(0x02, 7));
}

#[test]
fn prm_begin_reparameterizes_and_release_checks_the_session() {
    let (mut dev, connect) = counter_device();
    let t = to_data(&mut dev, &connect, 0);
    let begin = ControlBlock::prm_begin(AR_UUID, 1);
    let r = call(
        &mut dev,
        &request(opnum::CONTROL, ACTIVITY, 2, &begin.to_bytes(), false),
        t,
    );
    assert_eq!(status(&r), PnioStatus::OK);
    assert!(ControlBlock::parse(&r.blocks).unwrap().answers(&begin));
    assert_eq!(dev.ar().state(), ArState::Connected);
    let prm = ControlBlock::prm_end(AR_UUID, 1).to_bytes();
    let r = call(
        &mut dev,
        &request(opnum::CONTROL, ACTIVITY, 3, &prm, false),
        t,
    );
    assert_eq!(status(&r), PnioStatus::OK);
    let mut out = Vec::new();
    dev.poll(t + APP_READY_DELAY_NS, &mut out);
    let app = parse_reply(&datagrams(&out)[0].2);
    assert_eq!(app.header.interface, CONTROLLER_INTERFACE);
    assert_eq!(dev.ar().state(), ArState::WaitAppReadyConfirm);
    // A Release with the wrong SessionKey is refused, an unknown opnum rejected.
    let release = ControlBlock::release(AR_UUID, 9).to_bytes();
    let r = call(
        &mut dev,
        &request(opnum::RELEASE, ACTIVITY, 4, &release, false),
        t,
    );
    assert_eq!(status(&r), pnio(0xdc, 0x28, 6));
    let mut out = Vec::new();
    dev.on_datagram(
        S7_CLIENT,
        RPC_PORT,
        &request(17, ACTIVITY, 5, &[], false),
        t,
        &mut out,
    );
    let rej = datagrams(&out).remove(0).2;
    assert_eq!(
        wire_rpc::Packet::new_checked(&rej[..])
            .unwrap()
            .packet_type(),
        PacketType::Reject
    );
    assert_eq!(&rej[80..84], &rpc::NCA_OP_RANGE_ERROR.to_be_bytes());
    let release = ControlBlock::release(AR_UUID, 1).to_bytes();
    let r = call(
        &mut dev,
        &request(opnum::RELEASE, ACTIVITY, 6, &release, false),
        t,
    );
    assert_eq!(status(&r), PnioStatus::OK);
    assert_eq!(dev.ar().state(), ArState::Idle);
}

/// The LLDPDU of an LLDP frame among `out`, if there is one.
pub(super) fn lldp_announcement(out: &[DeviceAction]) -> Option<crate::wire::lldp::Repr> {
    use crate::wire::lldp;
    frames(out).iter().find_map(|f| {
        let eth = ethernet::Frame::new_checked(&f[..]).ok()?;
        if eth.ethertype() != lldp::ETHERTYPE_LLDP {
            return None;
        }
        assert_eq!(eth.dst(), lldp::MULTICAST_NEAREST_BRIDGE);
        assert_eq!(eth.src(), PNET_MAC);
        lldp::Repr::parse(&lldp::Packet::new_checked(eth.payload()).ok()?).ok()
    })
}

#[test]
fn lldp_announces_at_start_every_five_seconds_and_after_dcp_changes() {
    use crate::wire::lldp::Id;
    let mut dev = Device::new(pnet_spec(TestApp::None));
    assert_eq!(
        dev.next_deadline_ns(),
        Some(0),
        "the first announcement at once"
    );
    let mut out = Vec::new();
    dev.poll(MS, &mut out);
    let r = lldp_announcement(&out).expect("an announcement");
    assert_eq!(out.len(), 1);
    assert_eq!(r.chassis_id, Id::Local("rt-labs-dev".into()));
    assert_eq!(r.port_id, Id::Local("port-001".into()));
    assert_eq!((r.ttl, r.management_ipv4()), (20, None));
    assert_eq!(r.profinet_chassis_mac(), Some(PNET_MAC));
    assert_eq!(dev.next_deadline_ns(), Some(MS + 5_000 * MS));
    out.clear();
    dev.poll(5_000 * MS, &mut out);
    assert!(out.is_empty());
    dev.poll(5_001 * MS, &mut out);
    assert!(lldp_announcement(&out).is_some());

    // DCP sets the address, then the name: each is announced at once.
    out.clear();
    dev.on_frame(&capture("cm/dcp_set_req"), 6_000 * MS, &mut out);
    assert_eq!(frames(&out).len(), 1, "the Set response");
    assert_eq!(dev.next_deadline_ns(), Some(0));
    out.clear();
    dev.poll(6_000 * MS, &mut out);
    let r = lldp_announcement(&out).unwrap();
    assert_eq!(r.management_ipv4(), Some(DEVICE_IP));
    let set = wire_dcp::Repr::set_name(7, "renamed", false);
    out.clear();
    dev.on_frame(
        &dcp_client::frame(PNET_MAC, S7_MAC, &set).unwrap(),
        6_500 * MS,
        &mut out,
    );
    out.clear();
    dev.poll(6_500 * MS, &mut out);
    let r = lldp_announcement(&out).unwrap();
    assert_eq!(r.chassis_id, Id::Local("renamed".into()));
    assert_eq!(dev.station().lldp().unwrap().station().name, "renamed");
    assert_eq!(dev.next_deadline_ns(), Some(11_500 * MS));

    // Reset to factory: no name, no address; the chassis ID becomes the MAC address.
    let reset = wire_dcp::Repr {
        frame_id: wire_dcp::FRAME_ID_GET_SET,
        service_id: wire_dcp::ServiceId::Set,
        service_type: wire_dcp::ServiceType::Request,
        xid: 8,
        response_delay: 0,
        blocks: vec![wire_dcp::Block::new(
            0x0002,
            BlockRepr::ResetToFactory(0x0002),
        )],
    };
    out.clear();
    dev.on_frame(
        &dcp_client::frame(PNET_MAC, S7_MAC, &reset).unwrap(),
        7_000 * MS,
        &mut out,
    );
    out.clear();
    dev.poll(7_000 * MS, &mut out);
    let r = lldp_announcement(&out).unwrap();
    assert_eq!(r.chassis_id, Id::MacAddress(PNET_MAC));
    assert_eq!(r.management_ipv4(), None);

    // Off: nothing more, and no deadline of its own.
    dev.station_mut().set_lldp(false);
    assert_eq!(dev.next_deadline_ns(), None);
    out.clear();
    dev.poll(60_000 * MS, &mut out);
    assert!(out.is_empty());
    // On again: at once.
    dev.station_mut().set_lldp(true);
    dev.poll(60_001 * MS, &mut out);
    assert!(lldp_announcement(&out).is_some());
}

#[test]
fn the_s7s_pd_interface_adjust_puts_the_name_into_the_lldp_port_id() {
    use crate::wire::lldp::Id;
    let mut dev = Device::new(DeviceSetup {
        ip: Some(DEVICE_IP),
        ..pnet_spec(TestApp::None)
    });
    let mut out = Vec::new();
    dev.poll(0, &mut out);
    let r = lldp_announcement(&out).unwrap();
    assert_eq!(r.port_id, Id::Local("port-001".into()));
    // The captured WriteMultiple carries PDInterfaceAdjust with MultipleInterfaceMode 1.
    assert_eq!(
        status(&call(&mut dev, &rpc_pdu("cm/connect_req"), MS)),
        PnioStatus::OK
    );
    assert_eq!(
        status(&call(&mut dev, &rpc_pdu("cm/write_req"), 2 * MS)),
        PnioStatus::OK
    );
    assert_eq!(
        dev.station().lldp().unwrap().station().mode,
        lldp::NameOfDeviceMode::PortAndStationName
    );
    assert_eq!(dev.next_deadline_ns(), Some(0), "announced at once");
    out.clear();
    dev.poll(2 * MS, &mut out);
    let r = lldp_announcement(&out).unwrap();
    assert_eq!(r.port_id, Id::Local("port-001.rt-labs-dev".into()));
    // The chassis ID is the SystemIdentification, starting with the type of station.
    assert_eq!(
        r.chassis_id
            .local()
            .and_then(|c| c.split_whitespace().next()),
        Some("procimg")
    );
}

#[test]
fn dcp_hello_at_start_up() {
    let mut dev = quiet_device(DeviceSetup {
        ip: Some(DEVICE_IP),
        ..pnet_spec(TestApp::None)
    });
    let mut out = Vec::new();
    dev.poll(0, &mut out);
    assert!(out.is_empty(), "no Hello unless asked for");
    dev.station_mut().set_hello(true);
    assert_eq!(dev.next_deadline_ns(), Some(0));
    dev.poll(MS, &mut out);
    let f = frames(&out);
    assert_eq!(f.len(), 1);
    assert_eq!(&f[0][..6], &MacAddress::DCP_HELLO.0);
    assert_eq!(&f[0][6..12], &PNET_MAC.0);
    let hello = parse_dcp(&f[0]);
    assert_eq!(hello.frame_id, wire_dcp::FRAME_ID_HELLO);
    assert_eq!(
        (hello.service_id, hello.service_type),
        (wire_dcp::ServiceId::Hello, wire_dcp::ServiceType::Request)
    );
    let codes: Vec<(u8, u8)> = hello.blocks.iter().map(|b| b.value.code()).collect();
    use wire_dcp::code;
    assert_eq!(
        codes,
        [
            code::NAME_OF_STATION,
            code::IP_PARAMETER,
            code::DEVICE_ID,
            code::DEVICE_VENDOR,
            code::DEVICE_ROLE,
            code::DEVICE_INITIATIVE
        ]
    );
    assert_eq!(hello.name_of_station(), Some("rt-labs-dev"));
    assert_eq!(hello.ip(), Some((DEVICE_IP, [255, 255, 255, 0], [0; 4])));
    assert!(
        hello
            .blocks
            .contains(&wire_dcp::Block::new(0, BlockRepr::DeviceInitiative(1)))
    );
    // Once.
    out.clear();
    dev.poll(2 * MS, &mut out);
    assert!(out.is_empty());
    assert_eq!(dev.next_deadline_ns(), None);
    // Get reads the DeviceInitiative.
    let get = wire_dcp::Repr::get(9, &[code::DEVICE_INITIATIVE]);
    dev.on_frame(
        &dcp_client::frame(PNET_MAC, S7_MAC, &get).unwrap(),
        3 * MS,
        &mut out,
    );
    let res = parse_dcp(&frames(&out)[0]);
    assert_eq!(res.blocks[0].value, BlockRepr::DeviceInitiative(1));
}
