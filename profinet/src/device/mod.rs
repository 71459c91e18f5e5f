// SPDX-License-Identifier: MIT OR Apache-2.0
//! The PROFINET IO device's protocol engine (RT class 1), sans-IO: procimgd's device role
//! runs it on a real interface, and `procimgd --demo` puts instances of it on its in-process
//! network so that the controller runs its real protocol end to end without root or
//! hardware.
//!
//! It behaves like a standard device towards a controller: it answers DCP (Identify with the
//! requested response delay, Get, Set IP / NameOfStation / Signal / reset), serves the PNIO
//! RPC interface on UDP 34964 in either NDR byte order (Connect with full validation and a
//! ModuleDiffBlock when the plugged submodules differ, Write and WriteMultiple, Read and
//! ReadImplicit, PrmEnd/PrmBegin, Release; duplicates, fragments, ping), sends the
//! ApplicationReady CControl to the controller and retransmits it until answered, produces
//! the input CR and consumes the output CR at the offsets the controller chose, supervises
//! the output CR with the data hold watchdog, and acknowledges alarms on both RTA channels.
//! Its port announces the station by LLDP ([`lldp`]: at start, every 5 s and at once after
//! DCP changed its name or address; [`Station::set_lldp`] turns that off), and it sends a DCP
//! Hello request at start-up when asked to ([`Station::set_hello`]).
//! Its inputs come from its [`Application`], which the user of the crate provides.
//!
//! The application reports to the controller through it: process alarms
//! ([`Device::raise_process_alarm`]) and diagnosis ([`Device::add_diagnosis`],
//! [`Device::remove_diagnosis`], [`Device::clear_diagnosis`]), which the device keeps in its
//! [`DiagnosisStore`], announces with diagnosis alarms, reports in the SubmoduleStates of the
//! ModuleDiffBlock and, while a fault is pending, in the station problem of the DataStatus.
//! The device serves the records that describe it itself: the diagnosis records of every
//! level, the expected and real identification, the AR's ModuleDiffBlock, I&M0–I&M4 (I&M1–4
//! writable and kept in the engine, [`ImRecords`]) and I&M0FilterData.
//!
//! No socket and no clock inside: feed it every Ethernet frame on the link
//! ([`Device::on_frame`]), every UDP datagram to its IP ([`Device::on_datagram`]) and
//! call [`Device::poll`] at [`Device::next_deadline_ns`]; put the [`DeviceAction`]s it
//! returns on the link. Times are `CLOCK_MONOTONIC` nanoseconds.
//!
//! The [`Device`] is made of parts that own their data, each with its own impl: the
//! [`Station`] (identity, I&M, LLDP; `station.rs`), what is plugged where ([`Plugging`],
//! `plug.rs`), the AR and what the device keeps across ARs ([`ArSlot`], `ar_slot.rs`), the
//! controller's AlarmAcks ([`AlarmAcks`], `alarms.rs`), the diagnosis ([`DiagnosisStore`],
//! `diagnosis/`), the user records and the calls waiting for the application's answers
//! ([`Records`], `records.rs`, with `params.rs` and `delegated_records.rs`), and the
//! application's checks of new ARs ([`ArChecks`], `ar_check.rs`) and of DCP Sets
//! ([`DcpSetChecks`], `dcp_veto.rs`, kept by the DCP responder of `dcp.rs`). One accessor
//! each gives their read-only view ([`Device::station`], [`Device::plugging`],
//! [`Device::ar`], [`Device::alarm_acks`], [`Device::diagnosis`], [`Device::records`],
//! [`Device::ar_checks`], [`Device::dcp_set_checks`]); the device's own methods are the ones
//! that take the network's input, run the timers, or coordinate parts (a pull changes what
//! is plugged, clears the submodule's diagnosis and sends the AR its alarm).
//!
//! ```text
//!            Connect ok                 PrmEnd              AppReady sent
//!   Idle ───────────────▶ Connected ─────────────▶ Parameterized ──────────▶ WaitAppReadyConfirm
//!    ▲                        ▲                    (input CR starts)               │ response Done
//!    │ Release, abort         │ PrmBegin                                           ▼
//!    └────────────────────────┴──────────────────────────────────────────────── Data
//!   abort = data hold timer expired, CMI activity timeout, ApplicationReady unanswered or
//!   refused, ERR-RTA from the controller, alarm retries exhausted, station name/IP changed
//!   or reset by DCP, a Connect re-running the AR
//! ```
//!
//! The input CR runs from PrmEnd on (as p-net does) with DataStatus 0x35 (0x15 while a fault
//! is pending); its IOPS and IOCS
//! stay BAD until the controller confirmed the ApplicationReady, then turn GOOD. The consumer
//! watchdog starts with the first valid output frame, at the latest when data exchange
//! begins.

