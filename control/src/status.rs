// SPDX-License-Identifier: MIT OR Apache-2.0
//! The server's state as `procimg status` shows it: clients, claims, devices or the station,
//! the network counters, forces, subscribers and the cycle's latency histograms.

use crate::{ArState, ClientRole, DeviceState, Space, hex_id};
use procimg_shm_layout::Mode;
use serde::{Deserialize, Serialize};

/// Percentiles of a latency histogram, in ns.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Percentiles {
    /// Number of samples.
    pub count: u64,
    /// Smallest.
    pub min_ns: u64,
    /// Median.
    pub p50_ns: u64,
    /// 99th percentile.
    pub p99_ns: u64,
    /// 99.9th percentile.
    pub p999_ns: u64,
    /// Largest.
    pub max_ns: u64,
    /// Mean.
    pub mean_ns: u64,
}

/// One bucket of a latency histogram: `count` values at most `ns` (and more than the
/// previous bucket's `ns`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Bucket {
    /// The bucket's highest value, in ns.
    pub ns: u64,
    /// Values recorded in it.
    pub count: u64,
}

/// The cycle thread's latency histograms since the server started, to 2 significant digits
/// (each bucket's `ns` within 1 % of the values in it),
/// with only the buckets that hold values, in rising order.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct HistogramsReport {
    /// Cycles run when the histograms were taken.
    pub cycles: u64,
    /// Actual minus planned cycle start (the cycle thread's wake-up latency).
    pub wakeup: Vec<Bucket>,
    /// STARTOP (the image's stamp) → OPDONE received, per synchronous client and cycle (the
    /// round trip).
    pub handshake: Vec<Bucket>,
    /// A client's OPDONE sent → received by the cycle thread (one way).
    pub opdone: Vec<Bucket>,
    /// Cycle start → outputs handed to the IO system.
    pub work: Vec<Bucket>,
}

/// One claimed output submodule in a status report.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ClaimReport {
    /// Submodule table index.
    pub submodule: u32,
    /// Station name of its device.
    pub device: String,
    /// Slot.
    pub slot: u16,
    /// Subslot.
    pub subslot: u16,
    /// First logical output address.
    pub output_address: u32,
    /// Output bytes.
    pub output_length: u16,
}

/// One attached client in a status report.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ClientReport {
    /// Slot.
    pub slot: u32,
    /// Name it registered with.
    pub name: String,
    /// Process id.
    pub pid: u32,
    /// Role.
    pub role: ClientRole,
    /// OPFAULTs it got.
    pub opfaults: u64,
    /// The cycle of its last OPFAULT (0: none yet).
    #[serde(default)]
    pub last_opfault_cycle: u64,
    /// Its claims.
    pub claims: Vec<ClaimReport>,
}

/// One IO device in a status report.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct DeviceReport {
    /// NameOfStation.
    pub name: String,
    /// Where it is in its life.
    pub state: DeviceState,
}

/// What arrived at the network interface, as the cycle thread counted it.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct NetworkReport {
    /// Cyclic frames taken into the image.
    pub cyclic_frames: u64,
    /// Frames too short or malformed for what they claimed to be (dropped).
    pub malformed: u64,
    /// Frames with a FrameID no AR uses, from a foreign MAC, or not PROFINET (dropped).
    pub unknown: u64,
    /// Cyclic frames with an old CycleCounter (dropped).
    pub stale: u64,
    /// Frames dropped for lack of buffer or queue space.
    pub dropped: u64,
    /// Cyclic frames sent from the image, where the clients' outputs are (one server copy
    /// of each output byte).
    #[serde(default)]
    pub sent_in_place: u64,
    /// Cyclic frames written from the image before they were sent: frames without outputs
    /// (consumer statuses only), and the frames of an AR whose peer laid them out otherwise
    /// than the image holds them (two server copies of each output byte).
    #[serde(default)]
    pub sent_copied: u64,
    /// Frames the interface refused to send.
    pub send_errors: u64,
    /// Consumer watchdog expiries (devices lost).
    pub watchdog_expiries: u64,
    /// UDP datagrams on port 34964 that were not a well-formed RPC PDU (dropped).
    #[serde(default)]
    pub malformed_datagrams: u64,
    /// Well-formed RPC datagrams no call or AR was waiting for (dropped).
    #[serde(default)]
    pub unexpected_datagrams: u64,
}

