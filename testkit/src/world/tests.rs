// SPDX-License-Identifier: MIT OR Apache-2.0
//! The world on its own port: devices come up, a run replays byte for byte from its seed,
//! lost frames fail a device that comes back once the network heals.

use super::tap::{Message, Origin, Record, pcap};
use super::*;
use procimg_profinet::controller::FailureCause;
use procimg_profinet::controller::cyclic::CyclicAr;
use procimg_profinet::controller::plan::{DeviceSpec, SubmoduleSpec};
use procimg_profinet::device::DeviceSetup;
use procimg_profinet::wire::PnioStatus;

/// Inputs that count the frames produced.
struct Counter;

impl Application for Counter {
    fn fill_inputs(&mut self, k: u64, inputs: &mut [u8], _: &[u8], _: &[u8], _: bool) {
        let n = inputs.len().min(8);
        inputs[..n].copy_from_slice(&k.to_be_bytes()[..n]);
    }
}

const CONTROLLER_IP: Ipv4Addr = Ipv4Addr::new(192, 168, 0, 1);

/// Two devices: the first is given its address by DCP and a record, the second has one.
fn world(seed: u64) -> World<Counter> {
    let submodule = |slot: u16, len: u16, records| SubmoduleSpec {
        api: 0,
        slot,
        subslot: 1,
        module_ident: 0x10 + u32::from(slot),
        submodule_ident: 1,
        input_length: len,
        output_length: len,
        records,
    };
    let specs: Vec<DeviceSpec> = (0..2u8)
        .map(|d| DeviceSpec {
            name: format!("dev-{d}"),
            ip: (d == 0).then_some(Ipv4Addr::new(192, 168, 0, 11)),
            vendor_id: 0x0493,
            device_id: 1,
            instance: 1,
            reduction_ratio: 1,
            watchdog_factor: 3,
            submodules: vec![
                submodule(0, 0, vec![]),
                submodule(1, 4, vec![(0x100, vec![1, 2, 3])]),
            ],
            ..Default::default()
        })
        .collect();
    let devices = specs
        .iter()
        .enumerate()
        .map(|(d, s)| {
            Device::new(DeviceSetup {
                name: s.name.clone(),
                mac: MacAddress([2, 0, 0, 0, 1, d as u8]),
                ip: s.ip.is_none().then_some([192, 168, 0, 20 + d as u8]),
                vendor_id: s.vendor_id,
                device_id: s.device_id,
                instance: s.instance,
                submodules: s.submodules.iter().map(SubmoduleSpec::plugged).collect(),
                application: Counter,
                im0: Default::default(),
            })
        })
        .collect();
    let plans = DevicePlan::all(&specs, MS).expect("plans");
    let id = controller_identity(MacAddress([2, 0, 0, 0, 0, 1]), CONTROLLER_IP, "plc");
    World::direct(
        Setup {
            seed,
            ..Setup::new(id, plans)
        },
        devices,
    )
}

/// Brings `w` up, recording everything.
fn bring_up(w: &mut World<Counter>) -> Vec<Record> {
    w.tap(|_| true);
    w.set_online(true);
    let cycles = w.step_until_running(2_000);
    assert!(cycles.is_some(), "no bring-up: {:?}", w.states());
    w.run(20);
    w.take_tapped()
}

#[test]
fn the_devices_come_up_and_exchange_data() {
    let mut w = world(1);
    let records = bring_up(&mut w);
    let exchanges: Vec<usize> = w.port().exchanges().map(|ar| ar.device).collect();
    assert_eq!(exchanges, [0, 1]);
    // As the controller handed them over: the port sends from frames of its own.
    for ar in w.port().exchanges() {
        let plan = w.controller().plan(ar.device).unwrap();
        let ids = (ar.input.frame_id, ar.output.frame_id);
        let own = w.controller().identity().mac;
        assert_eq!(*ar, CyclicAr::new(plan, ar.epoch, own, ar.peer, ids));
    }
    assert!(w.devices().iter().all(|d| d.ar().ar_uuid().is_some()));
    assert!(
        w.events()
            .iter()
            .any(|e| matches!(e, DeviceEvent::Return { device: 1 }))
    );
    // Both directions, both kinds, and the controller's datagrams from port 34964.
    let from = |o: Origin| records.iter().filter(move |r| r.origin == o);
    assert!(from(Origin::Controller).any(|r| matches!(r.message, Message::Frame(_))));
    assert!(from(Origin::Device(1)).any(|r| matches!(r.message, Message::Frame(_))));
    assert!(from(Origin::Controller).any(|r| matches!(
        r.message,
        Message::Datagram { from, .. } if from == SocketAddrV4::new(CONTROLLER_IP, RPC_PORT)
    )));
    assert!(from(Origin::Device(0)).any(|r| matches!(r.message, Message::Datagram { .. })));
    let c = w.counters();
    assert!(c.controller_frames > 0 && c.device_frames > 0);
    assert!(c.controller_datagrams > 0 && c.device_datagrams > 0);
}

