// SPDX-License-Identifier: MIT OR Apache-2.0
//! The blocks of a Connect request and response (RPC opnum 0).
//!
//! A Connect request carries an ARBlockReq, one IOCRBlockReq per IO CR, an AlarmCRBlockReq
//! and one ExpectedSubmoduleBlockReq per module entry; the positive response an ARBlockRes,
//! one IOCRBlockRes per IO CR, an AlarmCRBlockRes, a ModuleDiffBlock when the real modules
//! differ from the expected ones, and an ARServerBlock in advanced startup. Every block starts
//! with a [`BlockHeader`] (version 1.0 for all of them) and is big-endian whatever the RPC DREP.
//!
//! The blocks nest variable-length lists, so they have no buffer views: each is an owned
//! `Repr` with `parse` (the block at the start of a slice, header included; bytes after it are
//! ignored), `buffer_len` and `emit`. `parse` checks the block type, version 1.0 and that the
//! lists fill the block exactly; [`ConnectRequest::parse`] and [`ConnectResponse::parse`]
//! take the whole block sequence after the NDR header.
//!
//! `emit` writes into the first `buffer_len()` bytes of a buffer and gives [`EmitError`]
//! (never a panic) when the buffer is shorter or a value does not fit its wire field: a list
//! longer than its 16-bit count, a block longer than 65 539 bytes, a station name over
//! 65 535 bytes, or data descriptions that do not match the submodule type.

use super::common::{BLOCK_HEADER_LEN, blocks};
use super::cursor::{Reader, Writer};
use super::{BlockHeader, BlockType, EmitError, EmitResult, Error, MacAddress, Result, Uuid};

#[cfg(test)]
mod tests;

/// The LT field of IOCR and alarm CR blocks: the PROFINET EtherType.
pub const LT_PROFINET: u16 = 0x8892;
/// CMInitiatorUDPRTPort / CMResponderUDPRTPort when RT runs over Ethernet (0x8892).
pub const UDP_RT_PORT_NONE: u16 = 0x8892;
/// ARType IOCARSingle: the AR type of a plain IO controller.
pub const AR_TYPE_IOC_SINGLE: u16 = 0x0001;

/// ARProperties bits.
pub mod ar_properties {
    /// Bits 0–2: State.
    pub const STATE_MASK: u32 = 0x0000_0007;
    /// State = Active (the only valid value).
    pub const STATE_ACTIVE: u32 = 0x0000_0001;
    /// Bit 3: SupervisorTakeoverAllowed.
    pub const SUPERVISOR_TAKEOVER_ALLOWED: u32 = 1 << 3;
    /// Bit 4: ParametrizationServer = CM initiator (p-net rejects 0).
    pub const PARAMETERIZATION_SERVER_CM_INITIATOR: u32 = 1 << 4;
    /// Bit 8: DeviceAccess.
    pub const DEVICE_ACCESS: u32 = 1 << 8;
    /// Bits 9–10: CompanionAR.
    pub const COMPANION_AR_MASK: u32 = 0x0000_0600;
    /// Bit 11: AcknowledgeCompanionAR.
    pub const ACKNOWLEDGE_COMPANION_AR: u32 = 1 << 11;
    /// Bit 29: CombinedObjectContainer.
    pub const COMBINED_OBJECT_CONTAINER: u32 = 1 << 29;
    /// Bit 30: StartupMode advanced (0 = legacy).
    pub const STARTUP_MODE_ADVANCED: u32 = 1 << 30;
    /// Bit 31: PullModuleAlarmAllowed.
    pub const PULL_MODULE_ALARM_ALLOWED: u32 = 1 << 31;
    /// Active, CM initiator as parameterization server, legacy startup: 0x00000011.
    pub const LEGACY: u32 = STATE_ACTIVE | PARAMETERIZATION_SERVER_CM_INITIATOR;
    /// [`LEGACY`] with advanced startup: 0x40000011 (what the S7-1515 sends).
    pub const ADVANCED: u32 = LEGACY | STARTUP_MODE_ADVANCED;
}

/// IOCRType values.
pub mod iocr_type {
    /// Input CR (device → controller).
    pub const INPUT: u16 = 1;
    /// Output CR (controller → device).
    pub const OUTPUT: u16 = 2;
    /// Multicast provider.
    pub const MULTICAST_PROVIDER: u16 = 3;
    /// Multicast consumer.
    pub const MULTICAST_CONSUMER: u16 = 4;
}

