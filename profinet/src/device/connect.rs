// SPDX-License-Identifier: MIT OR Apache-2.0
//! The Connect request as a device checks it, and the blocks of its answer.
//!
//! [`validate`] walks the blocks itself (not [`ConnectRequest::parse`]) so that a refusal can
//! name the faulty block and field the way PROFINET devices do: PNIOStatus `DB 81 <block>
//! <field>` with the block as ErrorCode1 (0x01 AR, 0x02 IOCR, 0x03 expected submodule, 0x04
//! alarm CR, 0x07 ARRPC) and the index of the offending field, counted from the BlockType as
//! field 0, as ErrorCode2; or `DB 81 40 xx` (CMRPC) for a request that does not hold together
//! (unknown blocks, missing IOCRs, wrong block count, ArgsLength).
//!
//! [`ConnectRequest::parse`]: crate::wire::connect::ConnectRequest::parse

use super::PluggedSubmodule;
use super::diagnosis::SubslotAddr;
use crate::wire::common::blocks;
use crate::wire::connect::{
    AlarmCrBlockReq, AlarmCrBlockRes, ArBlockReq, ArBlockRes, ArServerBlock, ExpectedSubmodule,
    ExpectedSubmoduleBlockReq, IocrBlockReq, IocrBlockRes, ModuleDiffApi, ModuleDiffBlock,
    ModuleDiffModule, ModuleDiffSubmodule, ModuleState, SubmoduleState, ar_properties,
    iocr_properties, iocr_type, submodule,
};
use crate::wire::record::{ArDataEntry, ArDataIocr};
use crate::wire::rpc::{RPC_PORT, object_uuid_parts};
use crate::wire::{BlockHeader, BlockType, EmitResult, MacAddress, PnioStatus, rt};

/// ErrorCode of a Connect response.
pub(super) const ERROR_CODE_CONNECT: u8 = 0xdb;
/// ErrorDecode PNIO.
const ERROR_DECODE_PNIO: u8 = 0x81;
/// ErrorCode1 of the Connect blocks.
const AR: u8 = 0x01;
const IOCR: u8 = 0x02;
const EXPECTED: u8 = 0x03;
const ALARM_CR: u8 = 0x04;
const AR_RPC: u8 = 0x07;
/// ErrorCode1 CMRPC and its ErrorCode2 reasons.
pub(super) const CMRPC: u8 = 0x40;
pub(super) const CMRPC_ARGS_LENGTH: u8 = 0x00;
pub(super) const CMRPC_UNKNOWN_BLOCKS: u8 = 0x01;
const CMRPC_IOCR_MISSING: u8 = 0x02;
const CMRPC_WRONG_BLOCK_COUNT: u8 = 0x03;
pub(super) const CMRPC_NO_AR_RESOURCES: u8 = 0x04;
pub(super) const CMRPC_AR_UUID_UNKNOWN: u8 = 0x05;
/// ErrorCode1 CMDEV and its "state conflict" reason.
pub(super) const CMDEV: u8 = 0x3d;
pub(super) const CMDEV_STATE_CONFLICT: u8 = 0x00;

/// The MaxAlarmDataLength the device accepts (p-net's).
pub(super) const MAX_ALARM_DATA_LENGTH: u16 = 200;
/// The device's LocalAlarmReference (p-net's; the AR is identified by the MACs anyway).
pub(super) const DEVICE_ALARM_REFERENCE: u16 = 0;

/// Largest DataHoldFactor × period for RT (p-net's and the standard's limit).
const MAX_DATA_HOLD_NS: u64 = 1_920_000_000;

/// A Connect status `DB 81 c1 c2`.
pub(super) const fn refuse(c1: u8, c2: u8) -> PnioStatus {
    PnioStatus {
        error_code: ERROR_CODE_CONNECT,
        error_decode: ERROR_DECODE_PNIO,
        error_code1: c1,
        error_code2: c2,
    }
}

/// One expected submodule, flattened.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Expected {
    pub(super) api: u32,
    pub(super) slot: u16,
    pub(super) module_ident: u32,
    pub(super) subslot: u16,
    pub(super) submodule_ident: u32,
    pub(super) input_length: u16,
    pub(super) output_length: u16,
}

