// SPDX-License-Identifier: MIT OR Apache-2.0
//! One device's bring-up, with every Connect request the controller sends counted: one per
//! attempt, sent again (the same PDU: same activity, sequence number 0) only after the
//! call's retry time without an answer. A device that gets the same Connect twice while it
//! sets up the AR takes the second as a Connect for an AR it already holds and aborts it.
//!
//! The controller is driven the way procimgd's acyclic thread drives it, and worse: after
//! every single frame or datagram it takes, and between them, `poll` runs several times at
//! the same instant and at instants just after it. Before the Connect, the controller hands
//! its driver the device's MAC address from DCP: a Connect waiting for ARP in the driver's
//! network stack would wait there with its repeats, and all would reach the device together
//! once the address resolves (what a device at first bring-up saw: the same Connect twice
//! within 40 µs).

use procimg_profinet::controller::plan::{
    ControllerIdentity, DevicePlan, DeviceSpec, SubmoduleSpec,
};
use procimg_profinet::controller::rpc_call::{ATTEMPTS, RETRY_NS};
use procimg_profinet::controller::{Controller, ControllerAction, DeviceState};
use procimg_profinet::device::{Application, Device, DeviceAction, DeviceSetup};
use procimg_profinet::wire::rpc::{self, Header, PacketType, RPC_PORT, opnum};
use procimg_profinet::wire::{MacAddress, Uuid};
use std::net::{Ipv4Addr, SocketAddrV4};

const MS: u64 = 1_000_000;
const DEVICE_IP: Ipv4Addr = Ipv4Addr::new(192, 168, 0, 11);
const CONTROLLER_IP: Ipv4Addr = Ipv4Addr::new(192, 168, 0, 1);
const DEVICE_MAC: MacAddress = MacAddress([2, 0, 0, 0, 0, 11]);

/// The device's program: zeros.
struct Zeros;
impl Application for Zeros {
    fn fill_inputs(&mut self, _: u64, inputs: &mut [u8], _: &[u8], _: &[u8], _: bool) {
        inputs.fill(0);
    }
}

/// One Connect PDU the controller sent.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct ConnectSent {
    activity: Uuid,
    sequence_number: u32,
    fragment: u16,
    at: u64,
}

/// The controller and one device, in memory; `answering` says whether the device gets the
/// controller's datagrams (DCP always goes through).
struct Rig {
    controller: Controller,
    device: Device<Zeros>,
    /// What the controller just asked for, before it is counted and queued.
    actions: Vec<ControllerAction>,
    to_device: Vec<ControllerAction>,
    to_controller: Vec<DeviceAction>,
    connects: Vec<ConnectSent>,
    /// The addresses the controller gave its driver, each with the number of Connect PDUs
    /// sent before it.
    neighbours: Vec<(Ipv4Addr, MacAddress, usize)>,
    answering: bool,
}

impl Rig {
    /// A controller that wants the device at `DEVICE_IP`, and the device, which has that
    /// address already or (`has_ip` false) none, so that the controller sets it by DCP.
    fn new(has_ip: bool) -> Rig {
        let io = SubmoduleSpec {
            api: 0,
            slot: 1,
            subslot: 1,
            module_ident: 0x20,
            submodule_ident: 1,
            input_length: 4,
            output_length: 4,
            records: vec![],
        };
        let dap = SubmoduleSpec {
            slot: 0,
            module_ident: 0x10,
            input_length: 0,
            output_length: 0,
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
            ip: has_ip.then_some(DEVICE_IP.octets()),
            vendor_id: spec.vendor_id,
            device_id: spec.device_id,
            instance: 1,
            submodules: spec.submodules.iter().map(SubmoduleSpec::plugged).collect(),
            application: Zeros,
            im0: Default::default(),
        });
        let id = ControllerIdentity {
            mac: MacAddress([2, 0, 0, 0, 0, 1]),
            ip: CONTROLLER_IP,
            station_name: "plc".into(),
            vendor_id: 0x0493,
            device_id: 2,
            instance: 1,
        };
        let plans = DevicePlan::all(&[spec], MS).expect("a 1 ms cycle suits the device");
        Rig {
            controller: Controller::new(id, plans, 0, 7),
            device,
            actions: Vec::new(),
            to_device: Vec::new(),
            to_controller: Vec::new(),
            connects: Vec::new(),
            neighbours: Vec::new(),
            answering: true,
        }
    }

    fn state(&self) -> DeviceState {
        self.controller.states().next().expect("one device")
    }

    /// Queues what the controller just asked for at `at`, counting its Connect PDUs.
    fn take(&mut self, at: u64) {
        for a in self.actions.drain(..) {
            if let ControllerAction::Neighbour { ip, mac } = a {
                self.neighbours.push((ip, mac, self.connects.len()));
            }
            if let ControllerAction::Datagram { payload, .. } = &a
                && let Ok(packet) = rpc::Packet::new_checked(&payload[..])
                && let Ok(h) = Header::parse(&packet)
                && h.packet_type == PacketType::Request
                && h.opnum == opnum::CONNECT
            {
                self.connects.push(ConnectSent {
                    activity: h.activity,
                    sequence_number: h.sequence_number,
                    fragment: h.fragment_number,
                    at,
                });
            }
            self.to_device.push(a);
        }
    }

    /// `poll` at `now` three times, and once each a nanosecond and a microsecond later: a
    /// driver may poll whenever it wakes, as often as it likes.
    fn poll_hard(&mut self, now: u64) {
        for at in [now, now, now, now + 1, now + 1_000] {
            self.controller.poll(at, &mut self.actions);
            self.take(at);
        }
    }

    /// Moves frames and datagrams between the two at `now` until both are quiet, polling the
    /// controller hard after each one it takes.
    fn exchange(&mut self, now: u64) {
        while !self.to_device.is_empty() || !self.to_controller.is_empty() {
            for a in std::mem::take(&mut self.to_device) {
                match a {
                    ControllerAction::Frame(f) => {
                        self.device.on_frame(&f, now, &mut self.to_controller)
                    }
                    ControllerAction::Datagram { to, payload } if self.answering => {
                        let from = SocketAddrV4::new(CONTROLLER_IP, RPC_PORT);
                        self.device.on_datagram(
                            from,
                            to.port(),
                            &payload,
                            now,
                            &mut self.to_controller,
                        )
                    }
                    // The controller runs no cyclic exchange here: the AR's data is not what
                    // is counted.
                    _ => {}
                }
            }
            for a in std::mem::take(&mut self.to_controller) {
                match a {
                    DeviceAction::Frame(f) => self.controller.on_frame(&f, now, &mut self.actions),
                    DeviceAction::Datagram {
                        from_port, payload, ..
                    } => {
                        let from = SocketAddrV4::new(DEVICE_IP, from_port);
                        self.controller
                            .on_datagram(from, &payload, now, &mut self.actions)
                    }
                    _ => {}
                }
                self.take(now);
                self.poll_hard(now);
            }
        }
    }

    /// One millisecond of the world from `now`: the device's timers, the exchange, the
    /// controller's timers.
    fn step(&mut self, now: u64) {
        self.device.poll(now, &mut self.to_controller);
        self.exchange(now);
        self.poll_hard(now);
        self.exchange(now);
    }

    /// The Connect PDUs of `activity`.
    fn sends_of(&self, activity: Uuid) -> Vec<ConnectSent> {
        self.connects
            .iter()
            .filter(|c| c.activity == activity)
            .copied()
            .collect()
    }

    /// The activities of the Connects so far, one per attempt, in order.
    fn attempts(&self) -> Vec<Uuid> {
        let mut a: Vec<Uuid> = Vec::new();
        for c in &self.connects {
            if !a.contains(&c.activity) {
                a.push(c.activity);
            }
        }
        a
    }
}

