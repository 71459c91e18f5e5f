// SPDX-License-Identifier: MIT OR Apache-2.0
//! An AR the device accepted and the controller then gives up is aborted towards the device,
//! whatever step gave it up: otherwise the device keeps it and refuses every Connect ("out of
//! AR resources") until its CMI timeout. Played against the crate's own device engine, with
//! time passed in.

use super::*;
use crate::controller::plan::{DeviceSpec, SubmoduleSpec};
use crate::device::{
    Application, ArState, Device, DeviceAction, DeviceSetup, RECORD_ANSWER_TIMEOUT_NS, RecordJob,
    SubslotAddr,
};
use crate::wire::rta_pdu::RtaBody;

const MS: u64 = 1_000_000;
const DEVICE_IP: Ipv4Addr = Ipv4Addr::new(192, 168, 0, 50);
const DEVICE_MAC: MacAddress = MacAddress([2, 0, 0, 0, 0, 0x50]);
/// The submodule whose parameter record the controller writes.
const PARAMETERIZED: SubslotAddr = SubslotAddr::new(0, 1, 1);

/// The device's program: zeros.
struct Zeros;
impl Application for Zeros {
    fn fill_inputs(&mut self, _: u64, inputs: &mut [u8], _: &[u8], _: &[u8], _: bool) {
        inputs.fill(0);
    }
}

/// The controller's side of one device, the device, and what went between them.
struct Rig {
    id: ControllerIdentity,
    ar: DeviceAr,
    device: Device<Zeros>,
    /// What the controller asked for and the device has not seen yet.
    to_device: Vec<ControllerAction>,
    /// Every frame the controller sent.
    frames: Vec<Vec<u8>>,
    /// Every event the controller reported.
    events: Vec<DeviceEvent>,
    /// The record jobs the device handed to its application, unanswered.
    jobs: Vec<RecordJob>,
}

impl Rig {
    /// A DAP and one submodule (4 bytes in and out) with one parameter record.
    fn new() -> Rig {
        let io = SubmoduleSpec {
            api: 0,
            slot: 1,
            subslot: 1,
            module_ident: 0x20,
            submodule_ident: 1,
            input_length: 4,
            output_length: 4,
            records: vec![(0x0001, vec![7, 7])],
        };
        let dap = SubmoduleSpec {
            slot: 0,
            module_ident: 0x10,
            input_length: 0,
            output_length: 0,
            records: Vec::new(),
            ..io.clone()
        };
        let spec = DeviceSpec {
            name: "dev".into(),
            ip: Some(DEVICE_IP),
            vendor_id: 0x0493,
            device_id: 1,
            instance: 1,
            reduction_ratio: 1,
            watchdog_factor: 3,
            submodules: vec![dap, io],
            ..Default::default()
        };
        let device = Device::new(DeviceSetup {
            name: spec.name.clone(),
            mac: DEVICE_MAC,
            ip: Some(DEVICE_IP.octets()),
            vendor_id: spec.vendor_id,
            device_id: spec.device_id,
            instance: 1,
            submodules: spec.submodules.iter().map(SubmoduleSpec::plugged).collect(),
            application: Zeros,
            im0: Default::default(),
        });
        // Device 3 of the controller: its alarm endpoint (3) differs from the device's (0),
        // so that the device checks both endpoints of the ERR-RTA for real.
        let plan = DevicePlan::new(3, 0, &spec, MS).expect("a 1 ms cycle suits the device");
        Rig {
            id: ControllerIdentity {
                mac: MacAddress([2, 0, 0, 0, 0, 1]),
                ip: Ipv4Addr::new(192, 168, 0, 1),
                station_name: "plc".into(),
                vendor_id: 0x0493,
                device_id: 2,
                instance: 1,
            },
            ar: DeviceAr::new(plan, UuidSource::new(7)),
            device,
            to_device: Vec::new(),
            frames: Vec::new(),
            events: Vec::new(),
            jobs: Vec::new(),
        }
    }

    /// Moves frames and datagrams between the two at `now` until both are quiet.
    fn exchange(&mut self, now: u64, mut from_device: Vec<DeviceAction>) {
        while !self.to_device.is_empty() || !from_device.is_empty() {
            for a in std::mem::take(&mut self.to_device) {
                match a {
                    ControllerAction::Frame(f) => {
                        self.device.on_frame(&f, now, &mut from_device);
                        self.frames.push(f);
                    }
                    ControllerAction::Datagram { to, payload } => {
                        let from = SocketAddrV4::new(self.id.ip, rpc::RPC_PORT);
                        self.device
                            .on_datagram(from, to.port(), &payload, now, &mut from_device);
                    }
                    ControllerAction::Event(e) => self.events.push(e),
                    // No cyclic exchange runs here: what is counted is the AR's set-up.
                    _ => {}
                }
            }
            let mut out = Vec::new();
            for a in std::mem::take(&mut from_device) {
                match a {
                    DeviceAction::Frame(f) => self.ar.on_frame(&f, &self.id, now, &mut out),
                    // The ApplicationReady is for the controller's RPC server, which is not
                    // here: the AR is followed up to PrmEnd.
                    DeviceAction::Datagram { payload, .. } => {
                        self.ar.on_datagram(&payload, &self.id, now, &mut out);
                    }
                    DeviceAction::Record(job) => self.jobs.push(job),
                    _ => {}
                }
            }
            self.to_device.append(&mut out);
        }
    }

