// SPDX-License-Identifier: MIT OR Apache-2.0
//! The `#[repr(C)]` types that server, Rust clients and C clients share.
//!
//! Every field is a fixed-width integer or a byte array; there is no implicit padding (checked
//! below at compile time), so the C header generated from this file describes the same bytes.

use core::mem::{align_of, offset_of, size_of};

#[cfg(feature = "iceoryx2")]
use iceoryx2_bb_derive_macros::ZeroCopySend;
#[cfg(feature = "iceoryx2")]
use iceoryx2_bb_elementary_traits::zero_copy_send::ZeroCopySend;

/// "PROCIMG1" as the bytes of a little-endian `u64`: the first field of every header.
pub const IMAGE_MAGIC: u64 = 0x3147_4D49_434F_5250;
/// Version of this layout. Raised on every incompatible change of a shared type.
pub const LAYOUT_VERSION: u32 = 2;
/// Most clients attached to one server instance at the same time.
pub const MAX_CLIENTS: usize = 64;
/// Mode changes an image header remembers.
pub const MODE_HISTORY: usize = 4;
/// A logical address field that holds no address (the submodule has no data in that space).
pub const NO_ADDRESS: u32 = 0xFFFF_FFFF;
/// Nanoseconds of one `CycleInfo::cycle_count` unit (the PROFINET base clock, 31.25 µs).
pub const CYCLE_COUNT_UNIT_NS: u64 = 31_250;
/// Bytes of a station name field, NUL-padded (PROFINET NameOfStation is at most 240).
pub const STATION_NAME_LEN: usize = 240;

/// The server is an IO controller: the image's inputs come from its devices, its outputs
/// go to them (`LayoutHeader::role`).
pub const ROLE_CONTROLLER: u32 = 0;
/// The server is an IO device: the server-written part of the image (the submodule table's
/// `input_*` fields) carries the output data the PLC wrote (Q), the client-written part
/// (`output_*`) the device's input data that the PLC reads (I). Directions are named from
/// the PLC's view, as in IO-Base's device interface.
pub const ROLE_DEVICE: u32 = 1;

/// Mode OFFLINE: no IO data is exchanged with the devices.
pub const MODE_OFFLINE: u32 = 0;
/// Mode CLEAR: the devices are connected, outputs go out marked invalid.
pub const MODE_CLEAR: u32 = 1;
/// Mode OPERATE: outputs go out valid.
pub const MODE_OPERATE: u32 = 2;

/// IOPS/IOCS value GOOD (DataState bit set, detected by the subslot).
pub const IOXS_GOOD: u8 = 0x80;
/// IOPS/IOCS value BAD, detected by the subslot.
pub const IOXS_BAD: u8 = 0x00;
/// IOPS/IOCS value BAD, detected by the IO controller (device failed, client late, mode CLEAR).
pub const IOXS_BAD_BY_CONTROLLER: u8 = 0x60;
/// IOPS/IOCS value BAD, detected by the IO device: what a server in the device role sends
/// for data no client provides (no owner, client late, mode CLEAR).
pub const IOXS_BAD_BY_DEVICE: u8 = 0x40;

/// `ClientSubmoduleStatus::flags`: the client wrote this submodule's output data.
pub const CLIENT_WROTE_OUTPUTS: u8 = 0x01;
/// `ClientSubmoduleStatus::flags`: `output_iops` is set.
pub const CLIENT_SET_OUTPUT_IOPS: u8 = 0x02;
/// `ClientSubmoduleStatus::flags`: `input_iocs` is set.
pub const CLIENT_SET_INPUT_IOCS: u8 = 0x04;

/// `OutputHeader::flags`: the sample is this client's OPDONE for `OutputHeader::cycle_number`.
pub const OUTPUT_SYNCHRONOUS: u32 = 0x01;

/// `SubmoduleEntry::rt_class` of RT class 1 (unsynchronised) data.
pub const RT_CLASS_1: u8 = 1;
/// `SubmoduleEntry::rt_class` of RT class 3 (IRT) data.
pub const RT_CLASS_3: u8 = 3;

