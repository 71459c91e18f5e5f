// SPDX-License-Identifier: MIT OR Apache-2.0
//! A PNIOStatus in words: the service, the error class and code, the block field a Connect
//! refused.

use super::*;

/// A PNIOStatus in words, e.g. "Connect refused: IOCRBlockReq field 9 (FrameID)" or
/// "Read failed: access: invalid index"; values this module does not know print in hex.
pub fn describe(status: PnioStatus) -> String {
    StatusText(status).to_string()
}

/// Displays a PNIOStatus in words (see [`describe`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct StatusText(pub PnioStatus);

impl core::fmt::Display for StatusText {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let s = self.0;
        if s.is_ok() {
            return f.write_str("OK");
        }
        match service_name(s.error_code) {
            Some(name) => f.write_str(name)?,
            None => write!(f, "ErrorCode {:#04x}", s.error_code)?,
        }
        f.write_str(": ")?;
        let (c1, c2) = (s.error_code1, s.error_code2);
        match s.error_decode {
            0x80 => describe_pniorw(f, c1, c2),
            0x81 => describe_pnio(f, c1, c2),
            0x82 => write!(f, "manufacturer specific {c1:#04x} {c2:#04x}"),
            d => write!(
                f,
                "ErrorDecode {d:#04x}, ErrorCode1 {c1:#04x}, ErrorCode2 {c2:#04x}"
            ),
        }
    }
}

/// The service an ErrorCode belongs to, as the start of a sentence.
const fn service_name(error_code: u8) -> Option<&'static str> {
    Some(match error_code {
        0x81 => "PNIO error",
        0xcf => "RTA error",
        0xda => "AlarmAck failed",
        0xdb => "Connect refused",
        0xdc => "Release refused",
        0xdd => "Control refused",
        0xde => "Read failed",
        0xdf => "Write failed",
        _ => return None,
    })
}

/// ErrorDecode 0x80 (PNIORW): ErrorCode1 = class (high nibble) and code (low nibble),
/// ErrorCode2 user specific.
fn describe_pniorw(f: &mut core::fmt::Formatter<'_>, c1: u8, c2: u8) -> core::fmt::Result {
    let code = c1 & 0x0f;
    let (class, what) = match c1 >> 4 {
        0xa => (
            "application",
            match code {
                0x0 => Some("read error"),
                0x1 => Some("write error"),
                0x2 => Some("module failure"),
                0x7 => Some("busy"),
                0x8 => Some("version conflict"),
                0x9 => Some("feature not supported"),
                _ => None,
            },
        ),
        0xb => (
            "access",
            match code {
                0x0 => Some("invalid index"),
                0x1 => Some("write length error"),
                0x2 => Some("invalid slot/subslot"),
                0x3 => Some("type conflict"),
                0x4 => Some("invalid area/API"),
                0x5 => Some("state conflict"),
                0x6 => Some("access denied"),
                0x7 => Some("invalid range"),
                0x8 => Some("invalid parameter"),
                0x9 => Some("invalid type"),
                0xa => Some("backup"),
                _ => None,
            },
        ),
        0xc => (
            "resource",
            match code {
                0x0 => Some("read constrain conflict"),
                0x1 => Some("write constrain conflict"),
                0x2 => Some("resource busy"),
                0x3 => Some("resource unavailable"),
                _ => None,
            },
        ),
        _ => ("", None),
    };
    match (class, what) {
        ("", _) => write!(f, "ErrorCode1 {c1:#04x}")?,
        (class, Some(what)) => write!(f, "{class}: {what}")?,
        (class, None) => write!(f, "{class} error {c1:#04x}")?,
    }
    if c2 != 0 {
        write!(f, ", user code {c2:#04x}")?;
    }
    Ok(())
}

/// The fields every block starts with, numbered 0..=3 in PNIO field indices.
const BLOCK_HEADER_FIELDS: [&str; 4] = [
    "BlockType",
    "BlockLength",
    "BlockVersionHigh",
    "BlockVersionLow",
];

/// ARBlockReq fields from index 4 on.
const AR_FIELDS: &[&str] = &[
    "ARType",
    "ARUUID",
    "SessionKey",
    "CMInitiatorMacAdd",
    "CMInitiatorObjectUUID",
    "ARProperties",
    "CMInitiatorActivityTimeoutFactor",
    "CMInitiatorUDPRTPort",
    "StationNameLength",
    "CMInitiatorStationName",
];

/// IOCRBlockReq fields from index 4 on.
const IOCR_FIELDS: &[&str] = &[
    "IOCRType",
    "IOCRReference",
    "LT",
    "IOCRProperties",
    "DataLength",
    "FrameID",
    "SendClockFactor",
    "ReductionRatio",
    "Phase",
    "Sequence",
    "FrameSendOffset",
    "WatchdogFactor",
    "DataHoldFactor",
    "IOCRTagHeader",
    "IOCRMulticastMACAdd",
    "NumberOfAPIs",
    "API",
    "NumberOfIODataObjects",
    "SlotNumber",
    "SubslotNumber",
    "IODataObjectFrameOffset",
    "NumberOfIOCS",
    "SlotNumber",
    "SubslotNumber",
    "IOCSFrameOffset",
];