mod access_ar;
mod alarms;
mod app_ready;
mod application;
mod ar;
mod ar_check;
mod ar_slot;
mod cm;
mod connect;
mod cyclic;
mod dcp;
mod dcp_veto;
mod delegated_records;
pub mod diagnosis;
mod handover;
#[cfg(test)]
mod handover_tests;
mod identification;
mod im;
mod iobase_alarms;
#[cfg(test)]
mod iobase_alarms_tests;
pub mod log_book;
mod params;
pub use crate::port::physical;
pub mod pe;
mod plug;
#[cfg(test)]
mod plug_tests;
mod records;
mod rpc;
mod served_records;
mod station;
#[cfg(test)]
mod tests;
pub mod topology;

use crate::cyclic::{CyclicAr, Verdict};
use crate::port::lldp;
use crate::wire::control::ControlBlock;
use crate::wire::ethernet::{self, ETHERTYPE_PROFINET};
use crate::wire::record::Im0;
use crate::wire::rpc::{self as wire_rpc, Header, PacketType};
use crate::wire::rt::FrameIdClass;
use crate::wire::rta_pdu::{self, AbortCode, RtaPdu};
use crate::wire::{MacAddress, Uuid};
pub use access_ar::AccessAr;
pub use alarms::{AlarmAcks, DiagnosisChange};
pub use app_ready::APP_READY_HOLD_TIMEOUT_NS;
pub use application::Application;
use ar::Ar;
pub use ar_check::{AR_CHECK_TIMEOUT_NS, ArCheck, ArChecks, CrInfo, ExpectedAt, UnknownArCheck};
pub use ar_slot::ArSlot;
pub use dcp_veto::{DCP_SET_CHECK_TIMEOUT_NS, DcpSetCheck, DcpSetChecks, UnknownDcpSetCheck};
pub use delegated_records::{
    MAX_WAITING_CALLS, RECORD_ANSWER_TIMEOUT_NS, RecordJob, UnknownRecordJob,
};
pub use diagnosis::{
    ChannelDiag, DiagEntry, DiagKey, DiagnosisError, DiagnosisStore, GenericDiag, Severity,
    SubslotAddr,
};
pub use im::ImRecords;
pub use iobase_alarms::{AlarmError, DiagnosisEdit};
pub use params::ParameterRecord;
pub use plug::{PlugError, Plugging};
pub use records::Records;
pub use station::Station;
use std::net::SocketAddrV4;

/// What the device is and what is plugged into it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DeviceSetup<A> {
    /// NameOfStation at start (DCP may change it).
    pub name: String,
    /// The device's MAC address.
    pub mac: MacAddress,
    /// IP address at start; `None` is 0.0.0.0 until a DCP Set IP.
    pub ip: Option<[u8; 4]>,
    /// VendorID.
    pub vendor_id: u16,
    /// DeviceID.
    pub device_id: u16,
    /// Device instance (the object UUID's instance, GSDML ObjectUUID_LocalIndex).
    pub instance: u16,
    /// The submodules really plugged.
    pub submodules: Vec<PluggedSubmodule>,
    /// What fills its inputs.
    pub application: A,
    /// The I&M0 record (index 0xAFF0) of every submodule.
    pub im0: Im0,
}

/// One plugged submodule.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PluggedSubmodule {
    /// API.
    pub api: u32,
    /// Slot.
    pub slot: u16,
    /// Subslot.
    pub subslot: u16,
    /// ModuleIdentNumber of the module in the slot.
    pub module_ident: u32,
    /// SubmoduleIdentNumber.
    pub submodule_ident: u32,
    /// Input bytes.
    pub input_length: u16,
    /// Output bytes.
    pub output_length: u16,
}

