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
//! `emit` writes into the first `buffer_len()` bytes of a buffer and gives [`Error`] (never a
//! panic) when the buffer is shorter or a value does not fit its wire field: a list longer
//! than its 16-bit count, a block longer than 65 539 bytes, a station name over 65 535
//! bytes, or data descriptions that do not match the submodule type.

use super::common::{BLOCK_HEADER_LEN, blocks};
use super::cursor::{Reader, Writer};
use super::{BlockHeader, Error, MacAddress, Result, Uuid};
use crate::iocr_layout::{CrLayout, SubmoduleIo};

/// Block types of the Connect blocks.
pub mod block_type {
    /// ARBlockReq.
    pub const AR_BLOCK_REQ: u16 = 0x0101;
    /// IOCRBlockReq.
    pub const IOCR_BLOCK_REQ: u16 = 0x0102;
    /// AlarmCRBlockReq.
    pub const ALARM_CR_BLOCK_REQ: u16 = 0x0103;
    /// ExpectedSubmoduleBlockReq.
    pub const EXPECTED_SUBMODULE_BLOCK_REQ: u16 = 0x0104;
    /// ARBlockRes.
    pub const AR_BLOCK_RES: u16 = 0x8101;
    /// IOCRBlockRes.
    pub const IOCR_BLOCK_RES: u16 = 0x8102;
    /// AlarmCRBlockRes.
    pub const ALARM_CR_BLOCK_RES: u16 = 0x8103;
    /// ModuleDiffBlock (also the body of record 0xE002 and a companion of ApplicationReady).
    pub const MODULE_DIFF_BLOCK: u16 = 0x8104;
    /// ARServerBlock.
    pub const AR_SERVER_BLOCK: u16 = 0x8106;
}

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
    const BLOCK_TYPE: u16;
    fn body_len(&self) -> usize;
    fn read(r: &mut Reader<'_>) -> Result<Self>;
    fn write(&self, w: &mut Writer<'_>) -> Result<()>;
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

fn emit_block<B: Body>(v: &B, buf: &mut [u8]) -> Result<()> {
    let body_len = v.body_len();
    let length = body_len
        .checked_add(2)
        .and_then(|n| u16::try_from(n).ok())
        .ok_or(Error)?;
    let total = block_len(v);
    let (header, body) = buf
        .get_mut(..total)
        .ok_or(Error)?
        .split_at_mut(BLOCK_HEADER_LEN);
    BlockHeader {
        block_type: B::BLOCK_TYPE,
        length,
        version_high: 1,
        version_low: 0,
    }
    .emit(header);
    let mut w = Writer::new(body);
    v.write(&mut w)?;
    if w.position() == body_len {
        Ok(())
    } else {
        Err(Error)
    }
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
            /// [`Error`] if `buf` is shorter or a value does not fit its wire field.
            pub fn emit(&self, buf: &mut [u8]) -> Result<()> {
                emit_block(self, buf)
            }

            /// The block as a new vector.
            pub fn to_vec(&self) -> Result<Vec<u8>> {
                let mut v = vec![0u8; self.buffer_len()];
                self.emit(&mut v)?;
                Ok(v)
            }
        }
    };
}

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

impl Body for ArBlockReq {
    const BLOCK_TYPE: u16 = block_type::AR_BLOCK_REQ;

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

    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
        w.u16(self.ar_type)?;
        w.put(&self.ar_uuid.0)?;
        w.u16(self.session_key)?;
        w.put(&self.initiator_mac.0)?;
        w.put(&self.initiator_object_uuid.0)?;
        w.u32(self.ar_properties)?;
        w.u16(self.activity_timeout_factor)?;
        w.u16(self.udp_rt_port)?;
        w.string(&self.station_name)
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

    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
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

    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
        w.u32(self.api)?;
        w.count(self.data_objects.len())?;
        self.data_objects.iter().try_for_each(|e| e.write(w))?;
        w.count(self.iocs.len())?;
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
    const BLOCK_TYPE: u16 = block_type::IOCR_BLOCK_REQ;

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

    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
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
        w.count(self.apis.len())?;
        self.apis.iter().try_for_each(|a| a.write(w))
    }
}

block_api!(IocrBlockReq, "IOCRBlockReq");

impl IocrBlockReq {
    /// An IO CR carrying `layout` (one CR of an [`IocrLayout`](crate::iocr_layout::IocrLayout)):
    /// DataLength from the layout, one IODataObject per data object (at its data offset) and
    /// one IOCS per consumer status, grouped by API in frame order. `submodules` is the list
    /// the layout was computed from (its indices are the layout's `submodule` fields); an index
    /// outside it gives [`Error`].
    ///
    /// The other fields are what the S7-1515 sends: LT 0x8892, RT class 2, SendClockFactor 32,
    /// ReductionRatio 32 (32 ms), phase 1, sequence 0, best-effort FrameSendOffset,
    /// watchdog and data hold factor 3, tag header 0xC000, no multicast address. Change the
    /// public fields for other timing.
    pub fn from_layout(
        iocr_type: u16,
        iocr_reference: u16,
        frame_id: u16,
        layout: &CrLayout,
        submodules: &[SubmoduleIo],
    ) -> Result<IocrBlockReq> {
        fn api_entry(apis: &mut Vec<IocrApi>, api: u32) -> &mut IocrApi {
            let i = match apis.iter().position(|a| a.api == api) {
                Some(i) => i,
                None => {
                    apis.push(IocrApi {
                        api,
                        ..IocrApi::default()
                    });
                    apis.len() - 1
                }
            };
            &mut apis[i]
        }
        let mut apis = Vec::new();
        for o in &layout.objects {
            let s = submodules.get(o.submodule).ok_or(Error)?;
            api_entry(&mut apis, s.api).data_objects.push(IocrEntry {
                slot: s.slot,
                subslot: s.subslot,
                frame_offset: o.data_offset,
            });
        }
        for c in &layout.iocs {
            let s = submodules.get(c.submodule).ok_or(Error)?;
            api_entry(&mut apis, s.api).iocs.push(IocrEntry {
                slot: s.slot,
                subslot: s.subslot,
                frame_offset: c.offset,
            });
        }
        Ok(IocrBlockReq {
            iocr_type,
            iocr_reference,
            lt: LT_PROFINET,
            iocr_properties: iocr_properties::RT_CLASS_2,
            data_length: layout.data_length,
            frame_id,
            send_clock_factor: 32,
            reduction_ratio: 32,
            phase: 1,
            sequence: 0,
            frame_send_offset: FRAME_SEND_OFFSET_BEST_EFFORT,
            watchdog_factor: 3,
            data_hold_factor: 3,
            tag_header: TAG_HEADER_PRIO_6,
            multicast_mac: MacAddress::default(),
            apis,
        })
    }

    /// RTClass from the IOCRProperties.
    pub const fn rt_class(&self) -> u32 {
        self.iocr_properties & iocr_properties::RT_CLASS_MASK
    }

    /// The period of the CR in ns: SendClockFactor × ReductionRatio × 31 250 ns.
    pub const fn period_ns(&self) -> u64 {
        self.send_clock_factor as u64 * self.reduction_ratio as u64 * 31_250
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

impl Body for AlarmCrBlockReq {
    const BLOCK_TYPE: u16 = block_type::ALARM_CR_BLOCK_REQ;

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

    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
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

/// A DataDescription of an expected submodule.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct DataDescription {
    /// DataDescription ([`submodule::DATA_INPUT`] or [`submodule::DATA_OUTPUT`]).
    pub direction: u16,
    /// SubmoduleDataLength: IO data bytes.
    pub length: u16,
    /// LengthIOCS (1).
    pub length_iocs: u8,
    /// LengthIOPS (1).
    pub length_iops: u8,
}

impl DataDescription {
    /// An input description of `length` bytes with 1-byte IOCS and IOPS.
    pub const fn input(length: u16) -> DataDescription {
        DataDescription {
            direction: submodule::DATA_INPUT,
            length,
            length_iocs: 1,
            length_iops: 1,
        }
    }

    /// An output description of `length` bytes with 1-byte IOCS and IOPS.
    pub const fn output(length: u16) -> DataDescription {
        DataDescription {
            direction: submodule::DATA_OUTPUT,
            ..DataDescription::input(length)
        }
    }

    fn read(r: &mut Reader<'_>) -> Result<DataDescription> {
        Ok(DataDescription {
            direction: r.u16()?,
            length: r.u16()?,
            length_iocs: r.u8()?,
            length_iops: r.u8()?,
        })
    }

    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
        w.u16(self.direction)?;
        w.u16(self.length)?;
        w.u8(self.length_iocs)?;
        w.u8(self.length_iops)
    }
}

/// An expected submodule.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct ExpectedSubmodule {
    /// SubslotNumber.
    pub subslot: u16,
    /// SubmoduleIdentNumber.
    pub submodule_ident: u32,
    /// SubmoduleProperties ([`submodule`] bits; bits 0–1 the type).
    pub properties: u16,
    /// The data descriptions: two (input, then output) for
    /// [`TYPE_INPUT_OUTPUT`](submodule::TYPE_INPUT_OUTPUT), one otherwise (an input of length
    /// 0 for a submodule without IO data). Other counts do not emit.
    pub data_descriptions: Vec<DataDescription>,
}

