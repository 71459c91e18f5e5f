// SPDX-License-Identifier: MIT OR Apache-2.0
//! One deterministic PROFINET network in memory: a [`Controller`] and simulated devices
//! ([`Device`]) on a virtual Ethernet segment and a virtual UDP network, in virtual time
//! that the caller steps. The controller draws its UUIDs from a seed and every frame and
//! datagram goes in one fixed order, so a run with the same seed and the same steps sends the
//! same bytes at the same times: what a [tap](World::tap) records replays exactly.
//!
//! The controller reaches the segment through a [`Port`]: [`Direct`] is the plainest one;
//! procimgd's tests plug in the cycle thread's PROFINET IO system instead, so that the real
//! cycle moves and supervises the cyclic frames. The devices run any [`Application`].
//!
//! ```
//! use procimg_profinet::controller::plan::{DevicePlan, DeviceSpec, SubmoduleSpec};
//! use procimg_profinet::device::{Application, Device, DeviceSetup};
//! use procimg_profinet::wire::MacAddress;
//! use procimg_testkit::world::{Setup, World, controller_identity};
//! use std::net::Ipv4Addr;
//!
//! struct Zeros;
//! impl Application for Zeros {
//!     fn fill_inputs(&mut self, _: u64, inputs: &mut [u8], _: &[u8], _: &[u8], _: bool) {
//!         inputs.fill(0);
//!     }
//! }
//!
//! let io = SubmoduleSpec {
//!     api: 0, slot: 1, subslot: 1, module_ident: 0x20, submodule_ident: 1,
//!     input_length: 4, output_length: 4, records: vec![],
//! };
//! let spec = DeviceSpec {
//!     name: "dev".into(), ip: Some(Ipv4Addr::new(192, 168, 0, 11)), vendor_id: 0x0493,
//!     device_id: 1, instance: 1, reduction_ratio: 1, watchdog_factor: 3,
//!     submodules: vec![SubmoduleSpec { slot: 0, input_length: 0, output_length: 0, ..io.clone() }, io],
//!     ..Default::default()
//! };
//! let device = Device::new(DeviceSetup {
//!     name: spec.name.clone(), mac: MacAddress([2, 0, 0, 0, 0, 11]), ip: None,
//!     vendor_id: spec.vendor_id, device_id: spec.device_id, instance: 1,
//!     submodules: spec.submodules.iter().map(SubmoduleSpec::plugged).collect(),
//!     application: Zeros,
//!     im0: Default::default(),
//! });
//! let plans = DevicePlan::all(&[spec], 1_000_000).unwrap();
//! let id = controller_identity(MacAddress([2, 0, 0, 0, 0, 1]), Ipv4Addr::new(192, 168, 0, 1), "plc");
//! let mut world = World::direct(Setup::new(id, plans), vec![device]);
//! world.set_online(true);
//! let cycles = world.step_until_running(3_000).expect("the device comes up");
//! assert!(world.port().exchanges().count() == 1, "after {cycles} cycles");
//! ```

mod intercept;
mod port;
pub mod tap;
#[cfg(test)]
mod tests;

pub use intercept::{Intercepted, Interceptor, Kind};
pub use port::{Direct, Port, Report, Tick};
use procimg_profinet::controller::plan::{ControllerIdentity, DevicePlan};
use procimg_profinet::controller::{Controller, ControllerAction, DeviceEvent, DeviceState};
use procimg_profinet::device::{Application, Device, DeviceAction};
use procimg_profinet::wire::MacAddress;
use procimg_profinet::wire::rpc::RPC_PORT;
use std::net::{Ipv4Addr, SocketAddrV4};
use tap::{Filter, Message, Origin, Record};

/// One millisecond in ns.
pub const MS: u64 = 1_000_000;

/// What a world is made of, apart from its devices and its port.
#[derive(Clone, Debug)]
pub struct Setup {
    /// The controller's identity; its MAC and IP are its addresses on the world's network.
    pub identity: ControllerIdentity,
    /// The controller's plan of every device, in device order.
    pub plans: Vec<DevicePlan>,
    /// Where the controller's ARUUIDs and activity UUIDs come from.
    pub seed: u64,
    /// The ServerBootTime of the controller's RPC answers.
    pub boot_time: u32,
    /// The length of a cycle (ns): [`World::step`] moves the clock on by this much.
    pub period_ns: u64,
    /// The clock at the start (ns).
    pub start_ns: u64,
}

impl Setup {
    /// `plans` for the controller `identity`: seed 1, boot time 1, cycles of 1 ms, the clock
    /// at the first cycle.
    pub fn new(identity: ControllerIdentity, plans: Vec<DevicePlan>) -> Setup {
        Setup {
            identity,
            plans,
            seed: 1,
            boot_time: 1,
            period_ns: MS,
            start_ns: MS,
        }
    }
}