/// IOCRProperties bits.
pub mod iocr_properties {
    /// Bits 0–3: RTClass.
    pub const RT_CLASS_MASK: u32 = 0x0000_000f;
    /// RTClass 1 (legacy RT, FrameIDs 0xC000–0xFBFF).
    pub const RT_CLASS_1: u32 = 1;
    /// RTClass 2 (RT, FrameIDs 0x8000–0xBFFF; what the S7 uses).
    pub const RT_CLASS_2: u32 = 2;
    /// RTClass 3 (IRT).
    pub const RT_CLASS_3: u32 = 3;
    /// RTClass UDP.
    pub const RT_CLASS_UDP: u32 = 4;
}

/// FrameSendOffset meaning "best effort" (RT class 1/2).
pub const FRAME_SEND_OFFSET_BEST_EFFORT: u32 = 0xffff_ffff;
/// IOCRTagHeader and AlarmCRTagHeaderHigh: VLAN 0, priority 6.
pub const TAG_HEADER_PRIO_6: u16 = 0xc000;
/// AlarmCRTagHeaderLow: VLAN 0, priority 5.
pub const TAG_HEADER_PRIO_5: u16 = 0xa000;
/// AlarmCRType of the alarm CR.
pub const ALARM_CR_TYPE: u16 = 0x0001;

/// SubmoduleProperties bits and DataDescription values of ExpectedSubmoduleBlockReq.
pub mod submodule {
    /// SubmoduleProperties bits 0–1: Type.
    pub const TYPE_MASK: u16 = 0x0003;
    /// Type: no IO data (described as an input of length 0).
    pub const TYPE_NO_IO: u16 = 0;
    /// Type: inputs.
    pub const TYPE_INPUT: u16 = 1;
    /// Type: outputs.
    pub const TYPE_OUTPUT: u16 = 2;
    /// Type: inputs and outputs (two data descriptions, input first).
    pub const TYPE_INPUT_OUTPUT: u16 = 3;
    /// SubmoduleProperties bit 2: SharedInput.
    pub const SHARED_INPUT: u16 = 1 << 2;
    /// SubmoduleProperties bit 3: ReduceInputSubmoduleDataLength.
    pub const REDUCE_INPUT_LENGTH: u16 = 1 << 3;
    /// SubmoduleProperties bit 4: ReduceOutputSubmoduleDataLength.
    pub const REDUCE_OUTPUT_LENGTH: u16 = 1 << 4;
    /// SubmoduleProperties bit 5: DiscardIOXS.
    pub const DISCARD_IOXS: u16 = 1 << 5;
    /// DataDescription: input.
    pub const DATA_INPUT: u16 = 1;
    /// DataDescription: output.
    pub const DATA_OUTPUT: u16 = 2;
}