/// Brings the device up from `set_online` at 0; the ms at which it runs.
fn bring_up(rig: &mut Rig) -> u64 {
    rig.controller.set_online(true, 0, &mut rig.actions);
    rig.take(0);
    for k in 0..5_000 {
        let now = k * MS;
        rig.step(now);
        if rig.state() == DeviceState::WaitingForApplicationReady
            || rig.state() == DeviceState::Running
        {
            return k;
        }
    }
    panic!("the device did not come up: {:?}", rig.state());
}

#[test]
fn a_bring_up_sends_one_connect() {
    for has_ip in [true, false] {
        let mut rig = Rig::new(has_ip);
        let ms = bring_up(&mut rig);
        let path = if has_ip {
            "found with its address"
        } else {
            "given its address by DCP Set"
        };
        assert_eq!(rig.attempts().len(), 1, "device {path}: one attempt");
        assert_eq!(
            rig.connects.len(),
            1,
            "device {path}: one Connect PDU in a bring-up of {ms} ms: {:#?}",
            rig.connects
        );
        assert_eq!(rig.connects[0].sequence_number, 0);
        assert_eq!(rig.connects[0].fragment, 0);
        // The device took it once, and holds the AR.
        assert_eq!(
            rig.device.ar().aborted_ars(),
            0,
            "device {path}: it aborted an AR"
        );
        // Its MAC address went to the driver before the Connect, so that the Connect need
        // not wait for ARP (where a repeat would wait beside it).
        assert_eq!(
            rig.neighbours,
            vec![(DEVICE_IP, DEVICE_MAC, 0)],
            "device {path}: the device's address once, before the Connect"
        );
    }
}

#[test]
fn an_unanswered_connect_goes_out_again_only_after_its_retry_time() {
    for has_ip in [true, false] {
        let mut rig = Rig::new(has_ip);
        // DCP goes through, the Connect is lost.
        rig.answering = false;
        rig.controller.set_online(true, 0, &mut rig.actions);
        rig.take(0);
        let mut k = 0;
        while rig.connects.is_empty() {
            rig.step(k * MS);
            k += 1;
            assert!(k < 5_000, "no Connect");
        }
        let first = rig.connects[0];
        // Every ms (polled hard) until the call has failed and the next attempt started.
        while rig.attempts().len() < 2 {
            rig.step(k * MS);
            k += 1;
            assert!(k < 20_000, "no second attempt");
        }
        let sends = rig.sends_of(first.activity);
        assert_eq!(
            sends.len(),
            ATTEMPTS as usize,
            "the first attempt's Connect went out {} times, not once and {} retries: {sends:#?}",
            sends.len(),
            ATTEMPTS - 1
        );
        for pair in sends.windows(2) {
            assert_eq!(pair[1].sequence_number, 0, "a retry is the same call");
            assert!(
                pair[1].at - pair[0].at >= RETRY_NS,
                "a retry before the retry time: {sends:#?}"
            );
        }
        let second = rig.attempts()[1];
        assert_eq!(
            rig.sends_of(second).len(),
            1,
            "the second attempt's Connect went out once so far"
        );
    }
}
