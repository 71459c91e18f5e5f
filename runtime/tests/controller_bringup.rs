// SPDX-License-Identifier: MIT OR Apache-2.0
//! The controller and the cycle thread's PROFINET IO system against the simulated devices of
//! the demo, in simulated time, in one process: every device comes up through DCP, Connect,
//! PrmEnd and ApplicationReady; outputs written into the image come back from the echo
//! device; an alarm is delivered and its AlarmAck waits for the acknowledgement; a record
//! read of I&M0 returns the device's identity and a 3000-byte record crosses in RPC
//! fragments both ways; hostile datagrams are counted and dropped without harm; a device
//! whose frames stop is failed by the
//! watchdog (inputs BAD) and comes back without help; OFFLINE releases every AR. Every frame
//! and datagram that crossed the simulated network, in both directions, must dissect clean in
//! Wireshark.

use procimg_nic::{Nic, sim_link};
use procimg_profinet::controller::plan::ControllerIdentity;
use procimg_profinet::controller::{Action, Controller, DeviceEvent, DeviceState, RecordRequest};
use procimg_profinet::device_sim::DeviceAction;
use procimg_profinet::wire::MacAddress;
use procimg_profinet::wire::alarm::AlarmType;
use procimg_profinet::wire::record::Im0;
use procimg_profinet::wire::rpc::{self, RPC_PORT};
use procimg_runtime::config::Config;
use procimg_runtime::image::{Image, Tables};
use procimg_runtime::io::pnio::PnioIo;
use procimg_runtime::io::pnio::channel::{Channel, FromCycle, ToCycle};
use procimg_runtime::io::{CycleTime, IoSystem};
use procimg_runtime::roles::controller::sim_plant::DemoDevice;
use procimg_runtime::roles::controller::{SIM_CONTROLLER_IP, SIM_CONTROLLER_MAC};
use procimg_shm_layout::{IOXS_BAD, IOXS_GOOD, Mode};
use std::net::SocketAddrV4;
use std::sync::Arc;

const MS: u64 = 1_000_000;
/// Cyclic frames kept for tshark per direction (the rest only counted).
const CYCLIC_KEPT: usize = 40;

struct World {
    controller: Controller,
    devices: Vec<DemoDevice>,
    io: PnioIo,
    channel: Arc<Channel>,
    plant: sim_link::LinkEnd,
    image: Image,
    /// Everything that crossed the network, for tshark.
    wire: Vec<Vec<u8>>,
    cyclic_kept: [usize; 2],
    events: Vec<DeviceEvent>,
    /// Device whose frames the network loses.
    cut: Option<usize>,
}

fn is_cyclic(frame: &[u8]) -> bool {
    let at = if frame.get(12..14) == Some(&[0x81, 0x00]) {
        16
    } else {
        12
    };
    let id = frame
        .get(at + 2..at + 4)
        .map_or(0, |b| u16::from_be_bytes([b[0], b[1]]));
    (0x8000..0xc000).contains(&id)
}

impl World {
    fn record_frame(&mut self, f: &[u8], from_controller: bool) {
        if is_cyclic(f) {
            let n = &mut self.cyclic_kept[from_controller as usize];
            if *n >= CYCLIC_KEPT {
                return;
            }
            *n += 1;
        }
        self.wire.push(f.to_vec());
    }

