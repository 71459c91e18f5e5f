// SPDX-License-Identifier: MIT OR Apache-2.0
//! Record data: the Write (single and WriteMultiple 0xE040) and Read services of the
//! device.
//!
//! Writes are accepted for user indices (0x0000–0x7FFF) of any plugged submodule, for the
//! PDev records (0x8000–0x80FF) of the interface and port submodules (subslots 0x8000 and
//! up; an S7 writes PDInterfaceAdjust 0x8071 there) and for I&M1–3; the data is kept for the
//! AR and read back as written. PDInterfaceAdjust also sets where the device's LLDP frames
//! carry its name ([`super::lldp::NameOfDeviceMode`]). Reads serve I&M0 (0xAFF0) from the device's description,
//! what was written, and the diagnosis indices (empty: the simulated device has none). The
//! rest is refused with a PNIORW status: invalid index, invalid slot/subslot, access denied.

use super::PluggedSubmodule;
use super::connect::{CMRPC, CMRPC_AR_UUID_UNKNOWN, CMRPC_ARGS_LENGTH, CMRPC_UNKNOWN_BLOCKS};
use crate::wire::record::Im0;
use crate::wire::record::{
    ERROR_CODE_READ, ERROR_CODE_WRITE, INDEX_IM0, IodHeader, IodKind, RecordError, RecordErrorCode,
    split_write_multiple,
};
use crate::wire::{PnioStatus, Uuid};
use std::collections::HashMap;

/// (API, slot, subslot, index) of a record.
pub(super) type RecordKey = (u32, u16, u16, u16);

/// The records written during an AR.
pub(super) type Records = HashMap<RecordKey, Vec<u8>>;

/// Bytes of record data kept per AR: a bound against a controller that writes without end.
const MAX_STORED: usize = 64 * 1024;

/// A PNIO-decoded status (`Dx 81 c1 c2`) of a record service.
const fn pnio(error_code: u8, c1: u8, c2: u8) -> PnioStatus {
    PnioStatus {
        error_code,
        error_decode: 0x81,
        error_code1: c1,
        error_code2: c2,
    }
}

/// The AR a record service runs in: its ARUUID and its records.
pub(super) struct ArRecords<'a> {
    /// ARUUID.
    pub(super) ar_uuid: Uuid,
    /// What was written.
    pub(super) records: &'a mut Records,
}

/// Handles a Write request's blocks: the RPC-level status and the response blocks.
pub(super) fn write(
    ar: Option<ArRecords<'_>>,
    real: &[PluggedSubmodule],
    blocks: &[u8],
) -> (PnioStatus, Vec<u8>) {
    let Ok((outer, data, rest)) = IodHeader::split(blocks) else {
        return (pnio(ERROR_CODE_WRITE, CMRPC, CMRPC_ARGS_LENGTH), Vec::new());
    };
    if outer.kind != IodKind::WriteReq {
        return (
            pnio(ERROR_CODE_WRITE, CMRPC, CMRPC_UNKNOWN_BLOCKS),
            Vec::new(),
        );
    }
    let respond = |h: &IodHeader, status: PnioStatus| IodHeader {
        status,
        // p-net answers every write with RecordDataLength 0; the S7 accepts it.
        ..h.response(0)
    };
    let Some(ar) = ar.filter(|a| a.ar_uuid == outer.ar_uuid) else {
        let s = pnio(ERROR_CODE_WRITE, CMRPC, CMRPC_AR_UUID_UNKNOWN);
        return (s, respond(&outer, s).to_bytes().to_vec());
    };
    if !rest.is_empty() {
        let s = pnio(ERROR_CODE_WRITE, CMRPC, CMRPC_ARGS_LENGTH);
        return (s, respond(&outer, s).to_bytes().to_vec());
    }
    if !outer.is_write_multiple() {
        let s = write_one(ar.records, real, &outer, data);
        return (s, respond(&outer, s).to_bytes().to_vec());
    }
    let Ok(writes) = split_write_multiple(data) else {
        let s = RecordError::write(RecordErrorCode::InvalidParameter, 0).status();
        return (s, respond(&outer, s).to_bytes().to_vec());
    };
    let statuses: Vec<PnioStatus> = writes
        .iter()
        .map(|(h, d)| {
            if h.ar_uuid != ar.ar_uuid {
                RecordError::write(RecordErrorCode::StateConflict, 0).status()
            } else {
                write_one(ar.records, real, h, d)
            }
        })
        .collect();
    // The call fails with the first failing write; each write reports its own status.
    let overall = statuses
        .iter()
        .copied()
        .find(|s| !s.is_ok())
        .unwrap_or(PnioStatus::OK);
    let mut out = respond(&outer, overall).to_bytes().to_vec();
    for ((h, _), s) in writes.iter().zip(statuses) {
        out.extend_from_slice(&respond(h, s).to_bytes());
    }
    (overall, out)
}

