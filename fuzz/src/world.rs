// SPDX-License-Identifier: MIT OR Apache-2.0
//! The controller and simulated devices on the test kit's simulated network in simulated
//! time ([`procimg_testkit::world`]), with procimgd's cycle thread as the controller's port
//! ([`Cycle`]: the PROFINET IO system over an in-process link, and its image), driven by a
//! sequence of operations ([`ops`]) that let libFuzzer advance time, inject arbitrary frames
//! and datagrams, corrupt, cut, drop or repeat what the devices send, and act as a client
//! would (online/offline, activation, record jobs, alarm acknowledgements, output data).
//!
//! The controller draws its ARUUIDs from a fixed seed here, so a run replays exactly; still,
//! corrupting the live answers of real simulated devices reaches every state of the
//! controller's state machine with inputs that differ from valid ones in a few bytes, which
//! recorded answers could not do once an operation changed the course of the exchange.
//!
//! [`DeviceBench`] drives one simulated device alone (the `device` target); its seeds
//! are what the controller sent to that device in a recorded bring-up ([`record_bringup`]).

use crate::ops::{Reader, Writer};
use crate::wire_check;
use procimg_nic::{MAX_FRAME, Nic, sim_link};
use procimg_profinet::controller::cyclic::CyclicAr;
use procimg_profinet::controller::{AlarmTicket, DeviceEvent, DeviceState, RecordRequest};
use procimg_profinet::device::{
    ChannelDiag, DeviceAction, DiagEntry, DiagnosisEdit, Severity, SubslotAddr,
};
use procimg_profinet::wire::MacAddress;
use procimg_profinet::wire::record::RecordErrorCode;
use procimg_profinet::wire::rpc::RPC_PORT;
use procimg_runtime::config::{self, Config};
use procimg_runtime::image::{Image, Tables};
use procimg_runtime::io::pnio::PnioIo;
use procimg_runtime::io::pnio::channel::{Channel, FromCycle, ToCycle};
use procimg_runtime::io::{CycleTime, IoSystem};
use procimg_runtime::roles::controller::sim_behaviour::DemoApplication;
use procimg_runtime::roles::controller::sim_plant;
use procimg_runtime::roles::controller::sim_plant::DemoDevice;
use procimg_runtime::roles::controller::{SIM_CONTROLLER_IP, SIM_CONTROLLER_MAC};
use procimg_shm_layout::{IOXS_BAD, IOXS_GOOD, Mode};
use procimg_testkit::world::tap::{Message, Origin, Record};
use procimg_testkit::world::{self as net, Intercepted, Kind, Port, Report, Setup, Tick};
use std::net::SocketAddrV4;
use std::sync::{Arc, OnceLock};

/// One millisecond in ns, the cycle time of [`CONFIG`].
pub const MS: u64 = 1_000_000;

/// At most this many cycles run per input, so that no input takes long; [`ops::SKIP`] jumps
/// over the controller's longer timers (identify window, retries, back-off) in one cycle.
pub const MAX_CYCLES: u32 = 600;

/// The configuration of the fuzzed network: a device the controller gives its address by DCP
/// and parameterizes with two records (a WriteMultiple), with inputs and outputs; and a
/// device with an address of its own and inputs only. Watchdog factor 3: simulated time is
/// exact, and a short watchdog lets dropped frames matter.
pub const CONFIG: &str = r#"
cycle_time = "1ms"

[[device]]
name = "echo"
ip = "192.168.0.11"
vendor_id = 0x0493
device_id = 0x0001
sim = "echo"
watchdog_factor = 3

[[device.submodule]]
slot = 0
subslot = 1
module_ident = 0x00000001
submodule_ident = 0x00000001

[[device.submodule]]
slot = 1
subslot = 1
module_ident = 0x00000020
submodule_ident = 0x00000001
input_length = 16
output_length = 16
records = [ { index = 0x100, data = [1, 2, 3] }, { index = 0x101, data = [4, 5, 6, 7, 8] } ]

[[device]]
name = "counter"
vendor_id = 0x0493
device_id = 0x0002
sim = "counter"
watchdog_factor = 3

[[device.submodule]]
slot = 0
subslot = 1
module_ident = 0x00000001
submodule_ident = 0x00000001

[[device.submodule]]
slot = 1
subslot = 1
module_ident = 0x00000030
submodule_ident = 0x00000001
input_length = 4
"#;

/// The parsed [`CONFIG`], parsed once: every fuzz input starts from it.
pub fn config() -> &'static Config {
    static PARSED: OnceLock<Config> = OnceLock::new();
    PARSED.get_or_init(|| {
        config::parse(CONFIG, "fuzz.toml").expect("the fuzz configuration is valid")
    })
}