/// The body of one block type, in and out.
trait Body: Sized {
    const BLOCK_TYPE: BlockType;
    fn body_len(&self) -> usize;
    fn read(r: &mut Reader<'_>) -> Result<Self>;
    fn write(&self, w: &mut Writer<'_>) -> EmitResult<()>;
}

fn parse_block<B: Body>(b: &[u8]) -> Result<B> {
    let h = BlockHeader::parse(b)?;
    if h.block_type != B::BLOCK_TYPE || (h.version_high, h.version_low) != (1, 0) {
        return Err(Error);
    }
    let mut r = Reader::new(h.body(b));
    let v = B::read(&mut r)?;
    r.end()?;
    Ok(v)
}

fn block_len<B: Body>(v: &B) -> usize {
    BLOCK_HEADER_LEN.saturating_add(v.body_len())
}

fn emit_block<B: Body>(v: &B, buf: &mut [u8]) -> EmitResult<()> {
    let header = BlockHeader::v1(B::BLOCK_TYPE, v.body_len())?;
    let what = B::BLOCK_TYPE.name().unwrap_or("block");
    let total = block_len(v);
    EmitError::check_len(what, total, buf.len())?;
    let body = put_bytes(buf, &header.to_bytes())?;
    let body = body.get_mut(..v.body_len()).unwrap_or_default();
    let mut w = Writer::new(what, body);
    v.write(&mut w)?;
    w.finish()
}

/// The public `parse`, `buffer_len`, `emit` and `to_vec` of a block type.
macro_rules! block_api {
    ($t:ty, $name:literal) => {
        impl $t {
            #[doc = concat!("Parses the ", $name, " at the start of `b` (bytes after it are ignored).")]
            pub fn parse(b: &[u8]) -> Result<$t> {
                parse_block(b)
            }

            /// Bytes of the block, header included.
            pub fn buffer_len(&self) -> usize {
                block_len(self)
            }

            /// Writes the block into the first [`buffer_len`](Self::buffer_len) bytes of `buf`.
            /// [`EmitError`] if `buf` is shorter or a value does not fit its wire field.
            pub fn emit(&self, buf: &mut [u8]) -> EmitResult<()> {
                emit_block(self, buf)
            }

            /// The block as a new vector.
            pub fn to_vec(&self) -> EmitResult<Vec<u8>> {
                crate::wire::emit_to_vec(self.buffer_len(), |b| self.emit(b))
            }
        }
    };
}

mod expected;
mod module_diff;
pub use expected::{DataDescription, ExpectedModule, ExpectedSubmodule, ExpectedSubmoduleBlockReq};
pub use module_diff::{
    ArInfo, IdentInfo, ModuleDiffApi, ModuleDiffBlock, ModuleDiffModule, ModuleDiffSubmodule,
    ModuleState, SubmoduleState,
};

/// ARBlockReq (0x0101): the AR the controller asks for.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct ArBlockReq {
    /// ARType ([`AR_TYPE_IOC_SINGLE`]).
    pub ar_type: u16,
    /// ARUUID: chosen by the controller, non-nil, new per AR.
    pub ar_uuid: Uuid,
    /// SessionKey: incremented by the controller per connect attempt.
    pub session_key: u16,
    /// CMInitiatorMacAdd: the controller's MAC (the source of its RT frames).
    pub initiator_mac: MacAddress,
    /// CMInitiatorObjectUUID: `DEA00000-6C97-11D1-8271-` + the controller's instance, device
    /// and vendor ID; the device's ApplicationReady is addressed to it.
    pub initiator_object_uuid: Uuid,
    /// ARProperties ([`ar_properties`] bits).
    pub ar_properties: u32,
    /// CMInitiatorActivityTimeoutFactor (× 100 ms, 1..=1000).
    pub activity_timeout_factor: u16,
    /// CMInitiatorUDPRTPort ([`UDP_RT_PORT_NONE`]).
    pub udp_rt_port: u16,
    /// CMInitiatorStationName: the controller's name of station.
    pub station_name: String,
}

impl ArBlockReq {
    /// The ARBlockReq of an IO controller's single AR, as the S7-1515 sends it: advanced
    /// startup ([`ar_properties::ADVANCED`]), activity timeout 20 s (factor 200), no UDP RT
    /// port.
    pub fn io_controller(
        ar_uuid: Uuid,
        session_key: u16,
        initiator_mac: MacAddress,
        initiator_object_uuid: Uuid,
        station_name: String,
    ) -> ArBlockReq {
        ArBlockReq {
            ar_type: AR_TYPE_IOC_SINGLE,
            ar_uuid,
            session_key,
            initiator_mac,
            initiator_object_uuid,
            ar_properties: ar_properties::ADVANCED,
            activity_timeout_factor: 200,
            udp_rt_port: UDP_RT_PORT_NONE,
            station_name,
        }
    }
}

impl Body for ArBlockReq {
    const BLOCK_TYPE: BlockType = BlockType::ArBlockReq;

    fn body_len(&self) -> usize {
        52usize.saturating_add(self.station_name.len())
    }

    fn read(r: &mut Reader<'_>) -> Result<Self> {
        Ok(ArBlockReq {
            ar_type: r.u16()?,
            ar_uuid: r.uuid()?,
            session_key: r.u16()?,
            initiator_mac: r.mac()?,
            initiator_object_uuid: r.uuid()?,
            ar_properties: r.u32()?,
            activity_timeout_factor: r.u16()?,
            udp_rt_port: r.u16()?,
            station_name: r.string()?,
        })
    }

    fn write(&self, w: &mut Writer<'_>) -> EmitResult<()> {
        w.u16(self.ar_type)?;
        w.put(&self.ar_uuid.0)?;
        w.u16(self.session_key)?;
        w.put(&self.initiator_mac.0)?;
        w.put(&self.initiator_object_uuid.0)?;
        w.u32(self.ar_properties)?;
        w.u16(self.activity_timeout_factor)?;
        w.u16(self.udp_rt_port)?;
        w.string("StationNameLength", &self.station_name)
    }
}

block_api!(ArBlockReq, "ARBlockReq");

/// A (slot, subslot, offset) entry of an IOCRBlockReq: an IODataObject (offset of the data;
/// its IOPS follows the data) or an IOCS (offset of the consumer status).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct IocrEntry {
    /// SlotNumber.
    pub slot: u16,
    /// SubslotNumber.
    pub subslot: u16,
    /// IODataObjectFrameOffset or IOCSFrameOffset: offset in the C_SDU.
    pub frame_offset: u16,
}

impl IocrEntry {
    fn read(r: &mut Reader<'_>) -> Result<IocrEntry> {
        Ok(IocrEntry {
            slot: r.u16()?,
            subslot: r.u16()?,
            frame_offset: r.u16()?,
        })
    }