/// Something the device puts on the network.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum DeviceAction {
    /// An Ethernet frame to put on the link (at least 60 bytes, without FCS).
    Frame(Vec<u8>),
    /// A UDP datagram (RPC) from the device's IP and `from_port`.
    Datagram {
        /// Destination.
        to: SocketAddrV4,
        /// Source port.
        from_port: u16,
        /// The UDP payload.
        payload: Vec<u8>,
    },
    /// Start the cyclic exchange of an AR on the caller's cycle (only after
    /// [`Device::hand_over_cyclic`]).
    StartCyclic(Box<CyclicAr>),
    /// Stop the cyclic exchange `epoch` (only after [`Device::hand_over_cyclic`]).
    StopCyclic {
        /// The epoch of the [`CyclicAr`] that was started.
        epoch: u32,
    },
    /// A record for the application to read or write (only for submodules given to it with
    /// [`Device::delegate_records`]); answer with [`Device::answer_record`].
    Record(RecordJob),
    /// A new AR for the application to accept or refuse (only with
    /// [`Device::check_connects`]); answer with [`Device::answer_connect`].
    ArCheck(ArCheck),
    /// A DCP Set of the station's name or address for the application to allow or veto
    /// (only with [`Device::verify_dcp_sets`]); answer with [`Device::answer_dcp_set`].
    DcpSetCheck(DcpSetCheck),
}

/// The identity a device keeps across a restart, as DCP set it.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct KeptIdentity {
    /// NameOfStation to keep (empty: none), if DCP set one permanently or reset the device.
    pub name: Option<String>,
    /// IP address, subnet mask and gateway to keep (zeros: none), likewise.
    pub ip_suite: Option<[[u8; 4]; 3]>,
    /// Changes so far: a caller that stores the identity stores it again when this grows.
    pub changes: u64,
}

/// Where the device's AR stands.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ArState {
    /// No AR.
    Idle,
    /// Connect accepted; parameters may be written until PrmEnd.
    Connected,
    /// PrmEnd answered; the input CR runs, the ApplicationReady is about to go out.
    Parameterized,
    /// ApplicationReady sent, waiting for the controller's confirmation.
    WaitAppReadyConfirm,
    /// ApplicationReady confirmed: data exchange with GOOD status.
    Data,
}

/// How long after PrmEnd the ApplicationReady goes out: the application's time to take over
/// its parameters, and time for the controller to see the PrmEnd response first.
const APP_READY_DELAY_NS: u64 = 1_000_000;
/// Writing this (manufacturer-specific) record index of a submodule makes the device raise a
/// process alarm on it, carrying the written bytes: alarms to try without hardware.
pub const SIM_ALARM_INDEX: u16 = 0x7FF0;
/// The UserStructureIdentifier of such an alarm (manufacturer-specific).
pub const SIM_ALARM_USI: u16 = 0x0001;
/// AlarmAcks [`AlarmAcks::list`] keeps, the most recent.
pub const MAX_KEPT_ACKS: usize = 64;
use crate::wire::ethernet::profinet_frame as ethernet_frame;

/// A PROFINET IO device.
pub struct Device<A> {
    /// Identity, I&M, LLDP: the station as the network knows it.
    station: Station,
    /// What is plugged where.
    plugging: Plugging,
    app: A,
    dcp: dcp::Responder,
    rpc: rpc::Server,
    /// The AR and what the device keeps across ARs.
    ar: ArSlot,
    /// The controller's acknowledgements of our alarms.
    acks: AlarmAcks,
    /// Set when the caller's cycle runs the cyclic exchange.
    handover: Option<handover::Handover>,
    diagnosis: DiagnosisStore,
    /// Which user records are accepted, which the application answers, and the calls
    /// waiting for its answers.
    records: Records,
    /// The application's checks of new ARs.
    ar_checks: ArChecks,
    /// What the device knows of its interface and port.
    physical: physical::Physical,
    /// The PLC's topology check and what it found.
    topology: topology::TopologyCheck,
}

