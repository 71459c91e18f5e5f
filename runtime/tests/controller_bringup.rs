// SPDX-License-Identifier: MIT OR Apache-2.0
//! The controller and the cycle thread's PROFINET IO system against the simulated devices of
//! the demo, in simulated time, in one process (the test kit's world, with the cycle thread
//! as the controller's port): every device comes up through DCP, Connect,
//! PrmEnd and ApplicationReady; outputs written into the image come back from the echo
//! device; an alarm is delivered and its AlarmAck waits for the acknowledgement; a record
//! read of I&M0 returns the device's identity and a 3000-byte record crosses in RPC
//! fragments both ways; hostile datagrams are counted and dropped without harm; a device
//! whose frames stop is failed by the
//! watchdog (inputs BAD) and comes back without help; OFFLINE releases every AR. Every frame
//! and datagram that crossed the simulated network, in both directions, must dissect clean in
//! Wireshark.

use procimg_nic::{Nic, sim_link};
use procimg_profinet::controller::cyclic::CyclicAr;
use procimg_profinet::controller::{DeviceEvent, DeviceState, RecordRequest, RecordResult};
use procimg_profinet::wire::MacAddress;
use procimg_profinet::wire::alarm::AlarmType;
use procimg_profinet::wire::record::Im0;
use procimg_profinet::wire::rpc::{self, RPC_PORT};
use procimg_runtime::config::Config;
use procimg_runtime::image::{Image, Tables};
use procimg_runtime::io::pnio::PnioIo;
use procimg_runtime::io::pnio::channel::{Channel, FromCycle, ToCycle};
use procimg_runtime::io::{CycleTime, IoSystem};
use procimg_runtime::roles::controller::sim_behaviour::DemoApplication;
use procimg_runtime::roles::controller::{SIM_CONTROLLER_IP, SIM_CONTROLLER_MAC};
use procimg_shm_layout::{IOXS_BAD, IOXS_GOOD, Mode};
use procimg_testkit::world::tap::{Message, Origin, Record};
use procimg_testkit::world::{self as net, Kind, Port, Report, Setup, Tick};
use std::net::SocketAddrV4;
use std::sync::Arc;

/// Cyclic frames kept for tshark per direction (the rest only counted).
const CYCLIC_KEPT: usize = 40;

/// The cycle thread as the controller's port: the PROFINET IO system over an in-process
/// link whose other end is the simulated segment, and its image. Nothing may be lost.
struct Cycle {
    io: PnioIo,
    channel: Arc<Channel>,
    plant: sim_link::LinkEnd,
    image: Image,
}

type World = net::World<DemoApplication, Cycle>;

fn cycle_time(tick: Tick) -> CycleTime {
    CycleTime {
        cycle: tick.cycle,
        now_ns: tick.now_ns,
    }
}

impl Port for Cycle {
    fn transmit(&mut self, frame: Vec<u8>) {
        assert!(self.channel.send(&frame));
    }

    fn start(&mut self, ar: Box<CyclicAr>) {
        assert!(self.channel.to_cycle.push(ToCycle::Start(ar)).is_ok());
    }

    fn stop(&mut self, device: usize) {
        assert!(self.channel.to_cycle.push(ToCycle::Stop { device }).is_ok());
    }

    fn arrive(&mut self, frame: &[u8]) {
        self.plant.send(frame).unwrap();
    }

    fn depart(&mut self, out: &mut Vec<Vec<u8>>) {
        while self
            .plant
            .receive(&mut |frame| out.push(frame.to_vec()))
            .unwrap()
        {}
    }

    fn receive(&mut self, tick: Tick, reports: &mut Vec<Report>) {
        self.io
            .receive(cycle_time(tick), Mode::Operate, &mut self.image);
        while let Some(r) = self.channel.from_cycle.pop() {
            match r {
                FromCycle::Received(f) => {
                    reports.push(Report::Frame(f.bytes().to_vec()));
                    self.channel.recycle(f);
                }
                FromCycle::WatchdogExpired { device, epoch } => {
                    reports.push(Report::Watchdog { device, epoch })
                }
                FromCycle::DataStarted { device, epoch } => {
                    reports.push(Report::DataStarted { device, epoch })
                }
                FromCycle::Retired(_) => {}
            }
        }
    }

    fn send(&mut self, tick: Tick) {
        self.io
            .send(cycle_time(tick), Mode::Operate, &mut self.image);
    }
}