    fn write(&self, w: &mut Writer<'_>) -> EmitResult<()> {
        w.u16(self.slot)?;
        w.u16(self.subslot)?;
        w.u16(self.frame_offset)
    }
}

/// The IO data objects and consumer statuses of one API in an IOCRBlockReq.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct IocrApi {
    /// API (0 by default).
    pub api: u32,
    /// IODataObjects: where each submodule's data (then its IOPS) sits in this CR.
    pub data_objects: Vec<IocrEntry>,
    /// IOCSs: where the consumer status of each submodule of the other direction sits.
    pub iocs: Vec<IocrEntry>,
}

impl IocrApi {
    fn wire_len(&self) -> usize {
        let entries = self.data_objects.len().saturating_add(self.iocs.len());
        8usize.saturating_add(entries.saturating_mul(6))
    }

    fn read(r: &mut Reader<'_>) -> Result<IocrApi> {
        Ok(IocrApi {
            api: r.u32()?,
            data_objects: r.list(IocrEntry::read)?,
            iocs: r.list(IocrEntry::read)?,
        })
    }

    fn write(&self, w: &mut Writer<'_>) -> EmitResult<()> {
        w.u32(self.api)?;
        w.count("NumberOfIODataObjects", self.data_objects.len())?;
        self.data_objects.iter().try_for_each(|e| e.write(w))?;
        w.count("NumberOfIOCS", self.iocs.len())?;
        self.iocs.iter().try_for_each(|e| e.write(w))
    }
}

/// IOCRBlockReq (0x0102): one IO CR, its timing and its C_SDU layout.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct IocrBlockReq {
    /// IOCRType ([`iocr_type`]).
    pub iocr_type: u16,
    /// IOCRReference: the controller's id for the CR, echoed in the IOCRBlockRes.
    pub iocr_reference: u16,
    /// LT ([`LT_PROFINET`]).
    pub lt: u16,
    /// IOCRProperties ([`iocr_properties`] bits).
    pub iocr_properties: u32,
    /// DataLength: C_SDU bytes (40..=1440).
    pub data_length: u16,
    /// FrameID proposed by the controller (the device may choose another for input CRs).
    pub frame_id: u16,
    /// SendClockFactor (× 31.25 µs; 32 = 1 ms).
    pub send_clock_factor: u16,
    /// ReductionRatio: a frame every RR send clocks.
    pub reduction_ratio: u16,
    /// Phase (1..=RR).
    pub phase: u16,
    /// Sequence (0).
    pub sequence: u16,
    /// FrameSendOffset ([`FRAME_SEND_OFFSET_BEST_EFFORT`] for RT).
    pub frame_send_offset: u32,
    /// WatchdogFactor (legacy; equal to the DataHoldFactor).
    pub watchdog_factor: u16,
    /// DataHoldFactor: cycles without a frame before the consumer gives up.
    pub data_hold_factor: u16,
    /// IOCRTagHeader ([`TAG_HEADER_PRIO_6`]).
    pub tag_header: u16,
    /// IOCRMulticastMACAdd (zeros for unicast CRs).
    pub multicast_mac: MacAddress,
    /// The data objects and consumer statuses per API.
    pub apis: Vec<IocrApi>,
}

impl Body for IocrBlockReq {
    const BLOCK_TYPE: BlockType = BlockType::IocrBlockReq;

    fn body_len(&self) -> usize {
        self.apis
            .iter()
            .fold(40usize, |n, a| n.saturating_add(a.wire_len()))
    }

    fn read(r: &mut Reader<'_>) -> Result<Self> {
        Ok(IocrBlockReq {
            iocr_type: r.u16()?,
            iocr_reference: r.u16()?,
            lt: r.u16()?,
            iocr_properties: r.u32()?,
            data_length: r.u16()?,
            frame_id: r.u16()?,
            send_clock_factor: r.u16()?,
            reduction_ratio: r.u16()?,
            phase: r.u16()?,
            sequence: r.u16()?,
            frame_send_offset: r.u32()?,
            watchdog_factor: r.u16()?,
            data_hold_factor: r.u16()?,
            tag_header: r.u16()?,
            multicast_mac: r.mac()?,
            apis: r.list(IocrApi::read)?,
        })
    }

    fn write(&self, w: &mut Writer<'_>) -> EmitResult<()> {
        w.u16(self.iocr_type)?;
        w.u16(self.iocr_reference)?;
        w.u16(self.lt)?;
        w.u32(self.iocr_properties)?;
        w.u16(self.data_length)?;
        w.u16(self.frame_id)?;
        w.u16(self.send_clock_factor)?;
        w.u16(self.reduction_ratio)?;
        w.u16(self.phase)?;
        w.u16(self.sequence)?;
        w.u32(self.frame_send_offset)?;
        w.u16(self.watchdog_factor)?;
        w.u16(self.data_hold_factor)?;
        w.u16(self.tag_header)?;
        w.put(&self.multicast_mac.0)?;
        w.count("NumberOfAPIs", self.apis.len())?;
        self.apis.iter().try_for_each(|a| a.write(w))
    }
}