/// The cycle's timing, as IO-Base's `PNIO_CYCLE_INFO` but in nanoseconds.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "iceoryx2", derive(ZeroCopySend))]
pub struct CycleInfo {
    /// Cycle index k since the server started (cycle k starts at epoch + k·T).
    pub cycle_number: u64,
    /// `CLOCK_MONOTONIC` time, in ns, at which cycle k was due to start.
    pub cycle_start_ns: u64,
    /// Free-running clock (`CLOCK_MONOTONIC`, ns) when this info was stamped.
    pub clock_ns: u64,
    /// `clock_ns - cycle_start_ns`.
    pub since_cycle_start_ns: u64,
    /// Cycle counter in 31.25 µs units, 16 significant bits: +32 per 1 ms cycle.
    pub cycle_count: u32,
    /// Reserved, zero.
    pub reserved: u32,
}

impl CycleInfo {
    /// Stamps the info with `clock_ns`: the clock and the time since the cycle's start.
    pub fn stamp(&mut self, clock_ns: u64) {
        self.clock_ns = clock_ns;
        self.since_cycle_start_ns = clock_ns.saturating_sub(self.cycle_start_ns);
    }
}

/// The iceoryx2 user header of every input-image sample.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(
    feature = "iceoryx2",
    derive(ZeroCopySend),
    type_name("procimg::ImageHeader")
)]
pub struct ImageHeader {
    /// [`IMAGE_MAGIC`].
    pub magic: u64,
    /// [`LAYOUT_VERSION`].
    pub layout_version: u32,
    /// `size_of::<ImageHeader>()`.
    pub header_size: u32,
    /// [`crate::layout_hash`] of the layout this image follows.
    pub layout_hash: u64,
    /// Identifies one run of the server; changes when the server restarts.
    pub generation: u64,
    /// This cycle's timing.
    pub cycle: CycleInfo,
    /// Current mode ([`MODE_OFFLINE`], [`MODE_CLEAR`], [`MODE_OPERATE`]).
    pub mode: u32,
    /// Number of submodules in the layout.
    pub submodule_count: u32,
    /// Bytes of the sample's payload.
    pub payload_size: u32,
    /// Mode changes since the server started; the mode after change n is
    /// `mode_history[n % MODE_HISTORY]`, so a client that missed MODE events can replay
    /// every step it did not see.
    pub mode_changes: u32,
    /// Cycle time in ns.
    pub cycle_ns: u64,
    /// OPDONE deadline, in ns after the cycle start.
    pub opdone_deadline_ns: u64,
    /// For each client slot, the last cycle in which that client got OPFAULT (0: never).
    pub opfault_cycle: [u64; MAX_CLIENTS],
    /// The modes after the last [`MODE_HISTORY`] changes (see `mode_changes`).
    pub mode_history: [u32; MODE_HISTORY],
}

/// One IO device of the IO system.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "iceoryx2", derive(ZeroCopySend))]
pub struct DeviceEntry {
    /// NameOfStation, NUL-padded.
    pub station_name: [u8; STATION_NAME_LEN],
    /// PROFINET vendor ID.
    pub vendor_id: u16,
    /// PROFINET device ID.
    pub device_id: u16,
    /// Device instance.
    pub instance: u16,
    /// Reduction ratio of this device's IO CRs (cycles per frame).
    pub reduction_ratio: u16,
    /// IPv4 address, network byte order.
    pub ip_address: [u8; 4],
    /// Index of the device's first entry in the submodule table.
    pub first_submodule: u32,
    /// Number of submodule table entries of this device.
    pub submodule_count: u32,
    /// Watchdog factor (DataHoldFactor) of the consumer CR.
    pub watchdog_factor: u16,
    /// Reserved, zero.
    pub reserved: u16,
}

