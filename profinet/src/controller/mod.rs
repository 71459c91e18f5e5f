// SPDX-License-Identifier: MIT OR Apache-2.0
//! The IO controller, sans-IO: one state machine per configured device (see [`device`]),
//! the RPC server side for the devices' ApplicationReady, and the routing of frames and
//! datagrams to the right device.
//!
//! Feed it Ethernet frames ([`Controller::on_frame`]), UDP datagrams of port 34964
//! ([`Controller::on_datagram`]), the cycle thread's reports ([`Controller::on_watchdog`],
//! [`Controller::on_data_started`]) and the time ([`Controller::poll`]); it answers with
//! [`ControllerAction`]s: frames and datagrams to send, devices' MAC addresses for the driver's
//! neighbour table, cyclic exchanges to start or stop, and events for clients and the log.
//! No socket, no clock, no thread inside.

pub mod cyclic;
pub mod device;
mod failure;
mod interface;
pub mod plan;
pub mod rpc_call;
mod station;
mod tailoring;
pub mod uuids;

use crate::wire::MacAddress;
use crate::wire::PnioStatus;
use crate::wire::alarm::{AlarmNotification, Priority};
use crate::wire::connect::ModuleDiffBlock;
use crate::wire::control::ControlBlock;
use crate::wire::rpc::{self, Header, Ndr, PacketType, opnum};
use cyclic::CyclicAr;
use device::DeviceAr;
pub use failure::FailureCause;
pub use interface::{
    AddressError, INTERFACE_SUBMODULE_IDENT, INTERFACE_SUBSLOT, InterfaceSetup, MODULE_IDENT,
    PORT_SUBMODULE_IDENT, PORT_SUBSLOT, StationAddress,
};
use plan::{ControllerIdentity, DevicePlan};
use std::net::{Ipv4Addr, SocketAddrV4};
pub use tailoring::{PortEnd, Reconfiguration, TailorError, port_id};

/// Where a device is in its life.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum DeviceState {
    /// Not wanted: the controller is OFFLINE.
    Offline,
    /// Deactivated by a client.
    Deactivated,
    /// Looking for it by name (DCP Identify).
    Searching,
    /// Giving it its IP address (DCP Set).
    SettingIp,
    /// Connect sent.
    Connecting,
    /// Writing its parameter records.
    Parameterizing,
    /// PrmEnd done; waiting for its ApplicationReady.
    WaitingForApplicationReady,
    /// Data exchange.
    Running,
    /// Something failed; it is tried again after a back-off.
    Failed,
}

impl DeviceState {
    /// A word for messages and status.
    pub const fn as_str(self) -> &'static str {
        match self {
            DeviceState::Offline => "offline",
            DeviceState::Deactivated => "deactivated",
            DeviceState::Searching => "searching",
            DeviceState::SettingIp => "setting-ip",
            DeviceState::Connecting => "connecting",
            DeviceState::Parameterizing => "parameterizing",
            DeviceState::WaitingForApplicationReady => "waiting-for-application-ready",
            DeviceState::Running => "running",
            DeviceState::Failed => "failed",
        }
    }
}

impl core::fmt::Display for DeviceState {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A record read or write a client asked for.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RecordRequest {
    /// The client's reference, echoed in the result.
    pub reference: u64,
    /// Device index.
    pub device: usize,
    /// API.
    pub api: u32,
    /// Slot.
    pub slot: u16,
    /// Subslot.
    pub subslot: u16,
    /// Record index.
    pub index: u16,
    /// Read: the most bytes wanted.
    pub max_len: u32,
    /// Write: the data; `None` for a read.
    pub write: Option<Vec<u8>>,
}

/// Why a record job failed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RecordFailure {
    /// The PNIOStatus of the answer, or (0xC0, 0x80, 0xA3, 0) when there was no connection
    /// or it broke, as IO-Base reports it.
    pub status: PnioStatus,
    /// AdditionalValue1 of the answer.
    pub add_value1: u16,
    /// AdditionalValue2 of the answer.
    pub add_value2: u16,
    /// The failure in words.
    pub reason: String,
}

impl RecordFailure {
    /// There is no connection to the device, or it broke.
    pub fn no_connection(reason: impl Into<String>) -> RecordFailure {
        RecordFailure {
            status: PnioStatus {
                error_code: 0xC0,
                error_decode: 0x80,
                error_code1: 0xA3,
                error_code2: 0,
            },
            add_value1: 0,
            add_value2: 0,
            reason: reason.into(),
        }
    }
}