block_api!(IocrBlockReq, "IOCRBlockReq");

impl IocrBlockReq {
    /// RTClass from the IOCRProperties.
    pub const fn rt_class(&self) -> u32 {
        self.iocr_properties & iocr_properties::RT_CLASS_MASK
    }

    /// The period of the CR in ns: SendClockFactor × ReductionRatio × 31 250 ns.
    pub const fn period_ns(&self) -> u64 {
        self.send_clock_factor as u64 * self.reduction_ratio as u64 * super::rt::TIME_UNIT_NS
    }
}

/// AlarmCRBlockReq (0x0103): the controller's alarm endpoint.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct AlarmCrBlockReq {
    /// AlarmCRType ([`ALARM_CR_TYPE`]).
    pub alarm_cr_type: u16,
    /// LT ([`LT_PROFINET`]).
    pub lt: u16,
    /// AlarmCRProperties: bit 0 priority (0 = user priority), bit 1 transport (0 = RTA over
    /// layer 2).
    pub properties: u32,
    /// RTATimeoutFactor (× 100 ms, 1..=100).
    pub rta_timeout_factor: u16,
    /// RTARetries (3..=15).
    pub rta_retries: u16,
    /// LocalAlarmReference: the controller's alarm reference (the device sends to it).
    pub local_alarm_reference: u16,
    /// MaxAlarmDataLength (200..=1432).
    pub max_alarm_data_length: u16,
    /// AlarmCRTagHeaderHigh ([`TAG_HEADER_PRIO_6`]).
    pub tag_header_high: u16,
    /// AlarmCRTagHeaderLow ([`TAG_HEADER_PRIO_5`]).
    pub tag_header_low: u16,
}

impl AlarmCrBlockReq {
    /// The AlarmCRBlockReq an IO controller sends, as the S7-1515 does: RTA over layer 2 with
    /// user priority, RTATimeoutFactor 1 (100 ms), 3 retries, at most 256 bytes of alarm
    /// data, VLAN priority 6 for high and 5 for low alarms; `local_alarm_reference` is the
    /// controller's.
    pub const fn io_controller(local_alarm_reference: u16) -> AlarmCrBlockReq {
        AlarmCrBlockReq {
            alarm_cr_type: ALARM_CR_TYPE,
            lt: LT_PROFINET,
            properties: 0,
            rta_timeout_factor: 1,
            rta_retries: 3,
            local_alarm_reference,
            max_alarm_data_length: 256,
            tag_header_high: TAG_HEADER_PRIO_6,
            tag_header_low: TAG_HEADER_PRIO_5,
        }
    }
}

impl Body for AlarmCrBlockReq {
    const BLOCK_TYPE: BlockType = BlockType::AlarmCrBlockReq;

    fn body_len(&self) -> usize {
        20
    }

    fn read(r: &mut Reader<'_>) -> Result<Self> {
        Ok(AlarmCrBlockReq {
            alarm_cr_type: r.u16()?,
            lt: r.u16()?,
            properties: r.u32()?,
            rta_timeout_factor: r.u16()?,
            rta_retries: r.u16()?,
            local_alarm_reference: r.u16()?,
            max_alarm_data_length: r.u16()?,
            tag_header_high: r.u16()?,
            tag_header_low: r.u16()?,
        })
    }

    fn write(&self, w: &mut Writer<'_>) -> EmitResult<()> {
        w.u16(self.alarm_cr_type)?;
        w.u16(self.lt)?;
        w.u32(self.properties)?;
        w.u16(self.rta_timeout_factor)?;
        w.u16(self.rta_retries)?;
        w.u16(self.local_alarm_reference)?;
        w.u16(self.max_alarm_data_length)?;
        w.u16(self.tag_header_high)?;
        w.u16(self.tag_header_low)
    }
}

block_api!(AlarmCrBlockReq, "AlarmCRBlockReq");

/// ARBlockRes (0x8101): the device's acceptance of the AR.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ArBlockRes {
    /// ARType (echoed).
    pub ar_type: u16,
    /// ARUUID (echoed).
    pub ar_uuid: Uuid,
    /// SessionKey (echoed).
    pub session_key: u16,
    /// CMResponderMacAdd: the device's MAC (the destination of the output CR).
    pub responder_mac: MacAddress,
    /// CMResponderUDPRTPort ([`UDP_RT_PORT_NONE`]).
    pub udp_rt_port: u16,
}