/// ExpectedSubmoduleBlockReq fields from index 4 on.
const EXPECTED_SUBMODULE_FIELDS: &[&str] = &[
    "NumberOfAPIs",
    "API",
    "SlotNumber",
    "ModuleIdentNumber",
    "ModuleProperties",
    "NumberOfSubmodules",
    "SubslotNumber",
    "SubmoduleIdentNumber",
    "SubmoduleProperties",
    "DataDescription",
    "SubmoduleDataLength",
    "LengthIOCS",
    "LengthIOPS",
];

/// AlarmCRBlockReq fields from index 4 on.
const ALARM_CR_FIELDS: &[&str] = &[
    "AlarmCRType",
    "LT",
    "AlarmCRProperties",
    "RTATimeoutFactor",
    "RTARetries",
    "LocalAlarmReference",
    "MaxAlarmDataLength",
    "AlarmCRTagHeaderHigh",
    "AlarmCRTagHeaderLow",
];

/// The name of a Connect request block (ErrorCode1 with ErrorDecode PNIO) and its fields
/// after the block header, in layout order.
const fn connect_block(c1: u8) -> Option<(&'static str, &'static [&'static str])> {
    Some(match c1 {
        0x01 => ("ARBlockReq", AR_FIELDS),
        0x02 => ("IOCRBlockReq", IOCR_FIELDS),
        0x03 => ("ExpectedSubmoduleBlockReq", EXPECTED_SUBMODULE_FIELDS),
        0x04 => ("AlarmCRBlockReq", ALARM_CR_FIELDS),
        0x05 => ("PrmServerBlockReq", &[]),
        0x06 => ("MCRBlockReq", &[]),
        0x07 => ("ARRPCBlockReq", &[]),
        0x0c => ("ARVendorBlockReq", &[]),
        _ => return None,
    })
}

/// ErrorCode2 of CMRPC (ErrorCode1 0x40).
const fn cmrpc_reason(c2: u8) -> Option<&'static str> {
    Some(match c2 {
        0 => "invalid NDR ArgsLength",
        1 => "unknown blocks",
        2 => "IOCR missing",
        3 => "wrong block count",
        4 => "out of AR resources",
        5 => "AR UUID unknown",
        6 => "state conflict",
        9 => "PDev already owned",
        _ => return None,
    })
}

/// ErrorCode2 of an AR abort (ErrorCode1 0xFD, e.g. in an ERR-RTA PDU `CF 81 FD xx`).
const fn abort_reason(c2: u8) -> Option<&'static str> {
    Some(match c2 {
        0x01 => "alarm sequence number error",
        0x02 => "instance closed",
        0x03 => "out of memory",
        0x05 => "consumer data hold timer expired",
        0x06 => "CM initiator activity timeout",
        0x0b => "alarm indication with error",
        0x0c => "RPC client call failed",
        0x0d => "abort requested",
        0x0e => "re-run aborts the existing AR",
        0x0f => "release indication received",
        0x12 => "protocol violation",
        0x1b => "link down",
        0x1f => "station name changed by DCP",
        0x20 => "reset to factory by DCP",
        0x24 => "PDEV check failed",
        0x25 => "IP address changed by DCP",
        _ => return None,
    })
}

/// ErrorDecode 0x81 (PNIO): ErrorCode1 = faulty block or protocol machine, ErrorCode2 =
/// field index or reason.
fn describe_pnio(f: &mut core::fmt::Formatter<'_>, c1: u8, c2: u8) -> core::fmt::Result {
    if let Some((block, fields)) = connect_block(c1) {
        write!(f, "{block} field {c2}")?;
        let i = usize::from(c2);
        let name = match i.checked_sub(BLOCK_HEADER_FIELDS.len()) {
            None => BLOCK_HEADER_FIELDS.get(i),
            Some(j) => fields.get(j),
        };
        if let Some(name) = name {
            write!(f, " ({name})")?;
        }
        return Ok(());
    }
    match c1 {
        0x08 => write!(f, "faulty record, field {c2}"),
        0x3d => write!(f, "device CM state machine (CMDEV), code {c2:#04x}"),
        0x40 => match cmrpc_reason(c2) {
            Some(r) => write!(f, "CMRPC: {r}"),
            None => write!(f, "CMRPC code {c2:#04x}"),
        },
        0xfd => match abort_reason(c2) {
            Some(r) => write!(f, "AR abort: {r}"),
            None => write!(f, "AR abort, code {c2:#04x}"),
        },
        _ => write!(f, "ErrorCode1 {c1:#04x}, ErrorCode2 {c2:#04x}"),
    }
}