/// A record job that succeeded.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RecordData {
    /// The record read (empty for a write).
    pub data: Vec<u8>,
    /// AdditionalValue1 (for a read, 1 means the record holds more than was read).
    pub add_value1: u16,
    /// AdditionalValue2.
    pub add_value2: u16,
}

/// The outcome of a [`RecordRequest`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RecordResult {
    /// The request.
    pub request: RecordRequest,
    /// The data read, or why it failed.
    pub result: Result<RecordData, RecordFailure>,
}

/// Names an alarm whose AlarmAck waits for [`Controller::acknowledge_alarm`]: the device
/// sends no further alarm of this priority until it has it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct AlarmTicket {
    /// Device index.
    pub device: usize,
    /// The AR the alarm came on (an AR set up later does not take its ack).
    pub epoch: u32,
    /// The alarm's priority (one outstanding alarm per priority).
    pub priority: Priority,
}

/// What happened to a device, for clients and the log.
#[derive(Clone, Debug, PartialEq)]
pub enum DeviceEvent {
    /// Its state changed.
    State {
        /// Device index.
        device: usize,
        /// New state.
        state: DeviceState,
    },
    /// It left data exchange: it failed, or it was deactivated or released (IO-Base
    /// DEV_FAILURE).
    Failure {
        /// Device index.
        device: usize,
        /// What kind of failure.
        cause: FailureCause,
        /// Why.
        reason: String,
        /// Asked for (deactivation, OFFLINE) rather than a fault.
        planned: bool,
        /// The PNIO status of the failure, if there is one: the ERR-RTA's `CF 81 FD <code>`
        /// of an AR aborted by either side.
        status: Option<PnioStatus>,
    },
    /// It entered data exchange, the first time or again (IO-Base DEV_RETURN).
    Return {
        /// Device index.
        device: usize,
    },
    /// Bringing it up failed (it was not yet running).
    Problem {
        /// Device index.
        device: usize,
        /// What kind of failure.
        cause: FailureCause,
        /// Why.
        reason: String,
        /// The PNIO status of the failure, if there is one: a negative Connect, Write or
        /// PrmEnd response's, or the ERR-RTA's of an aborted AR.
        status: Option<PnioStatus>,
    },
    /// Its real configuration differs from the expected one.
    ModuleDiff {
        /// Device index.
        device: usize,
        /// The difference, as the device reported it.
        diff: ModuleDiffBlock,
    },
    /// It sent an alarm; acknowledge it with [`Controller::acknowledge_alarm`].
    Alarm {
        /// Device index.
        device: usize,
        /// The notification.
        notification: Box<AlarmNotification>,
        /// What acknowledges it.
        ticket: AlarmTicket,
    },
    /// A client's activation or deactivation was taken (IO-Base `PNIO_CBE_DEV_ACT_CONF`).
    Activation {
        /// Device index.
        device: usize,
        /// Activated or deactivated.
        active: bool,
    },
    /// A record read or write finished.
    Record(RecordResult),
    /// A DCP Signal came to the controller's own station: flash its LED (IO-Base's
    /// `PNIO_CBE_START_LED_FLASH`).
    Signal,
    /// A reconfiguration of the IO system ([`Controller::reconfigure`]) was done: the
    /// devices it wanted are activated (`Ok(true)`, a tailoring) or all are deactivated
    /// (`Ok(false)`); or it was refused, changing nothing.
    Reconfigured {
        /// What became of it.
        result: Result<bool, TailorError>,
    },
    /// The controller's own interface raised an alarm (its port's topology check found a
    /// mismatch, or one went): IO-Base's `PNIO_CBE_IFC_ALARM_IND`. Nothing acknowledges it.
    InterfaceAlarm(Box<AlarmNotification>),
    /// The controller's station got a new name or IP suite by DCP from an engineering tool
    /// (`reference` `None`); or, from the runtime, a program's change
    /// ([`Controller::set_station_address`]) was made or refused. The runtime carries the
    /// address out on the host, keeps a permanent change, and tells the programs.
    StationAddress {
        /// What changed, or was to.
        change: StationAddress,
        /// The program's request, if a program asked.
        reference: Option<u64>,
        /// Done, or why not.
        result: Result<(), AddressError>,
    },
    /// A read of a record of the controller's own interface
    /// ([`Controller::read_interface_record`]) ended, for the program that asked.
    InterfaceRecord {
        /// The program's request.
        reference: u64,
        /// The subslot read.
        subslot: u16,
        /// The record index.
        index: u16,
        /// The record, or why not.
        result: Result<Vec<u8>, crate::wire::record::RecordErrorCode>,
    },
}