#[test]
fn a_seed_replays_byte_for_byte() {
    let run = |seed| pcap(&bring_up(&mut world(seed)), 1_700_000_000 * 1_000_000_000);
    let first = run(7);
    assert_eq!(first, run(7), "the same seed, another exchange");
    // Another seed draws other ARUUIDs.
    assert_ne!(first, run(8));
}

#[test]
fn lost_input_frames_fail_a_device_until_the_network_heals() {
    let mut w = world(1);
    bring_up(&mut w);
    w.intercept(Some(Box::new(|m: Intercepted| {
        if m.device == 1 && m.kind == Kind::Cyclic {
            Vec::new()
        } else {
            vec![m.bytes]
        }
    })));
    let failed = w.step_until(100, |w| w.states()[1] != DeviceState::Running);
    assert!(failed.is_some(), "the watchdog did not fire");
    assert_eq!(w.states()[0], DeviceState::Running);
    assert!(w.events().iter().any(|e| matches!(
        e,
        DeviceEvent::Failure {
            device: 1,
            planned: false,
            ..
        }
    )));
    // The controller aborted the AR: its ERR-RTA's status, "consumer DHT expired".
    assert_eq!(
        failure_status(&w, 1),
        Some(Some(PnioStatus::from_bytes([0xcf, 0x81, 0xfd, 0x05])))
    );
    w.intercept(None);
    let back = w.step_until_running(5_000);
    assert!(back.is_some(), "no return: {:?}", w.states());
}

/// The PNIO status of device `d`'s last failure (`None`: it did not fail).
fn failure_status(w: &World<Counter>, d: usize) -> Option<Option<PnioStatus>> {
    w.events().iter().rev().find_map(|e| match e {
        DeviceEvent::Failure { device, status, .. }
        | DeviceEvent::Problem { device, status, .. }
            if *device == d =>
        {
            Some(*status)
        }
        _ => None,
    })
}

#[test]
fn a_device_that_aborts_its_ar_is_failed_with_its_abort_status() {
    let mut w = world(1);
    bring_up(&mut w);
    // The device's clock jumps past its watchdog: it aborts the AR with an ERR-RTA.
    w.with_device(1, |dev, now, out| dev.poll(now + 10_000_000_000, out));
    let failed = w.step_until(100, |w| w.states()[1] != DeviceState::Running);
    assert!(failed.is_some(), "the device's abort did not end the AR");
    let code = w.devices()[1]
        .ar()
        .last_abort()
        .expect("the device aborted");
    assert!(w.events().iter().any(|e| matches!(
        e,
        DeviceEvent::Failure {
            device: 1,
            cause: FailureCause::DeviceAborted,
            ..
        }
    )));
    assert_eq!(
        failure_status(&w, 1),
        Some(Some(PnioStatus::from_bytes([
            0xcf,
            0x81,
            0xfd,
            code.into()
        ])))
    );
}

#[test]
fn a_refused_connect_is_reported_with_the_devices_status() {
    let mut w = world(1);
    // The first datagram of device 1 is its Connect response: its PNIOStatus (the first 4
    // bytes after the 80-byte RPC header, a u32 in the little-endian NDR of the simulated
    // device) becomes a refusal, DB 81 3F 04.
    let mut first = true;
    w.intercept(Some(Box::new(move |mut m: Intercepted| {
        if m.device == 1 && m.kind == Kind::Datagram && first && m.bytes.len() > 84 {
            first = false;
            m.bytes[80..84].copy_from_slice(&0xdb81_3f04u32.to_le_bytes());
        }
        vec![m.bytes]
    })));
    w.set_online(true);
    let refused = w.step_until(2_000, |w| failure_status(w, 1).is_some());
    assert!(refused.is_some(), "no failure: {:?}", w.states());
    assert!(w.events().iter().any(|e| matches!(
        e,
        DeviceEvent::Problem {
            device: 1,
            cause: FailureCause::Refused,
            ..
        }
    )));
    assert_eq!(
        failure_status(&w, 1),
        Some(Some(PnioStatus::from_bytes([0xdb, 0x81, 0x3f, 0x04])))
    );
}

#[test]
fn an_injected_frame_reaches_the_controller_port_and_the_tap() {
    let mut w = world(1);
    w.tap(|r| r.origin == Origin::Injected);
    w.inject_frame(&[0xff; 60]);
    assert_eq!(w.tapped().len(), 1);
    assert_eq!(w.counters().device_frames, 1);
    // Not a PROFINET frame: the port drops it, and nothing breaks.
    w.step();
    assert_eq!(w.cycle(), 2);
    w.run_until(10 * MS);
    assert_eq!((w.now(), w.cycle()), (10 * MS, 10));
    assert!(w.events().is_empty(), "offline, the controller did nothing");
}