/// The server's state, as `procimg status` shows it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StatusReport {
    /// Instance name.
    pub instance: String,
    /// procimgd's version (`0.1.0`).
    #[serde(default)]
    pub server_version: String,
    /// The server's PROFINET role: `"controller"` or `"device"`.
    #[serde(default = "controller_role")]
    pub role: String,
    /// In the device role: the station and its AR.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub station: Option<StationReport>,
    /// In the controller role: the controller's own station on its interface.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub controller: Option<ControllerReport>,
    /// Server process id.
    pub pid: u32,
    /// Server generation (in JSON a hex string: see [`hex_id`]).
    #[serde(with = "hex_id")]
    pub generation: u64,
    /// Layout hash (in JSON a hex string: see [`hex_id`]).
    #[serde(with = "hex_id")]
    pub layout_hash: u64,
    /// Current mode.
    pub mode: Mode,
    /// Cycle time in ns.
    pub cycle_ns: u64,
    /// OPDONE deadline in ns after the cycle start.
    pub opdone_deadline_ns: u64,
    /// Cycles run since the server started.
    pub cycle_count: u64,
    /// Cycles whose work did not finish within the cycle time (their successors were skipped).
    pub overruns: u64,
    /// OPFAULTs given to all clients.
    pub opfaults: u64,
    /// Whether the cycle thread runs with real-time scheduling.
    pub realtime: bool,
    /// Calls of the system allocator made by the cycle thread in its cycles: the figure that
    /// must stay 0.
    pub rt_heap_allocations: u64,
    /// Calls of the system allocator made by the cycle thread while it set up or tore down
    /// a client's shared-memory connection, outside the cycle (iceoryx2 allocates there; a
    /// few hundred per client attach are normal).
    #[serde(default)]
    pub rt_setup_allocations: u64,
    /// Receives of client outputs that failed (a dead client's connection being removed).
    #[serde(default)]
    pub receive_errors: u64,
    /// Cycles without an input image: every image slot was held (readers keep old images),
    /// so nobody got STARTOP; or whose image reached only the clients that read by their
    /// mark (iceoryx2's send of it failed). Must stay 0.
    #[serde(default)]
    pub unpublished_images: u64,
    /// Bytes of the input images faulted in and locked: the samples in use so far and a few
    /// ahead of them, out of one for every reader that may hold one (0 where memory is not
    /// locked on fault).
    #[serde(default)]
    pub input_images_locked_bytes: u64,
    /// Cycles whose input image was loaned beyond what was faulted in: each took the page
    /// faults of a new sample in the cycle. Should stay 0; readers that come to hold many
    /// more images at once than before move it.
    #[serde(default)]
    pub unready_image_loans: u64,
    /// Output writes dropped: the sender did not hold the claim, or a busy client wrote its
    /// sample again while it was read.
    #[serde(default)]
    pub rejected_writes: u64,
    /// OPDONE samples of busy-polling clients taken where the clients wrote them, without
    /// an iceoryx2 send and receive.
    #[serde(default)]
    pub outputs_in_place: u64,
    /// Wake-up latency of the cycle thread (actual minus planned cycle start).
    pub wakeup_latency: Percentiles,
    /// STARTOP → OPDONE round trip of synchronous clients.
    pub handshake_round_trip: Percentiles,
    /// OPDONE sent by a client → received by the cycle thread (one way).
    #[serde(default)]
    pub opdone_one_way: Percentiles,
    /// Time from cycle start until the outputs are sent.
    pub cycle_work: Percentiles,
    /// Attached clients.
    pub clients: Vec<ClientReport>,
    /// The IO devices, in configuration order.
    #[serde(default)]
    pub devices: Vec<DeviceReport>,
    /// Network interface counters.
    #[serde(default)]
    pub network: NetworkReport,
    /// Announced notification subscribers.
    #[serde(default)]
    pub subscribers: Vec<SubscriberReport>,
    /// Forced bytes, one entry per run of consecutive forced addresses.
    #[serde(default)]
    pub forces: Vec<ForceReport>,
}