/// Opcodes of the `controller` target. Arguments follow the opcode (see [`Reader`]).
pub mod ops {
    /// `n: u8`: run `max(n, 1)` cycles of 1 ms.
    pub const STEP: u8 = 0;
    /// `ms: u16`: jump `max(ms, 1)` ms ahead and run one cycle (a stalled machine).
    pub const SKIP: u8 = 1;
    /// `bytes`: hand the controller an acyclic frame, as the cycle thread does.
    pub const FRAME: u8 = 2;
    /// `device: u8, port: u16, bytes`: a UDP datagram to port 34964 from a device's address.
    pub const DATAGRAM: u8 = 3;
    /// `bytes`: a frame on the wire, received by the cycle thread (cyclic or handed over).
    pub const WIRE: u8 = 4;
    /// `filter: u8, skip: u8, how: u8, at: u16, value: u8`: change a message a device sends
    /// to the controller: the `skip`-th next one that passes `filter` (0 any, 1 datagrams,
    /// 2 acyclic frames, 3 cyclic frames); `how` 0 flips bits (`value`, at least one) at
    /// `at`, 1 cuts it to `at` bytes, 2 drops it, 3 delivers it twice.
    pub const TAMPER: u8 = 5;
    /// `online: u8`: online (odd) or offline (even).
    pub const ONLINE: u8 = 6;
    /// `device: u8, active: u8`: activate (odd) or deactivate (even) a device.
    pub const ACTIVATE: u8 = 7;
    /// `device: u8, slot: u16, subslot: u16, index: u16, max_len: u16, write: u8, bytes`: a
    /// record read (`write` even) or write of `bytes`.
    pub const RECORD: u8 = 8;
    /// Acknowledge every alarm the controller reported and is waiting for.
    pub const ACK_ALARMS: u8 = 9;
    /// `device: u8, usi: u16, bytes`: the device raises a process alarm on its IO submodule.
    pub const RAISE_ALARM: u8 = 10;
    /// `device: u8, epoch: u32`: the cycle thread reports a watchdog expiry.
    pub const WATCHDOG: u8 = 11;
    /// `submodule: u8, iops: u8, bytes`: a client writes outputs (IOPS GOOD if `iops` odd).
    pub const OUTPUTS: u8 = 12;
    /// Number of opcodes (an opcode byte is taken modulo this).
    pub const COUNT: u8 = 13;
}

/// Opcodes of the `device` target.
pub mod device_ops {
    /// `n: u8`: `max(n, 1)` ms of time, polling every ms.
    pub const STEP: u8 = 0;
    /// `bytes`: an Ethernet frame on the device's link.
    pub const FRAME: u8 = 1;
    /// `from_port: u16, to_port: u16, bytes`: a UDP datagram from the controller's address to
    /// the device's port 34964 (a call) or another port (the answer to a call of the
    /// device's own).
    pub const DATAGRAM: u8 = 2;
    /// `usi: u16, bytes`: the device raises a process alarm on its IO submodule.
    pub const RAISE_ALARM: u8 = 3;
    /// `ms: u8`: the device hands its cyclic exchange over to a cycle of `max(ms, 1)` ms (as
    /// procimgd's device role does); what it hands out is checked against its frames.
    pub const HAND_OVER: u8 = 4;
    /// `expired: u8, epoch: u8`: the cycle reports the first frame (even) or the watchdog
    /// (odd) of exchange `epoch`.
    pub const CYCLE_REPORT: u8 = 5;
    /// `op: u8, slot: u8, channel: u16, error: u16, severity: u8`: a diagnosis added (op
    /// even) or removed on slot `slot % 3`, subslot 1.
    pub const DIAGNOSIS: u8 = 6;
    /// `on: u8`: the device takes part (odd) or stops.
    pub const ACCEPTING: u8 = 7;
    /// `what: u8, arg: u8, len: u8`: the application's part (`what % 14`): 0 takes (arg odd)
    /// or gives back the records of slot `arg % 3`, subslot 1; 1 answers job `arg` of those
    /// given out (with `len` bytes, or an error when `len` > 200; a job number never given out
    /// when there are none); 2 holds the ApplicationReady (arg odd) or not; 3 releases it;
    /// 4 checks new ARs (arg odd) or not; 5 answers the last AR check (accepts when `len` is
    /// even, else refuses with ErrorCode1 `arg`, ErrorCode2 `len`); 6 pulls the submodule
    /// of slot `arg % 3`, subslot 1, if it is plugged, else plugs it (with what was there
    /// when `len` is even, else with module `len`, submodule `arg`); 7 announces its return;
    /// 8 hands its I&M records to the application (arg odd) or not; 9 keeps a diagnosis of
    /// it without an alarm (added when `len` is even, removed when odd, all cleared when
    /// `len` > 200); 10 sends the application's diagnosis alarm (appearing when `arg` is
    /// odd) with USI `0x8000 + len % 4` (manufacturer `len` when `len` > 100) and `len`
    /// bytes; 11 a process alarm with `len` bytes; 12 marks it "application ready pending";
    /// 13 takes the submodules whose PlugPrmEnd came.
    pub const APPLICATION: u8 = 8;
    /// Number of opcodes.
    pub const COUNT: u8 = 9;
}