/// Whether (API, slot, subslot) is plugged.
fn plugged(real: &[PluggedSubmodule], api: u32, slot: u16, subslot: u16) -> bool {
    real.iter()
        .any(|r| (r.api, r.slot, r.subslot) == (api, slot, subslot))
}

fn write_one(
    records: &mut Records,
    real: &[PluggedSubmodule],
    h: &IodHeader,
    data: &[u8],
) -> PnioStatus {
    let fail = |code| RecordError::write(code, 0).status();
    if !plugged(real, h.api, h.slot, h.subslot) {
        return fail(RecordErrorCode::InvalidSlotSubslot);
    }
    let writable = match h.index {
        0x0000..=0x7fff => true,
        0x8000..=0x80ff => h.subslot >= 0x8000,
        0xaff1..=0xaff3 => true,
        INDEX_IM0 => return fail(RecordErrorCode::AccessDenied),
        _ => false,
    };
    if !writable {
        return fail(RecordErrorCode::InvalidIndex);
    }
    let key = (h.api, h.slot, h.subslot, h.index);
    let stored: usize = records
        .iter()
        .filter(|(k, _)| **k != key)
        .map(|(_, v)| v.len())
        .sum();
    if stored.saturating_add(data.len()) > MAX_STORED {
        return fail(RecordErrorCode::ResourceUnavailable);
    }
    records.insert(key, data.to_vec());
    PnioStatus::OK
}

/// Whether `index` is one of the diagnosis records (channel, all, DMQS, maintenance) at
/// subslot, slot, AR, API or device level: the device has no diagnosis, so they read empty.
fn is_diagnosis(index: u16) -> bool {
    let low = index & 0x0fff;
    let level_ok = matches!(index >> 12, 0x8 | 0xc | 0xe | 0xf);
    (level_ok && matches!(low, 0x00a..=0x00c | 0x010..=0x013)) || index == 0xf80c
}

/// Handles a Read (or ReadImplicit) request's blocks: the RPC-level status and the response
/// blocks. `ar` is the current AR; a Read (not implicit) must name it.
pub(super) fn read(
    implicit: bool,
    ar: Option<(Uuid, &Records)>,
    real: &[PluggedSubmodule],
    im0: &Im0,
    blocks: &[u8],
) -> (PnioStatus, Vec<u8>) {
    let Ok(h) = IodHeader::parse(blocks) else {
        return (pnio(ERROR_CODE_READ, CMRPC, CMRPC_ARGS_LENGTH), Vec::new());
    };
    if h.kind != IodKind::ReadReq {
        return (
            pnio(ERROR_CODE_READ, CMRPC, CMRPC_UNKNOWN_BLOCKS),
            Vec::new(),
        );
    }
    let result = if implicit {
        // ReadImplicit runs outside any AR; records written in an AR are read through it
        // when the TargetARUUID names it.
        let records = ar.filter(|(u, _)| *u == h.target_ar_uuid).map(|(_, r)| r);
        read_one(records, real, im0, &h)
    } else {
        match ar.filter(|(u, _)| *u == h.ar_uuid) {
            Some((_, records)) => read_one(Some(records), real, im0, &h),
            None => Err(pnio(ERROR_CODE_READ, CMRPC, CMRPC_AR_UUID_UNKNOWN)),
        }
    };
    let (status, data) = match result {
        Ok(mut d) => {
            d.truncate(usize::try_from(h.record_data_length).unwrap_or(usize::MAX));
            (PnioStatus::OK, d)
        }
        Err(s) => (s, Vec::new()),
    };
    let Ok(len) = u32::try_from(data.len()) else {
        return (pnio(ERROR_CODE_READ, CMRPC, CMRPC_ARGS_LENGTH), Vec::new());
    };
    let mut out = h.response(len).to_bytes().to_vec();
    out.extend_from_slice(&data);
    (status, out)
}

fn read_one(
    records: Option<&Records>,
    real: &[PluggedSubmodule],
    im0: &Im0,
    h: &IodHeader,
) -> Result<Vec<u8>, PnioStatus> {
    let fail = |code| RecordError::read(code, 0).status();
    if !plugged(real, h.api, h.slot, h.subslot) {
        return Err(fail(RecordErrorCode::InvalidSlotSubslot));
    }
    if h.index == INDEX_IM0 {
        return Ok(im0.to_bytes().to_vec());
    }
    if let Some(d) = records.and_then(|r| r.get(&(h.api, h.slot, h.subslot, h.index))) {
        return Ok(d.clone());
    }
    if is_diagnosis(h.index) {
        return Ok(Vec::new());
    }
    Err(fail(RecordErrorCode::InvalidIndex))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn diagnosis_indices() {
        for i in [0x800a, 0x800c, 0x8010, 0xc00b, 0xe00a, 0xf00c, 0xf80c] {
            assert!(is_diagnosis(i), "{i:#06x}");
        }
        for i in [0x8000, 0x8071, 0xaff0, 0x000a, 0xf841] {
            assert!(!is_diagnosis(i), "{i:#06x}");
        }
    }
}