impl Expected {
    /// Inputs or no IO at all: data + IOPS in the input CR, IOCS in the output CR.
    pub(super) const fn is_input(&self) -> bool {
        self.input_length > 0 || self.output_length == 0
    }

    /// Outputs: data + IOPS in the output CR, IOCS in the input CR.
    pub(super) const fn is_output(&self) -> bool {
        self.output_length > 0
    }

    /// Where it is.
    pub(super) const fn addr(&self) -> SubslotAddr {
        SubslotAddr::new(self.api, self.slot, self.subslot)
    }
}

/// A Connect request that passed every check.
#[derive(Clone, Debug)]
pub(super) struct Plan {
    pub(super) ar: ArBlockReq,
    pub(super) input: IocrBlockReq,
    pub(super) output: IocrBlockReq,
    /// IOCRBlockReq (type, reference) in request order, for the response.
    pub(super) iocr_order: Vec<(u16, u16)>,
    pub(super) alarm_cr: AlarmCrBlockReq,
    pub(super) expected: Vec<Expected>,
    /// The initiator's RPC server port from an ARRPCBlockReq, if one came.
    pub(super) rpc_port: Option<u16>,
}

impl Plan {
    /// Whether the AR uses advanced startup (and gets an ARServerBlock).
    pub(super) const fn advanced(&self) -> bool {
        self.ar.ar_properties & ar_properties::STARTUP_MODE_ADVANCED != 0
    }
}

/// Checks the blocks of a Connect request (the `ArgsLength` bytes after the NDR header).
pub(super) fn validate(bytes: &[u8]) -> Result<Plan, PnioStatus> {
    let (mut ar, mut alarm_cr, mut rpc_port) = (None, None, None);
    let mut iocrs = Vec::new();
    let mut expected_blocks = Vec::new();
    for r in blocks(bytes) {
        let (h, block) = r.map_err(|_| refuse(CMRPC, CMRPC_ARGS_LENGTH))?;
        let code = match h.block_type {
            BlockType::ArBlockReq => AR,
            BlockType::IocrBlockReq => IOCR,
            BlockType::AlarmCrBlockReq => ALARM_CR,
            BlockType::ExpectedSubmoduleBlockReq => EXPECTED,
            // ARRPCBlockReq: the initiator's RPC server port.
            BlockType::ArRpcBlockReq => AR_RPC,
            _ => return Err(refuse(CMRPC, CMRPC_UNKNOWN_BLOCKS)),
        };
        if h.version_high != 1 {
            return Err(refuse(code, 2));
        }
        if h.version_low != 0 {
            return Err(refuse(code, 3));
        }
        // A body that does not parse has a BlockLength that does not match its content.
        let malformed = || refuse(code, 1);
        let once = || refuse(CMRPC, CMRPC_WRONG_BLOCK_COUNT);
        match code {
            AR => {
                if ar
                    .replace(ArBlockReq::parse(block).map_err(|_| malformed())?)
                    .is_some()
                {
                    return Err(once());
                }
            }
            IOCR => iocrs.push(IocrBlockReq::parse(block).map_err(|_| malformed())?),
            ALARM_CR => {
                let a = AlarmCrBlockReq::parse(block).map_err(|_| malformed())?;
                if alarm_cr.replace(a).is_some() {
                    return Err(once());
                }
            }
            EXPECTED => expected_blocks
                .push(ExpectedSubmoduleBlockReq::parse(block).map_err(|_| malformed())?),
            _ => {
                let port = match h.body(block) {
                    [hi, lo] => u16::from_be_bytes([*hi, *lo]),
                    _ => return Err(malformed()),
                };
                if rpc_port.replace(port).is_some() {
                    return Err(once());
                }
            }
        }
    }
    let ar = ar.ok_or_else(|| refuse(CMRPC, CMRPC_WRONG_BLOCK_COUNT))?;
    let alarm_cr = alarm_cr.ok_or_else(|| refuse(CMRPC, CMRPC_WRONG_BLOCK_COUNT))?;
    check_ar(&ar)?;
    let iocr_order = iocrs
        .iter()
        .map(|c| (c.iocr_type, c.iocr_reference))
        .collect();
    let (input, output) = split_iocrs(iocrs)?;
    let expected = check_expected(&expected_blocks)?;
    let advanced = ar.ar_properties & ar_properties::STARTUP_MODE_ADVANCED != 0;
    check_iocr(&input, advanced, &expected)?;
    check_iocr(&output, advanced, &expected)?;
    if input.frame_id == output.frame_id && input.frame_id != FRAME_ID_ASSIGN {
        return Err(refuse(IOCR, 9));
    }
    check_alarm_cr(&alarm_cr)?;
    Ok(Plan {
        ar,
        input,
        output,
        iocr_order,
        alarm_cr,
        expected,
        rpc_port,
    })
}