/// What tshark gets: every acyclic frame and datagram, and the first cyclic frames of each
/// direction.
fn for_tshark() -> impl FnMut(&Record) -> bool {
    let mut cyclic_kept = [0usize; 2];
    move |r| match &r.message {
        Message::Frame(f) if net::Kind::of_frame(f) == Kind::Cyclic => {
            let n = &mut cyclic_kept[usize::from(r.origin == Origin::Controller)];
            *n += 1;
            *n <= CYCLIC_KEPT
        }
        _ => true,
    }
}

/// The result of record job `reference`, once it finished.
fn record_result(w: &World, reference: u64) -> Option<RecordResult> {
    w.events().iter().find_map(|e| match e {
        DeviceEvent::Record(r) if r.request.reference == reference => Some(r.clone()),
        _ => None,
    })
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
    let id = net::controller_identity(SIM_CONTROLLER_MAC, SIM_CONTROLLER_IP, "procimgd-test");
    let (nic, plant) = sim_link::link(SIM_CONTROLLER_MAC, MacAddress::default());
    let channel = Arc::new(Channel::new());
    let cycle = Cycle {
        io: PnioIo::new(Box::new(nic), channel.clone(), ranges, config.cycle_ns),
        channel,
        plant,
        image: Image::new(&tables),
    };
    let devices = procimg_runtime::roles::controller::sim_plant::devices(&config);
    let mut w = World::new(Setup::new(id, plans), devices, cycle);
    w.tap(for_tshark());
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

    w.set_online(true);
    let up = w.step_until_running(2000);
    assert!(up.is_some(), "devices not up after 2 s: {:?}", w.states());
    // Every device's start of data exchange is a station return, as IO-Base reports it.
    for d in 0..w.states().len() {
        assert!(
            w.events()
                .iter()
                .any(|e| matches!(e, DeviceEvent::Return { device } if *device == d)),
            "no DEV_RETURN for device {d}"
        );
    }

    // Outputs go out GOOD and come back from the echo device.
    let pattern: Vec<u8> = (1..=16).collect();
    let image = &mut w.port_mut().image;
    image.outputs_mut(echo).copy_from_slice(&pattern);
    let mut st = image.status(echo);
    st.output_iops = IOXS_GOOD;
    image.set_status(echo, st);
    let echoed = w.step_until(50, |w| w.port().image.inputs(echo) == &pattern[..]);
    assert!(
        echoed.is_some(),
        "the echo never came back: {:?}",
        w.port().image.inputs(echo)
    );
    assert_eq!(w.port().image.status(echo).input_iops, IOXS_GOOD);
    let count = |w: &World| u32::from_be_bytes(w.port().image.inputs(counter).try_into().unwrap());
    let c0 = count(&w);
    w.run(20);
    let c1 = count(&w);
    assert!(c1 > c0, "the counter did not count: {c0} then {c1}");

    // A process alarm of the echo device is delivered, and its AlarmAck waits for the
    // acknowledgement (IO-Base: until the alarm callback returned).
    let echo_device = tables.submodules[echo].device as usize;
    assert!(w.with_device(echo_device, |d, now, out| {
        d.raise_process_alarm(0, 1, 1, 0x0042, &[0xde, 0xad], now, out)
    }));
    let alarm = |w: &World| {
        w.events().iter().find_map(|e| match e {
            DeviceEvent::Alarm {
                device,
                notification,
                ticket,
            } if *device == echo_device => Some((notification.clone(), *ticket)),
            _ => None,
        })
    };
    assert!(
        w.step_until(100, |w| alarm(w).is_some()).is_some(),
        "the alarm did not arrive"
    );
    let (n, ticket) = alarm(&w).unwrap();
    assert_eq!((n.slot, n.subslot), (1, 1));
    assert_eq!(n.alarm_type, AlarmType::Process);
    w.run(300);
    assert!(
        w.devices()[echo_device].alarm_acks().list().is_empty(),
        "AlarmAck sent before the acknowledgement"
    );
    assert!(w.with_controller(|c, now, out| c.acknowledge_alarm(ticket, now, out)));
    let acked = w.step_until(100, |w| {
        !w.devices()[echo_device].alarm_acks().list().is_empty()
    });
    assert!(acked.is_some(), "no AlarmAck reached the device");
    assert!(
        !w.with_controller(|c, now, out| c.acknowledge_alarm(ticket, now, out)),
        "an alarm was acknowledged twice"
    );

    // A record read of I&M0 returns the device's identity, with the reference echoed.
    w.with_controller(|c, _, out| {
        c.record(
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
            out,
        )
    });
    let done = w.step_until(100, |w| record_result(w, 77).is_some());
    assert!(done.is_some(), "the record read did not finish");
    let result = record_result(&w, 77).unwrap();
    let data = result.result.expect("the I&M0 read failed").data;
    let im0 = Im0::parse(&data).expect("the I&M0 record does not parse");
    assert_eq!(im0.vendor_id, 0x0493);

    // A record longer than one PDU: the write goes out in fragments, the read comes back in
    // fragments, and the bytes survive both ways.
    let long: Vec<u8> = (0..3000u32).map(|i| (i * 7) as u8).collect();
    let job = |w: &mut World, reference: u64, write: Option<Vec<u8>>| {
        w.with_controller(|c, _, out| {
            c.record(
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
                out,
            )
        });
        let done = w.step_until(100, |w| record_result(w, reference).is_some());
        assert!(done.is_some(), "record job {reference} did not finish");
        record_result(w, reference).unwrap()
    };
    job(&mut w, 78, Some(long.clone()))
        .result
        .expect("the long write failed");
    let back = job(&mut w, 79, None).result.expect("the long read failed");
    assert_eq!(back.data, long);

    // Hostile datagrams on port 34964: truncated, garbage NDR, a control block with a bad
    // BlockLength, an answer nobody waits for. Counted and dropped; nothing breaks.
    let from = SocketAddrV4::new(w.devices()[echo_device].station().ip().into(), RPC_PORT);
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
    let before = w.controller().dropped_datagrams();
    let events_before = w.events().len();
    for d in &hostile {
        let answer = w.with_controller(|c, now, out| {
            c.on_datagram(from, d, now, out);
            (!out.is_empty()).then(|| format!("{out:?}"))
        });
        assert!(
            answer.is_none(),
            "a hostile datagram was answered: {answer:?}"
        );
    }
    let after = w.controller().dropped_datagrams();
    assert_eq!(after.malformed - before.malformed, 3);
    assert_eq!(after.unexpected - before.unexpected, 1);
    w.run(50);
    assert!(w.all_running());
    assert!(
        !w.events()[events_before..]
            .iter()
            .any(|e| matches!(e, DeviceEvent::Failure { .. } | DeviceEvent::Problem { .. })),
        "a hostile datagram broke a connection"
    );

    // The counter device's frames are lost: the watchdog (100 cycles in the demo) fails it,
    // its inputs go BAD; the others run on.
    w.intercept(Some(Box::new(move |m| {
        if m.device == counter_device && m.kind == Kind::Cyclic {
            Vec::new()
        } else {
            vec![m.bytes]
        }
    })));
    let before_cut = w.events().len();
    w.run(150);
    assert!(
        w.events()
            .iter()
            .any(|e| matches!(e, DeviceEvent::Failure { device, .. } if *device == counter_device))
    );
    assert_eq!(w.port().image.status(counter).input_iops, IOXS_BAD);
    assert_eq!(w.states()[counter_device], DeviceState::Failed);
    // The network heals: the device comes back by itself.
    w.intercept(None);
    let back = w.step_until(5000, |w| {
        w.events()[before_cut..]
            .iter()
            .any(|e| matches!(e, DeviceEvent::Return { device } if *device == counter_device))
    });
    assert!(
        back.is_some(),
        "the device did not return: {:?}",
        w.states()
    );
    w.run(20);
    assert_eq!(w.port().image.status(counter).input_iops, IOXS_GOOD);
    assert!(w.all_running());
    // Only the cut device failed.
    assert!(
        !w.events()
            .iter()
            .any(|e| matches!(e, DeviceEvent::Failure { device, .. } if *device != counter_device))
    );

    // OFFLINE: every AR released, the devices back to idle.
    let offline_at = w.events().len();
    w.set_online(false);
    w.run(20);
    assert!(w.states().iter().all(|s| *s == DeviceState::Offline));
    assert!(w.devices().iter().all(|d| d.ar().ar_uuid().is_none()));
    // Leaving data exchange on OFFLINE is a station failure for every device.
    for d in 0..w.states().len() {
        assert!(
            w.events()[offline_at..]
                .iter()
                .any(|e| matches!(e, DeviceEvent::Failure { device, .. } if *device == d)),
            "no DEV_FAILURE for device {d} on OFFLINE"
        );
    }

    let wire: Vec<Vec<u8>> = w.tapped().iter().map(Record::to_frame).collect();
    let dissected = procimg_testkit::tshark::dissect_clean("controller-bringup", &wire);
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