fn controller_role() -> String {
    String::from("controller")
}

/// The station of a server in the IO device role, for the status report.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct StationReport {
    /// NameOfStation now.
    pub name: String,
    /// The station's MAC address (the interface's).
    #[serde(default)]
    pub mac: String,
    /// IPv4 address now (`0.0.0.0`: none).
    pub ip: String,
    /// Subnet mask now.
    #[serde(default)]
    pub netmask: String,
    /// Default gateway now (`0.0.0.0`: none).
    #[serde(default)]
    pub gateway: String,
    /// The type of station DCP reports (DeviceVendorValue).
    #[serde(default)]
    pub type_of_station: String,
    /// I&M0 OrderID.
    #[serde(default)]
    pub order_number: String,
    /// I&M0 IM_Serial_Number.
    #[serde(default)]
    pub serial_number: String,
    /// I&M0 IM_Hardware_Revision.
    #[serde(default)]
    pub hardware_revision: u16,
    /// VendorID.
    pub vendor_id: u16,
    /// DeviceID.
    pub device_id: u16,
    /// The AR with a PLC, if there is one.
    pub ar: Option<ArReport>,
    /// ARs that ended other than by the PLC's Release.
    pub aborted_ars: u64,
    /// AlarmAcks the PLCs sent for the station's alarms.
    #[serde(default)]
    pub alarms_acknowledged: u64,
    /// Why the last one ended so.
    #[serde(default)]
    pub last_abort: Option<String>,
    /// The pending diagnosis, by submodule in (API, slot, subslot) order, each submodule's
    /// entries oldest first: what the PLC reads in the diagnosis records.
    #[serde(default)]
    pub diagnosis: Vec<crate::StationDiagnosis>,
    /// The station problem indicator of the station's frames: a fault is pending, or a
    /// client reported a problem.
    #[serde(default)]
    pub station_problem: bool,
    /// For a station its program defines (`[station] gsdml` and no submodules): its file and
    /// its program.
    #[serde(default)]
    pub program: Option<StationProgramReport>,
    /// The port's LLDP neighbours, as they announced themselves.
    #[serde(default)]
    pub neighbours: Vec<NeighbourReport>,
    /// The alias name the neighbour gives the station (`<peer port>.<peer station>`), which
    /// DCP Identify answers to.
    #[serde(default)]
    pub alias_name: Option<String>,
    /// An engineering tool's device access AR beside the PLC's, if one is up.
    #[serde(default)]
    pub access_ar: Option<AccessArReport>,
}

/// An engineering tool's device access AR, for the status report.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct AccessArReport {
    /// Its ARUUID.
    pub ar_uuid: String,
    /// The tool's NameOfStation.
    pub tool_name: String,
    /// The tool's MAC address.
    pub tool_mac: String,
}