/// What the controller asks its driver to do.
#[derive(Debug)]
pub enum ControllerAction {
    /// Send this Ethernet frame.
    Frame(Vec<u8>),
    /// Send this UDP datagram from port 34964.
    Datagram {
        /// Destination.
        to: SocketAddrV4,
        /// The RPC PDU.
        payload: Vec<u8>,
    },
    /// The device at `ip` has the MAC address `mac` (DCP found it there): the driver tells
    /// its network stack, before the RPC calls to the device that follow. Otherwise the stack
    /// resolves the address itself (ARP) and holds the calls until it does; a call repeated
    /// meanwhile (after its retry time) is held beside the first, and both reach the device
    /// at once when the address resolves, which some devices take for a second Connect to an
    /// AR they hold and abort.
    Neighbour {
        /// The device's IP address.
        ip: Ipv4Addr,
        /// Its MAC address.
        mac: MacAddress,
    },
    /// Start (or replace) a device's cyclic exchange.
    Start(Box<CyclicAr>),
    /// Stop a device's cyclic exchange.
    Stop {
        /// Device index.
        device: usize,
    },
    /// Tell clients and the log.
    Event(DeviceEvent),
}

/// Datagrams of port 34964 the controller dropped.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DatagramCounters {
    /// Not an RPC PDU, or one whose header, NDR header or blocks do not parse.
    pub malformed: u64,
    /// Well-formed, but no outstanding call or known AR is theirs.
    pub unexpected: u64,
}

/// The controller.
pub struct Controller {
    id: ControllerIdentity,
    devices: Vec<DeviceAr>,
    /// ServerBootTime in our RPC responses.
    boot_time: u32,
    wanted: bool,
    dropped: DatagramCounters,
    /// What the controller's port announces by LLDP, when it does.
    lldp: Option<crate::port::lldp::Announcer>,
    /// Its port's LLDP neighbours.
    neighbours: crate::port::neighbours::Neighbours,
    /// Its own station's DCP side, when it answers DCP.
    station: Option<station::OwnStation>,
    /// Its own interface: records, settable address, port check.
    interface: interface::OwnInterface,
}

impl Controller {
    /// A controller for `plans`, all devices offline. `seed` is where the UUIDs of its ARs
    /// and RPC activities come from: random in procimgd, a constant where an exchange must
    /// replay.
    pub fn new(
        id: ControllerIdentity,
        plans: Vec<DevicePlan>,
        boot_time: u32,
        seed: u64,
    ) -> Controller {
        let mut uuids = uuids::UuidSource::new(seed);
        Controller {
            id,
            devices: plans
                .into_iter()
                .map(|plan| DeviceAr::new(plan, uuids.split()))
                .collect(),
            boot_time,
            wanted: false,
            dropped: DatagramCounters::default(),
            lldp: None,
            neighbours: Default::default(),
            station: None,
            interface: Default::default(),
        }
    }

    /// Makes the controller's port announce the controller by LLDP (its name, MAC and IP
    /// address, as a PROFINET station's port does: [`crate::port::lldp`]), from the next
    /// poll on and every 5 s, so that its devices know their neighbour; `port` says how the
    /// port is described (its link, ifIndex), the name and addresses come from the
    /// controller's identity. Off until called.
    pub fn announce_by_lldp(&mut self, port: impl FnOnce(&mut crate::port::lldp::LldpStation)) {
        let ip = (!self.id.ip.is_unspecified()).then(|| self.id.ip.octets());
        let mut station = crate::port::lldp::LldpStation::new(
            &self.id.station_name,
            self.id.mac,
            self.id.mac,
            ip,
            1,
        );
        port(&mut station);
        self.lldp = Some(crate::port::lldp::Announcer::new(station));
    }

    /// The controller's port's LLDP neighbours.
    pub fn neighbours(&self) -> &crate::port::neighbours::Neighbours {
        &self.neighbours
    }

    /// The datagrams dropped so far.
    pub fn dropped_datagrams(&self) -> DatagramCounters {
        self.dropped
    }