    fn controller_actions(&mut self, out: Vec<Action>, now: u64) {
        let mut pending = out;
        while !pending.is_empty() {
            let mut next = Vec::new();
            for a in pending {
                match a {
                    Action::Frame(f) => {
                        self.record_frame(&f, true);
                        assert!(self.channel.send(&f));
                    }
                    Action::Datagram { to, payload } => {
                        let ctl = SIM_CONTROLLER_IP.octets();
                        self.wire.push(procimg_testkit::udp::udp_frame(
                            ctl,
                            to.ip().octets(),
                            RPC_PORT,
                            to.port(),
                            &payload,
                        ));
                        let from = SocketAddrV4::new(SIM_CONTROLLER_IP, RPC_PORT);
                        let mut dout = Vec::new();
                        if let Some(d) = self
                            .devices
                            .iter_mut()
                            .position(|d| d.ip() == to.ip().octets())
                        {
                            self.devices[d].on_datagram(from, to.port(), &payload, now, &mut dout);
                            next.extend(self.device_actions(d, dout, now));
                        }
                    }
                    Action::Start(ar) => {
                        assert!(self.channel.to_cycle.push(ToCycle::Start(ar)).is_ok())
                    }
                    Action::Stop { device } => {
                        assert!(self.channel.to_cycle.push(ToCycle::Stop { device }).is_ok())
                    }
                    Action::Event(e) => self.events.push(e),
                }
            }
            pending = next;
        }
    }

    /// Carries out a device's actions; returns what the controller answered to datagrams.
    fn device_actions(&mut self, d: usize, out: Vec<DeviceAction>, now: u64) -> Vec<Action> {
        let mut answers = Vec::new();
        for a in out {
            match a {
                DeviceAction::Frame(f) => {
                    if self.cut == Some(d) && is_cyclic(&f) {
                        continue;
                    }
                    self.record_frame(&f, false);
                    self.plant.send(&f).unwrap();
                }
                DeviceAction::Datagram {
                    to,
                    from_port,
                    payload,
                } => {
                    let ip = self.devices[d].ip();
                    self.wire.push(procimg_testkit::udp::udp_frame(
                        ip,
                        to.ip().octets(),
                        from_port,
                        to.port(),
                        &payload,
                    ));
                    let from = SocketAddrV4::new(ip.into(), from_port);
                    self.controller
                        .on_datagram(from, &payload, now, &mut answers);
                }
            }
        }
        answers
    }

    /// One millisecond: the plant, the controller, the cycle.
    fn step(&mut self, k: u64) {
        let now = k * MS;
        let t = CycleTime {
            cycle: k,
            now_ns: now,
        };
        // The plant takes what the controller sent and does its work.
        let mut f = Vec::new();
        while self.plant.receive(&mut |frame| f = frame.to_vec()).unwrap() {
            self.record_frame(&f, true);
            for d in 0..self.devices.len() {
                let mut out = Vec::new();
                self.devices[d].on_frame(&f, now, &mut out);
                let answers = self.device_actions(d, out, now);
                self.controller_actions(answers, now);
            }
        }
        for d in 0..self.devices.len() {
            let mut out = Vec::new();
            self.devices[d].poll(now, &mut out);
            let answers = self.device_actions(d, out, now);
            self.controller_actions(answers, now);
        }
        // The cycle: inputs in, reports to the controller, outputs out.
        self.io.receive(t, Mode::Operate, &mut self.image);
        let mut out = Vec::new();
        while let Some(r) = self.channel.from_cycle.pop() {
            match r {
                FromCycle::Received(f) => {
                    self.controller.on_frame(f.bytes(), now, &mut out);
                    self.channel.recycle(f);
                }
                FromCycle::WatchdogExpired { device, epoch } => {
                    self.controller.on_watchdog(device, epoch, now, &mut out)
                }
                FromCycle::DataStarted { device, epoch } => {
                    self.controller.on_data_started(device, epoch)
                }
                FromCycle::Retired(_) => {}
            }
        }
        self.controller.poll(now, &mut out);
        self.controller_actions(out, now);
        self.io.send(t, Mode::Operate, &self.image);
    }

    fn states(&self) -> Vec<DeviceState> {
        self.controller.states().collect()
    }
}