/// How a message is changed.
#[derive(Clone, Copy, Debug)]
enum How {
    Flip { at: usize, xor: u8 },
    Cut(usize),
    Drop,
    Twice,
}

/// A pending change to a device's message.
#[derive(Clone, Copy, Debug)]
struct Tamper {
    filter: u8,
    skip: u8,
    how: How,
}

/// Applies a pending [`Tamper`] to a device's message: the messages to deliver instead. The
/// tamper is used up once it changed a message.
fn tampered(pending: &mut Option<Tamper>, m: Intercepted) -> Vec<Vec<u8>> {
    let Some(t) = pending.as_mut() else {
        return vec![m.bytes];
    };
    let wanted = match t.filter {
        1 => m.kind == Kind::Datagram,
        2 => m.kind == Kind::Acyclic,
        3 => m.kind == Kind::Cyclic,
        _ => true,
    };
    if !wanted {
        return vec![m.bytes];
    }
    if t.skip > 0 {
        t.skip -= 1;
        return vec![m.bytes];
    }
    let how = t.how;
    *pending = None;
    let mut msg = m.bytes;
    match how {
        How::Flip { at, xor } => {
            if !msg.is_empty() {
                let i = at % msg.len();
                msg[i] ^= xor;
            }
            vec![msg]
        }
        How::Cut(n) => {
            msg.truncate(n);
            vec![msg]
        }
        How::Drop => Vec::new(),
        How::Twice => vec![msg.clone(), msg],
    }
}

/// What the controller sent toward one device, with the cycle it was sent in.
#[derive(Clone, Debug)]
pub enum Sent {
    /// An Ethernet frame the device took a look at.
    Frame(u64, Vec<u8>),
    /// A datagram to the device: (cycle, source port, destination port, payload).
    Datagram(u64, u16, u16, Vec<u8>),
}

/// procimgd's cycle thread as the controller's port: the PROFINET IO system over an
/// in-process link whose other end is the simulated segment, with the image it fills and
/// sends from. Full queues drop frames and commands, as they would in procimgd.
pub struct Cycle {
    io: PnioIo,
    channel: Arc<Channel>,
    /// The segment's end of the link.
    plant: sim_link::LinkEnd,
    image: Image,
}

impl Cycle {
    fn new(config: &Config, tables: &Tables, ranges: Vec<core::ops::Range<usize>>) -> Cycle {
        let (nic, plant) = sim_link::link(SIM_CONTROLLER_MAC, MacAddress::default());
        let channel = Arc::new(Channel::new());
        Cycle {
            io: PnioIo::new(Box::new(nic), channel.clone(), ranges, config.cycle_ns),
            channel,
            plant,
            image: Image::new(tables),
        }
    }

    const fn time(tick: Tick) -> CycleTime {
        CycleTime {
            cycle: tick.cycle,
            now_ns: tick.now_ns,
        }
    }
}

impl Port for Cycle {
    fn transmit(&mut self, frame: Vec<u8>) {
        wire_check::emitted_frame("the controller", &frame);
        let _ = self.channel.send(&frame);
    }

    fn start(&mut self, ar: Box<CyclicAr>) {
        let _ = self.channel.to_cycle.push(ToCycle::Start(ar));
    }

    fn stop(&mut self, device: usize) {
        let _ = self.channel.to_cycle.push(ToCycle::Stop { device });
    }

    fn arrive(&mut self, frame: &[u8]) {
        // A full link drops the frame, as a real one would.
        let _ = self.plant.send(&frame[..frame.len().min(MAX_FRAME)]);
    }

    fn depart(&mut self, out: &mut Vec<Vec<u8>>) {
        while let Ok(true) = self.plant.receive(&mut |frame| out.push(frame.to_vec())) {}
    }