/// The controller's own station, for the status report (IO-Base's CONFIG_NAME_ADDR_INFO
/// and communication counters).
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct ControllerReport {
    /// Its NameOfStation.
    pub station_name: String,
    /// Its type of station.
    pub type_of_station: String,
    /// The network interface (`"sim"`: the simulated network).
    pub interface: String,
    /// The interface's MAC address.
    #[serde(default)]
    pub mac: String,
    /// Its IPv4 address.
    pub ip: String,
    /// Its subnet mask.
    pub netmask: String,
    /// Its default router ("0.0.0.0": none known).
    pub gateway: String,
    /// The interface's Ethernet counters since procimgd started or they were reset (none on
    /// the simulated network).
    pub counters: Option<InterfaceCounters>,
    /// The interface submodule's diagnostic address (`[interface] diagnostic_address`).
    #[serde(default)]
    pub interface_address: u32,
    /// The port submodule's diagnostic address.
    #[serde(default)]
    pub port_address: u32,
    /// Whether programs may set the station's NameOfStation (`[interface]
    /// name_by_program`).
    #[serde(default)]
    pub name_by_program: bool,
    /// Whether programs may set its IP suite (`address_by_program`).
    #[serde(default)]
    pub address_by_program: bool,
}

/// An interface's Ethernet counters (the kernel's, since the last reset).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct InterfaceCounters {
    /// Frames sent.
    pub frames_sent: u64,
    /// Sends failed by a collision.
    pub send_collisions: u64,
    /// Sends failed otherwise.
    pub send_errors: u64,
    /// Frames received.
    pub frames_received: u64,
    /// Frames received with errors.
    pub receive_errors: u64,
    /// Frames received and dropped.
    pub received_dropped: u64,
}

/// An LLDP neighbour of the station's port, for the status report.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct NeighbourReport {
    /// Its Chassis ID, as text (a MAC address as `aa:bb:…`).
    pub chassis_id: String,
    /// Its Port ID, as text.
    pub port_id: String,
    /// Its PROFINET station name, if it announced one.
    pub station: Option<String>,
    /// Its port name (`port-001`), if it announced one.
    pub port: Option<String>,
    /// Its interface MAC address.
    pub mac: String,
    /// Its IPv4 management address, if it announced one.
    pub ip: Option<String>,
    /// The MAU type it runs (IETF RFC 4836), if it announced one.
    pub mau_type: Option<u16>,
    /// Seconds until it is forgotten without a newer frame.
    pub ttl_left_s: u64,
}

/// A station its program defines, for the status report.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct StationProgramReport {
    /// The station's GSDML file, as configured.
    pub gsdml: String,
    /// The program that defined the station (its name and process id); none while the
    /// station waits for one, off the wire.
    pub defined_by: Option<String>,
}

/// An AR of the device role, for the status report.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ArReport {
    /// Where it stands.
    pub state: ArState,
    /// The ARUUID.
    pub ar_uuid: String,
    /// The PLC's MAC address.
    pub controller_mac: String,
    /// The PLC's NameOfStation (empty from an older server).
    #[serde(default)]
    pub controller_name: String,
    /// Whether the PLC's provider is in RUN (its output frames' DataStatus); none before its
    /// first frame.
    #[serde(default)]
    pub plc_running: Option<bool>,
}

/// A run of forced bytes in a status report.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct ForceReport {
    /// I or Q.
    pub space: Space,
    /// First logical address.
    pub address: u32,
    /// The forced values.
    pub data: Vec<u8>,
    /// Station name of the submodule's device.
    pub device: String,
    /// Slot.
    pub slot: u16,
    /// Subslot.
    pub subslot: u16,
}

impl StatusReport {
    /// The forces that cover any of `length` bytes from `address` in `space`.
    pub fn forces_in(
        &self,
        space: Space,
        address: u32,
        length: u32,
    ) -> impl Iterator<Item = &ForceReport> {
        let end = address.saturating_add(length);
        self.forces.iter().filter(move |f| {
            f.space == space
                && f.address < end
                && address < f.address.saturating_add(f.data.len() as u32)
        })
    }
}

/// One announced notification subscriber in a status report.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct SubscriberReport {
    /// Name it announced.
    pub name: String,
    /// Process id.
    pub pid: u32,
    /// Whether alarms wait for its acknowledgement.
    pub acknowledges_alarms: bool,
    /// Alarms waiting for its acknowledgement now.
    pub alarms_waiting: u32,
}