impl Body for ArBlockRes {
    const BLOCK_TYPE: BlockType = BlockType::ArBlockRes;

    fn body_len(&self) -> usize {
        28
    }

    fn read(r: &mut Reader<'_>) -> Result<Self> {
        Ok(ArBlockRes {
            ar_type: r.u16()?,
            ar_uuid: r.uuid()?,
            session_key: r.u16()?,
            responder_mac: r.mac()?,
            udp_rt_port: r.u16()?,
        })
    }

    fn write(&self, w: &mut Writer<'_>) -> EmitResult<()> {
        w.u16(self.ar_type)?;
        w.put(&self.ar_uuid.0)?;
        w.u16(self.session_key)?;
        w.put(&self.responder_mac.0)?;
        w.u16(self.udp_rt_port)
    }
}

block_api!(ArBlockRes, "ARBlockRes");

/// IOCRBlockRes (0x8102): the FrameID the device assigned to one IO CR.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct IocrBlockRes {
    /// IOCRType (echoed).
    pub iocr_type: u16,
    /// IOCRReference (echoed).
    pub iocr_reference: u16,
    /// FrameID: authoritative for the CR.
    pub frame_id: u16,
}

impl Body for IocrBlockRes {
    const BLOCK_TYPE: BlockType = BlockType::IocrBlockRes;

    fn body_len(&self) -> usize {
        6
    }

    fn read(r: &mut Reader<'_>) -> Result<Self> {
        Ok(IocrBlockRes {
            iocr_type: r.u16()?,
            iocr_reference: r.u16()?,
            frame_id: r.u16()?,
        })
    }

    fn write(&self, w: &mut Writer<'_>) -> EmitResult<()> {
        w.u16(self.iocr_type)?;
        w.u16(self.iocr_reference)?;
        w.u16(self.frame_id)
    }
}

block_api!(IocrBlockRes, "IOCRBlockRes");

/// AlarmCRBlockRes (0x8103): the device's alarm endpoint.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct AlarmCrBlockRes {
    /// AlarmCRType (echoed).
    pub alarm_cr_type: u16,
    /// LocalAlarmReference: the device's alarm reference (the controller sends to it).
    pub local_alarm_reference: u16,
    /// MaxAlarmDataLength the device accepts.
    pub max_alarm_data_length: u16,
}

impl Body for AlarmCrBlockRes {
    const BLOCK_TYPE: BlockType = BlockType::AlarmCrBlockRes;

    fn body_len(&self) -> usize {
        6
    }

    fn read(r: &mut Reader<'_>) -> Result<Self> {
        Ok(AlarmCrBlockRes {
            alarm_cr_type: r.u16()?,
            local_alarm_reference: r.u16()?,
            max_alarm_data_length: r.u16()?,
        })
    }

    fn write(&self, w: &mut Writer<'_>) -> EmitResult<()> {
        w.u16(self.alarm_cr_type)?;
        w.u16(self.local_alarm_reference)?;
        w.u16(self.max_alarm_data_length)
    }
}

block_api!(AlarmCrBlockRes, "AlarmCRBlockRes");

/// ARServerBlock (0x8106): the device's name of station, zero-padded so the block is a
/// multiple of 4 bytes long.
///
/// `parse` accepts 0 to 3 padding bytes of any value; `emit` writes the zeros the name needs.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct ArServerBlock {
    /// CMResponderStationName.
    pub station_name: String,
}

impl ArServerBlock {
    /// Padding bytes after a name of `n` bytes.
    const fn padding(n: usize) -> usize {
        (4 - (BLOCK_HEADER_LEN + 2 + n) % 4) % 4
    }
}

impl Body for ArServerBlock {
    const BLOCK_TYPE: BlockType = BlockType::ArServerBlock;

    fn body_len(&self) -> usize {
        let n = self.station_name.len();
        n.saturating_add(2 + ArServerBlock::padding(n))
    }

    fn read(r: &mut Reader<'_>) -> Result<Self> {
        let station_name = r.string()?;
        // Up to 3 padding bytes of any value fill the block to a multiple of 4.
        let padding = r.rest().len();
        if padding > 3 {
            return Err(Error);
        }
        r.take(padding)?;
        Ok(ArServerBlock { station_name })
    }

    fn write(&self, w: &mut Writer<'_>) -> EmitResult<()> {
        w.string("StationNameLength", &self.station_name)?;
        w.put(&[0u8; 3][..ArServerBlock::padding(self.station_name.len())])
    }
}

block_api!(ArServerBlock, "ARServerBlock");