/// FrameID a controller writes to let the device choose.
pub(super) const FRAME_ID_ASSIGN: u16 = 0xffff;

fn check_ar(ar: &ArBlockReq) -> Result<(), PnioStatus> {
    check_ar_block(ar, false)
}

/// ARType of a supervisor AR (IOSAR), which with ARProperties.DeviceAccess is a device
/// access AR.
pub(super) const AR_TYPE_IOSAR: u16 = 0x0006;

/// Checks an ARBlockReq: of a single IOC-AR (`device_access` false), or of a device access
/// AR (an IOSAR with ARProperties.DeviceAccess).
fn check_ar_block(ar: &ArBlockReq, device_access: bool) -> Result<(), PnioStatus> {
    // Bits an AR of an RT device leaves clear: reserved 5–7 and 12–28, companion ARs, the
    // combined object container; device access only in a device access AR.
    const UNSUPPORTED: u32 = 0x0000_00e0
        | 0x1fff_f000
        | ar_properties::COMPANION_AR_MASK
        | ar_properties::COMBINED_OBJECT_CONTAINER;
    let p = ar.ar_properties;
    let (ar_type, access_bit) = if device_access {
        (AR_TYPE_IOSAR, ar_properties::DEVICE_ACCESS)
    } else {
        (0x0001, 0)
    };
    let checks = [
        (ar.ar_type == ar_type, 4),
        (!ar.ar_uuid.is_nil(), 5),
        (
            !ar.initiator_mac.is_multicast() && ar.initiator_mac != MacAddress::default(),
            7,
        ),
        (object_uuid_parts(&ar.initiator_object_uuid).is_some(), 8),
        (
            p & ar_properties::STATE_MASK == ar_properties::STATE_ACTIVE
                && p & ar_properties::PARAMETERIZATION_SERVER_CM_INITIATOR != 0
                && p & UNSUPPORTED == 0
                && p & ar_properties::DEVICE_ACCESS == access_bit,
            9,
        ),
        ((1..=1000).contains(&ar.activity_timeout_factor), 10),
        (ar.udp_rt_port == 0x8892, 11),
        (
            (1..=240).contains(&ar.station_name.len())
                && ar.station_name.bytes().all(|c| c.is_ascii_graphic()),
            12,
        ),
    ];
    first_failure(AR, &checks)
}

/// A device access AR's Connect, checked.
pub(super) struct AccessPlan {
    pub(super) ar: ArBlockReq,
    /// The initiator's RPC server port from an ARRPCBlockReq, if one came.
    pub(super) rpc_port: Option<u16>,
}