/// procimgd's identity as a controller (vendor 0x0493, device 0x0FFF, instance 1) at `mac`
/// and `ip`, called `station_name`.
pub fn controller_identity(
    mac: MacAddress,
    ip: Ipv4Addr,
    station_name: &str,
) -> ControllerIdentity {
    ControllerIdentity {
        mac,
        ip,
        station_name: station_name.into(),
        vendor_id: 0x0493,
        device_id: 0x0fff,
        instance: 1,
    }
}

/// What crossed the world's network so far.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    /// Frames the controller's port put on the segment.
    pub controller_frames: u64,
    /// Frames that reached the controller's port (after an interceptor; injected ones too).
    pub device_frames: u64,
    /// Datagrams the controller sent.
    pub controller_datagrams: u64,
    /// Datagrams that reached the controller (after an interceptor).
    pub device_datagrams: u64,
}

/// A tap: what it keeps, and what it kept.
struct Tap {
    keep: Filter,
    records: Vec<Record>,
}

/// The controller, the devices and their network; see the [module](self).
pub struct World<A: Application, P: Port = Direct> {
    controller: Controller,
    devices: Vec<Device<A>>,
    port: P,
    controller_ip: Ipv4Addr,
    period_ns: u64,
    now_ns: u64,
    events: Vec<DeviceEvent>,
    tap: Option<Tap>,
    interceptor: Option<Interceptor>,
    counters: Counters,
}

impl<A: Application> World<A, Direct> {
    /// The controller of `setup` and `devices` on a [`Direct`] port, offline.
    pub fn direct(setup: Setup, devices: Vec<Device<A>>) -> World<A, Direct> {
        World::new(setup, devices, Direct::new())
    }
}

impl<A: Application, P: Port> World<A, P> {
    /// The controller of `setup` and `devices` (device `d` is the one of plan `d`), the
    /// controller reaching the segment through `port`; the controller is offline.
    pub fn new(setup: Setup, devices: Vec<Device<A>>, port: P) -> World<A, P> {
        let controller_ip = setup.identity.ip;
        World {
            controller: Controller::new(setup.identity, setup.plans, setup.boot_time, setup.seed),
            devices,
            port,
            controller_ip,
            period_ns: setup.period_ns.max(1),
            now_ns: setup.start_ns,
            events: Vec::new(),
            tap: None,
            interceptor: None,
            counters: Counters::default(),
        }
    }

    /// The time (ns).
    pub const fn now(&self) -> u64 {
        self.now_ns
    }

    /// The cycle: the time in whole cycles.
    pub const fn cycle(&self) -> u64 {
        self.now_ns / self.period_ns
    }

    /// The controller.
    pub const fn controller(&self) -> &Controller {
        &self.controller
    }

    /// The controller's view of every device.
    pub fn states(&self) -> Vec<DeviceState> {
        self.controller.states().collect()
    }

    /// Whether the controller has every device in data exchange.
    pub fn all_running(&self) -> bool {
        self.controller.states().all(|s| s == DeviceState::Running)
    }

    /// The devices.
    pub fn devices(&self) -> &[Device<A>] {
        &self.devices
    }

    /// The controller's port.
    pub const fn port(&self) -> &P {
        &self.port
    }

    /// The controller's port, to change (e.g. the image behind procimgd's cycle).
    pub fn port_mut(&mut self) -> &mut P {
        &mut self.port
    }

    /// Every event the controller reported, oldest first.
    pub fn events(&self) -> &[DeviceEvent] {
        &self.events
    }

    /// Takes the events reported so far.
    pub fn take_events(&mut self) -> Vec<DeviceEvent> {
        std::mem::take(&mut self.events)
    }

    /// What crossed the network so far.
    pub const fn counters(&self) -> Counters {
        self.counters
    }

    /// Calls `f` with the controller, the time and a place for its actions, then carries
    /// the actions out.
    pub fn with_controller<R>(
        &mut self,
        f: impl FnOnce(&mut Controller, u64, &mut Vec<ControllerAction>) -> R,
    ) -> R {
        let mut out = Vec::new();
        let r = f(&mut self.controller, self.now_ns, &mut out);
        self.carry_out(out);
        r
    }

    /// Calls `f` with device `d`, the time and a place for its actions, then carries the
    /// actions out. Panics if there is no device `d`.
    pub fn with_device<R>(
        &mut self,
        d: usize,
        f: impl FnOnce(&mut Device<A>, u64, &mut Vec<DeviceAction>) -> R,
    ) -> R {
        let mut out = Vec::new();
        let r = f(&mut self.devices[d], self.now_ns, &mut out);
        let answers = self.device_actions(d, out);
        self.carry_out(answers);
        r
    }