    /// The controller's identity.
    pub fn identity(&self) -> &ControllerIdentity {
        &self.id
    }

    /// The state of every device.
    pub fn states(&self) -> impl Iterator<Item = DeviceState> + '_ {
        self.devices.iter().map(DeviceAr::state)
    }

    /// The plan of device `d` (for one planned from its RealIdentificationData, the plan of
    /// its last Connect).
    pub fn plan(&self, d: usize) -> Option<&DevicePlan> {
        self.devices.get(d).map(|d| &d.plan)
    }

    /// Online (CLEAR or OPERATE: every active device is brought up) or OFFLINE (every AR
    /// released).
    pub fn set_online(&mut self, online: bool, now: u64, out: &mut Vec<ControllerAction>) {
        self.wanted = online;
        for d in &mut self.devices {
            d.set_wanted(online, &self.id, now, out);
        }
    }

    /// Activates or deactivates one device (IO-Base `PNIO_device_activate`). `false` when
    /// there is no such device.
    pub fn activate(
        &mut self,
        device: usize,
        active: bool,
        now: u64,
        out: &mut Vec<ControllerAction>,
    ) -> bool {
        let Some(d) = self.devices.get_mut(device) else {
            return false;
        };
        if active {
            d.deactivated = false;
            d.set_wanted(self.wanted, &self.id, now, out);
        } else {
            d.deactivated = true;
            d.set_wanted(false, &self.id, now, out);
        }
        out.push(ControllerAction::Event(DeviceEvent::Activation {
            device,
            active,
        }));
        true
    }

    /// Whether every device's RealIdentificationData (0xF000) is read before each Connect,
    /// the expected ident numbers then following what is plugged at the planned positions
    /// (as an engineering tool learns a station). Off from the start.
    pub fn learn_real_identification(&mut self, on: bool) {
        for d in &mut self.devices {
            d.learn_real_identification(on);
        }
    }

    /// Device `device`'s RealIdentificationData (0xF000) is read before each Connect and
    /// `planner` makes the plan connected from it: the device connects with the tree it
    /// has, with the lengths and records its owner knows for it (a GSDML file, say), rather
    /// than with the tree it was planned with (see [`device::TreePlanner`]). `false` when
    /// there is no such device.
    pub fn plan_from_real_identification(
        &mut self,
        device: usize,
        planner: device::TreePlanner,
    ) -> bool {
        let Some(d) = self.devices.get_mut(device) else {
            return false;
        };
        d.plan_from_real_identification(planner);
        true
    }

    /// Sends the AlarmAck of the alarm `ticket` names (positive, as IO-Base does when the
    /// alarm callback returns). `false` when that alarm is no longer waiting (acknowledged
    /// already, or its AR is gone).
    pub fn acknowledge_alarm(
        &mut self,
        ticket: AlarmTicket,
        now: u64,
        out: &mut Vec<ControllerAction>,
    ) -> bool {
        match self.devices.get_mut(ticket.device) {
            Some(d) => d.acknowledge_alarm(ticket, &self.id, now, out),
            None => false,
        }
    }

    /// Queues a record read or write.
    pub fn record(&mut self, r: RecordRequest, out: &mut Vec<ControllerAction>) {
        match self.devices.get_mut(r.device) {
            Some(d) => d.record(r, out),
            None => {
                let why = format!("there is no device {} in the configuration", r.device);
                out.push(ControllerAction::Event(DeviceEvent::Record(RecordResult {
                    request: r,
                    result: Err(RecordFailure::no_connection(why)),
                })));
            }
        }
    }

    /// An acyclic frame: a PROFINET one (DCP response, alarm; a DCP request to its own
    /// station), or the port neighbour's LLDP.
    pub fn on_frame(&mut self, frame: &[u8], now: u64, out: &mut Vec<ControllerAction>) {
        let Ok(eth) = crate::wire::ethernet::Frame::new_checked(frame) else {
            return;
        };
        if self.on_station_frame(&eth, now, out) {
            return;
        }
        if eth.ethertype() == crate::wire::lldp::ETHERTYPE_LLDP {
            if eth.dst() == crate::wire::lldp::MULTICAST_NEAREST_BRIDGE && eth.src() != self.id.mac
            {
                self.neighbours.on_lldpdu(eth.src(), eth.payload(), now);
                self.sync_station_identity();
                self.check_port(out);
            }
            return;
        }
        for d in &mut self.devices {
            d.on_frame(frame, &self.id, now, out);
        }
    }

    /// A UDP datagram that arrived at port 34964 from `from`.
    pub fn on_datagram(
        &mut self,
        from: SocketAddrV4,
        datagram: &[u8],
        now: u64,
        out: &mut Vec<ControllerAction>,
    ) {
        let Ok(packet) = rpc::Packet::new_checked(datagram) else {
            self.dropped.malformed += 1;
            return;
        };
        let Ok(h) = Header::parse(&packet) else {
            self.dropped.malformed += 1;
            return;
        };
        if h.packet_type == PacketType::Request {
            self.on_request(from, &h, packet.body(), now, out);
            return;
        }
        for d in &mut self.devices {
            if d.on_datagram(datagram, &self.id, now, out) {
                return;
            }
        }
        self.dropped.unexpected += 1;
    }

    /// A call to our controller interface: the devices' ApplicationReady.
    fn on_request(
        &mut self,
        from: SocketAddrV4,
        h: &Header,
        body: &[u8],
        now: u64,
        out: &mut Vec<ControllerAction>,
    ) {
        if h.interface != rpc::CONTROLLER_INTERFACE || h.opnum != opnum::CONTROL {
            self.dropped.unexpected += 1;
            return;
        }
        let Ok((Ndr::Request(ndr), blocks)) =
            rpc::parse_body(PacketType::Request, h.little_endian, body)
        else {
            self.dropped.malformed += 1;
            return;
        };
        let Ok(block) = ControlBlock::parse(blocks) else {
            self.dropped.malformed += 1;
            return;
        };
        if !block.is_request() {
            self.dropped.unexpected += 1;
            return;
        }
        let answer = self
            .devices
            .iter_mut()
            .find_map(|d| d.on_application_ready(&block, now, out));
        let (status, blocks) = match answer {
            Some(a) => (PnioStatus::OK, a.to_bytes().to_vec()),
            // An AR we do not know (CMRPC: AR UUID unknown): refused, so the device drops it.
            None => (PnioStatus::from_bytes([0xdd, 0x81, 0x40, 0x05]), Vec::new()),
        };
        // Little-endian like every PDU of ours, whatever order the request came in (the S7's
        // choice as well).
        let reply = Header {
            little_endian: true,
            ..h.reply(self.boot_time)
        };
        if let Ok(pdu) = rpc::emit_response(&reply, status, ndr.args_maximum, &blocks) {
            out.push(ControllerAction::Datagram {
                to: from,
                payload: pdu,
            });
        }
    }

    /// The cycle thread gave up device `device`'s AR of `epoch`.
    pub fn on_watchdog(
        &mut self,
        device: usize,
        epoch: u32,
        now: u64,
        out: &mut Vec<ControllerAction>,
    ) {
        if let Some(d) = self.devices.get_mut(device) {
            d.on_watchdog(epoch, now, out);
        }
    }

    /// The first valid frame of device `device`'s AR arrived.
    pub fn on_data_started(&mut self, device: usize, epoch: u32) {
        let _ = (device, epoch);
    }

    /// Timers.
    pub fn poll(&mut self, now: u64, out: &mut Vec<ControllerAction>) {
        for d in &mut self.devices {
            d.poll(&self.id, now, out);
        }
        if let Some(frame) = self.lldp.as_mut().and_then(|l| l.poll(now)) {
            out.push(ControllerAction::Frame(frame));
        }
        self.neighbours.age(now);
        self.poll_station(now, out);
        self.check_port(out);
    }

    /// Whether a Release still waits for a device's answer (a stopping controller waits for
    /// it a little before it closes its socket).
    pub fn releasing(&self) -> bool {
        self.devices.iter().any(DeviceAr::releasing)
    }

    /// When [`poll`](Self::poll) is due next, at the latest.
    pub fn next_deadline_ns(&self) -> Option<u64> {
        self.devices
            .iter()
            .filter_map(DeviceAr::deadline)
            .chain(
                self.lldp
                    .as_ref()
                    .map(crate::port::lldp::Announcer::next_deadline_ns),
            )
            .chain(self.neighbours.next_deadline_ns())
            .chain(self.station_deadline_ns())
            .min()
    }
}

#[cfg(test)]
mod interface_tests;