/// Whether a Connect's blocks ask for a device access AR (an ARBlockReq with
/// ARProperties.DeviceAccess), and if so the checked request or its refusal: one ARBlockReq
/// and perhaps an ARRPCBlockReq, no CRs, no expected submodules.
pub(super) fn validate_device_access(bytes: &[u8]) -> Option<Result<AccessPlan, PnioStatus>> {
    let asks = blocks(bytes).flatten().any(|(h, b)| {
        h.block_type == BlockType::ArBlockReq
            && ArBlockReq::parse(b)
                .is_ok_and(|ar| ar.ar_properties & ar_properties::DEVICE_ACCESS != 0)
    });
    asks.then(|| {
        let (mut ar, mut rpc_port) = (None, None);
        for r in blocks(bytes) {
            let (h, block) = r.map_err(|_| refuse(CMRPC, CMRPC_ARGS_LENGTH))?;
            if (h.version_high, h.version_low) != (1, 0) {
                return Err(refuse(AR, 2));
            }
            match h.block_type {
                BlockType::ArBlockReq if ar.is_none() => {
                    ar = Some(ArBlockReq::parse(block).map_err(|_| refuse(AR, 1))?);
                }
                BlockType::ArRpcBlockReq if rpc_port.is_none() => match h.body(block) {
                    [hi, lo] => rpc_port = Some(u16::from_be_bytes([*hi, *lo])),
                    _ => return Err(refuse(AR_RPC, 1)),
                },
                BlockType::ArBlockReq | BlockType::ArRpcBlockReq => {
                    return Err(refuse(CMRPC, CMRPC_WRONG_BLOCK_COUNT));
                }
                // A device access AR has no IO, no alarms, no expected submodules.
                _ => return Err(refuse(CMRPC, CMRPC_UNKNOWN_BLOCKS)),
            }
        }
        let ar = ar.ok_or_else(|| refuse(CMRPC, CMRPC_WRONG_BLOCK_COUNT))?;
        check_ar_block(&ar, true)?;
        Ok(AccessPlan { ar, rpc_port })
    })
}

/// The positive response to a device access Connect: ARBlockRes, and ARRPCBlockRes if
/// asked for.
pub(super) fn access_response_blocks(
    plan: &AccessPlan,
    device_mac: MacAddress,
) -> EmitResult<Vec<u8>> {
    let mut out = ar_block_res(&plan.ar, device_mac)?;
    rpc_block_res(&mut out, plan.rpc_port)?;
    Ok(out)
}

/// The ARBlockRes answering `ar` from the device at `device_mac`.
fn ar_block_res(ar: &ArBlockReq, device_mac: MacAddress) -> EmitResult<Vec<u8>> {
    ArBlockRes {
        ar_type: ar.ar_type,
        ar_uuid: ar.ar_uuid,
        session_key: ar.session_key,
        responder_mac: device_mac,
        udp_rt_port: 0x8892,
    }
    .to_vec()
}

/// Appends the ARRPCBlockRes (the responder's RPC server port) if the Connect asked with an
/// ARRPCBlockReq.
fn rpc_block_res(out: &mut Vec<u8>, asked: Option<u16>) -> EmitResult<()> {
    if asked.is_some() {
        out.extend_from_slice(&BlockHeader::v1(BlockType::ArRpcBlockRes, 2)?.to_bytes());
        out.extend_from_slice(&RPC_PORT.to_be_bytes());
    }
    Ok(())
}

/// An AR as ARData describes it, from its Connect: `iocrs` its CRs with their FrameIDs.
pub(super) fn described(
    ar: &ArBlockReq,
    alarm_cr: Option<&AlarmCrBlockReq>,
    iocrs: &[(&IocrBlockReq, u16)],
    apis: Vec<u32>,
) -> ArDataEntry {
    ArDataEntry {
        ar_uuid: ar.ar_uuid,
        initiator_object_uuid: ar.initiator_object_uuid,
        parameter_server_object_uuid: crate::wire::Uuid([0; 16]),
        ar_properties: ar.ar_properties,
        ar_type: ar.ar_type,
        alarm_cr_type: alarm_cr.map_or(0, |a| a.alarm_cr_type),
        local_alarm_reference: alarm_cr.map_or(0, |_| DEVICE_ALARM_REFERENCE),
        remote_alarm_reference: alarm_cr.map_or(0, |a| a.local_alarm_reference),
        initiator_udp_rt_port: ar.udp_rt_port,
        responder_udp_rt_port: 0x8892,
        initiator_station_name: ar.station_name.clone(),
        parameter_server_station_name: String::new(),
        iocrs: iocrs
            .iter()
            .map(|(c, frame_id)| ArDataIocr {
                properties: c.iocr_properties,
                iocr_type: c.iocr_type,
                frame_id: *frame_id,
                cycle_counter: 0,
                data_status: 0,
                transfer_status: 0,
            })
            .collect(),
        apis,
    }
}