/// One submodule of the process image.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "iceoryx2", derive(ZeroCopySend))]
pub struct SubmoduleEntry {
    /// Index of the device in the device table.
    pub device: u16,
    /// Slot number.
    pub slot: u16,
    /// Subslot number.
    pub subslot: u16,
    /// RT class of its data ([`RT_CLASS_1`], [`RT_CLASS_3`]).
    pub rt_class: u8,
    /// Reserved, zero.
    pub reserved0: u8,
    /// Application process identifier.
    pub api: u32,
    /// Module ident number.
    pub module_ident: u32,
    /// Submodule ident number.
    pub submodule_ident: u32,
    /// First logical address in the input (I) space, or [`NO_ADDRESS`]. A submodule
    /// without any IO data has its diagnostic address here (input and output length 0).
    pub input_address: u32,
    /// First logical address in the output (Q) space, or [`NO_ADDRESS`].
    pub output_address: u32,
    /// Bytes of input data.
    pub input_length: u16,
    /// Bytes of output data.
    pub output_length: u16,
    /// Offset of the input data in the input-image payload.
    pub input_offset: u32,
    /// Offset of the output data in an output-sample payload.
    pub output_offset: u32,
    /// Offset of the output data's mirror in the input-image payload. The mirror is not
    /// packed: in the controller role each device's outputs lie in its output frame, which
    /// the mirror holds whole (header and status bytes between the outputs), so that the
    /// frame is sent from the image. Read each submodule at its own offset.
    pub output_mirror_offset: u32,
    /// Offset in the input-image payload of this submodule's [`SubmoduleStatus`].
    pub status_offset: u32,
    /// Offset in an output-sample payload of this submodule's [`ClientSubmoduleStatus`].
    pub client_status_offset: u32,
    /// Reserved, zero.
    pub reserved1: u32,
    /// Reserved, zero.
    pub reserved2: u32,
    /// Reserved, zero.
    pub reserved3: u32,
}

/// The status bytes of one submodule in the input image, as exchanged in the cycle.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "iceoryx2", derive(ZeroCopySend))]
pub struct SubmoduleStatus {
    /// Remote status of the inputs: the device's IOPS.
    pub input_iops: u8,
    /// Local status of the inputs as sent to the device: our IOCS.
    pub input_iocs: u8,
    /// Local status of the outputs as sent to the device: our IOPS.
    pub output_iops: u8,
    /// Remote status of the outputs: the device's IOCS for the previous cycle's outputs.
    pub output_iocs: u8,
}

/// What a client sets for one submodule in an output sample.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "iceoryx2", derive(ZeroCopySend))]
pub struct ClientSubmoduleStatus {
    /// Local status for the outputs (IOPS), valid with [`CLIENT_SET_OUTPUT_IOPS`].
    pub output_iops: u8,
    /// Local status for the inputs (IOCS), valid with [`CLIENT_SET_INPUT_IOCS`].
    pub input_iocs: u8,
    /// `CLIENT_*` flags.
    pub flags: u8,
    /// Reserved, zero.
    pub reserved: u8,
}

/// The iceoryx2 user header of the layout sample.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(
    feature = "iceoryx2",
    derive(ZeroCopySend),
    type_name("procimg::LayoutHeader")
)]
pub struct LayoutHeader {
    /// [`IMAGE_MAGIC`].
    pub magic: u64,
    /// [`LAYOUT_VERSION`].
    pub layout_version: u32,
    /// `size_of::<LayoutHeader>()`.
    pub header_size: u32,
    /// [`crate::layout_hash`] of this layout.
    pub layout_hash: u64,
    /// Identifies one run of the server.
    pub generation: u64,
    /// Cycle time in ns.
    pub cycle_ns: u64,
    /// OPDONE deadline, in ns after the cycle start.
    pub opdone_deadline_ns: u64,
    /// Entries in the device table.
    pub device_count: u32,
    /// Entries in the submodule table.
    pub submodule_count: u32,
    /// Bytes of input data.
    pub input_size: u32,
    /// Bytes of output data.
    pub output_size: u32,
    /// Bytes of an input-image payload.
    pub input_payload_size: u32,
    /// Bytes of an output-sample payload.
    pub output_payload_size: u32,
    /// Offset of the device table in the layout payload.
    pub device_table_offset: u32,
    /// Offset of the submodule table in the layout payload.
    pub submodule_table_offset: u32,
    /// Offset of the status array in the input-image payload.
    pub status_offset: u32,
    /// Offset of the output mirror in the input-image payload: where it starts. Its
    /// submodules are not packed (see `SubmoduleEntry::output_mirror_offset`).
    pub output_mirror_offset: u32,
    /// Offset of the client status array in an output-sample payload.
    pub client_status_offset: u32,
    /// The PROFINET role of the server: [`ROLE_CONTROLLER`] or [`ROLE_DEVICE`].
    pub role: u32,
}