#[test]
fn the_demo_devices_come_up_exchange_data_fail_and_return() {
    let config = Config::demo();
    let tables = Tables::from_config(&config).unwrap();
    let plans = procimg_runtime::roles::controller::plan_devices(&config).unwrap();
    let ranges = plans
        .iter()
        .map(|p| p.first_submodule..p.first_submodule + p.submodules.len())
        .collect();
    let id = ControllerIdentity {
        mac: SIM_CONTROLLER_MAC,
        ip: SIM_CONTROLLER_IP,
        station_name: "procimgd-test".into(),
        vendor_id: 0x0493,
        device_id: 0x0fff,
        instance: 1,
    };
    let (nic, plant) = sim_link::link(SIM_CONTROLLER_MAC, MacAddress::default());
    let channel = Arc::new(Channel::new());
    let mut w = World {
        controller: Controller::new(id, plans, 1, 1),
        devices: procimg_runtime::roles::controller::sim_plant::devices(&config),
        io: PnioIo::new(Box::new(nic), channel.clone(), ranges, config.cycle_ns),
        channel,
        plant,
        image: Image::new(&tables),
        wire: Vec::new(),
        cyclic_kept: [0; 2],
        events: Vec::new(),
        cut: None,
    };
    let echo = tables
        .submodules
        .iter()
        .position(|s| s.output_length == 16)
        .unwrap();
    let counter = tables
        .submodules
        .iter()
        .position(|s| s.input_length == 4)
        .unwrap();
    let counter_device = tables.submodules[counter].device as usize;

    let mut out = Vec::new();
    w.controller.set_online(true, MS, &mut out);
    w.controller_actions(out, MS);
    let mut k = 1;
    while w.states().iter().any(|s| *s != DeviceState::Running) {
        k += 1;
        w.step(k);
        assert!(k < 2000, "devices not up after 2 s: {:?}", w.states());
    }
    // Every device's start of data exchange is a station return, as IO-Base reports it.
    for d in 0..w.states().len() {
        assert!(
            w.events
                .iter()
                .any(|e| matches!(e, DeviceEvent::Return { device } if *device == d)),
            "no DEV_RETURN for device {d}"
        );
    }

    // Outputs go out GOOD and come back from the echo device.
    let pattern: Vec<u8> = (1..=16).collect();
    w.image.outputs_mut(echo).copy_from_slice(&pattern);
    let mut st = w.image.status(echo);
    st.output_iops = IOXS_GOOD;
    w.image.set_status(echo, st);
    let until = k + 50;
    while w.image.inputs(echo) != &pattern[..] {
        k += 1;
        w.step(k);
        assert!(
            k < until,
            "the echo never came back: {:?}",
            w.image.inputs(echo)
        );
    }
    assert_eq!(w.image.status(echo).input_iops, IOXS_GOOD);
    let c0 = u32::from_be_bytes(w.image.inputs(counter).try_into().unwrap());
    for _ in 0..20 {
        k += 1;
        w.step(k);
    }
    let c1 = u32::from_be_bytes(w.image.inputs(counter).try_into().unwrap());
    assert!(c1 > c0, "the counter did not count: {c0} then {c1}");

    // A process alarm of the echo device is delivered, and its AlarmAck waits for the
    // acknowledgement (IO-Base: until the alarm callback returned).
    let echo_device = tables.submodules[echo].device as usize;
    let mut dev_out = Vec::new();
    assert!(w.devices[echo_device].raise_process_alarm(
        0,
        1,
        1,
        0x0042,
        &[0xde, 0xad],
        k * MS,
        &mut dev_out
    ));
    let answers = w.device_actions(echo_device, dev_out, k * MS);
    w.controller_actions(answers, k * MS);
    let until = k + 100;
    let ticket = loop {
        let alarm = w.events.iter().find_map(|e| match e {
            DeviceEvent::Alarm {
                device,
                notification,
                ticket,
            } if *device == echo_device => Some((notification.clone(), *ticket)),
            _ => None,
        });
        if let Some((n, t)) = alarm {
            assert_eq!((n.slot, n.subslot), (1, 1));
            assert_eq!(n.alarm_type, AlarmType::Process);
            break t;
        }
        k += 1;
        w.step(k);
        assert!(k < until, "the alarm did not arrive");
    };
    for _ in 0..300 {
        k += 1;
        w.step(k);
    }
    assert!(
        w.devices[echo_device].alarm_acks().is_empty(),
        "AlarmAck sent before the acknowledgement"
    );
    let mut out = Vec::new();
    assert!(w.controller.acknowledge_alarm(ticket, k * MS, &mut out));
    w.controller_actions(out, k * MS);
    let until = k + 100;
    while w.devices[echo_device].alarm_acks().is_empty() {
        k += 1;
        w.step(k);
        assert!(k < until, "no AlarmAck reached the device");
    }
    let mut out = Vec::new();
    assert!(
        !w.controller.acknowledge_alarm(ticket, k * MS, &mut out),
        "an alarm was acknowledged twice"
    );

    // A record read of I&M0 returns the device's identity, with the reference echoed.
    let mut out = Vec::new();
    w.controller.record(
        RecordRequest {
            reference: 77,
            device: echo_device,
            api: 0,
            slot: 0,
            subslot: 1,
            index: 0xAFF0,
            max_len: 4096,
            write: None,
        },
        &mut out,
    );
    w.controller_actions(out, k * MS);
    let until = k + 100;
    let result = loop {
        if let Some(r) = w.events.iter().find_map(|e| match e {
            DeviceEvent::Record(r) if r.request.reference == 77 => Some(r.clone()),
            _ => None,
        }) {
            break r;
        }
        k += 1;
        w.step(k);
        assert!(k < until, "the record read did not finish");
    };
    let data = result.result.expect("the I&M0 read failed").data;
    let im0 = Im0::parse(&data).expect("the I&M0 record does not parse");
    assert_eq!(im0.vendor_id, 0x0493);

    // A record longer than one PDU: the write goes out in fragments, the read comes back in
    // fragments, and the bytes survive both ways.
    let long: Vec<u8> = (0..3000u32).map(|i| (i * 7) as u8).collect();
    let mut job = |reference: u64, write: Option<Vec<u8>>, k: &mut u64| {
        let mut out = Vec::new();
        w.controller.record(
            RecordRequest {
                reference,
                device: echo_device,
                api: 0,
                slot: 1,
                subslot: 1,
                index: 0x0042,
                max_len: 4096,
                write,
            },
            &mut out,
        );
        w.controller_actions(out, *k * MS);
        let until = *k + 100;
        loop {
            if let Some(r) = w.events.iter().find_map(|e| match e {
                DeviceEvent::Record(r) if r.request.reference == reference => Some(r.clone()),
                _ => None,
            }) {
                break r;
            }
            *k += 1;
            w.step(*k);
            assert!(*k < until, "record job {reference} did not finish");
        }
    };
    job(78, Some(long.clone()), &mut k)
        .result
        .expect("the long write failed");
    let back = job(79, None, &mut k).result.expect("the long read failed");
    assert_eq!(back.data, long);

    // Hostile datagrams on port 34964: truncated, garbage NDR, a control block with a bad
    // BlockLength, an answer nobody waits for. Counted and dropped; nothing breaks.
    let from = SocketAddrV4::new(w.devices[echo_device].ip().into(), RPC_PORT);
    let control = |activity: u8, blocks: &[u8], ndr_ok: bool| {
        let h = rpc::Header::request(
            rpc::object_uuid(1, 1, 0x0493),
            rpc::CONTROLLER_INTERFACE,
            procimg_profinet::wire::Uuid([activity; 16]),
            1,
            rpc::opnum::CONTROL,
        );
        if ndr_ok {
            rpc::emit_request(&h, 256, blocks).unwrap()
        } else {
            rpc::emit_with_body(&h, blocks).unwrap()
        }
    };
    let response = {
        let h = rpc::Header::request(
            rpc::object_uuid(1, 1, 0x0493),
            rpc::DEVICE_INTERFACE,
            procimg_profinet::wire::Uuid([9; 16]),
            77,
            rpc::opnum::READ,
        );
        rpc::emit_response(&h.reply(0), Default::default(), 64, &[1, 2, 3]).unwrap()
    };
    let hostile = [
        control(1, &[], false)[..10].to_vec(),
        control(2, &[0xff; 5], false),
        control(3, &[0x01, 0x12, 0xff, 0xff, 0x01, 0x00], true),
        response,
    ];
    let before = w.controller.dropped_datagrams();
    let events_before = w.events.len();
    for d in &hostile {
        let mut out = Vec::new();
        w.controller.on_datagram(from, d, k * MS, &mut out);
        assert!(out.is_empty(), "a hostile datagram was answered: {out:?}");
    }
    let after = w.controller.dropped_datagrams();
    assert_eq!(after.malformed - before.malformed, 3);
    assert_eq!(after.unexpected - before.unexpected, 1);
    for _ in 0..50 {
        k += 1;
        w.step(k);
    }
    assert!(w.states().iter().all(|s| *s == DeviceState::Running));
    assert!(
        !w.events[events_before..]
            .iter()
            .any(|e| matches!(e, DeviceEvent::Failure { .. } | DeviceEvent::Problem { .. })),
        "a hostile datagram broke a connection"
    );

    // The counter device's frames are lost: the watchdog (100 cycles in the demo) fails it,
    // its inputs go BAD; the others run on.
    w.cut = Some(counter_device);
    let before_cut = w.events.len();
    for _ in 0..150 {
        k += 1;
        w.step(k);
    }
    assert!(
        w.events
            .iter()
            .any(|e| matches!(e, DeviceEvent::Failure { device, .. } if *device == counter_device))
    );
    assert_eq!(w.image.status(counter).input_iops, IOXS_BAD);
    assert_eq!(w.states()[counter_device], DeviceState::Failed);
    // The network heals: the device comes back by itself.
    w.cut = None;
    let until = k + 5000;
    while !w.events[before_cut..]
        .iter()
        .any(|e| matches!(e, DeviceEvent::Return { device } if *device == counter_device))
    {
        k += 1;
        w.step(k);
        assert!(k < until, "the device did not return: {:?}", w.states());
    }
    for _ in 0..20 {
        k += 1;
        w.step(k);
    }
    assert_eq!(w.image.status(counter).input_iops, IOXS_GOOD);
    assert!(w.states().iter().all(|s| *s == DeviceState::Running));
    // Only the cut device failed.
    assert!(
        !w.events
            .iter()
            .any(|e| matches!(e, DeviceEvent::Failure { device, .. } if *device != counter_device))
    );

    // OFFLINE: every AR released, the devices back to idle.
    let offline_at = w.events.len();
    let mut out = Vec::new();
    w.controller.set_online(false, k * MS, &mut out);
    w.controller_actions(out, k * MS);
    for _ in 0..20 {
        k += 1;
        w.step(k);
    }
    assert!(w.states().iter().all(|s| *s == DeviceState::Offline));
    assert!(w.devices.iter().all(|d| d.ar_uuid().is_none()));
    // Leaving data exchange on OFFLINE is a station failure for every device.
    for d in 0..w.states().len() {
        assert!(
            w.events[offline_at..]
                .iter()
                .any(|e| matches!(e, DeviceEvent::Failure { device, .. } if *device == d)),
            "no DEV_FAILURE for device {d} on OFFLINE"
        );
    }

    let dissected = procimg_testkit::tshark::dissect_clean("controller-bringup", &w.wire);
    for call in [
        "Connect request",
        "Read request",
        "Alarm Ack",
        "Prm End",
        "Application Ready",
        "Release request",
    ] {
        assert!(
            dissected.iter().any(|d| d.info.contains(call)),
            "no {call:?} among the dissected frames"
        );
    }
    for proto in ["PN-DCP", "PNIO-CM", "PNIO"] {
        assert!(
            dissected.iter().any(|d| d.protocol == proto),
            "no {proto} frame among {} dissected",
            dissected.len()
        );
    }
}