    fn receive(&mut self, tick: Tick, reports: &mut Vec<Report>) {
        self.io
            .receive(Cycle::time(tick), Mode::Operate, &mut self.image);
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
            .send(Cycle::time(tick), Mode::Operate, &mut self.image);
    }
}

/// Checks what the controller and the devices send, before the network changes it; what the
/// controller sends as frames is checked on its way to the cycle ([`Cycle`]).
fn check(r: &Record) {
    let who = match r.origin {
        Origin::Controller => "the controller",
        Origin::Device(_) => "a simulated device",
        Origin::Injected => return,
    };
    match &r.message {
        Message::Frame(f) if r.origin != Origin::Controller => wire_check::emitted_frame(who, f),
        Message::Frame(_) => {}
        Message::Datagram { payload, .. } => wire_check::emitted_datagram(who, payload),
    }
}

/// The controller, the cycle thread's IO system and the simulated devices.
pub struct World {
    net: net::World<DemoApplication, Cycle>,
    /// Image submodule index of each device's IO submodule (slot 1).
    io_submodules: Vec<usize>,
    cycles_run: u32,
}

impl Default for World {
    fn default() -> Self {
        World::new()
    }
}

impl World {
    /// The network of [`CONFIG`], offline, at cycle 1.
    pub fn new() -> World {
        let config = config();
        let tables = Tables::from_config(config).expect("tables");
        let plans = procimg_runtime::roles::controller::plan_devices(config).expect("plans");
        let ranges = plans
            .iter()
            .map(|p| p.first_submodule..p.first_submodule + p.submodules.len())
            .collect();
        let id = net::controller_identity(SIM_CONTROLLER_MAC, SIM_CONTROLLER_IP, "procimgd-fuzz");
        let io_submodules = config
            .devices
            .iter()
            .enumerate()
            .filter_map(|(d, _)| {
                tables
                    .submodules
                    .iter()
                    .position(|s| s.device as usize == d && s.slot == 1)
            })
            .collect();
        let cycle = Cycle::new(config, &tables, ranges);
        let mut net = net::World::new(Setup::new(id, plans), sim_plant::devices(config), cycle);
        // The controller's own station answers DCP, as on a real interface: the arbitrary
        // frames reach its responder too.
        net.with_controller(|c, _, _| c.answer_dcp("procimg controller"));
        net.tap(|r| {
            check(r);
            false
        });
        World {
            net,
            io_submodules,
            cycles_run: 0,
        }
    }

    /// Records what the controller sends to device 0 from now on.
    pub fn start_recording(&mut self) {
        let mac = sim_plant::device_mac(0);
        let ip = config().devices[0]
            .ip
            .map_or(sim_plant::own_ip(0), |ip| ip.octets());
        self.net.tap(move |r| {
            check(r);
            r.origin == Origin::Controller
                && match &r.message {
                    Message::Frame(f) => {
                        f.get(..6) == Some(&mac.0[..])
                            || f.get(..6) == Some(&MacAddress::DCP_IDENTIFY.0[..])
                    }
                    Message::Datagram { to, .. } => to.ip().octets() == ip,
                }
        });
    }

    /// What was recorded.
    pub fn recorded(&self) -> Vec<Sent> {
        self.net
            .tapped()
            .iter()
            .map(|r| {
                let cycle = r.at_ns / MS;
                match &r.message {
                    Message::Frame(f) => Sent::Frame(cycle, f.clone()),
                    Message::Datagram { from, to, payload } => {
                        Sent::Datagram(cycle, from.port(), to.port(), payload.clone())
                    }
                }
            })
            .collect()
    }

    /// The controller's view of every device.
    pub fn states(&self) -> Vec<DeviceState> {
        self.net.states()
    }

    /// The current cycle (= ms of simulated time).
    pub const fn cycle(&self) -> u64 {
        self.net.cycle()
    }

    /// Runs a whole operation sequence; stops at the first incomplete operation.
    pub fn run(&mut self, input: &[u8]) {
        let mut r = Reader::new(input);
        while self.op(&mut r).is_some() {}
    }