/// The iceoryx2 user header of an output sample sent by a client.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(
    feature = "iceoryx2",
    derive(ZeroCopySend),
    type_name("procimg::OutputHeader")
)]
pub struct OutputHeader {
    /// [`IMAGE_MAGIC`].
    pub magic: u64,
    /// Layout hash the client wrote against.
    pub layout_hash: u64,
    /// The cycle these outputs belong to (synchronous), or the newest cycle seen (asynchronous).
    pub cycle_number: u64,
    /// Token the server gave the client at registration; samples with a stale token are dropped.
    pub client_token: u64,
    /// The client's slot.
    pub client_slot: u32,
    /// `OUTPUT_*` flags.
    pub flags: u32,
    /// The client's `CLOCK_MONOTONIC` in ns when it sent the sample: the server measures the
    /// OPDONE one-way latency from it.
    pub sent_ns: u64,
}

const _: () = {
    assert!(size_of::<CycleInfo>() == 40 && align_of::<CycleInfo>() == 8);
    assert!(offset_of!(CycleInfo, cycle_count) == 32);
    assert!(offset_of!(ImageHeader, cycle) == 32);
    assert!(offset_of!(ImageHeader, mode) == 72);
    assert!(offset_of!(ImageHeader, cycle_ns) == 88);
    assert!(offset_of!(ImageHeader, opfault_cycle) == 104);
    assert!(offset_of!(ImageHeader, mode_history) == 104 + 8 * MAX_CLIENTS);
    assert!(size_of::<ImageHeader>() == 104 + 8 * MAX_CLIENTS + 4 * MODE_HISTORY);
    assert!(size_of::<DeviceEntry>() == 264 && align_of::<DeviceEntry>() == 4);
    assert!(offset_of!(DeviceEntry, ip_address) == 248);
    assert!(offset_of!(DeviceEntry, watchdog_factor) == 260);
    assert!(size_of::<SubmoduleEntry>() == 64 && align_of::<SubmoduleEntry>() == 4);
    assert!(offset_of!(SubmoduleEntry, api) == 8);
    assert!(offset_of!(SubmoduleEntry, input_address) == 20);
    assert!(offset_of!(SubmoduleEntry, input_length) == 28);
    assert!(offset_of!(SubmoduleEntry, input_offset) == 32);
    assert!(offset_of!(SubmoduleEntry, status_offset) == 44);
    assert!(offset_of!(SubmoduleEntry, reserved3) == 60);
    assert!(size_of::<SubmoduleStatus>() == 4);
    assert!(size_of::<ClientSubmoduleStatus>() == 4);
    assert!(size_of::<LayoutHeader>() == 96);
    assert!(offset_of!(LayoutHeader, device_count) == 48);
    assert!(offset_of!(LayoutHeader, role) == 92);
    assert!(size_of::<OutputHeader>() == 48 && offset_of!(OutputHeader, sent_ns) == 40);
    assert!(offset_of!(OutputHeader, client_slot) == 32);
};