/// `Err(DB 81 code field)` for the first check that fails.
fn first_failure(code: u8, checks: &[(bool, u8)]) -> Result<(), PnioStatus> {
    match checks.iter().find(|(ok, _)| !ok) {
        Some((_, field)) => Err(refuse(code, *field)),
        None => Ok(()),
    }
}

/// Exactly one input and one output CR (multicast CRs are not supported).
fn split_iocrs(iocrs: Vec<IocrBlockReq>) -> Result<(IocrBlockReq, IocrBlockReq), PnioStatus> {
    let (mut input, mut output) = (None, None);
    for c in iocrs {
        let slot = match c.iocr_type {
            iocr_type::INPUT => &mut input,
            iocr_type::OUTPUT => &mut output,
            _ => return Err(refuse(IOCR, 4)),
        };
        if slot.replace(c).is_some() {
            return Err(refuse(CMRPC, CMRPC_WRONG_BLOCK_COUNT));
        }
    }
    match (input, output) {
        (Some(i), Some(o)) => Ok((i, o)),
        _ => Err(refuse(CMRPC, CMRPC_IOCR_MISSING)),
    }
}

/// Flattens the expected submodules, checking their descriptions.
fn check_expected(blocks: &[ExpectedSubmoduleBlockReq]) -> Result<Vec<Expected>, PnioStatus> {
    let mut out: Vec<Expected> = Vec::new();
    for m in blocks.iter().flat_map(|b| b.modules.iter()) {
        if out
            .iter()
            .any(|e| (e.api, e.slot) == (m.api, m.slot) && e.module_ident != m.module_ident)
        {
            return Err(refuse(EXPECTED, 7));
        }
        for s in &m.submodules {
            check_descriptions(s)?;
            if out
                .iter()
                .any(|e| (e.api, e.slot, e.subslot) == (m.api, m.slot, s.subslot))
            {
                return Err(refuse(EXPECTED, 10));
            }
            out.push(Expected {
                api: m.api,
                slot: m.slot,
                module_ident: m.module_ident,
                subslot: s.subslot,
                submodule_ident: s.submodule_ident,
                input_length: s.input_length(),
                output_length: s.output_length(),
            });
        }
    }
    Ok(out)
}

/// The data descriptions must match the submodule type: NO_IO one input of length 0, INPUT
/// one input, OUTPUT one output, INPUT_OUTPUT an input then an output; 1-byte IOCS and IOPS.
fn check_descriptions(s: &ExpectedSubmodule) -> Result<(), PnioStatus> {
    let dirs: Vec<u16> = s.data_descriptions.iter().map(|d| d.direction).collect();
    let shape_ok = match s.submodule_type() {
        submodule::TYPE_NO_IO => dirs == [submodule::DATA_INPUT] && s.input_length() == 0,
        submodule::TYPE_INPUT => dirs == [submodule::DATA_INPUT],
        submodule::TYPE_OUTPUT => dirs == [submodule::DATA_OUTPUT],
        _ => dirs == [submodule::DATA_INPUT, submodule::DATA_OUTPUT],
    };
    let reserved = submodule::SHARED_INPUT
        | submodule::REDUCE_INPUT_LENGTH
        | submodule::REDUCE_OUTPUT_LENGTH
        | submodule::DISCARD_IOXS
        | 0xffc0;
    let checks = [
        (s.properties & reserved == 0, 12),
        (shape_ok, 13),
        (
            s.data_descriptions
                .iter()
                .all(|d| usize::from(d.length) < rt::MAX_DATA_LENGTH),
            14,
        ),
        (s.data_descriptions.iter().all(|d| d.length_iocs == 1), 15),
        (s.data_descriptions.iter().all(|d| d.length_iops == 1), 16),
    ];
    first_failure(EXPECTED, &checks)
}

/// Refuses a Connect whose IO CRs' period the device cannot keep (`fits` says which it
/// can), as a faulty ReductionRatio of the first such IOCRBlockReq.
pub(super) fn check_period(plan: &Plan, fits: impl Fn(u64) -> bool) -> Result<(), PnioStatus> {
    for c in [&plan.input, &plan.output] {
        first_failure(IOCR, &[(fits(c.period_ns()), 11)])?;
    }
    Ok(())
}

