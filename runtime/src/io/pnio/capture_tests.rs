// SPDX-License-Identifier: MIT OR Apache-2.0
//! The controller against the S7-1515 captures: configured like the S7 was for the p-net
//! sample device, it must send what the S7 sent, byte for byte, and take every captured
//! device answer.
//!
//! Masked, because they are chosen anew per AR or per run and the protocol does not fix
//! them: the DCP Xid, the RPC activity UUID, the ARUUID, the SessionKey, the
//! ServerBootTime of our ApplicationReady response and the CycleCounter of cyclic frames.
//! The DCP Set goes out untagged where the S7 tags it with priority 0, so the comparison
//! starts at the FrameID there. The S7 sends its alarm frames from its interface MAC address
//! and everything else from its port's; one controller MAC serves all here, so the source
//! address of the alarm frames is not compared.

use crate::config;
use crate::image::{Image, Tables};
use crate::io::pnio::PnioIo;
use crate::io::pnio::channel::{Channel, ToCycle};
use crate::io::{CycleTime, IoSystem};
use procimg_nic::{Nic, sim_link};
use procimg_profinet::controller::plan::ControllerIdentity;
use procimg_profinet::controller::{Controller, ControllerAction, DeviceState};
use procimg_profinet::wire::rpc::{self, Pdu};
use procimg_profinet::wire::{MacAddress, Uuid};
use procimg_shm_layout::{IOXS_GOOD, Mode, SubmoduleStatus};
use procimg_testkit::fixtures::profinet_capture as capture;
use std::net::{Ipv4Addr, SocketAddrV4};
use std::sync::Arc;

/// The S7's configuration of the p-net sample device, as its Connect and Write show it.
const PNET_SAMPLE: &str = include_str!("../../../tests/fixtures/pnet_sample.toml");

const S7_MAC: MacAddress = MacAddress([0xec, 0x1c, 0x5d, 0x61, 0xe7, 0x3f]);
const S7_IP: Ipv4Addr = Ipv4Addr::new(172, 16, 2, 100);
const DEVICE_IP: Ipv4Addr = Ipv4Addr::new(172, 16, 2, 10);

fn s7() -> ControllerIdentity {
    ControllerIdentity {
        mac: S7_MAC,
        ip: S7_IP,
        station_name: "plcxbbench.profinetxainterfacexb25fbd".into(),
        vendor_id: 0x002a,
        device_id: 0x010e,
        instance: 0x1064,
    }
}

/// The UDP payload of a captured IPv4/UDP frame (untagged), without Ethernet padding.
fn udp_payload(frame: &[u8]) -> Vec<u8> {
    let len = u16::from_be_bytes([frame[38], frame[39]]) as usize;
    frame[42..34 + len].to_vec()
}

fn replace_all(b: &mut [u8], from: &[u8], to: &[u8]) -> usize {
    let mut n = 0;
    let mut i = 0;
    while i + from.len() <= b.len() {
        if &b[i..i + from.len()] == from {
            b[i..i + from.len()].copy_from_slice(to);
            n += 1;
            i += from.len();
        } else {
            i += 1;
        }
    }
    n
}

/// A captured PDU with the per-AR values of the capture replaced by ours.
struct Masks {
    activity: (Uuid, Uuid),
    ar: (Uuid, Uuid),
    session_key: (u16, u16),
}

impl Masks {
    fn apply(&self, pdu: &[u8], with_session_key: bool) -> Vec<u8> {
        let mut b = pdu.to_vec();
        let le = b[4] == 0x10;
        replace_all(
            &mut b[40..56],
            &self.activity.0.to_drep(le),
            &self.activity.1.to_drep(le),
        );
        let (from, to) = (self.ar.0.0, self.ar.1.0);
        let mut i = rpc::HEADER_LEN;
        while i + 18 <= b.len() {
            if b[i..i + 16] == from {
                b[i..i + 16].copy_from_slice(&to);
                if with_session_key && b[i + 16..i + 18] == self.session_key.0.to_be_bytes() {
                    b[i + 16..i + 18].copy_from_slice(&self.session_key.1.to_be_bytes());
                }
                i += 16;
            } else {
                i += 1;
            }
        }
        b
    }
}

fn datagram(out: &mut Vec<ControllerAction>) -> (SocketAddrV4, Vec<u8>) {
    let i = out
        .iter()
        .position(|a| matches!(a, ControllerAction::Datagram { .. }))
        .unwrap_or_else(|| panic!("no datagram among {out:?}"));
    match out.remove(i) {
        ControllerAction::Datagram { to, payload } => (to, payload),
        _ => unreachable!(),
    }
}

fn frame(out: &mut Vec<ControllerAction>) -> Vec<u8> {
    let i = out
        .iter()
        .position(|a| matches!(a, ControllerAction::Frame(_)))
        .unwrap_or_else(|| panic!("no frame among {out:?}"));
    match out.remove(i) {
        ControllerAction::Frame(f) => f,
        _ => unreachable!(),
    }
}