/// The modes of the IO controller, as IO-Base's `PNIO_MODE_TYPE`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "UPPERCASE"))]
pub enum Mode {
    /// No IO data exchange; connections released.
    Offline,
    /// Connected; outputs go out marked invalid.
    Clear,
    /// Normal operation.
    Operate,
}

impl Mode {
    /// The value stored in shared memory.
    pub const fn as_u32(self) -> u32 {
        match self {
            Mode::Offline => MODE_OFFLINE,
            Mode::Clear => MODE_CLEAR,
            Mode::Operate => MODE_OPERATE,
        }
    }

    /// The mode for a shared-memory value, `None` for an unknown value.
    pub const fn from_u32(v: u32) -> Option<Mode> {
        match v {
            MODE_OFFLINE => Some(Mode::Offline),
            MODE_CLEAR => Some(Mode::Clear),
            MODE_OPERATE => Some(Mode::Operate),
            _ => None,
        }
    }

    /// Upper-case name as IO-Base spells it: OFFLINE, CLEAR, OPERATE.
    pub const fn name(self) -> &'static str {
        match self {
            Mode::Offline => "OFFLINE",
            Mode::Clear => "CLEAR",
            Mode::Operate => "OPERATE",
        }
    }
}

impl core::fmt::Display for Mode {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

impl core::str::FromStr for Mode {
    type Err = UnknownMode;
    fn from_str(s: &str) -> Result<Mode, UnknownMode> {
        match s.to_ascii_lowercase().as_str() {
            "offline" => Ok(Mode::Offline),
            "clear" => Ok(Mode::Clear),
            "operate" => Ok(Mode::Operate),
            _ => Err(UnknownMode),
        }
    }
}

/// A mode name that is none of offline, clear, operate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct UnknownMode;

impl core::fmt::Display for UnknownMode {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str("unknown mode: use offline, clear or operate")
    }
}

impl core::error::Error for UnknownMode {}

/// Whether an IOPS/IOCS byte says GOOD (its DataState bit).
pub const fn ioxs_is_good(ioxs: u8) -> bool {
    ioxs & 0x80 != 0
}

/// IO-Base's CycleCount for cycle `k` of length `cycle_ns`: 31.25 µs units, 16 bits significant.
pub const fn cycle_count(k: u64, cycle_ns: u64) -> u32 {
    ((k.wrapping_mul(cycle_ns) / CYCLE_COUNT_UNIT_NS) & 0xFFFF) as u32
}

impl SubmoduleEntry {
    /// An entry with every field zero except the addresses, which hold [`NO_ADDRESS`].
    pub const EMPTY: SubmoduleEntry = SubmoduleEntry {
        device: 0,
        slot: 0,
        subslot: 0,
        rt_class: RT_CLASS_1,
        reserved0: 0,
        api: 0,
        module_ident: 0,
        submodule_ident: 0,
        input_address: NO_ADDRESS,
        output_address: NO_ADDRESS,
        input_length: 0,
        output_length: 0,
        input_offset: 0,
        output_offset: 0,
        output_mirror_offset: 0,
        status_offset: 0,
        client_status_offset: 0,
        reserved1: 0,
        reserved2: 0,
        reserved3: 0,
    };

    /// Whether logical input address `addr` lies in this submodule's inputs.
    pub const fn has_input_address(&self, addr: u32) -> bool {
        self.input_address != NO_ADDRESS
            && addr >= self.input_address
            && (addr - self.input_address) < self.input_length as u32
    }

    /// Whether logical output address `addr` lies in this submodule's outputs.
    pub const fn has_output_address(&self, addr: u32) -> bool {
        self.output_address != NO_ADDRESS
            && addr >= self.output_address
            && (addr - self.output_address) < self.output_length as u32
    }