/// Whether `n` is a power of two within `1..=max`.
fn power_of_two(n: u16, max: u16) -> bool {
    n.is_power_of_two() && n <= max
}

fn check_iocr(c: &IocrBlockReq, advanced: bool, expected: &[Expected]) -> Result<(), PnioStatus> {
    let rt_class = c.rt_class();
    // Reserved bits 4–12 and 24–31; classes 3 (IRT) and 4 (UDP) are not ours; advanced
    // startup needs class 2 (class 1 FrameIDs are the legacy range).
    let properties_ok = c.iocr_properties & 0xff00_1ff0 == 0
        && match rt_class {
            iocr_properties::RT_CLASS_1 => !advanced,
            iocr_properties::RT_CLASS_2 => true,
            _ => false,
        };
    let frame_id_ok = c.frame_id == FRAME_ID_ASSIGN
        || match rt_class {
            iocr_properties::RT_CLASS_1 => (0xc000..=0xf7ff).contains(&c.frame_id),
            _ => (0x8000..=0xbbff).contains(&c.frame_id),
        };
    let period = c.period_ns();
    let fso_ok = c.frame_send_offset == u32::MAX
        || u64::from(c.frame_send_offset)
            < u64::from(c.send_clock_factor) * crate::wire::rt::TIME_UNIT_NS;
    let dhf_ok = (1..=0x1e00).contains(&c.data_hold_factor)
        && u64::from(c.data_hold_factor) * period <= MAX_DATA_HOLD_NS;
    let checks = [
        (c.lt == 0x8892, 6),
        (properties_ok, 7),
        (
            (rt::MIN_DATA_LENGTH..=rt::MAX_DATA_LENGTH).contains(&usize::from(c.data_length)),
            8,
        ),
        (frame_id_ok, 9),
        (power_of_two(c.send_clock_factor, 128), 10),
        (power_of_two(c.reduction_ratio, 512), 11),
        ((1..=c.reduction_ratio).contains(&c.phase), 12),
        (fso_ok, 14),
        (dhf_ok, 16),
        // VLAN 0, priority 6, as the standard fixes it for RT class 1/2.
        (c.tag_header == 0xc000, 17),
        (c.multicast_mac == MacAddress::default(), 18),
    ];
    first_failure(IOCR, &checks)?;
    check_layout(c, expected)
}

/// The IO data objects and IOCSs of a CR: every entry names an expected submodule of the
/// right direction, fits the C_SDU and overlaps nothing, and every submodule that belongs in
/// the CR is there.
fn check_layout(c: &IocrBlockReq, expected: &[Expected]) -> Result<(), PnioStatus> {
    let input = c.iocr_type == iocr_type::INPUT;
    let len = usize::from(c.data_length);
    let mut used = vec![false; len];
    let mut claim = |at: u16, n: usize, field: u8| -> Result<(), PnioStatus> {
        let start = usize::from(at);
        let span = used
            .get_mut(start..start.saturating_add(n))
            .filter(|s| s.len() == n)
            .ok_or(refuse(IOCR, field))?;
        if span.iter().any(|&u| u) {
            return Err(refuse(IOCR, field));
        }
        span.fill(true);
        Ok(())
    };
    let find = |api: u32, slot: u16, subslot: u16| {
        expected
            .iter()
            .find(|e| (e.api, e.slot, e.subslot) == (api, slot, subslot))
    };
    let (mut data_seen, mut iocs_seen) = (Vec::new(), Vec::new());
    for a in &c.apis {
        for o in &a.data_objects {
            let e = find(a.api, o.slot, o.subslot).ok_or(refuse(IOCR, 23))?;
            let (fits, n) = if input {
                (e.is_input(), e.input_length)
            } else {
                (e.is_output(), e.output_length)
            };
            if !fits || data_seen.contains(e) {
                return Err(refuse(IOCR, 23));
            }
            claim(o.frame_offset, usize::from(n) + 1, 24)?;
            data_seen.push(*e);
        }
        for o in &a.iocs {
            let e = find(a.api, o.slot, o.subslot).ok_or(refuse(IOCR, 27))?;
            let fits = if input { e.is_output() } else { e.is_input() };
            if !fits || iocs_seen.contains(e) {
                return Err(refuse(IOCR, 27));
            }
            claim(o.frame_offset, 1, 28)?;
            iocs_seen.push(*e);
        }
    }
    // What belongs in this CR: data objects of its direction, IOCSs of the other.
    let data_wanted = |e: &&Expected| if input { e.is_input() } else { e.is_output() };
    let iocs_wanted = |e: &&Expected| if input { e.is_output() } else { e.is_input() };
    if expected.iter().filter(data_wanted).count() != data_seen.len() {
        return Err(refuse(IOCR, 21));
    }
    if expected.iter().filter(iocs_wanted).count() != iocs_seen.len() {
        return Err(refuse(IOCR, 25));
    }
    Ok(())
}