    /// One operation; `None` when the input ended inside it.
    fn op(&mut self, r: &mut Reader<'_>) -> Option<()> {
        match r.u8()? % ops::COUNT {
            ops::STEP => {
                for _ in 0..r.u8()?.max(1) {
                    self.advance(1);
                }
            }
            ops::SKIP => self.advance(u64::from(r.u16()?.max(1))),
            ops::FRAME => {
                let f = r.bytes()?;
                self.net
                    .with_controller(|c, now, out| c.on_frame(f, now, out));
            }
            ops::DATAGRAM => {
                let d = usize::from(r.u8()?);
                let port = r.u16()?;
                let devices = self.net.devices();
                let ip = devices.get(d % devices.len()).map(|d| d.station().ip());
                let from = SocketAddrV4::new(ip.unwrap_or([0; 4]).into(), port);
                let bytes = r.bytes()?;
                self.net
                    .with_controller(|c, now, out| c.on_datagram(from, bytes, now, out));
            }
            ops::WIRE => {
                let f = r.bytes()?;
                self.net.inject_frame(&f[..f.len().min(MAX_FRAME)]);
            }
            ops::TAMPER => {
                let (filter, skip, how) = (r.u8()?, r.u8()?, r.u8()?);
                let (at, value) = (usize::from(r.u16()?), r.u8()?);
                let how = match how % 4 {
                    0 => How::Flip {
                        at,
                        xor: value.max(1),
                    },
                    1 => How::Cut(at),
                    2 => How::Drop,
                    _ => How::Twice,
                };
                let mut pending = Some(Tamper {
                    filter: filter % 4,
                    skip,
                    how,
                });
                self.net
                    .intercept(Some(Box::new(move |m| tampered(&mut pending, m))));
            }
            ops::ONLINE => {
                let online = r.u8()? % 2 == 1;
                self.net.set_online(online);
            }
            ops::ACTIVATE => {
                let (d, active) = (usize::from(r.u8()?), r.u8()? % 2 == 1);
                // Also an index past the devices: the controller must refuse it.
                self.net.with_controller(|c, now, out| {
                    let _ = c.activate(d % 4, active, now, out);
                });
            }
            ops::RECORD => {
                let device = usize::from(r.u8()? % 4);
                let (slot, subslot, index) = (r.u16()?, r.u16()?, r.u16()?);
                let max_len = u32::from(r.u16()?);
                let write = r.u8()? % 2 == 1;
                let data = r.bytes()?;
                let request = RecordRequest {
                    reference: self.net.cycle(),
                    device,
                    api: 0,
                    slot,
                    subslot,
                    index,
                    max_len,
                    write: write.then(|| data.to_vec()),
                };
                self.net.with_controller(|c, _, out| c.record(request, out));
            }
            ops::ACK_ALARMS => {
                // Every alarm reported since the last acknowledgement.
                let tickets: Vec<AlarmTicket> = self
                    .net
                    .take_events()
                    .into_iter()
                    .filter_map(|e| match e {
                        DeviceEvent::Alarm { ticket, .. } => Some(ticket),
                        _ => None,
                    })
                    .collect();
                self.net.with_controller(|c, now, out| {
                    for t in tickets {
                        let _ = c.acknowledge_alarm(t, now, out);
                    }
                });
            }
            ops::RAISE_ALARM => {
                let d = usize::from(r.u8()?) % self.net.devices().len();
                let usi = r.u16()?;
                let data = r.bytes()?;
                self.net.with_device(d, |dev, now, out| {
                    let _ = dev.raise_process_alarm(0, 1, 1, usi, data, now, out);
                });
            }
            ops::WATCHDOG => {
                let (d, epoch) = (usize::from(r.u8()?), r.u32()?);
                self.net
                    .with_controller(|c, now, out| c.on_watchdog(d % 4, epoch, now, out));
            }
            ops::OUTPUTS => {
                let s = usize::from(r.u8()?) % self.io_submodules.len();
                let good = r.u8()? % 2 == 1;
                let data = r.bytes()?;
                let s = self.io_submodules[s];
                let image = &mut self.net.port_mut().image;
                let outputs = image.outputs_mut(s);
                let n = outputs.len().min(data.len());
                outputs[..n].copy_from_slice(&data[..n]);
                let mut st = image.status(s);
                st.output_iops = if good { IOXS_GOOD } else { IOXS_BAD };
                image.set_status(s, st);
            }
            _ => unreachable!("opcode taken modulo COUNT"),
        }
        Some(())
    }

    /// Moves time on by `ms` and runs one cycle, unless the input already used its cycles.
    fn advance(&mut self, ms: u64) {
        if self.cycles_run >= MAX_CYCLES {
            return;
        }
        self.cycles_run += 1;
        self.net.advance(ms * MS);
        // The controller never asks to be polled later than it needs to.
        if let Some(d) = self.net.controller().next_deadline_ns() {
            assert!(d > 0, "a deadline at time 0");
        }
    }
}