/// Writes `bytes` at the front of `buf` and returns the rest of it.
fn put_bytes<'b>(buf: &'b mut [u8], bytes: &[u8]) -> EmitResult<&'b mut [u8]> {
    let len = buf.len();
    let (head, rest) = buf
        .split_at_mut_checked(bytes.len())
        .ok_or(EmitError::BufferTooShort {
            what: "block",
            needed: bytes.len(),
            len,
        })?;
    head.copy_from_slice(bytes);
    Ok(rest)
}

/// Writes `block` at the front of `buf` and returns the rest of it.
fn put_block<'b, B: Body>(buf: &'b mut [u8], block: &B) -> EmitResult<&'b mut [u8]> {
    emit_block(block, buf)?;
    let len = buf.len();
    let needed = block_len(block);
    let short = EmitError::BufferTooShort {
        what: "block",
        needed,
        len,
    };
    Ok(buf.split_at_mut_checked(needed).ok_or(short)?.1)
}

/// Stores `v` in `slot`; [`Error`] if the slot is already taken (a duplicate block).
fn set_once<T>(slot: &mut Option<T>, v: T) -> Result<()> {
    if slot.replace(v).is_some() {
        Err(Error)
    } else {
        Ok(())
    }
}

/// The blocks of a Connect request.
///
/// [`parse`](Self::parse) takes the blocks in any order but needs exactly one ARBlockReq and
/// one AlarmCRBlockReq; other block types (ARRPCBlockReq, PrmServerBlock, MCRBlockReq, ...)
/// give [`Error`] (a device answers them with "unknown blocks"). [`emit`](Self::emit) writes
/// them in the order the S7-1515 does: AR, IO CRs, expected submodules, alarm CR.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct ConnectRequest {
    /// ARBlockReq.
    pub ar: ArBlockReq,
    /// IOCRBlockReqs (input and output CRs), in order.
    pub iocrs: Vec<IocrBlockReq>,
    /// AlarmCRBlockReq.
    pub alarm_cr: AlarmCrBlockReq,
    /// ExpectedSubmoduleBlockReqs, in order.
    pub expected: Vec<ExpectedSubmoduleBlockReq>,
}

impl ConnectRequest {
    /// Parses the PNIO blocks of a Connect request (the bytes after the NDR header).
    pub fn parse(bytes: &[u8]) -> Result<ConnectRequest> {
        let (mut ar, mut alarm_cr) = (None, None);
        let (mut iocrs, mut expected) = (Vec::new(), Vec::new());
        for r in blocks(bytes) {
            let (h, block) = r?;
            match h.block_type {
                BlockType::ArBlockReq => set_once(&mut ar, ArBlockReq::parse(block)?)?,
                BlockType::IocrBlockReq => iocrs.push(IocrBlockReq::parse(block)?),
                BlockType::AlarmCrBlockReq => {
                    set_once(&mut alarm_cr, AlarmCrBlockReq::parse(block)?)?
                }
                BlockType::ExpectedSubmoduleBlockReq => {
                    expected.push(ExpectedSubmoduleBlockReq::parse(block)?)
                }
                _ => return Err(Error),
            }
        }
        Ok(ConnectRequest {
            ar: ar.ok_or(Error)?,
            iocrs,
            alarm_cr: alarm_cr.ok_or(Error)?,
            expected,
        })
    }

    /// Bytes of all blocks.
    pub fn buffer_len(&self) -> usize {
        let iocrs = self.iocrs.iter().map(IocrBlockReq::buffer_len);
        let expected = self
            .expected
            .iter()
            .map(ExpectedSubmoduleBlockReq::buffer_len);
        iocrs
            .chain(expected)
            .fold(self.ar.buffer_len(), usize::saturating_add)
            .saturating_add(self.alarm_cr.buffer_len())
    }

    /// Writes the blocks (the NDR ArgsLength/ActualCount bytes after the NDR header) into
    /// the first [`buffer_len`](Self::buffer_len) bytes of `buf`. [`EmitError`] when `buf` is
    /// shorter or a value does not fit its wire field (a list over 65 535 entries, a block
    /// over 65 539 bytes, data descriptions that do not match their submodule type).
    pub fn emit(&self, buf: &mut [u8]) -> EmitResult<()> {
        EmitError::check_len("Connect request", self.buffer_len(), buf.len())?;
        let mut rest = put_block(buf, &self.ar)?;
        for b in &self.iocrs {
            rest = put_block(rest, b)?;
        }
        for b in &self.expected {
            rest = put_block(rest, b)?;
        }
        put_block(rest, &self.alarm_cr).map(|_| ())
    }

    /// The blocks as a new vector of [`buffer_len`](Self::buffer_len) bytes.
    pub fn to_vec(&self) -> EmitResult<Vec<u8>> {
        crate::wire::emit_to_vec(self.buffer_len(), |b| self.emit(b))
    }
}