/// The DCP Xid of a frame (untagged: FrameID at 14).
fn xid(frame: &[u8], at: usize) -> [u8; 4] {
    frame[at + 4..at + 8].try_into().unwrap()
}

#[test]
fn the_controller_brings_up_the_pnet_sample_as_the_s7_did() {
    let config = config::parse(PNET_SAMPLE, "pnet-sample.toml").unwrap();
    let plans = crate::roles::controller::plan_devices(&config).unwrap();
    let mut c = Controller::new(s7(), plans, 0x5156, 1);
    let mut out = Vec::new();
    let ms = 1_000_000u64;

    // Identify by name; the device's answer (Xid masked) names it with IP 0.0.0.0.
    c.set_online(true, 0, &mut out);
    let ident = frame(&mut out);
    assert_eq!(&ident[..6], &[0x01, 0x0e, 0xcf, 0, 0, 0]);
    let mut answer = capture("cm/ident_ok_pnet");
    answer[18..22].copy_from_slice(&xid(&ident, 14));
    c.on_frame(&answer, 10 * ms, &mut out);
    c.poll(600 * ms, &mut out);
    assert_eq!(c.states().next(), Some(DeviceState::SettingIp));

    // Set IP: the S7's DCP PDU, Xid aside.
    let set = frame(&mut out);
    let mut expected = capture("cm/dcp_set_req");
    let our_xid = xid(&set, 14);
    expected[22..26].copy_from_slice(&our_xid);
    assert_eq!(&set[..12], &expected[..12], "addresses");
    assert_eq!(
        &set[14..14 + 36],
        &expected[18..18 + 36],
        "DCP Set IP request"
    );
    let mut done = capture("cm/dcp_set_res");
    let at = if done[12] == 0x81 { 18 } else { 14 };
    done[at + 4..at + 8].copy_from_slice(&our_xid);
    c.on_frame(&done, 610 * ms, &mut out);

    // Connect.
    let (to, connect) = datagram(&mut out);
    assert_eq!(to, SocketAddrV4::new(DEVICE_IP, rpc::RPC_PORT));
    let ours = Pdu::parse(&connect).unwrap();
    let captured = udp_payload(&capture("cm/connect_req"));
    let theirs = Pdu::parse(&captured).unwrap();
    let ours_req = procimg_profinet::wire::connect::ConnectRequest::parse(ours.blocks).unwrap();
    let theirs_req = procimg_profinet::wire::connect::ConnectRequest::parse(theirs.blocks).unwrap();
    let masks = Masks {
        activity: (theirs.header.activity, ours.header.activity),
        ar: (theirs_req.ar.ar_uuid, ours_req.ar.ar_uuid),
        session_key: (theirs_req.ar.session_key, ours_req.ar.session_key),
    };
    assert_eq!(connect, masks.apply(&captured, true), "Connect request");

    // The device's Connect response, then Write.
    let res_masks = Masks {
        activity: masks.activity,
        ar: masks.ar,
        session_key: masks.session_key,
    };
    let response = res_masks.apply(&udp_payload(&capture("cm/connect_res")), true);
    c.on_datagram(to, &response, 620 * ms, &mut out);
    let start = out
        .iter()
        .position(|a| matches!(a, ControllerAction::Start(_)))
        .expect("the cyclic exchange starts with the Connect response");
    let ControllerAction::Start(ar) = out.remove(start) else {
        unreachable!()
    };
    assert_eq!((ar.input.frame_id, ar.output.frame_id), (0x8000, 0x8001));
    assert_eq!(ar.peer, MacAddress([0x8c, 0xf3, 0x19, 0xcd, 0x19, 0xf8]));
    let (_, write) = datagram(&mut out);
    let captured = udp_payload(&capture("cm/write_req"));
    assert_eq!(write, masks.apply(&captured, false), "Write request");
    let response = res_masks.apply(&udp_payload(&capture("cm/write_res")), false);
    c.on_datagram(to, &response, 630 * ms, &mut out);

    // PrmEnd.
    let (_, prmend) = datagram(&mut out);
    let captured = udp_payload(&capture("cm/prmend_req"));
    assert_eq!(prmend, masks.apply(&captured, true), "PrmEnd request");
    let response = res_masks.apply(&udp_payload(&capture("cm/prmend_res")), true);
    c.on_datagram(to, &response, 640 * ms, &mut out);
    assert_eq!(
        c.states().next(),
        Some(DeviceState::WaitingForApplicationReady)
    );

    // The device's ApplicationReady and our answer.
    let app_ready = udp_payload(&capture("cm/appready_req"));
    let their_activity = Pdu::parse(&app_ready).unwrap().header.activity;
    let request = Masks {
        activity: (their_activity, their_activity),
        ar: masks.ar,
        session_key: masks.session_key,
    }
    .apply(&app_ready, true);
    let device = SocketAddrV4::new(DEVICE_IP, 49153);
    c.on_datagram(device, &request, 650 * ms, &mut out);
    let (back, answer) = datagram(&mut out);
    assert_eq!(back, device);
    let captured = udp_payload(&capture("cm/appready_res"));
    let expected = Masks {
        activity: (their_activity, their_activity),
        ar: masks.ar,
        session_key: masks.session_key,
    }
    .apply(&captured, true);
    assert_eq!(answer, expected, "ApplicationReady response");
    assert_eq!(c.states().next(), Some(DeviceState::Running));
    out.clear();

    alarm_ack_equals_the_capture(&mut c, &mut out);

    cyclic_frames_equal_the_captures(&config, ar);
}