/// Runs the fuzz network from OFFLINE until both devices are in data exchange, then 20 ms
/// more; returns the operations that did it (a seed for the `controller` target) and what
/// the controller sent to device 0 (the material of the `device` seeds).
pub fn record_bringup() -> (Vec<u8>, Vec<Sent>) {
    let mut seed = Writer::new();
    let mut w = World::new();
    w.start_recording();
    let mut online = Writer::new();
    online.u8(ops::ONLINE).u8(1);
    w.run(&online.finish());
    seed.u8(ops::ONLINE).u8(1);
    // 1 ms steps, so that every answer is seen at its time, batched as one STEP per 255.
    let mut steps: u32 = 0;
    while w.states().iter().any(|s| *s != DeviceState::Running) {
        w.run(&[ops::STEP, 1]);
        steps += 1;
        assert!(steps < 2 * MAX_CYCLES, "no bring-up: {:?}", w.states());
    }
    for _ in 0..20 {
        w.run(&[ops::STEP, 1]);
        steps += 1;
    }
    while steps > 0 {
        let n = steps.min(255);
        seed.u8(ops::STEP).u8(n as u8);
        steps -= n;
    }
    (seed.finish(), w.recorded())
}

/// One simulated device alone: the `device` target.
pub struct DeviceBench {
    device: DemoDevice,
    /// Record jobs given to the application so far.
    jobs: Vec<u64>,
    /// AR checks given to the application so far.
    checks: Vec<u64>,
    /// What was plugged at each position pulled so far: (position, module, submodule).
    pulled: Vec<(SubslotAddr, u32, u32)>,
    now: u64,
    steps: u32,
    /// The last operation polled the device at `now`.
    polled: bool,
}

impl Default for DeviceBench {
    fn default() -> Self {
        DeviceBench::new()
    }
}

impl DeviceBench {
    /// Device 0 of [`CONFIG`], at time 1 ms.
    pub fn new() -> DeviceBench {
        let device = sim_plant::devices(config()).swap_remove(0);
        DeviceBench {
            device,
            jobs: Vec::new(),
            checks: Vec::new(),
            pulled: Vec::new(),
            now: MS,
            steps: 0,
            polled: false,
        }
    }

    /// The application's part of [`device_ops::APPLICATION`].
    fn application(&mut self, what: u8, arg: u8, len: u8, out: &mut Vec<DeviceAction>) {
        match what {
            0 => self
                .device
                .delegate_records(SubslotAddr::new(0, u16::from(arg % 3), 1), arg % 2 == 1),
            1 => {
                let job = match self.jobs.len() {
                    0 => u64::from(arg) << 40,
                    n => self.jobs.remove(usize::from(arg) % n),
                };
                let answer = if len > 200 {
                    Err((RecordErrorCode::InvalidParameter, len))
                } else {
                    Ok(vec![len; usize::from(len)])
                };
                // Answered jobs, timed-out ones and unknown numbers are refused: fine.
                let _ = self.device.answer_record(job, answer, out);
            }
            2 => self.device.hold_application_ready(arg % 2 == 1),
            3 => {
                let _ = self.device.release_application_ready(self.now);
            }
            4 => self.device.check_connects(arg % 2 == 1),
            6 => {
                let at = SubslotAddr::new(0, u16::from(arg % 3), 1);
                // Refusals (unconfigured, starting up) are part of what is tried: fine.
                if self.device.plugging().is_plugged(at) {
                    let was = self.device.plugging().real_submodule(at);
                    if self.device.pull_submodule(at, self.now, out).is_ok()
                        && let Some((m, sub)) = was
                    {
                        self.pulled.push((at, m, sub));
                    }
                } else {
                    let idents = self
                        .pulled
                        .iter()
                        .rev()
                        .find(|p| p.0 == at && len.is_multiple_of(2))
                        .map_or((u32::from(len), u32::from(arg)), |p| (p.1, p.2));
                    let _ = self
                        .device
                        .plug_submodule(at, idents.0, idents.1, self.now, out);
                }
            }
            7 => {
                let at = SubslotAddr::new(0, u16::from(arg % 3), 1);
                let _ = self.device.return_submodule(at, self.now, out);
            }
            8 => self
                .device
                .delegate_im_records(SubslotAddr::new(0, u16::from(arg % 3), 1), arg % 2 == 1),
            9 => {
                let at = SubslotAddr::new(0, u16::from(arg % 3), 1);
                let entry = DiagEntry::Channel(ChannelDiag::new(u16::from(arg), u16::from(len)));
                let edit = match len {
                    201.. => DiagnosisEdit::Clear,
                    l if l % 2 == 0 => DiagnosisEdit::Add(entry),
                    _ => DiagnosisEdit::Remove(entry.key()),
                };
                // Unknown submodules and invalid entries are refused: fine.
                let _ = self.device.keep_diagnosis(at, edit);
            }
            10 => {
                let at = SubslotAddr::new(0, u16::from(arg % 3), 1);
                let usi = if len > 100 {
                    u16::from(len)
                } else {
                    0x8000 + u16::from(len % 4)
                };
                let data = vec![len; usize::from(len)];
                // Without data exchange, or too long: refused, fine.
                let _ =
                    self.device
                        .raise_diagnosis_alarm(at, arg % 2 == 1, usi, &data, self.now, out);
            }
            11 => {
                let at = SubslotAddr::new(0, u16::from(arg % 3), 1);
                let data = vec![arg; usize::from(len)];
                let _ = self
                    .device
                    .send_process_alarm(at, u16::from(arg), &data, self.now, out);
            }
            12 => {
                self.device
                    .application_ready_pending([SubslotAddr::new(0, u16::from(arg % 3), 1)])
            }
            13 => {
                let _ = self.device.take_plug_parameterized();
            }
            _ => {
                let answer = if len.is_multiple_of(2) {
                    Ok(())
                } else {
                    Err((arg, len))
                };
                let check = self.checks.pop().unwrap_or(u64::from(arg) << 40);
                // Answered, timed-out and unknown checks are refused: fine.
                let _ = self.device.answer_connect(check, answer, self.now, out);
            }
        }
    }