fn check_alarm_cr(a: &AlarmCrBlockReq) -> Result<(), PnioStatus> {
    let checks = [
        (a.alarm_cr_type == 0x0001, 4),
        (a.lt == 0x8892, 5),
        // Bit 0 priority (either), bit 1 transport must be 0 (RTA over layer 2), rest reserved.
        (a.properties & !1 == 0, 6),
        ((1..=100).contains(&a.rta_timeout_factor), 7),
        ((3..=15).contains(&a.rta_retries), 8),
        ((200..=1432).contains(&a.max_alarm_data_length), 10),
        (a.tag_header_high == 0xc000, 11),
        (a.tag_header_low == 0xa000, 12),
    ];
    first_failure(ALARM_CR, &checks)
}

/// How an expected submodule compares with what is plugged.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Fit {
    /// The expected submodule is plugged: data exchange.
    Proper,
    /// Something else is plugged (another ident or other IO lengths).
    Wrong,
    /// Nothing is plugged there.
    Missing,
}

/// Compares the expected submodules with the real ones: the fit of each, in order, and the
/// ModuleDiffBlock listing the differences (`None` when there are none). `diagnosis` gives
/// the diagnosis bits of a plugged submodule's SubmoduleState (QualifiedInfo,
/// MaintenanceRequired/Demanded, DiagInfo): an expected submodule that is plugged but has
/// diagnosis is listed too, with IdentInfo OK and those bits, its module as the proper one.
pub(super) fn module_diff(
    expected: &[Expected],
    real: &[PluggedSubmodule],
    diagnosis: impl Fn(u32, u16, u16) -> u16,
) -> (Vec<Fit>, Option<ModuleDiffBlock>) {
    let fits: Vec<Fit> = expected
        .iter()
        .map(|e| {
            match real
                .iter()
                .find(|r| (r.api, r.slot, r.subslot) == (e.api, e.slot, e.subslot))
            {
                None => Fit::Missing,
                Some(r)
                    if r.module_ident == e.module_ident
                        && r.submodule_ident == e.submodule_ident
                        && r.input_length == e.input_length
                        && r.output_length == e.output_length =>
                {
                    Fit::Proper
                }
                Some(_) => Fit::Wrong,
            }
        })
        .collect();
    let mut apis: Vec<ModuleDiffApi> = Vec::new();
    for (e, fit) in expected.iter().zip(&fits) {
        let diag_bits = match fit {
            Fit::Proper => diagnosis(e.api, e.slot, e.subslot),
            Fit::Wrong | Fit::Missing => 0,
        };
        if *fit == Fit::Proper && diag_bits == 0 {
            continue;
        }
        let real_module = real
            .iter()
            .find(|r| (r.api, r.slot) == (e.api, e.slot))
            .map(|r| r.module_ident);
        let (module_ident, state) = match real_module {
            None => (0, ModuleState::NoModule),
            Some(m) if m != e.module_ident => (m, ModuleState::WrongModule),
            Some(m) => (m, ModuleState::ProperModule),
        };
        let api_at = match apis.iter().position(|a| a.api == e.api) {
            Some(i) => i,
            None => {
                apis.push(ModuleDiffApi {
                    api: e.api,
                    modules: Vec::new(),
                });
                apis.len() - 1
            }
        };
        let modules = &mut apis[api_at].modules;
        let module_at = match modules.iter().position(|m| m.slot == e.slot) {
            Some(i) => i,
            None => {
                modules.push(ModuleDiffModule {
                    slot: e.slot,
                    module_ident,
                    state,
                    submodules: Vec::new(),
                });
                modules.len() - 1
            }
        };
        // An empty slot lists no submodules; otherwise each expected one that does not fit.
        if state == ModuleState::NoModule {
            continue;
        }
        let real_sub = real
            .iter()
            .find(|r| (r.api, r.slot, r.subslot) == (e.api, e.slot, e.subslot));
        let (ident, ident_info) = match (fit, real_sub) {
            (Fit::Proper, Some(r)) => (r.submodule_ident, IDENT_OK),
            (_, Some(r)) => (r.submodule_ident, IDENT_WRONG),
            (_, None) => (0, IDENT_NO_SUBMODULE),
        };
        modules[module_at].submodules.push(ModuleDiffSubmodule {
            subslot: e.subslot,
            submodule_ident: ident,
            state: SubmoduleState(SubmoduleState::FORMAT_INDICATOR | ident_info << 11 | diag_bits),
        });
    }
    let diff = (!apis.is_empty()).then_some(ModuleDiffBlock { apis });
    (fits, diff)
}