impl<A: Application> Device<A> {
    /// A device as `spec` describes it, without an AR.
    pub fn new(spec: DeviceSetup<A>) -> Device<A> {
        let ip = spec.ip.unwrap_or([0; 4]);
        let mask = if ip == [0; 4] {
            [0; 4]
        } else {
            [255, 255, 255, 0]
        };
        Device {
            station: Station::new(
                dcp::Identity {
                    mac: spec.mac,
                    name: spec.name,
                    ip,
                    mask,
                    gateway: [0; 4],
                    vendor_id: spec.vendor_id,
                    device_id: spec.device_id,
                    instance: spec.instance,
                    type_of_station: "procimg simulated device".into(),
                    role: dcp::ROLE_IO_DEVICE,
                    hello: false,
                    alias: None,
                },
                spec.im0,
            ),
            plugging: Plugging::new(spec.submodules),
            app: spec.application,
            dcp: dcp::Responder::default(),
            rpc: rpc::Server::default(),
            ar: ArSlot::default(),
            acks: AlarmAcks::default(),
            handover: None,
            diagnosis: DiagnosisStore::new(),
            records: Records::default(),
            ar_checks: ArChecks::default(),
            physical: physical::Physical::default(),
            topology: topology::TopologyCheck::default(),
        }
    }

    /// The PLC's topology check (PDPortDataCheck) and the mismatches it finds.
    pub fn topology(&self) -> &topology::TopologyCheck {
        &self.topology
    }

    /// What the device knows of its interface and port (the physical device's records).
    pub fn physical(&self) -> &physical::Physical {
        &self.physical
    }

    /// Tells the device its port's link, as its runtime reads it from the interface: the
    /// physical device's records report it, and a link that went down takes the port's
    /// LLDP neighbours with it.
    pub fn set_port_link(&mut self, link: physical::PortLink) {
        if self.physical.link.up && !link.up {
            self.station.link_down();
        }
        if self.physical.link.mau_type != link.mau_type
            && let Some(l) = self.station.lldp_mut()
        {
            l.update(|s| s.link.mau_type = link.mau_type);
        }
        self.physical.link = link;
    }

    /// Tells the device its interface's counters (`None`: it has none to read).
    pub fn set_port_counters(&mut self, counters: Option<physical::PortCounters>) {
        self.physical.counters = counters;
    }

    /// The station: identity, I&M, LLDP.
    pub fn station(&self) -> &Station {
        &self.station
    }

    /// The station, to set up before the device goes on the network (name, address, LLDP,
    /// Hello, I&M).
    pub fn station_mut(&mut self) -> &mut Station {
        &mut self.station
    }

    /// The AR, if the device holds one, and what it keeps across ARs.
    pub fn ar(&self) -> &ArSlot {
        &self.ar
    }

    /// Which user records the device takes, and the calls waiting for its application.
    pub fn records(&self) -> &Records {
        &self.records
    }

    /// The AlarmAcks the controller sent for our alarms.
    pub fn alarm_acks(&self) -> &AlarmAcks {
        &self.acks
    }

    /// Takes an Ethernet frame seen on the link; what is not for us is ignored.
    pub fn on_frame(&mut self, frame: &[u8], now_ns: u64, out: &mut Vec<DeviceAction>) {
        self.ar.now_ns = now_ns;
        self.take_frame(frame, now_ns, out);
        self.check_topology(now_ns, out);
        self.sync_handover(now_ns, out);
    }

    fn take_frame(&mut self, frame: &[u8], now_ns: u64, out: &mut Vec<DeviceAction>) {
        let Ok(eth) = ethernet::Frame::new_checked(frame) else {
            return;
        };
        if eth.ethertype() == crate::wire::lldp::ETHERTYPE_LLDP
            && eth.dst() == crate::wire::lldp::MULTICAST_NEAREST_BRIDGE
            && eth.src() != self.station.id.mac
        {
            self.station.on_lldpdu(eth.src(), eth.payload(), now_ns);
            return;
        }
        if eth.ethertype() != ETHERTYPE_PROFINET {
            return;
        }
        let (dst, src, mac) = (eth.dst(), eth.src(), self.station.id.mac);
        if dst != mac && dst != MacAddress::DCP_IDENTIFY {
            return;
        }
        let pdu = eth.payload();
        let Some(&[hi, lo]) = pdu.get(..2) else {
            return;
        };
        let frame_id = u16::from_be_bytes([hi, lo]);
        match FrameIdClass::of(frame_id) {
            FrameIdClass::Dcp if dcp::is_request_frame_id(frame_id) => {
                let changes = self
                    .dcp
                    .on_pdu(&mut self.station.id, dst, src, pdu, now_ns, out);
                self.after_dcp(changes, out);
            }
            FrameIdClass::AlarmHigh | FrameIdClass::AlarmLow if dst == mac => {
                self.on_rta(src, pdu, now_ns, out)
            }
            class if class.is_cyclic() && dst == mac => self.on_cyclic(src, pdu, now_ns),
            _ => {}
        }
    }