/// The blocks of a positive Connect response.
///
/// [`parse`](Self::parse) needs exactly one ARBlockRes and one AlarmCRBlockRes and at most one
/// ModuleDiffBlock and ARServerBlock; blocks of other types (ARRPCBlockRes, ARVendorBlockRes,
/// ...) are kept whole in `others`. [`emit`](Self::emit) writes them in p-net's order: AR, IO
/// CRs, alarm CR, module diff, the others, AR server.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct ConnectResponse {
    /// ARBlockRes.
    pub ar: ArBlockRes,
    /// IOCRBlockRes, in order (normally the request's).
    pub iocrs: Vec<IocrBlockRes>,
    /// AlarmCRBlockRes.
    pub alarm_cr: AlarmCrBlockRes,
    /// ModuleDiffBlock, if the real configuration differs from the expected one.
    pub module_diff: Option<ModuleDiffBlock>,
    /// ARServerBlock (advanced startup).
    pub ar_server: Option<ArServerBlock>,
    /// Other blocks: (BlockType, the whole block, header included), emitted as they are.
    pub others: Vec<(BlockType, Vec<u8>)>,
}

impl ConnectResponse {
    /// Parses the PNIO blocks of a Connect response (the bytes after the NDR header of a
    /// response whose PNIOStatus is OK).
    pub fn parse(bytes: &[u8]) -> Result<ConnectResponse> {
        let (mut ar, mut alarm_cr, mut module_diff, mut ar_server) = (None, None, None, None);
        let (mut iocrs, mut others) = (Vec::new(), Vec::new());
        for r in blocks(bytes) {
            let (h, block) = r?;
            match h.block_type {
                BlockType::ArBlockRes => set_once(&mut ar, ArBlockRes::parse(block)?)?,
                BlockType::IocrBlockRes => iocrs.push(IocrBlockRes::parse(block)?),
                BlockType::AlarmCrBlockRes => {
                    set_once(&mut alarm_cr, AlarmCrBlockRes::parse(block)?)?
                }
                BlockType::ModuleDiffBlock => {
                    set_once(&mut module_diff, ModuleDiffBlock::parse(block)?)?
                }
                BlockType::ArServerBlock => set_once(&mut ar_server, ArServerBlock::parse(block)?)?,
                other => others.push((other, block.to_vec())),
            }
        }
        Ok(ConnectResponse {
            ar: ar.ok_or(Error)?,
            iocrs,
            alarm_cr: alarm_cr.ok_or(Error)?,
            module_diff,
            ar_server,
            others,
        })
    }

    /// Bytes of all blocks.
    pub fn buffer_len(&self) -> usize {
        let iocrs = self.iocrs.iter().map(IocrBlockRes::buffer_len);
        let others = self.others.iter().map(|(_, b)| b.len());
        let diff = self.module_diff.iter().map(ModuleDiffBlock::buffer_len);
        let server = self.ar_server.iter().map(ArServerBlock::buffer_len);
        iocrs
            .chain(others)
            .chain(diff)
            .chain(server)
            .fold(self.ar.buffer_len(), usize::saturating_add)
            .saturating_add(self.alarm_cr.buffer_len())
    }

    /// Writes the blocks into the first [`buffer_len`](Self::buffer_len) bytes of `buf`.
    /// [`EmitError`] when `buf` is shorter or a value does not fit its wire field (a list over
    /// 65 535 entries, a block over 65 539 bytes).
    pub fn emit(&self, buf: &mut [u8]) -> EmitResult<()> {
        EmitError::check_len("Connect response", self.buffer_len(), buf.len())?;
        let mut rest = put_block(buf, &self.ar)?;
        for b in &self.iocrs {
            rest = put_block(rest, b)?;
        }
        rest = put_block(rest, &self.alarm_cr)?;
        if let Some(d) = &self.module_diff {
            rest = put_block(rest, d)?;
        }
        for (_, b) in &self.others {
            rest = put_bytes(rest, b)?;
        }
        if let Some(s) = &self.ar_server {
            put_block(rest, s)?;
        }
        Ok(())
    }

    /// The blocks as a new vector of [`buffer_len`](Self::buffer_len) bytes.
    pub fn to_vec(&self) -> EmitResult<Vec<u8>> {
        crate::wire::emit_to_vec(self.buffer_len(), |b| self.emit(b))
    }

    /// The FrameID the device assigned to the IO CR with this IOCRReference.
    pub fn frame_id(&self, iocr_reference: u16) -> Option<u16> {
        self.iocrs
            .iter()
            .find(|c| c.iocr_reference == iocr_reference)
            .map(|c| c.frame_id)
    }
}