impl ExpectedSubmodule {
    /// A submodule with `input_length` input and `output_length` output bytes, typed and
    /// described as the controller must: no IO data is an input of length 0.
    pub fn with_io(
        subslot: u16,
        submodule_ident: u32,
        input_length: u16,
        output_length: u16,
    ) -> ExpectedSubmodule {
        let (properties, data_descriptions) = match (input_length, output_length) {
            (0, 0) => (submodule::TYPE_NO_IO, vec![DataDescription::input(0)]),
            (i, 0) => (submodule::TYPE_INPUT, vec![DataDescription::input(i)]),
            (0, o) => (submodule::TYPE_OUTPUT, vec![DataDescription::output(o)]),
            (i, o) => (
                submodule::TYPE_INPUT_OUTPUT,
                vec![DataDescription::input(i), DataDescription::output(o)],
            ),
        };
        ExpectedSubmodule {
            subslot,
            submodule_ident,
            properties,
            data_descriptions,
        }
    }

    /// The type from the properties ([`submodule::TYPE_NO_IO`]..=[`submodule::TYPE_INPUT_OUTPUT`]).
    pub const fn submodule_type(&self) -> u16 {
        self.properties & submodule::TYPE_MASK
    }

    /// How many data descriptions the type calls for.
    const fn description_count(properties: u16) -> usize {
        if properties & submodule::TYPE_MASK == submodule::TYPE_INPUT_OUTPUT {
            2
        } else {
            1
        }
    }

    fn length(&self, direction: u16) -> u16 {
        self.data_descriptions
            .iter()
            .find(|d| d.direction == direction)
            .map_or(0, |d| d.length)
    }

    /// Input bytes (0 without an input description).
    pub fn input_length(&self) -> u16 {
        self.length(submodule::DATA_INPUT)
    }

    /// Output bytes (0 without an output description).
    pub fn output_length(&self) -> u16 {
        self.length(submodule::DATA_OUTPUT)
    }

    fn wire_len(&self) -> usize {
        8usize.saturating_add(self.data_descriptions.len().saturating_mul(6))
    }

    fn read(r: &mut Reader<'_>) -> Result<ExpectedSubmodule> {
        let subslot = r.u16()?;
        let submodule_ident = r.u32()?;
        let properties = r.u16()?;
        let data_descriptions = (0..ExpectedSubmodule::description_count(properties))
            .map(|_| DataDescription::read(r))
            .collect::<Result<Vec<_>>>()?;
        Ok(ExpectedSubmodule {
            subslot,
            submodule_ident,
            properties,
            data_descriptions,
        })
    }

    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
        if self.data_descriptions.len() != ExpectedSubmodule::description_count(self.properties) {
            return Err(Error);
        }
        w.u16(self.subslot)?;
        w.u32(self.submodule_ident)?;
        w.u16(self.properties)?;
        self.data_descriptions.iter().try_for_each(|d| d.write(w))
    }
}

/// An expected module: one API entry of an ExpectedSubmoduleBlockReq.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct ExpectedModule {
    /// API.
    pub api: u32,
    /// SlotNumber.
    pub slot: u16,
    /// ModuleIdentNumber.
    pub module_ident: u32,
    /// ModuleProperties (0).
    pub properties: u16,
    /// The submodules expected in the slot.
    pub submodules: Vec<ExpectedSubmodule>,
}

impl ExpectedModule {
    fn wire_len(&self) -> usize {
        self.submodules
            .iter()
            .fold(14usize, |n, s| n.saturating_add(s.wire_len()))
    }

    fn read(r: &mut Reader<'_>) -> Result<ExpectedModule> {
        Ok(ExpectedModule {
            api: r.u32()?,
            slot: r.u16()?,
            module_ident: r.u32()?,
            properties: r.u16()?,
            submodules: r.list(ExpectedSubmodule::read)?,
        })
    }

    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
        w.u32(self.api)?;
        w.u16(self.slot)?;
        w.u32(self.module_ident)?;
        w.u16(self.properties)?;
        w.count(self.submodules.len())?;
        self.submodules.iter().try_for_each(|s| s.write(w))
    }
}

/// ExpectedSubmoduleBlockReq (0x0104): the modules and submodules the controller expects.
///
/// On the wire NumberOfAPIs counts entries of (API, slot, module, submodules), so each
/// [`ExpectedModule`] carries its API. The S7 sends one block per slot.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct ExpectedSubmoduleBlockReq {
    /// The module entries.
    pub modules: Vec<ExpectedModule>,
}

impl ExpectedSubmoduleBlockReq {
    /// Every submodule as the IOCR layout needs it, in block order.
    pub fn submodules(&self) -> impl Iterator<Item = SubmoduleIo> + '_ {
        self.modules.iter().flat_map(|m| {
            m.submodules.iter().map(|s| SubmoduleIo {
                api: m.api,
                slot: m.slot,
                subslot: s.subslot,
                input_length: s.input_length(),
                output_length: s.output_length(),
            })
        })
    }
}

impl Body for ExpectedSubmoduleBlockReq {
    const BLOCK_TYPE: u16 = block_type::EXPECTED_SUBMODULE_BLOCK_REQ;

    fn body_len(&self) -> usize {
        self.modules
            .iter()
            .fold(2usize, |n, m| n.saturating_add(m.wire_len()))
    }

    fn read(r: &mut Reader<'_>) -> Result<Self> {
        Ok(ExpectedSubmoduleBlockReq {
            modules: r.list(ExpectedModule::read)?,
        })
    }

    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
        w.count(self.modules.len())?;
        self.modules.iter().try_for_each(|m| m.write(w))
    }
}

block_api!(ExpectedSubmoduleBlockReq, "ExpectedSubmoduleBlockReq");

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
    const BLOCK_TYPE: u16 = block_type::AR_BLOCK_RES;

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

    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
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
    const BLOCK_TYPE: u16 = block_type::IOCR_BLOCK_RES;

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

    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
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
    const BLOCK_TYPE: u16 = block_type::ALARM_CR_BLOCK_RES;

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

    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
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
    const BLOCK_TYPE: u16 = block_type::AR_SERVER_BLOCK;

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

    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
        w.string(&self.station_name)?;
        w.put(&[0u8; 3][..ArServerBlock::padding(self.station_name.len())])
    }
}

block_api!(ArServerBlock, "ARServerBlock");

/// ModuleState of a ModuleDiffBlock entry.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ModuleState {
    /// 0: no module plugged.
    NoModule,
    /// 1: a wrong module (another ModuleIdentNumber).
    WrongModule,
    /// 2: the proper module, but at least one submodule is locked, wrong, missing or has
    /// diagnosis.
    ProperModule,
    /// 3: a substitute the device adapts.
    Substitute,
    /// Any other (reserved) value, never 0..=3.
    Unknown(u16),
}

impl From<u16> for ModuleState {
    fn from(v: u16) -> ModuleState {
        match v {
            0 => ModuleState::NoModule,
            1 => ModuleState::WrongModule,
            2 => ModuleState::ProperModule,
            3 => ModuleState::Substitute,
            other => ModuleState::Unknown(other),
        }
    }
}

impl From<ModuleState> for u16 {
    fn from(v: ModuleState) -> u16 {
        match v {
            ModuleState::NoModule => 0,
            ModuleState::WrongModule => 1,
            ModuleState::ProperModule => 2,
            ModuleState::Substitute => 3,
            ModuleState::Unknown(other) => other,
        }
    }
}

/// IdentInfo of a [`SubmoduleState`]: how the real submodule matches the expected one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum IdentInfo {
    /// 0: the expected submodule.
    Ok,
    /// 1: a substitute.
    Substitute,
    /// 2: a wrong submodule.
    Wrong,
    /// 3: no submodule.
    NoSubmodule,
    /// 4..=15: reserved.
    Reserved(u8),
}

/// ARInfo of a [`SubmoduleState`]: who owns the submodule.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ArInfo {
    /// 0: owned by this AR.
    Own,
    /// 1: ApplicationReady pending (e.g. a parameter error).
    ApplicationReadyPending,
    /// 2: locked by a superordinated function.
    SuperordinatedLocked,
    /// 3: locked by another IO controller.
    LockedByIoController,
    /// 4: locked by an IO supervisor.
    LockedByIoSupervisor,
    /// 5..=15: reserved.
    Reserved(u8),
}

/// SubmoduleState of a ModuleDiffBlock entry (the FormatIndicator = 1 layout).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct SubmoduleState(pub u16);