    /// Sets the controller online (every active device is brought up) or offline.
    pub fn set_online(&mut self, online: bool) {
        self.with_controller(|c, now, out| c.set_online(online, now, out));
    }

    /// Puts `frame` on the segment toward the controller's interface, as if a device had
    /// sent it (no interceptor applies).
    pub fn inject_frame(&mut self, frame: &[u8]) {
        let frame = self.show_frame(Origin::Injected, frame.to_vec());
        self.counters.device_frames += 1;
        self.port.arrive(&frame);
    }

    /// Starts recording: from now on every frame and datagram is shown to `keep`, and kept
    /// if it says so. The tap sees each message as its sender put it on the network, before
    /// an interceptor changes or drops it. Replaces an earlier tap and what it kept.
    pub fn tap(&mut self, keep: impl FnMut(&Record) -> bool + 'static) -> &mut Self {
        self.tap = Some(Tap {
            keep: Box::new(keep),
            records: Vec::new(),
        });
        self
    }

    /// What the tap kept so far.
    pub fn tapped(&self) -> &[Record] {
        self.tap.as_ref().map_or(&[], |t| &t.records)
    }

    /// Takes what the tap kept so far; it goes on recording.
    pub fn take_tapped(&mut self) -> Vec<Record> {
        self.tap
            .as_mut()
            .map(|t| std::mem::take(&mut t.records))
            .unwrap_or_default()
    }

    /// Puts `interceptor` between the devices and the controller (`None`: a perfect network).
    pub fn intercept(&mut self, interceptor: Option<Interceptor>) {
        self.interceptor = interceptor;
    }

    /// Moves the clock on by one cycle and runs the cycle.
    pub fn step(&mut self) {
        self.advance(self.period_ns);
    }

    /// Moves the clock on by `ns` (a stalled machine, if longer than a cycle) and runs one
    /// cycle. In a cycle:
    /// 1. every frame the port put on the segment since the last cycle reaches every device,
    ///    in order; what a device answers is carried out before the next device sees it;
    /// 2. every device runs its timers, in device order;
    /// 3. the port receives (the devices' frames) and reports to the controller;
    /// 4. the controller runs its timers;
    /// 5. the port sends.
    ///
    /// Datagrams cross at once: the answer to a datagram arrives in the same call, and so
    /// on until nobody has anything left to say.
    pub fn advance(&mut self, ns: u64) {
        self.now_ns += ns;
        let now = self.now_ns;
        let tick = Tick {
            cycle: self.cycle(),
            now_ns: now,
        };
        let mut departed = Vec::new();
        self.port.depart(&mut departed);
        for frame in departed {
            let frame = self.show_frame(Origin::Controller, frame);
            self.counters.controller_frames += 1;
            for d in 0..self.devices.len() {
                let mut out = Vec::new();
                self.devices[d].on_frame(&frame, now, &mut out);
                let answers = self.device_actions(d, out);
                self.carry_out(answers);
            }
        }
        for d in 0..self.devices.len() {
            let mut out = Vec::new();
            self.devices[d].poll(now, &mut out);
            let answers = self.device_actions(d, out);
            self.carry_out(answers);
        }
        let mut reports = Vec::new();
        self.port.receive(tick, &mut reports);
        let mut out = Vec::new();
        for r in reports {
            match r {
                Report::Frame(f) => self.controller.on_frame(&f, now, &mut out),
                Report::Watchdog { device, epoch } => {
                    self.controller.on_watchdog(device, epoch, now, &mut out)
                }
                Report::DataStarted { device, epoch } => {
                    self.controller.on_data_started(device, epoch)
                }
            }
        }
        self.controller.poll(now, &mut out);
        self.carry_out(out);
        self.port.send(tick);
    }

    /// Runs `cycles` cycles.
    pub fn run(&mut self, cycles: u64) {
        for _ in 0..cycles {
            self.step();
        }
    }

    /// Runs cycles until the clock reaches `t_ns`.
    pub fn run_until(&mut self, t_ns: u64) {
        while self.now_ns < t_ns {
            self.step();
        }
    }

    /// Runs cycles until `done` holds (looked at before each); the cycles it took, or `None`
    /// if it did not hold after `max` cycles.
    pub fn step_until(&mut self, max: u64, mut done: impl FnMut(&Self) -> bool) -> Option<u64> {
        for n in 0..=max {
            if done(self) {
                return Some(n);
            }
            if n < max {
                self.step();
            }
        }
        None
    }