/// p-net's process alarm, the first of the AR: the transport ACK goes out at once, the
/// AlarmAck when the alarm is acknowledged; both equal the S7's frames byte for byte.
fn alarm_ack_equals_the_capture(c: &mut Controller, out: &mut Vec<ControllerAction>) {
    let ms = 1_000_000u64;
    // Our MAC in the S7's alarm frames (see the module comment).
    let s7_alarm = |name: &str| {
        let mut f = capture(name);
        f[6..12].copy_from_slice(&S7_MAC.0);
        f
    };
    c.on_frame(&capture("alarm/alarm_process_notif"), 700 * ms, out);
    let ack_rta = frame(out);
    assert_eq!(
        ack_rta,
        s7_alarm("alarm/alarm_ack_rta_high_cpu"),
        "transport ACK of the alarm"
    );
    let ticket = out
        .iter()
        .find_map(|a| match a {
            ControllerAction::Event(procimg_profinet::controller::DeviceEvent::Alarm {
                notification,
                ticket,
                ..
            }) => {
                assert_eq!((notification.slot, notification.subslot), (1, 1));
                Some(*ticket)
            }
            _ => None,
        })
        .expect("the alarm is delivered");
    out.clear();
    c.poll(800 * ms, out);
    assert!(
        !out.iter().any(|a| matches!(a, ControllerAction::Frame(_))),
        "the AlarmAck went out before the acknowledgement: {out:?}"
    );
    assert!(c.acknowledge_alarm(ticket, 900 * ms, out));
    assert_eq!(
        frame(out),
        s7_alarm("alarm/alarm_ack_high_cpu"),
        "AlarmAck DATA"
    );
    c.on_frame(&capture("alarm/alarm_ack_rta_high_dev"), 910 * ms, out);
    assert!(
        !out.iter().any(|a| matches!(a, ControllerAction::Frame(_))),
        "the device's ACK needs no answer: {out:?}"
    );
    assert_eq!(c.states().next(), Some(DeviceState::Running));
}

/// The output frame the cycle builds equals the S7's (CycleCounter aside); the device's
/// captured frame lands in the image.
fn cyclic_frames_equal_the_captures(
    config: &config::Config,
    ar: Box<procimg_profinet::controller::cyclic::CyclicAr>,
) {
    let tables = Tables::from_config(config).unwrap();
    let mut image = Image::new(&tables);
    for s in 0..tables.submodules.len() {
        image.set_status(
            s,
            SubmoduleStatus {
                input_iops: IOXS_GOOD,
                input_iocs: IOXS_GOOD,
                output_iops: IOXS_GOOD,
                output_iocs: IOXS_GOOD,
            },
        );
    }
    let peer = ar.peer;
    let (ours, mut wire) = sim_link::link(S7_MAC, peer);
    let channel = Arc::new(Channel::new());
    let ranges = std::iter::once(0..tables.submodules.len()).collect();
    let mut io = PnioIo::new(Box::new(ours), channel.clone(), ranges, config.cycle_ns);
    assert!(channel.to_cycle.push(ToCycle::Start(ar)).is_ok());
    let t = |cycle| CycleTime {
        cycle,
        now_ns: cycle * 1_000_000,
    };
    io.receive(t(0), Mode::Operate, &mut image);
    io.send(t(0), Mode::Operate, &mut image);
    let mut buf = Vec::new();
    assert!(
        wire.receive(&mut |f| buf = f.to_vec()).unwrap(),
        "an output frame"
    );
    let expected = capture("rt/rtc_cpu_8001");
    let n = buf.len();
    assert_eq!(n, expected.len());
    // CycleCounter masked: bytes n-4..n-2.
    assert_eq!(&buf[..n - 4], &expected[..n - 4], "cyclic output frame");
    assert_eq!(&buf[n - 2..n], &expected[n - 2..n]);

    wire.send(&capture("rt/rtc_dev_8000")).unwrap();
    io.receive(t(1), Mode::Operate, &mut image);
    let di8 = 3; // slot 1
    let dio8 = 5; // slot 3
    assert_eq!(image.inputs(di8), &[0x2c]);
    assert_eq!(image.inputs(dio8), &[0x2d]);
    assert_eq!(image.status(di8).input_iops, IOXS_GOOD);
    assert_eq!(image.status(dio8).output_iocs, IOXS_GOOD);
}