    /// Runs a whole operation sequence ([`device_ops`]).
    pub fn run(&mut self, input: &[u8]) {
        let mut r = Reader::new(input);
        while self.op(&mut r).is_some() {}
    }

    fn op(&mut self, r: &mut Reader<'_>) -> Option<()> {
        let mut out = Vec::new();
        let controller = SocketAddrV4::new(SIM_CONTROLLER_IP, RPC_PORT);
        let op = r.u8()? % device_ops::COUNT;
        self.polled = false;
        match op {
            device_ops::STEP => {
                for _ in 0..r.u8()?.max(1) {
                    if self.steps >= MAX_CYCLES {
                        break;
                    }
                    self.steps += 1;
                    self.now += MS;
                    self.device.poll(self.now, &mut out);
                    self.polled = true;
                }
            }
            device_ops::FRAME => self.device.on_frame(r.bytes()?, self.now, &mut out),
            device_ops::DATAGRAM => {
                let (from_port, to_port) = (r.u16()?, r.u16()?);
                let bytes = r.bytes()?;
                let from = SocketAddrV4::new(*controller.ip(), from_port);
                self.device
                    .on_datagram(from, to_port, bytes, self.now, &mut out);
            }
            device_ops::RAISE_ALARM => {
                let usi = r.u16()?;
                let data = r.bytes()?;
                let _ = self
                    .device
                    .raise_process_alarm(0, 1, 1, usi, data, self.now, &mut out);
            }
            device_ops::HAND_OVER => {
                let ms = u64::from(r.u8()?.max(1));
                self.device.hand_over_cyclic(ms * MS);
            }
            device_ops::CYCLE_REPORT => {
                let (expired, epoch) = (r.u8()? % 2 == 1, u32::from(r.u8()?));
                if expired {
                    self.device.cyclic_expired(epoch, self.now, &mut out);
                } else {
                    let _ = self.device.cyclic_started(epoch, self.now);
                }
            }
            device_ops::DIAGNOSIS => {
                let (op, slot) = (r.u8()?, u16::from(r.u8()? % 3));
                let (channel, error, severity) = (r.u16()?, r.u16()?, r.u8()?);
                let entry = ChannelDiag::new(channel, error).with_severity(match severity % 3 {
                    0 => Severity::Fault,
                    1 => Severity::MaintenanceRequired,
                    _ => Severity::MaintenanceDemanded,
                });
                let _ = if op % 2 == 0 {
                    self.device
                        .add_diagnosis(0, slot, 1, entry, self.now, &mut out)
                } else {
                    self.device.remove_diagnosis(
                        0,
                        slot,
                        1,
                        &DiagEntry::from(entry).key(),
                        self.now,
                        &mut out,
                    )
                };
            }
            device_ops::ACCEPTING => {
                let on = r.u8()? % 2 == 1;
                self.device.set_accepting(on, self.now, &mut out);
            }
            device_ops::APPLICATION => {
                let (what, arg, len) = (r.u8()? % 14, r.u8()?, r.u8()?);
                self.application(what, arg, len, &mut out);
            }
            _ => unreachable!("opcode taken modulo COUNT"),
        }
        for a in out {
            match a {
                DeviceAction::Frame(f) => wire_check::emitted_frame("the simulated device", &f),
                DeviceAction::Datagram { payload, .. } => {
                    wire_check::emitted_datagram("the simulated device", &payload)
                }
                DeviceAction::StartCyclic(ar) => self.check_exchange(&ar),
                DeviceAction::StopCyclic { .. } => {}
                DeviceAction::Record(job) => {
                    assert!(
                        job.index <= 0x7fff,
                        "only user records go to the application: {job:?}"
                    );
                    self.jobs.push(job.job);
                }
                DeviceAction::ArCheck(check) => self.checks.push(check.job),
                // DCP Sets are not checked here.
                DeviceAction::DcpSetCheck(_) => {}
            }
        }
        // A poll does what is due: what it leaves is due later (else its caller would spin).
        // Before the first poll, "due at once" (the first announcements) is fine.
        if self.polled
            && let Some(d) = self.device.next_deadline_ns()
        {
            assert!(
                d > self.now,
                "a deadline at {d} ns, not after the poll at {} ns",
                self.now
            );
        }
        Some(())
    }
}