    /// Its addresses in the I space (`output` false) or the Q space, for people: `0..15`,
    /// `diag 22` for a diagnostic address, `-` for none.
    pub fn address_text(&self, output: bool) -> alloc::string::String {
        let (first, len) = if output {
            (self.output_address, self.output_length)
        } else {
            (self.input_address, self.input_length)
        };
        match self.diagnostic_address() {
            Some(a) if !output => alloc::format!("diag {a}"),
            _ if len == 0 || first == NO_ADDRESS => alloc::string::String::from("-"),
            _ => alloc::format!("{first}..{}", u64::from(first) + u64::from(len) - 1),
        }
    }

    /// The diagnostic address of a submodule without IO data: the I-space address of
    /// length 0 that record jobs and alarms name it by.
    pub const fn diagnostic_address(&self) -> Option<u32> {
        if self.input_length == 0 && self.output_length == 0 && self.input_address != NO_ADDRESS {
            Some(self.input_address)
        } else {
            None
        }
    }
}

impl DeviceEntry {
    /// The station name without its NUL padding; `None` if it is not UTF-8.
    pub fn station_name(&self) -> Option<&str> {
        let end = self
            .station_name
            .iter()
            .position(|&b| b == 0)
            .unwrap_or(STATION_NAME_LEN);
        core::str::from_utf8(&self.station_name[..end]).ok()
    }
}

impl ImageHeader {
    /// A header for `generation` with everything else zero or empty.
    pub const fn new(layout_hash: u64, generation: u64) -> ImageHeader {
        ImageHeader {
            magic: IMAGE_MAGIC,
            layout_version: LAYOUT_VERSION,
            header_size: size_of::<ImageHeader>() as u32,
            layout_hash,
            generation,
            cycle: CycleInfo {
                cycle_number: 0,
                cycle_start_ns: 0,
                clock_ns: 0,
                since_cycle_start_ns: 0,
                cycle_count: 0,
                reserved: 0,
            },
            mode: MODE_OFFLINE,
            submodule_count: 0,
            payload_size: 0,
            mode_changes: 0,
            cycle_ns: 0,
            opdone_deadline_ns: 0,
            opfault_cycle: [0; MAX_CLIENTS],
            mode_history: [MODE_OFFLINE; MODE_HISTORY],
        }
    }
}

impl Default for ImageHeader {
    fn default() -> Self {
        ImageHeader::new(0, 0)
    }
}

impl Default for LayoutHeader {
    fn default() -> Self {
        LayoutHeader {
            magic: IMAGE_MAGIC,
            layout_version: LAYOUT_VERSION,
            header_size: size_of::<LayoutHeader>() as u32,
            layout_hash: 0,
            generation: 0,
            cycle_ns: 0,
            opdone_deadline_ns: 0,
            device_count: 0,
            submodule_count: 0,
            input_size: 0,
            output_size: 0,
            input_payload_size: 0,
            output_payload_size: 0,
            device_table_offset: 0,
            submodule_table_offset: 0,
            status_offset: 0,
            output_mirror_offset: 0,
            client_status_offset: 0,
            role: ROLE_CONTROLLER,
        }
    }
}

impl Default for OutputHeader {
    fn default() -> Self {
        OutputHeader {
            magic: IMAGE_MAGIC,
            layout_hash: 0,
            cycle_number: 0,
            client_token: 0,
            client_slot: 0,
            flags: 0,
            sent_ns: 0,
        }
    }
}

#[cfg(test)]
mod stamp_tests {
    use super::CycleInfo;

    #[test]
    fn a_stamp_sets_the_clock_and_the_time_since_the_cycle_started() {
        let mut c = CycleInfo {
            cycle_number: 7,
            cycle_start_ns: 1_000,
            ..CycleInfo::default()
        };
        c.stamp(1_250);
        assert_eq!((c.clock_ns, c.since_cycle_start_ns), (1_250, 250));
        // A clock behind the cycle's start (a start in the future) gives 0, not a wrap.
        c.stamp(900);
        assert_eq!((c.clock_ns, c.since_cycle_start_ns), (900, 0));
        assert_eq!(c.cycle_number, 7, "only the stamp changes");
    }
}