/// SubmoduleState IdentInfo: the expected submodule.
const IDENT_OK: u16 = 0;
/// SubmoduleState IdentInfo: wrong submodule.
const IDENT_WRONG: u16 = 2;
/// SubmoduleState IdentInfo: no submodule.
const IDENT_NO_SUBMODULE: u16 = 3;

/// The blocks of the positive Connect response, in p-net's order: ARBlockRes, the
/// IOCRBlockRes in request order, AlarmCRBlockRes, the ModuleDiffBlock if any, ARRPCBlockRes
/// if asked for, ARServerBlock in advanced startup.
pub(super) fn response_blocks(
    plan: &Plan,
    device_mac: MacAddress,
    station_name: &str,
    input_frame_id: u16,
    output_frame_id: u16,
    diff: Option<&ModuleDiffBlock>,
) -> EmitResult<Vec<u8>> {
    let mut out = ar_block_res(&plan.ar, device_mac)?;
    for &(t, reference) in &plan.iocr_order {
        let frame_id = if t == iocr_type::INPUT {
            input_frame_id
        } else {
            output_frame_id
        };
        let b = IocrBlockRes {
            iocr_type: t,
            iocr_reference: reference,
            frame_id,
        };
        out.extend(b.to_vec()?);
    }
    let alarm = AlarmCrBlockRes {
        alarm_cr_type: plan.alarm_cr.alarm_cr_type,
        local_alarm_reference: DEVICE_ALARM_REFERENCE,
        max_alarm_data_length: plan
            .alarm_cr
            .max_alarm_data_length
            .min(MAX_ALARM_DATA_LENGTH),
    };
    out.extend(alarm.to_vec()?);
    if let Some(d) = diff {
        out.extend(d.to_vec()?);
    }
    rpc_block_res(&mut out, plan.rpc_port)?;
    if plan.advanced() {
        let server = ArServerBlock {
            station_name: station_name.to_string(),
        };
        out.extend(server.to_vec()?);
    }
    Ok(out)
}

/// The FrameIDs of the two CRs: the controller's, or, where it wrote 0xFFFF, the first free
/// one of the CR's RT class range.
pub(super) fn frame_ids(plan: &Plan) -> (u16, u16) {
    let first = |c: &IocrBlockReq| {
        if c.rt_class() == iocr_properties::RT_CLASS_1 {
            0xc000
        } else {
            0x8000
        }
    };
    let pick = |c: &IocrBlockReq, taken: u16| {
        if c.frame_id != FRAME_ID_ASSIGN {
            return c.frame_id;
        }
        let f = first(c);
        if f == taken { f + 1 } else { f }
    };
    let input = pick(&plan.input, plan.output.frame_id);
    let output = pick(&plan.output, input);
    (input, output)
}