impl DeviceBench {
    /// An exchange handed to a cycle must stay within its frames and the submodule table,
    /// whatever the Connect asked for: the cycle thread trusts it.
    fn check_exchange(&self, ar: &CyclicAr) {
        let plugged = ar.submodules.end;
        for (cr, what) in [(&ar.input, "consumed"), (&ar.output, "produced")] {
            assert!(
                cr.data_length <= procimg_profinet::wire::rt::MAX_DATA_LENGTH,
                "the {what} CR's C_SDU is {} bytes",
                cr.data_length
            );
            for o in &cr.objects {
                assert!(
                    o.data + o.len <= cr.data_length && o.iops < cr.data_length,
                    "a data object of the {what} CR lies outside it: {o:?}"
                );
                assert!(
                    o.submodule < plugged,
                    "a data object of no plugged submodule: {o:?}"
                );
            }
            for c in &cr.iocs {
                assert!(
                    c.offset < cr.data_length,
                    "an IOCS of the {what} CR lies outside it"
                );
                assert!(
                    c.submodule < plugged,
                    "an IOCS of no plugged submodule: {c:?}"
                );
            }
        }
        assert_eq!(
            ar.frame.len(),
            ar.payload_offset() + 2 + ar.output.data_length + 4,
            "the produced frame's length"
        );
        assert!(ar.timing.every_cycles >= 1);
    }
}

/// The `device` seed for what the controller sent to device 0: the frames and datagrams
/// at the cycles they were sent.
pub fn device_seed(sent: &[Sent]) -> Vec<u8> {
    let mut w = Writer::new();
    let mut at = 1u64;
    for s in sent {
        let cycle = match s {
            Sent::Frame(c, _) | Sent::Datagram(c, ..) => *c,
        };
        let mut gap = cycle.saturating_sub(at);
        while gap > 0 {
            let n = gap.min(255);
            w.u8(device_ops::STEP).u8(n as u8);
            gap -= n;
        }
        at = cycle;
        match s {
            Sent::Frame(_, f) => {
                w.u8(device_ops::FRAME).bytes(f);
            }
            Sent::Datagram(_, from_port, to_port, p) => {
                w.u8(device_ops::DATAGRAM)
                    .u16(*from_port)
                    .u16(*to_port)
                    .bytes(p);
            }
        }
    }
    w.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_recorded_bring_up_brings_both_devices_up_again() {
        let (seed, sent) = record_bringup();
        let mut w = World::new();
        w.run(&seed);
        assert!(w.states().iter().all(|s| *s == DeviceState::Running));
        assert!(sent.iter().any(|s| matches!(s, Sent::Datagram(..))));
    }

    #[test]
    fn the_device_replays_the_recorded_conversation() {
        let (_, sent) = record_bringup();
        let mut b = DeviceBench::new();
        b.run(&device_seed(&sent));
        let kinds: Vec<_> = sent
            .iter()
            .map(|s| match s {
                Sent::Frame(c, f) => format!("{c} frame {}", f.len()),
                Sent::Datagram(c, _, to, p) => format!("{c} datagram to {to} {}", p.len()),
            })
            .collect();
        assert!(
            b.device.ar().ar_uuid().is_some(),
            "no AR after the replay of {kinds:#?}"
        );
    }
}