    fn after_dcp(&mut self, changes: dcp::Changes, out: &mut Vec<DeviceAction>) {
        self.station.after_dcp(&changes);
        // The AR is bound to the station's name and address: a change ends it (CMINA).
        if changes.reset {
            self.abort_ar(AbortCode::ResetToFactory, out);
        } else if changes.name || changes.ip {
            self.abort_ar(AbortCode::StationNameChanged, out);
        }
    }

    /// Applies a PDInterfaceAdjust the controller wrote to an interface submodule: where
    /// the LLDP frames carry the name (kept after the AR, as a PDev parameter is).
    fn adjust_lldp(&mut self) {
        let Some(ar) = self.ar.current.as_ref() else {
            return;
        };
        let mode = ar
            .records
            .iter()
            .find_map(|(&(_, _, subslot, index), data)| {
                (index == lldp::INDEX_PD_INTERFACE_ADJUST && subslot >= 0x8000)
                    .then(|| lldp::name_of_device_mode(data))
                    .flatten()
            });
        if let Some(mode) = mode {
            self.station.set_lldp_mode(mode);
        }
    }

    fn on_rta(&mut self, src: MacAddress, pdu: &[u8], now_ns: u64, out: &mut Vec<DeviceAction>) {
        let mac = self.station.id.mac;
        let Some(ar) = self
            .ar
            .current
            .as_mut()
            .filter(|a| a.controller_mac() == src)
        else {
            return;
        };
        let Ok(packet) = rta_pdu::Packet::new_checked(pdu) else {
            return;
        };
        let Ok(pdu) = RtaPdu::parse(&packet) else {
            return;
        };
        let abort = ar.alarms.on_pdu(&pdu, mac, now_ns, out);
        self.acks.take(&mut ar.alarms.acks);
        if let Some(a) = abort {
            self.end_ar(a.code);
        }
    }

    fn on_cyclic(&mut self, src: MacAddress, pdu: &[u8], now_ns: u64) {
        let Some(ar) = self.ar.current.as_mut() else {
            return;
        };
        if let Verdict::Accepted { c_sdu, .. } = ar.consumer.consume(src, pdu, now_ns) {
            ar.consume(c_sdu);
        }
    }

    /// Takes a UDP datagram from `from` to our port `to_port`.
    pub fn on_datagram(
        &mut self,
        from: SocketAddrV4,
        to_port: u16,
        payload: &[u8],
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) {
        self.ar.now_ns = now_ns;
        self.take_datagram(from, to_port, payload, now_ns, out);
        self.sync_handover(now_ns, out);
    }

    fn take_datagram(
        &mut self,
        from: SocketAddrV4,
        to_port: u16,
        payload: &[u8],
        now_ns: u64,
        out: &mut Vec<DeviceAction>,
    ) {
        // Without an address the device has no UDP endpoint.
        if self.station.id.ip == [0; 4] {
            return;
        }
        let packet = wire_rpc::Packet::new_unchecked(payload);
        let Ok(header) = Header::parse(&packet) else {
            return;
        };
        let Some(body) = payload
            .get(wire_rpc::HEADER_LEN..)
            .and_then(|b| b.get(..usize::from(header.body_len)))
        else {
            return;
        };
        let server = to_port == wire_rpc::RPC_PORT;
        if server && (self.records.waiting.has_call(&header) || self.ar_checks.has_call(&header)) {
            // The call waits for the application: a retransmission is dropped, a ping learns
            // that we are at it.
            if header.packet_type == PacketType::Ping {
                self.rpc.working(&header, from, out);
            }
            return;
        }
        match header.packet_type {
            PacketType::Request if server => {
                if let Some((h, body)) = self.rpc.request(&header, body, from, out) {
                    self.call(&h, &body, from, now_ns, out);
                }
            }
            PacketType::Ping if server => self.rpc.ping(&header, from, out),
            PacketType::Ack if server => self.rpc.ack(&header),
            PacketType::Response
            | PacketType::Fault
            | PacketType::Reject
            | PacketType::Working
            | PacketType::NoCall => self.client_pdu(&header, body, now_ns, out),
            _ => {}
        }
    }

    /// A new activity UUID for a client call.
    fn new_activity(&mut self) -> Uuid {
        self.ar.new_activity(self.station.id.mac)
    }