    /// Runs cycles until the controller has every device in data exchange; the cycles it
    /// took, or `None` after `max`.
    pub fn step_until_running(&mut self, max: u64) -> Option<u64> {
        self.step_until(max, Self::all_running)
    }

    /// Shows a message to the tap; returns it.
    fn show(&mut self, origin: Origin, message: Message) -> Message {
        let Some(tap) = self.tap.as_mut() else {
            return message;
        };
        let record = Record {
            at_ns: self.now_ns,
            origin,
            message,
        };
        if (tap.keep)(&record) {
            tap.records.push(record.clone());
        }
        record.message
    }

    /// Shows a frame to the tap; returns it.
    fn show_frame(&mut self, origin: Origin, frame: Vec<u8>) -> Vec<u8> {
        match self.show(origin, Message::Frame(frame)) {
            Message::Frame(f) => f,
            Message::Datagram { payload, .. } => payload,
        }
    }

    /// Shows a datagram to the tap; returns its payload.
    fn show_datagram(
        &mut self,
        origin: Origin,
        from: SocketAddrV4,
        to: SocketAddrV4,
        payload: Vec<u8>,
    ) -> Vec<u8> {
        match self.show(origin, Message::Datagram { from, to, payload }) {
            Message::Frame(p) | Message::Datagram { payload: p, .. } => p,
        }
    }

    /// What arrives of a message of device `d` (all of it, without an interceptor).
    fn intercepted(&mut self, device: usize, kind: Kind, bytes: Vec<u8>) -> Vec<Vec<u8>> {
        match self.interceptor.as_mut() {
            Some(i) => i(Intercepted {
                device,
                kind,
                bytes,
            }),
            None => vec![bytes],
        }
    }

    /// Carries out the controller's actions, and what they lead to, until none are left.
    pub fn carry_out(&mut self, actions: Vec<ControllerAction>) {
        let now = self.now_ns;
        let mut pending = actions;
        while !pending.is_empty() {
            let mut next = Vec::new();
            for a in pending {
                match a {
                    ControllerAction::Frame(f) => self.port.transmit(f),
                    ControllerAction::Datagram { to, payload } => {
                        let from = SocketAddrV4::new(self.controller_ip, RPC_PORT);
                        let payload = self.show_datagram(Origin::Controller, from, to, payload);
                        self.counters.controller_datagrams += 1;
                        // A datagram to an address nobody has is lost.
                        let Some(d) = self
                            .devices
                            .iter()
                            .position(|d| d.station().ip() == to.ip().octets())
                        else {
                            continue;
                        };
                        let mut out = Vec::new();
                        self.devices[d].on_datagram(from, to.port(), &payload, now, &mut out);
                        next.extend(self.device_actions(d, out));
                    }
                    // The world's network reaches a device by its address alone.
                    ControllerAction::Neighbour { .. } => {}
                    ControllerAction::Start(ar) => self.port.start(ar),
                    ControllerAction::Stop { device } => self.port.stop(device),
                    ControllerAction::Event(e) => self.events.push(e),
                }
            }
            pending = next;
        }
    }

    /// Carries out device `d`'s actions; returns what the controller answered to datagrams.
    fn device_actions(&mut self, d: usize, out: Vec<DeviceAction>) -> Vec<ControllerAction> {
        let now = self.now_ns;
        let mut answers = Vec::new();
        for a in out {
            match a {
                DeviceAction::Frame(f) => {
                    let f = self.show_frame(Origin::Device(d), f);
                    for f in self.intercepted(d, Kind::of_frame(&f), f) {
                        self.counters.device_frames += 1;
                        self.port.arrive(&f);
                    }
                }
                DeviceAction::Datagram {
                    to,
                    from_port,
                    payload,
                } => {
                    let from = SocketAddrV4::new(
                        Ipv4Addr::from(self.devices[d].station().ip()),
                        from_port,
                    );
                    let payload = self.show_datagram(Origin::Device(d), from, to, payload);
                    // Only the controller has an address on this network.
                    if *to.ip() != self.controller_ip {
                        continue;
                    }
                    for p in self.intercepted(d, Kind::Datagram, payload) {
                        self.counters.device_datagrams += 1;
                        self.controller.on_datagram(from, &p, now, &mut answers);
                    }
                }
                // The world's devices run their own cyclic exchange.
                DeviceAction::StartCyclic(_)
                | DeviceAction::StopCyclic { .. }
                | DeviceAction::Record(_)
                | DeviceAction::ArCheck(_)
                | DeviceAction::DcpSetCheck(_) => {}
            }
        }
        answers
    }
}