impl SubmoduleState {
    /// Bit 15: FormatIndicator; the fields below are valid only when it is set.
    pub const FORMAT_INDICATOR: u16 = 1 << 15;
    /// Bit 3: QualifiedInfo (qualified diagnosis available).
    pub const QUALIFIED_INFO: u16 = 1 << 3;
    /// Bit 4: MaintenanceRequired.
    pub const MAINTENANCE_REQUIRED: u16 = 1 << 4;
    /// Bit 5: MaintenanceDemanded.
    pub const MAINTENANCE_DEMANDED: u16 = 1 << 5;
    /// Bit 6: DiagInfo / fault: diagnosis data available.
    pub const DIAG_INFO: u16 = 1 << 6;

    /// Whether the FormatIndicator is set.
    pub const fn format_indicator(&self) -> bool {
        self.0 & SubmoduleState::FORMAT_INDICATOR != 0
    }

    /// Bits 0–2: AddInfo (1 = takeover not allowed).
    pub const fn add_info(&self) -> u8 {
        (self.0 & 0x7) as u8
    }

    /// Bit 3: QualifiedInfo.
    pub const fn qualified_info(&self) -> bool {
        self.0 & SubmoduleState::QUALIFIED_INFO != 0
    }

    /// Bit 4: MaintenanceRequired.
    pub const fn maintenance_required(&self) -> bool {
        self.0 & SubmoduleState::MAINTENANCE_REQUIRED != 0
    }

    /// Bit 5: MaintenanceDemanded.
    pub const fn maintenance_demanded(&self) -> bool {
        self.0 & SubmoduleState::MAINTENANCE_DEMANDED != 0
    }

    /// Bit 6: DiagInfo, i.e. a fault: diagnosis is available in the records.
    pub const fn fault(&self) -> bool {
        self.0 & SubmoduleState::DIAG_INFO != 0
    }

    /// Bits 7–10: ARInfo.
    pub const fn ar_info(&self) -> ArInfo {
        match (self.0 >> 7) & 0xf {
            0 => ArInfo::Own,
            1 => ArInfo::ApplicationReadyPending,
            2 => ArInfo::SuperordinatedLocked,
            3 => ArInfo::LockedByIoController,
            4 => ArInfo::LockedByIoSupervisor,
            other => ArInfo::Reserved(other as u8),
        }
    }

    /// Bits 11–14: IdentInfo.
    pub const fn ident_info(&self) -> IdentInfo {
        match (self.0 >> 11) & 0xf {
            0 => IdentInfo::Ok,
            1 => IdentInfo::Substitute,
            2 => IdentInfo::Wrong,
            3 => IdentInfo::NoSubmodule,
            other => IdentInfo::Reserved(other as u8),
        }
    }

    /// Whether the controller may exchange data with the submodule: the format is known, the
    /// submodule is the expected one or a substitute, and this AR owns it.
    pub const fn is_usable(&self) -> bool {
        self.format_indicator()
            && matches!(self.ident_info(), IdentInfo::Ok | IdentInfo::Substitute)
            && matches!(self.ar_info(), ArInfo::Own)
    }
}

/// A submodule entry of a ModuleDiffBlock.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ModuleDiffSubmodule {
    /// SubslotNumber.
    pub subslot: u16,
    /// SubmoduleIdentNumber (the real one).
    pub submodule_ident: u32,
    /// SubmoduleState.
    pub state: SubmoduleState,
}

/// A module entry of a ModuleDiffBlock.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct ModuleDiffModule {
    /// SlotNumber.
    pub slot: u16,
    /// ModuleIdentNumber (the real one).
    pub module_ident: u32,
    /// ModuleState.
    pub state: ModuleState,
    /// The submodules that differ.
    pub submodules: Vec<ModuleDiffSubmodule>,
}

/// The modules of one API in a ModuleDiffBlock.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct ModuleDiffApi {
    /// API.
    pub api: u32,
    /// The modules that differ.
    pub modules: Vec<ModuleDiffModule>,
}

/// ModuleDiffBlock (0x8104): the modules and submodules whose real state differs from the
/// expected configuration. Not an error: the AR is up; submodules that are not
/// [usable](SubmoduleState::is_usable) must be treated as absent.
#[derive(Clone, Debug, Default, PartialEq, Eq, Hash)]
pub struct ModuleDiffBlock {
    /// The APIs with differences.
    pub apis: Vec<ModuleDiffApi>,
}

impl ModuleDiffBlock {
    /// Every listed submodule as (API, slot, subslot, state).
    pub fn submodules(&self) -> impl Iterator<Item = (u32, u16, u16, SubmoduleState)> + '_ {
        self.apis.iter().flat_map(|a| {
            a.modules.iter().flat_map(move |m| {
                m.submodules
                    .iter()
                    .map(move |s| (a.api, m.slot, s.subslot, s.state))
            })
        })
    }
}

impl Body for ModuleDiffBlock {
    const BLOCK_TYPE: u16 = block_type::MODULE_DIFF_BLOCK;

    fn body_len(&self) -> usize {
        self.apis.iter().fold(2usize, |n, a| {
            a.modules.iter().fold(n.saturating_add(6), |n, m| {
                n.saturating_add(10)
                    .saturating_add(m.submodules.len().saturating_mul(8))
            })
        })
    }

    fn read(r: &mut Reader<'_>) -> Result<Self> {
        let apis = r.list(|r| {
            Ok(ModuleDiffApi {
                api: r.u32()?,
                modules: r.list(|r| {
                    Ok(ModuleDiffModule {
                        slot: r.u16()?,
                        module_ident: r.u32()?,
                        state: ModuleState::from(r.u16()?),
                        submodules: r.list(|r| {
                            Ok(ModuleDiffSubmodule {
                                subslot: r.u16()?,
                                submodule_ident: r.u32()?,
                                state: SubmoduleState(r.u16()?),
                            })
                        })?,
                    })
                })?,
            })
        })?;
        Ok(ModuleDiffBlock { apis })
    }

    fn write(&self, w: &mut Writer<'_>) -> Result<()> {
        w.count(self.apis.len())?;
        for a in &self.apis {
            w.u32(a.api)?;
            w.count(a.modules.len())?;
            for m in &a.modules {
                w.u16(m.slot)?;
                w.u32(m.module_ident)?;
                w.u16(m.state.into())?;
                w.count(m.submodules.len())?;
                for s in &m.submodules {
                    w.u16(s.subslot)?;
                    w.u32(s.submodule_ident)?;
                    w.u16(s.state.0)?;
                }
            }
        }
        Ok(())
    }
}

block_api!(ModuleDiffBlock, "ModuleDiffBlock");