    /// Runs the timers: delayed DCP responses, LLDP announcements, the ApplicationReady and
    /// its retransmission, input CR frames, the watchdogs, alarm retransmissions.
    pub fn poll(&mut self, now_ns: u64, out: &mut Vec<DeviceAction>) {
        self.ar.now_ns = now_ns;
        self.expire_access_ar(now_ns);
        self.run_timers(now_ns, out);
        self.check_topology(now_ns, out);
        self.sync_handover(now_ns, out);
    }

    fn run_timers(&mut self, now_ns: u64, out: &mut Vec<DeviceAction>) {
        self.dcp.poll(now_ns, out);
        self.expire_record_jobs(now_ns, out);
        self.expire_ar_check(now_ns, out);
        self.expire_dcp_check(now_ns, out);
        self.expire_app_ready_hold(now_ns);
        self.station.poll(now_ns, out);
        let mac = self.station.id.mac;
        let station_ok = !self.diagnosis.has_fault();
        let activity = if self
            .ar
            .current
            .as_ref()
            .is_some_and(|a| a.app_ready_due.is_some_and(|d| now_ns >= d))
        {
            // The ApplicationReady carries the differences as they are now, diagnosis that
            // came since the Connect included.
            let diff = self
                .ar_module_diff()
                .and_then(|d| d.to_vec().ok())
                .unwrap_or_default();
            Some((self.new_activity(), diff))
        } else {
            None
        };
        let Some(ar) = self.ar.current.as_mut() else {
            return;
        };
        if ar.cmi_deadline.is_some_and(|d| now_ns >= d) {
            self.abort_ar(AbortCode::CmiTimeout, out);
            return;
        }
        if ar.consumer.expired(now_ns) {
            self.abort_ar(AbortCode::ConsumerDhtExpired, out);
            return;
        }
        let alarm_abort = ar.alarms.poll(mac, now_ns, out);
        if let Some(a) = alarm_abort {
            // The channel sent its ERR-RTA itself.
            self.end_ar(a.code);
            return;
        }
        if let Some((activity, diff)) = activity {
            ar.app_ready_due = None;
            let call = rpc::ClientCall::control(
                ControlBlock::application_ready(ar.ar_uuid, ar.session_key),
                &diff,
                ar.initiator_object,
                activity,
                ar.controller,
            );
            let Some(mut call) = call else {
                self.abort_ar(AbortCode::RpcClientCallNegative, out);
                return;
            };
            call.transmit(now_ns, out);
            ar.app_ready = Some(call);
            ar.state = ArState::WaitAppReadyConfirm;
        }
        if let Some(call) = ar.app_ready.as_mut()
            && !call.poll(now_ns, out)
        {
            self.abort_ar(AbortCode::RpcClientCallNegative, out);
            return;
        }
        self.run_plug_ready(now_ns, out);
        let Some(ar) = self.ar.current.as_mut() else {
            return;
        };
        if let Some(cc) = ar.provider.take_due(now_ns)
            && let Some(frame) =
                ar.produce(&mut self.app, self.ar.frames_produced, mac, cc, station_ok)
        {
            self.ar.frames_produced += 1;
            out.push(DeviceAction::Frame(frame));
        }
    }

    /// When [`poll`](Self::poll) needs calling next, if anything is pending.
    pub fn next_deadline_ns(&self) -> Option<u64> {
        [
            self.station.next_deadline_ns(),
            self.dcp.next_deadline_ns(),
            self.ar.current.as_ref().and_then(Ar::deadline),
            self.ar.access.as_ref().map(|a| a.deadline_ns),
            self.topology_due().then_some(0),
            self.records.waiting.deadline(),
            self.ar_checks.deadline(),
            self.dcp.checks.held.as_ref().map(|h| h.deadline),
        ]
        .into_iter()
        .flatten()
        .min()
    }

    /// Ends the AR from our side: ERR-RTA to the controller, back to Idle.
    fn abort_ar(&mut self, code: AbortCode, out: &mut Vec<DeviceAction>) {
        self.ar.abort(code, self.station.id.mac, out);
    }

    /// The AR ended without a further ERR-RTA from us (the controller aborted it, or the
    /// alarm channel already sent one).
    fn end_ar(&mut self, code: AbortCode) {
        self.ar.end(code);
    }
}