    /// One step of the world at `now`: both sides' timers, then the exchange.
    fn step(&mut self, now: u64) {
        let mut from_device = Vec::new();
        self.device.poll(now, &mut from_device);
        self.ar.poll(&self.id, now, &mut self.to_device);
        self.exchange(now, from_device);
    }

    /// Steps every 10 ms from `from` until `done` holds; the time it does.
    fn run_until(&mut self, from: u64, mut done: impl FnMut(&Rig) -> bool) -> u64 {
        let mut now = from;
        while !done(self) {
            assert!(now < from + 30_000 * MS, "not reached: {:?}", self.events);
            self.step(now);
            now += 10 * MS;
        }
        now
    }

    /// The ERR-RTAs among the controller's frames: their destination and PDU.
    fn err_rtas(&self) -> Vec<(MacAddress, RtaPdu)> {
        self.frames
            .iter()
            .filter_map(|f| {
                let eth = ethernet::Frame::new_checked(&f[..]).ok()?;
                let packet = rta_pdu::Packet::new_checked(eth.payload()).ok()?;
                let pdu = RtaPdu::parse(&packet).ok()?;
                matches!(pdu.body, RtaBody::Err(_)).then_some((eth.dst(), pdu))
            })
            .collect()
    }
}

#[test]
fn a_failed_parameter_write_aborts_the_ar_and_the_next_connect_is_taken() {
    let mut rig = Rig::new();
    // The application takes slot 1's records and never answers: the device answers the
    // Write itself after its timeout, with "resource busy".
    rig.device.delegate_records(PARAMETERIZED, true);
    let mut out = Vec::new();
    rig.ar.set_wanted(true, &rig.id, 0, &mut out);
    rig.to_device = out;
    let t = rig.run_until(0, |r| r.ar.state() == DeviceState::Failed);
    assert_eq!(rig.jobs.len(), 1, "the Write reached the application once");
    assert!(
        t >= RECORD_ANSWER_TIMEOUT_NS,
        "failed before the device's answer"
    );
    let problem = rig.events.iter().find_map(|e| match e {
        DeviceEvent::Problem {
            cause,
            reason,
            status,
            ..
        } => Some((*cause, reason.clone(), *status)),
        _ => None,
    });
    let Some((cause, reason, status)) = problem else {
        panic!("no Problem event: {:?}", rig.events);
    };
    assert_eq!(cause, FailureCause::Refused);
    assert!(reason.contains("resource busy"), "{reason}");
    // The Write's own status (PNIORW), not the abort's.
    assert_eq!(status.map(|s| s.error_decode), Some(0x80), "{status:?}");

    // The controller told the device, on the low-priority alarm channel of the AR it
    // connected, with the abort code of the cause.
    let errs = rig.err_rtas();
    assert_eq!(errs.len(), 1, "one ERR-RTA: {errs:?}");
    let (dst, pdu) = &errs[0];
    assert_eq!(*dst, DEVICE_MAC);
    assert_eq!(pdu.priority, Priority::Low);
    assert_eq!(pdu.header.src_endpoint, 3);
    assert_eq!(
        pdu.body,
        RtaBody::Err(ErrRta::abort(FailureCause::Refused.abort_code()))
    );
    // The device took it (its endpoints and addresses are the AR's) and ended the AR at
    // once: it did not wait for its CMI timeout.
    assert_eq!(rig.device.ar().state(), ArState::Idle);
    assert_eq!(rig.device.ar().aborted_ars(), 1);
    assert_eq!(
        rig.device.ar().last_abort(),
        Some(FailureCause::Refused.abort_code())
    );

    // The application gives the records back: the next attempt's Connect is taken and the
    // AR goes on to PrmEnd.
    rig.device.delegate_records(PARAMETERIZED, false);
    rig.events.clear();
    rig.run_until(t, |r| {
        r.ar.state() == DeviceState::WaitingForApplicationReady
    });
    let refused = rig
        .events
        .iter()
        .filter(|e| matches!(e, DeviceEvent::Problem { .. }))
        .count();
    assert_eq!(refused, 0, "{:?}", rig.events);
    assert_ne!(rig.device.ar().state(), ArState::Idle);
    assert_eq!(rig.device.ar().aborted_ars(), 1);
}