/// Appends a block to `out`.
fn push_block<B: Body>(out: &mut Vec<u8>, block: &B) -> Result<()> {
    let len = block_len(block);
    if len > usize::from(u16::MAX) + 4 {
        return Err(Error);
    }
    let at = out.len();
    out.resize(at.saturating_add(len), 0);
    emit_block(block, out.get_mut(at..).ok_or(Error)?)
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
                block_type::AR_BLOCK_REQ => set_once(&mut ar, ArBlockReq::parse(block)?)?,
                block_type::IOCR_BLOCK_REQ => iocrs.push(IocrBlockReq::parse(block)?),
                block_type::ALARM_CR_BLOCK_REQ => {
                    set_once(&mut alarm_cr, AlarmCrBlockReq::parse(block)?)?
                }
                block_type::EXPECTED_SUBMODULE_BLOCK_REQ => {
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

    /// The blocks (the NDR ArgsLength/ActualCount bytes after the NDR header), or [`Error`]
    /// when a value does not fit its wire field.
    pub fn try_emit(&self) -> Result<Vec<u8>> {
        let mut out = Vec::with_capacity(self.buffer_len());
        push_block(&mut out, &self.ar)?;
        self.iocrs
            .iter()
            .try_for_each(|b| push_block(&mut out, b))?;
        self.expected
            .iter()
            .try_for_each(|b| push_block(&mut out, b))?;
        push_block(&mut out, &self.alarm_cr)?;
        Ok(out)
    }

    /// The blocks, as [`try_emit`](Self::try_emit); empty when a value does not fit its wire
    /// field (a list over 65 535 entries, a block over 65 539 bytes, data descriptions that do
    /// not match their submodule type), which no valid configuration reaches.
    pub fn emit(&self) -> Vec<u8> {
        self.try_emit().unwrap_or_default()
    }

    /// Every expected submodule, in block order: the input of [`IocrLayout::new`](crate::iocr_layout::IocrLayout::new).
    pub fn submodules(&self) -> impl Iterator<Item = SubmoduleIo> + '_ {
        self.expected
            .iter()
            .flat_map(ExpectedSubmoduleBlockReq::submodules)
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
    pub others: Vec<(u16, Vec<u8>)>,
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
                block_type::AR_BLOCK_RES => set_once(&mut ar, ArBlockRes::parse(block)?)?,
                block_type::IOCR_BLOCK_RES => iocrs.push(IocrBlockRes::parse(block)?),
                block_type::ALARM_CR_BLOCK_RES => {
                    set_once(&mut alarm_cr, AlarmCrBlockRes::parse(block)?)?
                }
                block_type::MODULE_DIFF_BLOCK => {
                    set_once(&mut module_diff, ModuleDiffBlock::parse(block)?)?
                }
                block_type::AR_SERVER_BLOCK => {
                    set_once(&mut ar_server, ArServerBlock::parse(block)?)?
                }
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

    /// The blocks, or [`Error`] when a value does not fit its wire field.
    pub fn try_emit(&self) -> Result<Vec<u8>> {
        let mut out = Vec::with_capacity(self.buffer_len());
        push_block(&mut out, &self.ar)?;
        self.iocrs
            .iter()
            .try_for_each(|b| push_block(&mut out, b))?;
        push_block(&mut out, &self.alarm_cr)?;
        if let Some(d) = &self.module_diff {
            push_block(&mut out, d)?;
        }
        for (_, b) in &self.others {
            out.extend_from_slice(b);
        }
        if let Some(s) = &self.ar_server {
            push_block(&mut out, s)?;
        }
        Ok(out)
    }

    /// The blocks, as [`try_emit`](Self::try_emit); empty when a value does not fit its wire
    /// field (a list over 65 535 entries, a block over 65 539 bytes), which no valid
    /// configuration reaches.
    pub fn emit(&self) -> Vec<u8> {
        self.try_emit().unwrap_or_default()
    }

    /// The FrameID the device assigned to the IO CR with this IOCRReference.
    pub fn frame_id(&self, iocr_reference: u16) -> Option<u16> {
        self.iocrs
            .iter()
            .find(|c| c.iocr_reference == iocr_reference)
            .map(|c| c.frame_id)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::iocr_layout::IocrLayout;
    use proptest::prelude::*;

    // The two frames below come from the test data of the `pnio` crate 0.1.0
    // (core-engineering/pnio-rs, MIT OR Apache-2.0): an S7-1515 connecting to the p-net sample
    // device (captures/cm/connect_{req,res}.hex). Bytes from the Ethernet header; the RPC PDU
    // starts at byte 42, the blocks at byte 142 after the 80-byte RPC and 20-byte NDR header.

    /// captures/cm/connect_req.hex: S7 Connect request (frame 50, DREP LE), 699 bytes: ARBlockReq,
    /// 2× IOCRBlockReq, 5× ExpectedSubmoduleBlockReq, AlarmCRBlockReq.
    static CONNECT_REQ: [u8; 699] = [
        0x8c, 0xf3, 0x19, 0xcd, 0x19, 0xf8, 0xec, 0x1c, 0x5d, 0x61, 0xe7, 0x3f, 0x08, 0x00, 0x45,
        0x00, 0x02, 0xad, 0xea, 0x68, 0x00, 0x00, 0x40, 0x11, 0x31, 0x49, 0xac, 0x10, 0x02, 0x64,
        0xac, 0x10, 0x02, 0x0a, 0xd5, 0xee, 0x88, 0x94, 0x02, 0x99, 0x3a, 0xa4, 0x04, 0x00, 0x20,
        0x00, 0x10, 0x00, 0x00, 0x00, 0x00, 0x00, 0xa0, 0xde, 0x97, 0x6c, 0xd1, 0x11, 0x82, 0x71,
        0x00, 0x01, 0x00, 0x02, 0x04, 0x93, 0x01, 0x00, 0xa0, 0xde, 0x97, 0x6c, 0xd1, 0x11, 0x82,
        0x71, 0x00, 0xa0, 0x24, 0x42, 0xdf, 0x7d, 0xae, 0xa1, 0xac, 0xd2, 0x32, 0x00, 0x10, 0x10,
        0xb0, 0x58, 0xec, 0x1c, 0x5d, 0x61, 0xe7, 0x3f, 0x00, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00,
        0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xff, 0xff, 0xff, 0xff, 0x41, 0x02, 0x00, 0x00,
        0x00, 0x00, 0x2d, 0x02, 0x00, 0x00, 0x2d, 0x02, 0x00, 0x00, 0x2d, 0x02, 0x00, 0x00, 0x00,
        0x00, 0x00, 0x00, 0x2d, 0x02, 0x00, 0x00, 0x01, 0x01, 0x00, 0x5b, 0x01, 0x00, 0x00, 0x01,
        0xe5, 0xe1, 0xae, 0xcc, 0xb1, 0x33, 0x4b, 0x4d, 0xb1, 0x87, 0xcc, 0x68, 0xb0, 0x21, 0x1e,
        0xd2, 0x00, 0x02, 0xec, 0x1c, 0x5d, 0x61, 0xe7, 0x3f, 0xde, 0xa0, 0x00, 0x00, 0x6c, 0x97,
        0x11, 0xd1, 0x82, 0x71, 0x10, 0x64, 0x01, 0x0e, 0x00, 0x2a, 0x40, 0x00, 0x00, 0x11, 0x00,
        0xc8, 0x88, 0x92, 0x00, 0x25, 0x70, 0x6c, 0x63, 0x78, 0x62, 0x62, 0x65, 0x6e, 0x63, 0x68,
        0x2e, 0x70, 0x72, 0x6f, 0x66, 0x69, 0x6e, 0x65, 0x74, 0x78, 0x61, 0x69, 0x6e, 0x74, 0x65,
        0x72, 0x66, 0x61, 0x63, 0x65, 0x78, 0x62, 0x32, 0x35, 0x66, 0x62, 0x64, 0x01, 0x02, 0x00,
        0x68, 0x01, 0x00, 0x00, 0x01, 0x00, 0x01, 0x88, 0x92, 0x00, 0x00, 0x00, 0x02, 0x00, 0x28,
        0x80, 0x00, 0x00, 0x20, 0x00, 0x20, 0x00, 0x01, 0x00, 0x00, 0xff, 0xff, 0xff, 0xff, 0x00,
        0x03, 0x00, 0x03, 0xc0, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00,
        0x00, 0x00, 0x00, 0x06, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x80, 0x00, 0x00,
        0x01, 0x00, 0x00, 0x80, 0x01, 0x00, 0x02, 0x00, 0x01, 0x00, 0x01, 0x00, 0x03, 0x00, 0x03,
        0x00, 0x01, 0x00, 0x06, 0x00, 0x04, 0x00, 0x01, 0x00, 0x09, 0x00, 0x03, 0x00, 0x02, 0x00,
        0x01, 0x00, 0x05, 0x00, 0x03, 0x00, 0x01, 0x00, 0x08, 0x00, 0x04, 0x00, 0x01, 0x00, 0x12,
        0x01, 0x02, 0x00, 0x68, 0x01, 0x00, 0x00, 0x02, 0x00, 0x02, 0x88, 0x92, 0x00, 0x00, 0x00,
        0x02, 0x00, 0x28, 0x80, 0x01, 0x00, 0x20, 0x00, 0x20, 0x00, 0x01, 0x00, 0x00, 0xff, 0xff,
        0xff, 0xff, 0x00, 0x03, 0x00, 0x03, 0xc0, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x03, 0x00, 0x02, 0x00, 0x01, 0x00, 0x04, 0x00, 0x03,
        0x00, 0x01, 0x00, 0x07, 0x00, 0x04, 0x00, 0x01, 0x00, 0x0a, 0x00, 0x06, 0x00, 0x00, 0x00,
        0x01, 0x00, 0x00, 0x00, 0x00, 0x80, 0x00, 0x00, 0x01, 0x00, 0x00, 0x80, 0x01, 0x00, 0x02,
        0x00, 0x01, 0x00, 0x01, 0x00, 0x03, 0x00, 0x03, 0x00, 0x01, 0x00, 0x06, 0x00, 0x04, 0x00,
        0x01, 0x00, 0x09, 0x01, 0x04, 0x00, 0x3c, 0x01, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00,
        0x00, 0x00, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x03, 0x00, 0x01, 0x00, 0x00, 0x00,
        0x01, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x01, 0x01, 0x80, 0x00, 0x00, 0x00, 0x80, 0x00,
        0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x01, 0x01, 0x80, 0x01, 0x00, 0x00, 0x80, 0x01, 0x00,
        0x00, 0x00, 0x01, 0x00, 0x00, 0x01, 0x01, 0x01, 0x04, 0x00, 0x20, 0x01, 0x00, 0x00, 0x01,
        0x00, 0x00, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x30, 0x00, 0x00, 0x00, 0x01, 0x00,
        0x01, 0x00, 0x00, 0x01, 0x30, 0x00, 0x01, 0x00, 0x01, 0x00, 0x01, 0x01, 0x01, 0x01, 0x04,
        0x00, 0x20, 0x01, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00,
        0x31, 0x00, 0x00, 0x00, 0x01, 0x00, 0x01, 0x00, 0x00, 0x01, 0x31, 0x00, 0x02, 0x00, 0x02,
        0x00, 0x01, 0x01, 0x01, 0x01, 0x04, 0x00, 0x26, 0x01, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00,
        0x00, 0x00, 0x03, 0x00, 0x00, 0x00, 0x32, 0x00, 0x00, 0x00, 0x01, 0x00, 0x01, 0x00, 0x00,
        0x01, 0x32, 0x00, 0x03, 0x00, 0x01, 0x00, 0x01, 0x01, 0x01, 0x00, 0x02, 0x00, 0x01, 0x01,
        0x01, 0x01, 0x04, 0x00, 0x26, 0x01, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x04,
        0x00, 0x00, 0x00, 0x40, 0x00, 0x00, 0x00, 0x01, 0x00, 0x01, 0x00, 0x00, 0x01, 0x40, 0x00,
        0x03, 0x00, 0x01, 0x00, 0x08, 0x01, 0x01, 0x00, 0x02, 0x00, 0x08, 0x01, 0x01, 0x01, 0x03,
        0x00, 0x16, 0x01, 0x00, 0x00, 0x01, 0x88, 0x92, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01, 0x00,
        0x03, 0x00, 0x00, 0x01, 0x00, 0xc0, 0x00, 0xa0, 0x00,
    ];

    /// captures/cm/connect_res.hex: p-net Connect response (frame 53, DREP BE), 232 bytes:
    /// ARBlockRes, 2× IOCRBlockRes, AlarmCRBlockRes, ARServerBlock.
    static CONNECT_RES: [u8; 232] = [
        0xec, 0x1c, 0x5d, 0x61, 0xe7, 0x3f, 0x8c, 0xf3, 0x19, 0xcd, 0x19, 0xf8, 0x08, 0x00, 0x45,
        0x00, 0x00, 0xda, 0x90, 0x22, 0x40, 0x00, 0x40, 0x11, 0x4d, 0x62, 0xac, 0x10, 0x02, 0x0a,
        0xac, 0x10, 0x02, 0x64, 0x88, 0x94, 0xd5, 0xee, 0x00, 0xc6, 0x5d, 0x66, 0x04, 0x02, 0x28,
        0x00, 0x00, 0x00, 0x00, 0x00, 0xde, 0xa0, 0x00, 0x00, 0x6c, 0x97, 0x11, 0xd1, 0x82, 0x71,
        0x00, 0x01, 0x00, 0x02, 0x04, 0x93, 0xde, 0xa0, 0x00, 0x01, 0x6c, 0x97, 0x11, 0xd1, 0x82,
        0x71, 0x00, 0xa0, 0x24, 0x42, 0xdf, 0x7d, 0xd2, 0xac, 0xa1, 0xae, 0x00, 0x32, 0x10, 0x10,
        0xb0, 0x58, 0xec, 0x1c, 0x5d, 0x61, 0xe7, 0x3f, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xff, 0xff, 0xff, 0xff, 0x00, 0x6e, 0x00, 0x00,
        0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x5a, 0x00, 0x00, 0x02, 0x2d, 0x00,
        0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x5a, 0x81, 0x01, 0x00, 0x1e, 0x01, 0x00, 0x00, 0x01,
        0xe5, 0xe1, 0xae, 0xcc, 0xb1, 0x33, 0x4b, 0x4d, 0xb1, 0x87, 0xcc, 0x68, 0xb0, 0x21, 0x1e,
        0xd2, 0x00, 0x02, 0x8c, 0xf3, 0x19, 0xcd, 0x19, 0xf8, 0x88, 0x92, 0x81, 0x02, 0x00, 0x08,
        0x01, 0x00, 0x00, 0x01, 0x00, 0x01, 0x80, 0x00, 0x81, 0x02, 0x00, 0x08, 0x01, 0x00, 0x00,
        0x02, 0x00, 0x02, 0x80, 0x01, 0x81, 0x03, 0x00, 0x08, 0x01, 0x00, 0x00, 0x01, 0x00, 0x00,
        0x00, 0xc8, 0x81, 0x06, 0x00, 0x10, 0x01, 0x00, 0x00, 0x0b, 0x72, 0x74, 0x2d, 0x6c, 0x61,
        0x62, 0x73, 0x2d, 0x64, 0x65, 0x76, 0x00,
    ];

    /// ModuleDiffBlock of the worked example "record 0xE002" (TV7) of the Siemens manual
    /// "PROFINET IO: From PROFIBUS DP to PROFINET IO" (A5E00879152-01, section 6.6): slot 2
    /// missing, slot 4 holding a wrong module whose subslot 1 is wrong (0x9000).
    static MODULE_DIFF_TV7: [u8; 42] = [
        0x81, 0x04, 0x00, 0x26, 0x01, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x02, 0x00,
        0x02, 0x00, 0x00, 0x88, 0xa1, 0x00, 0x00, 0x00, 0x00, 0x00, 0x04, 0x00, 0x00, 0x17, 0xff,
        0x00, 0x01, 0x00, 0x01, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x90, 0x00,
    ];

    /// The blocks of a captured frame, checked against the NDR ActualCount (in DREP order).
    fn blocks_of(frame: &[u8]) -> &[u8] {
        let little_endian = frame[42 + 4] & 0xf0 == 0x10;
        let count: [u8; 4] = frame[138..142].try_into().unwrap();
        let count = if little_endian {
            u32::from_le_bytes(count)
        } else {
            u32::from_be_bytes(count)
        };
        let blocks = &frame[142..];
        assert_eq!(blocks.len(), count as usize);
        blocks
    }

    /// The captured blocks of one type, whole.
    fn captured(bytes: &[u8], t: u16) -> Vec<&[u8]> {
        blocks(bytes)
            .map(Result::unwrap)
            .filter(|(h, _)| h.block_type == t)
            .map(|(_, b)| b)
            .collect()
    }

    fn entries(v: &[(u16, u16, u16)]) -> Vec<IocrEntry> {
        v.iter()
            .map(|&(slot, subslot, frame_offset)| IocrEntry {
                slot,
                subslot,
                frame_offset,
            })
            .collect()
    }

    #[test]
    fn connect_request_capture() {
        let bytes = blocks_of(&CONNECT_REQ);
        let req = ConnectRequest::parse(bytes).unwrap();

        let ar = &req.ar;
        assert_eq!(ar.ar_type, AR_TYPE_IOC_SINGLE);
        assert_eq!(
            ar.ar_uuid.to_string(),
            "e5e1aecc-b133-4b4d-b187-cc68b0211ed2"
        );
        assert_eq!(ar.session_key, 2);
        assert_eq!(ar.initiator_mac.to_string(), "ec:1c:5d:61:e7:3f");
        assert_eq!(
            ar.initiator_object_uuid.to_string(),
            "dea00000-6c97-11d1-8271-1064010e002a"
        );
        assert_eq!(ar.ar_properties, ar_properties::ADVANCED);
        assert_eq!(ar.ar_properties, 0x4000_0011);
        assert_eq!(ar.activity_timeout_factor, 200);
        assert_eq!(ar.udp_rt_port, UDP_RT_PORT_NONE);
        assert_eq!(ar.station_name, "plcxbbench.profinetxainterfacexb25fbd");

        assert_eq!(req.iocrs.len(), 2);
        let (input, output) = (&req.iocrs[0], &req.iocrs[1]);
        for (cr, t, r, frame_id) in [
            (input, iocr_type::INPUT, 1, 0x8000),
            (output, iocr_type::OUTPUT, 2, 0x8001),
        ] {
            assert_eq!(
                (cr.iocr_type, cr.iocr_reference, cr.frame_id),
                (t, r, frame_id)
            );
            assert_eq!(cr.lt, LT_PROFINET);
            assert_eq!(cr.rt_class(), iocr_properties::RT_CLASS_2);
            assert_eq!(cr.data_length, 40);
            assert_eq!((cr.send_clock_factor, cr.reduction_ratio), (32, 32));
            assert_eq!(cr.period_ns(), 32_000_000);
            assert_eq!((cr.phase, cr.sequence), (1, 0));
            assert_eq!(cr.frame_send_offset, FRAME_SEND_OFFSET_BEST_EFFORT);
            assert_eq!((cr.watchdog_factor, cr.data_hold_factor), (3, 3));
            assert_eq!(cr.tag_header, TAG_HEADER_PRIO_6);
            assert_eq!(cr.multicast_mac, MacAddress::default());
            assert_eq!(cr.apis.len(), 1);
            assert_eq!(cr.apis[0].api, 0);
        }
        // Input CR: IOPS of the DAP submodules, DI8 data, DIO8 in, echo in; IOCS of the
        // output submodules.
        assert_eq!(
            input.apis[0].data_objects,
            entries(&[
                (0, 1, 0),
                (0, 0x8000, 1),
                (0, 0x8001, 2),
                (1, 1, 3),
                (3, 1, 6),
                (4, 1, 9)
            ])
        );
        assert_eq!(
            input.apis[0].iocs,
            entries(&[(2, 1, 5), (3, 1, 8), (4, 1, 18)])
        );
        assert_eq!(
            output.apis[0].data_objects,
            entries(&[(2, 1, 4), (3, 1, 7), (4, 1, 10)])
        );
        assert_eq!(
            output.apis[0].iocs,
            entries(&[
                (0, 1, 0),
                (0, 0x8000, 1),
                (0, 0x8001, 2),
                (1, 1, 3),
                (3, 1, 6),
                (4, 1, 9)
            ])
        );

        assert_eq!(
            req.alarm_cr,
            AlarmCrBlockReq {
                alarm_cr_type: ALARM_CR_TYPE,
                lt: LT_PROFINET,
                properties: 0,
                rta_timeout_factor: 1,
                rta_retries: 3,
                local_alarm_reference: 0,
                max_alarm_data_length: 256,
                tag_header_high: TAG_HEADER_PRIO_6,
                tag_header_low: TAG_HEADER_PRIO_5,
            }
        );

        // One block per slot: the DAP (interface, port) and the four IO modules.
        let module = |api, slot, module_ident, submodules| ExpectedModule {
            api,
            slot,
            module_ident,
            properties: 0,
            submodules,
        };
        let one = |m| ExpectedSubmoduleBlockReq { modules: vec![m] };
        let expected = vec![
            one(module(
                0,
                0,
                0x1,
                vec![
                    ExpectedSubmodule::with_io(1, 0x1, 0, 0),
                    ExpectedSubmodule::with_io(0x8000, 0x8000, 0, 0),
                    ExpectedSubmodule::with_io(0x8001, 0x8001, 0, 0),
                ],
            )),
            one(module(
                0,
                1,
                0x30,
                vec![ExpectedSubmodule::with_io(1, 0x130, 1, 0)],
            )),
            one(module(
                0,
                2,
                0x31,
                vec![ExpectedSubmodule::with_io(1, 0x131, 0, 1)],
            )),
            one(module(
                0,
                3,
                0x32,
                vec![ExpectedSubmodule::with_io(1, 0x132, 1, 1)],
            )),
            one(module(
                0,
                4,
                0x40,
                vec![ExpectedSubmodule::with_io(1, 0x140, 8, 8)],
            )),
        ];
        assert_eq!(req.expected, expected);
        assert_eq!(
            req.expected[3].modules[0].submodules[0].submodule_type(),
            submodule::TYPE_INPUT_OUTPUT
        );

        // Byte for byte: the whole sequence and every block on its own.
        assert_eq!(req.buffer_len(), bytes.len());
        assert_eq!(req.emit(), bytes);
        assert_eq!(req.try_emit().unwrap(), bytes);
        assert_eq!(
            req.ar.to_vec().unwrap(),
            captured(bytes, block_type::AR_BLOCK_REQ)[0]
        );
        for (cr, raw) in req
            .iocrs
            .iter()
            .zip(captured(bytes, block_type::IOCR_BLOCK_REQ))
        {
            assert_eq!(cr.buffer_len(), raw.len());
            let mut out = vec![0xa5u8; raw.len()];
            cr.emit(&mut out).unwrap();
            assert_eq!(out, raw);
        }
        let raw = captured(bytes, block_type::EXPECTED_SUBMODULE_BLOCK_REQ);
        for (e, raw) in req.expected.iter().zip(raw) {
            assert_eq!(e.to_vec().unwrap(), raw);
        }
        let raw = captured(bytes, block_type::ALARM_CR_BLOCK_REQ)[0];
        assert_eq!(req.alarm_cr.to_vec().unwrap(), raw);
    }

    /// The S7's IOCR data objects are what `IocrLayout::new` computes for the expected
    /// submodules, and `from_layout` rebuilds both IOCRBlockReqs byte for byte.
    #[test]
    fn capture_iocrs_match_the_layout() {
        let req = ConnectRequest::parse(blocks_of(&CONNECT_REQ)).unwrap();
        let subs: Vec<SubmoduleIo> = req.submodules().collect();
        assert_eq!(subs.len(), 7);
        let layout = IocrLayout::new(&subs).unwrap();
        let input =
            IocrBlockReq::from_layout(iocr_type::INPUT, 1, 0x8000, &layout.input, &subs).unwrap();
        let output =
            IocrBlockReq::from_layout(iocr_type::OUTPUT, 2, 0x8001, &layout.output, &subs).unwrap();
        assert_eq!(input, req.iocrs[0]);
        assert_eq!(output, req.iocrs[1]);
        let raw = captured(blocks_of(&CONNECT_REQ), block_type::IOCR_BLOCK_REQ);
        assert_eq!(input.to_vec().unwrap(), raw[0]);
        assert_eq!(output.to_vec().unwrap(), raw[1]);
        // A layout from another submodule list does not build.
        assert_eq!(
            IocrBlockReq::from_layout(iocr_type::INPUT, 1, 0x8000, &layout.input, &subs[..3]),
            Err(Error)
        );
    }

    #[test]
    fn connect_response_capture() {
        let bytes = blocks_of(&CONNECT_RES);
        let res = ConnectResponse::parse(bytes).unwrap();
        assert_eq!(res.ar.ar_type, AR_TYPE_IOC_SINGLE);
        assert_eq!(
            res.ar.ar_uuid.to_string(),
            "e5e1aecc-b133-4b4d-b187-cc68b0211ed2"
        );
        assert_eq!(res.ar.session_key, 2);
        assert_eq!(res.ar.responder_mac.to_string(), "8c:f3:19:cd:19:f8");
        assert_eq!(res.ar.udp_rt_port, UDP_RT_PORT_NONE);
        assert_eq!(
            res.iocrs,
            vec![
                IocrBlockRes {
                    iocr_type: iocr_type::INPUT,
                    iocr_reference: 1,
                    frame_id: 0x8000
                },
                IocrBlockRes {
                    iocr_type: iocr_type::OUTPUT,
                    iocr_reference: 2,
                    frame_id: 0x8001
                },
            ]
        );
        assert_eq!(
            (res.frame_id(1), res.frame_id(2), res.frame_id(3)),
            (Some(0x8000), Some(0x8001), None)
        );
        assert_eq!(
            res.alarm_cr,
            AlarmCrBlockRes {
                alarm_cr_type: ALARM_CR_TYPE,
                local_alarm_reference: 0,
                max_alarm_data_length: 200
            }
        );
        assert_eq!(res.module_diff, None);
        let server = res.ar_server.as_ref().unwrap();
        assert_eq!(server.station_name, "rt-labs-dev");
        assert_eq!(server.buffer_len(), 20, "one pad byte");
        assert!(res.others.is_empty());
        assert_eq!(res.buffer_len(), bytes.len());
        assert_eq!(res.emit(), bytes);
        let raw = captured(bytes, block_type::AR_SERVER_BLOCK)[0];
        assert_eq!(server.to_vec().unwrap(), raw);
    }

    #[test]
    fn module_diff_worked_example() {
        let d = ModuleDiffBlock::parse(&MODULE_DIFF_TV7).unwrap();
        assert_eq!(d.apis.len(), 1);
        let m = &d.apis[0].modules;
        assert_eq!(
            (m[0].slot, m[0].module_ident, m[0].state),
            (2, 0x88a1, ModuleState::NoModule)
        );
        assert!(m[0].submodules.is_empty());
        assert_eq!(
            (m[1].slot, m[1].module_ident, m[1].state),
            (4, 0x17ff, ModuleState::WrongModule)
        );
        let subs: Vec<_> = d.submodules().collect();
        assert_eq!(subs, vec![(0, 4, 1, SubmoduleState(0x9000))]);
        let s = subs[0].3;
        assert!(s.format_indicator());
        assert_eq!(s.ident_info(), IdentInfo::Wrong);
        assert_eq!(s.ar_info(), ArInfo::Own);
        assert!(!s.fault() && !s.maintenance_required() && !s.maintenance_demanded());
        assert!(!s.qualified_info());
        assert_eq!(s.add_info(), 0);
        assert!(!s.is_usable());
        assert_eq!(d.to_vec().unwrap(), MODULE_DIFF_TV7);

        // Bit decoding on a made-up state: substitute, ApplicationReady pending, fault, MR.
        let s = SubmoduleState(0x8000 | 1 << 11 | 1 << 7 | 1 << 6 | 1 << 4 | 1);
        assert_eq!(s.ident_info(), IdentInfo::Substitute);
        assert_eq!(s.ar_info(), ArInfo::ApplicationReadyPending);
        assert!(s.fault() && s.maintenance_required() && !s.maintenance_demanded());
        assert_eq!(s.add_info(), 1);
        assert!(!s.is_usable());
        assert!(SubmoduleState(0x8000).is_usable());
        assert!(!SubmoduleState(0).is_usable());
        assert_eq!(SubmoduleState(0xf800).ident_info(), IdentInfo::Reserved(15));
        assert_eq!(SubmoduleState(0x8780).ar_info(), ArInfo::Reserved(15));
        for v in 0..6u16 {
            assert_eq!(u16::from(ModuleState::from(v)), v);
        }
    }

    #[test]
    fn response_with_module_diff_and_other_blocks() {
        let mut res = ConnectResponse::parse(blocks_of(&CONNECT_RES)).unwrap();
        res.module_diff = Some(ModuleDiffBlock::parse(&MODULE_DIFF_TV7).unwrap());
        // An ARRPCBlockRes-like block the module does not model.
        let other = vec![0x81, 0x07, 0x00, 0x04, 0x01, 0x00, 0x88, 0x94];
        res.others.push((0x8107, other.clone()));
        let bytes = res.emit();
        assert_eq!(bytes.len(), res.buffer_len());
        // Order: ..., AlarmCR, ModuleDiff, others, ARServer.
        let types: Vec<u16> = blocks(&bytes).map(|r| r.unwrap().0.block_type).collect();
        assert_eq!(
            types,
            vec![0x8101, 0x8102, 0x8102, 0x8103, 0x8104, 0x8107, 0x8106]
        );
        assert_eq!(ConnectResponse::parse(&bytes), Ok(res));
    }

    #[test]
    fn malformed() {
        let req_bytes = blocks_of(&CONNECT_REQ);
        let res_bytes = blocks_of(&CONNECT_RES);
        // Truncated anywhere: an error, never a panic.
        for n in 0..req_bytes.len() {
            assert!(ConnectRequest::parse(&req_bytes[..n]).is_err(), "{n}");
        }
        for n in 0..res_bytes.len() {
            let _ = ConnectResponse::parse(&res_bytes[..n]);
        }
        assert!(ConnectResponse::parse(&res_bytes[..res_bytes.len() - 1]).is_err());
        // Without the ARServerBlock (the last 20 bytes) the response is complete.
        let legacy = ConnectResponse::parse(&res_bytes[..res_bytes.len() - 20]).unwrap();
        assert_eq!(legacy.ar_server, None);
        // Missing or duplicate AR block.
        let ar_len = captured(req_bytes, block_type::AR_BLOCK_REQ)[0].len();
        assert!(ConnectRequest::parse(&req_bytes[ar_len..]).is_err());
        let mut twice = req_bytes.to_vec();
        twice.extend_from_slice(&req_bytes[..ar_len]);
        assert!(ConnectRequest::parse(&twice).is_err());
        // An unknown block type in a request.
        let mut unknown = req_bytes.to_vec();
        unknown.extend_from_slice(&[0x01, 0x07, 0x00, 0x04, 0x01, 0x00, 0x88, 0x94]);
        assert!(ConnectRequest::parse(&unknown).is_err());
        // Wrong version, wrong type, trailing bytes in the body.
        let alarm = captured(req_bytes, block_type::ALARM_CR_BLOCK_REQ)[0];
        let mut b = alarm.to_vec();
        b[5] = 1;
        assert!(AlarmCrBlockReq::parse(&b).is_err());
        assert!(ArBlockReq::parse(alarm).is_err());
        let mut b = alarm.to_vec();
        b[3] += 2;
        b.extend_from_slice(&[0, 0]);
        assert!(AlarmCrBlockReq::parse(&b).is_err());
        // A station name that is not UTF-8.
        let mut b = captured(res_bytes, block_type::AR_SERVER_BLOCK)[0].to_vec();
        b[8] = 0xff;
        assert!(ArServerBlock::parse(&b).is_err());
        // Four padding bytes are too many.
        let mut b = captured(res_bytes, block_type::AR_SERVER_BLOCK)[0].to_vec();
        b[3] += 3;
        b.extend_from_slice(&[0, 0, 0]);
        assert!(ArServerBlock::parse(&b).is_err());
        b.truncate(b.len() - 3);
        b[3] -= 3;
        assert!(ArServerBlock::parse(&b).is_ok());
    }

    #[test]
    fn unrepresentable_values_do_not_emit() {
        let req = ConnectRequest::parse(blocks_of(&CONNECT_REQ)).unwrap();
        let mut short = vec![0u8; req.ar.buffer_len() - 1];
        assert_eq!(req.ar.emit(&mut short), Err(Error));
        // Data descriptions that do not match the submodule type.
        let mut bad = req.clone();
        bad.expected[0].modules[0].submodules[0].properties = submodule::TYPE_INPUT_OUTPUT;
        assert_eq!(bad.expected[0].to_vec(), Err(Error));
        assert_eq!(bad.try_emit(), Err(Error));
        assert!(bad.emit().is_empty());
        // A list longer than its 16-bit count.
        let mut bad = req.clone();
        let e = IocrEntry {
            slot: 1,
            subslot: 1,
            frame_offset: 0,
        };
        bad.iocrs[0].apis[0].iocs = vec![e; 0x1_0000];
        assert_eq!(bad.iocrs[0].to_vec(), Err(Error));
        assert!(bad.emit().is_empty());
        // A block longer than 65 539 bytes.
        let mut bad = req;
        bad.iocrs[0].apis[0].iocs = vec![e; 0x3000];
        bad.iocrs[0].apis[0].data_objects = vec![e; 0x3000];
        assert_eq!(bad.iocrs[0].to_vec(), Err(Error));
        let long = ArServerBlock {
            station_name: "x".repeat(0x1_0000),
        };
        assert_eq!(long.to_vec(), Err(Error));
    }

    fn uuid() -> impl Strategy<Value = Uuid> {
        any::<[u8; 16]>().prop_map(Uuid)
    }

    fn mac() -> impl Strategy<Value = MacAddress> {
        any::<[u8; 6]>().prop_map(MacAddress)
    }

    fn name() -> impl Strategy<Value = String> {
        "[a-z0-9.-]{0,64}"
    }

    fn ar_block_req() -> impl Strategy<Value = ArBlockReq> {
        (
            (any::<u16>(), uuid(), any::<u16>(), mac(), uuid()),
            (any::<u32>(), any::<u16>(), any::<u16>(), name()),
        )
            .prop_map(|((t, ar, key, m, obj), (props, tf, port, n))| ArBlockReq {
                ar_type: t,
                ar_uuid: ar,
                session_key: key,
                initiator_mac: m,
                initiator_object_uuid: obj,
                ar_properties: props,
                activity_timeout_factor: tf,
                udp_rt_port: port,
                station_name: n,
            })
    }

    fn entry() -> impl Strategy<Value = IocrEntry> {
        any::<(u16, u16, u16)>().prop_map(|(slot, subslot, frame_offset)| IocrEntry {
            slot,
            subslot,
            frame_offset,
        })
    }

    fn iocr_block_req() -> impl Strategy<Value = IocrBlockReq> {
        let api = (
            any::<u32>(),
            proptest::collection::vec(entry(), 0..8),
            proptest::collection::vec(entry(), 0..8),
        )
            .prop_map(|(api, data_objects, iocs)| IocrApi {
                api,
                data_objects,
                iocs,
            });
        (
            any::<[u16; 12]>(),
            any::<(u32, u32)>(),
            mac(),
            proptest::collection::vec(api, 0..3),
        )
            .prop_map(|(w, (props, fso), m, apis)| IocrBlockReq {
                iocr_type: w[0],
                iocr_reference: w[1],
                lt: w[2],
                iocr_properties: props,
                data_length: w[3],
                frame_id: w[4],
                send_clock_factor: w[5],
                reduction_ratio: w[6],
                phase: w[7],
                sequence: w[8],
                frame_send_offset: fso,
                watchdog_factor: w[9],
                data_hold_factor: w[10],
                tag_header: w[11],
                multicast_mac: m,
                apis,
            })
    }

    fn alarm_cr_block_req() -> impl Strategy<Value = AlarmCrBlockReq> {
        (any::<[u16; 8]>(), any::<u32>()).prop_map(|(w, p)| AlarmCrBlockReq {
            alarm_cr_type: w[0],
            lt: w[1],
            properties: p,
            rta_timeout_factor: w[2],
            rta_retries: w[3],
            local_alarm_reference: w[4],
            max_alarm_data_length: w[5],
            tag_header_high: w[6],
            tag_header_low: w[7],
        })
    }

    fn expected_block() -> impl Strategy<Value = ExpectedSubmoduleBlockReq> {
        let dd =
            any::<(u16, u16, u8, u8)>().prop_map(|(direction, length, c, p)| DataDescription {
                direction,
                length,
                length_iocs: c,
                length_iops: p,
            });
        let sub = (any::<u16>(), any::<u32>(), any::<u16>()).prop_flat_map(move |(ss, id, p)| {
            proptest::collection::vec(dd.clone(), ExpectedSubmodule::description_count(p)).prop_map(
                move |data_descriptions| ExpectedSubmodule {
                    subslot: ss,
                    submodule_ident: id,
                    properties: p,
                    data_descriptions,
                },
            )
        });
        let module = (
            any::<u32>(),
            any::<u16>(),
            any::<u32>(),
            any::<u16>(),
            proptest::collection::vec(sub, 0..4),
        )
            .prop_map(
                |(api, slot, module_ident, properties, submodules)| ExpectedModule {
                    api,
                    slot,
                    module_ident,
                    properties,
                    submodules,
                },
            );
        proptest::collection::vec(module, 0..3)
            .prop_map(|modules| ExpectedSubmoduleBlockReq { modules })
    }

    fn module_diff() -> impl Strategy<Value = ModuleDiffBlock> {
        let sub = any::<(u16, u32, u16)>().prop_map(|(subslot, submodule_ident, s)| {
            ModuleDiffSubmodule {
                subslot,
                submodule_ident,
                state: SubmoduleState(s),
            }
        });
        let module = (
            any::<(u16, u32, u16)>(),
            proptest::collection::vec(sub, 0..3),
        )
            .prop_map(|((slot, module_ident, s), submodules)| ModuleDiffModule {
                slot,
                module_ident,
                state: ModuleState::from(s),
                submodules,
            });
        let api = (any::<u32>(), proptest::collection::vec(module, 0..3))
            .prop_map(|(api, modules)| ModuleDiffApi { api, modules });
        proptest::collection::vec(api, 0..3).prop_map(|apis| ModuleDiffBlock { apis })
    }

    fn connect_request() -> impl Strategy<Value = ConnectRequest> {
        (
            ar_block_req(),
            proptest::collection::vec(iocr_block_req(), 0..3),
            alarm_cr_block_req(),
            proptest::collection::vec(expected_block(), 0..3),
        )
            .prop_map(|(ar, iocrs, alarm_cr, expected)| ConnectRequest {
                ar,
                iocrs,
                alarm_cr,
                expected,
            })
    }

    fn connect_response() -> impl Strategy<Value = ConnectResponse> {
        let ar = (any::<u16>(), uuid(), any::<u16>(), mac(), any::<u16>()).prop_map(
            |(ar_type, ar_uuid, session_key, responder_mac, udp_rt_port)| ArBlockRes {
                ar_type,
                ar_uuid,
                session_key,
                responder_mac,
                udp_rt_port,
            },
        );
        let iocr = any::<(u16, u16, u16)>().prop_map(|(iocr_type, iocr_reference, frame_id)| {
            IocrBlockRes {
                iocr_type,
                iocr_reference,
                frame_id,
            }
        });
        let alarm = any::<(u16, u16, u16)>().prop_map(|(t, r, l)| AlarmCrBlockRes {
            alarm_cr_type: t,
            local_alarm_reference: r,
            max_alarm_data_length: l,
        });
        let other = (
            0x8107u16..0x8110,
            proptest::collection::vec(any::<u8>(), 0..12),
        )
            .prop_map(|(t, body)| {
                let mut b = t.to_be_bytes().to_vec();
                b.extend_from_slice(&(body.len() as u16 + 2).to_be_bytes());
                b.extend_from_slice(&[1, 0]);
                b.extend_from_slice(&body);
                (t, b)
            });
        (
            ar,
            proptest::collection::vec(iocr, 0..3),
            alarm,
            proptest::option::of(module_diff()),
            proptest::option::of(name().prop_map(|station_name| ArServerBlock { station_name })),
            proptest::collection::vec(other, 0..2),
        )
            .prop_map(|(ar, iocrs, alarm_cr, module_diff, ar_server, others)| {
                ConnectResponse {
                    ar,
                    iocrs,
                    alarm_cr,
                    module_diff,
                    ar_server,
                    others,
                }
            })
    }

    /// Every block parser on the same bytes.
    fn parse_all(b: &[u8]) {
        let _ = ArBlockReq::parse(b);
        let _ = IocrBlockReq::parse(b);
        let _ = AlarmCrBlockReq::parse(b);
        let _ = ExpectedSubmoduleBlockReq::parse(b);
        let _ = ArBlockRes::parse(b);
        let _ = IocrBlockRes::parse(b);
        let _ = AlarmCrBlockRes::parse(b);
        let _ = ArServerBlock::parse(b);
        let _ = ModuleDiffBlock::parse(b);
        let _ = ConnectRequest::parse(b);
        let _ = ConnectResponse::parse(b);
    }

    proptest! {
        #[test]
        fn parse_never_panics(b in proptest::collection::vec(any::<u8>(), 0..600)) {
            parse_all(&b);
        }

        #[test]
        fn parse_never_panics_on_plausible_blocks(
            t in prop::sample::select(vec![
                0x0101u16, 0x0102, 0x0103, 0x0104, 0x8101, 0x8102, 0x8103, 0x8104, 0x8106,
            ]),
            body in proptest::collection::vec(any::<u8>(), 0..200),
            small in any::<bool>(),
        ) {
            // A valid header over random content; small counts make deep parses likely.
            let mut body = body;
            if small {
                for (i, b) in body.iter_mut().enumerate() {
                    if i % 2 == 0 { *b = 0; } else { *b &= 3; }
                }
            }
            let mut b = t.to_be_bytes().to_vec();
            b.extend_from_slice(&(body.len() as u16 + 2).to_be_bytes());
            b.extend_from_slice(&[1, 0]);
            b.extend_from_slice(&body);
            parse_all(&b);
        }

        #[test]
        fn mutated_captures_never_panic(
            at in 0usize..557,
            v in any::<u8>(),
            cut in 0usize..600,
        ) {
            for frame in [&CONNECT_REQ[..], &CONNECT_RES[..]] {
                let mut b = blocks_of(frame).to_vec();
                if let Some(x) = b.get_mut(at) { *x = v; }
                b.truncate(cut);
                parse_all(&b);
            }
        }

        #[test]
        fn ar_block_req_round_trip(ar in ar_block_req()) {
            let b = ar.to_vec().unwrap();
            prop_assert_eq!(b.len(), ar.buffer_len());
            prop_assert_eq!(ArBlockReq::parse(&b), Ok(ar));
        }

        #[test]
        fn iocr_block_req_round_trip(cr in iocr_block_req()) {
            let b = cr.to_vec().unwrap();
            prop_assert_eq!(b.len(), cr.buffer_len());
            prop_assert_eq!(IocrBlockReq::parse(&b), Ok(cr));
        }

        #[test]
        fn expected_and_module_diff_round_trip(e in expected_block(), d in module_diff()) {
            prop_assert_eq!(ExpectedSubmoduleBlockReq::parse(&e.to_vec().unwrap()), Ok(e));
            prop_assert_eq!(ModuleDiffBlock::parse(&d.to_vec().unwrap()), Ok(d));
        }

        #[test]
        fn connect_request_round_trip(req in connect_request()) {
            let b = req.emit();
            prop_assert_eq!(b.len(), req.buffer_len());
            prop_assert_eq!(ConnectRequest::parse(&b), Ok(req));
        }

        #[test]
        fn connect_response_round_trip(res in connect_response()) {
            let b = res.emit();
            prop_assert_eq!(b.len(), res.buffer_len());
            let parsed = ConnectResponse::parse(&b).unwrap();
            prop_assert_eq!(&parsed, &res);
            if let Some(s) = &parsed.ar_server {
                prop_assert_eq!(s.buffer_len() % 4, 0);
            }
        }

        #[test]
        fn from_layout_round_trips(lens in proptest::collection::vec((0u16..16, 0u16..16), 0..12)) {
            let subs: Vec<SubmoduleIo> = lens
                .iter()
                .enumerate()
                .map(|(i, &(input_length, output_length))| SubmoduleIo {
                    api: (i % 2) as u32,
                    slot: i as u16,
                    subslot: 1,
                    input_length,
                    output_length,
                })
                .collect();
            let l = IocrLayout::new(&subs).unwrap();
            for (t, cr) in [(iocr_type::INPUT, &l.input), (iocr_type::OUTPUT, &l.output)] {
                let b = IocrBlockReq::from_layout(t, t, 0x8000 + t, cr, &subs).unwrap();
                let n: usize = b.apis.iter().map(|a| a.data_objects.len()).sum();
                prop_assert_eq!(n, cr.objects.len());
                let n: usize = b.apis.iter().map(|a| a.iocs.len()).sum();
                prop_assert_eq!(n, cr.iocs.len());
                prop_assert_eq!(IocrBlockReq::parse(&b.to_vec().unwrap()), Ok(b));
            }
        }
    }
}
