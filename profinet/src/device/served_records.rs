// SPDX-License-Identifier: MIT OR Apache-2.0
//! Record data: the Write (single and WriteMultiple 0xE040) and Read services of the
//! device.
//!
//! The device serves these records itself:
//! - I&M0 (0xAFF0) from its description, I&M1–I&M4 (0xAFF1–0xAFF4) as written (see
//!   [`super::im`]), I&M0FilterData (0xF840);
//! - the diagnosis records of every level (0x800A–0x8013, 0xC00A–0xC013, 0xE00A–0xE013,
//!   0xF00A–0xF013, 0xF80C) from the diagnosis store;
//! - the identification records: expected 0x8000/0xC000/0xE000 (the AR's), real
//!   0x8001/0xC001/0xE001/0xF000 (what is plugged), and the AR's ModuleDiffBlock 0xE002.
//!
//! Writes are accepted for user indices (0x0000–0x7FFF) of any plugged submodule, for the
//! PDev records (0x8000–0x80FF) of the interface and port submodules (subslots 0x8000 and
//! up; an S7 writes PDInterfaceAdjust 0x8071 there) and for I&M1–I&M4; the user and PDev
//! data is kept for the AR and read back as written. PDInterfaceAdjust also sets where the
//! device's LLDP frames carry its name ([`crate::port::lldp::NameOfDeviceMode`]). The records the
//! device serves are read-only; the rest is refused with a PNIORW status: invalid index,
//! invalid slot/subslot, access denied, state conflict (the AR's records without an AR).

use super::PluggedSubmodule;
use super::ar::{ArSubmodule, WrittenRecords};
use super::connect::{CMRPC, CMRPC_AR_UUID_UNKNOWN, CMRPC_ARGS_LENGTH, CMRPC_UNKNOWN_BLOCKS};
use super::diagnosis::records::{DiagnosisScope, diagnosis_index};
use super::diagnosis::{DiagnosisStore, SubslotAddr};
use super::identification::{expected_data, module_diff, real_data};
use super::im::{ImRecords, filter_data};
use super::log_book::LogBook;
use super::params::ParameterRecords;
use super::physical::{self, PhysicalView};
use crate::port::lldp::INDEX_PD_INTERFACE_ADJUST;
use crate::wire::record::pe::INDEX_PE_SERVICE;
use crate::wire::record::{
    ApiData, ArData, ArDataEntry, INDEX_API_DATA, INDEX_AR_DATA, INDEX_LOG_BOOK_DATA,
    INDEX_PD_EXPECTED_DATA, INDEX_PD_INTERFACE_DATA_REAL, INDEX_PD_PORT_DATA_ADJUST,
    INDEX_PD_PORT_DATA_CHECK, INDEX_PD_PORT_DATA_REAL, INDEX_PD_PORT_STATISTIC, INDEX_PD_REAL_DATA,
    MultipleBlockHeader, PdPortDataAdjust, PdPortDataCheck,
};
use crate::wire::record::{
    ERROR_CODE_READ, ERROR_CODE_WRITE, INDEX_IM0, INDEX_IM0_FILTER_DATA, INDEX_IM4,
    INDEX_MODULE_DIFF, Im0, IodHeader, IodKind, RecordError, RecordErrorCode, split_write_multiple,
};
use crate::wire::{EmitResult, PnioStatus, Uuid};

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
    pub(super) records: &'a mut WrittenRecords,
}

/// What of the device a write may change besides the AR's records.
pub(super) struct DeviceWrite<'a> {
    /// What is plugged.
    pub(super) real: &'a [PluggedSubmodule],
    /// I&M1–I&M4.
    pub(super) im: &'a mut ImRecords,
    /// Writes of I&M1–I&M4 taken.
    pub(super) im_writes: &'a mut u64,
    /// Which user records are accepted, and which the application answers.
    pub(super) params: &'a ParameterRecords,
}

/// What became of a Write or Read request: answered at once, or waiting for the application
/// (some of its records are the application's, see [`super::delegated_records`]).
pub(super) enum Outcome {
    /// The RPC-level status and the response blocks.
    Done(PnioStatus, Vec<u8>),
    /// The request waits for the application's answers.
    Pending(Pending),
}

/// A Write or Read whose records the application answers, as far as the device got.
pub(super) enum Pending {
    /// A Write (single: one part, `outer` is its header) or WriteMultiple.
    Write {
        /// The request's header.
        outer: IodHeader,
        /// Each write: its header, and its status or the data the application is to take.
        parts: Vec<(IodHeader, Result<PnioStatus, Vec<u8>>)>,
    },
    /// A Read (or ReadImplicit) of one of the application's records.
    Read {
        /// The request's header.
        header: IodHeader,
        /// The AR it reads in: the one it names (Read), or targets (ReadImplicit).
        ar_uuid: Uuid,
    },
}

/// The response to a Write (`outer`) whose writes ended with `parts`' statuses: the
/// RPC-level status (the first failure, or OK) and the blocks.
pub(super) fn write_response(
    outer: &IodHeader,
    parts: &[(IodHeader, PnioStatus)],
) -> (PnioStatus, Vec<u8>) {
    let respond = |h: &IodHeader, status: PnioStatus| IodHeader {
        status,
        // p-net answers every write with RecordDataLength 0; the S7 accepts it.
        ..h.response(0)
    };
    if !outer.is_write_multiple() {
        let s = parts.first().map_or(PnioStatus::OK, |(_, s)| *s);
        return (s, respond(outer, s).to_bytes().to_vec());
    }
    // The call fails with the first failing write; each write reports its own status.
    let overall = parts
        .iter()
        .map(|(_, s)| *s)
        .find(|s| !s.is_ok())
        .unwrap_or(PnioStatus::OK);
    let mut out = respond(outer, overall).to_bytes().to_vec();
    for (h, s) in parts {
        out.extend_from_slice(&respond(h, *s).to_bytes());
    }
    (overall, out)
}

/// The response to a Read (`h`) of `data`, or its failure.
pub(super) fn read_response(
    h: &IodHeader,
    result: Result<Vec<u8>, PnioStatus>,
) -> (PnioStatus, Vec<u8>) {
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

/// Handles a Write request's blocks: answered at once, or waiting for the application.
pub(super) fn write(ar: Option<ArRecords<'_>>, dev: DeviceWrite<'_>, blocks: &[u8]) -> Outcome {
    let Ok((outer, data, rest)) = IodHeader::split(blocks) else {
        return Outcome::Done(pnio(ERROR_CODE_WRITE, CMRPC, CMRPC_ARGS_LENGTH), Vec::new());
    };
    if outer.kind != IodKind::WriteReq {
        return Outcome::Done(
            pnio(ERROR_CODE_WRITE, CMRPC, CMRPC_UNKNOWN_BLOCKS),
            Vec::new(),
        );
    }
    let done = |s: PnioStatus| {
        let (s, b) = write_response(&outer, &[(outer, s)]);
        Outcome::Done(s, b)
    };
    let Some(ar) = ar.filter(|a| a.ar_uuid == outer.ar_uuid) else {
        return done(pnio(ERROR_CODE_WRITE, CMRPC, CMRPC_AR_UUID_UNKNOWN));
    };
    if !rest.is_empty() {
        return done(pnio(ERROR_CODE_WRITE, CMRPC, CMRPC_ARGS_LENGTH));
    }
    let mut dev = dev;
    let writes = if outer.is_write_multiple() {
        let Ok(writes) = split_write_multiple(data) else {
            return done(RecordError::write(RecordErrorCode::InvalidParameter, 0).status());
        };
        writes
    } else {
        vec![(outer, data)]
    };
    let parts: Vec<(IodHeader, Result<PnioStatus, Vec<u8>>)> = writes
        .iter()
        .map(|(h, d)| {
            let r = if h.ar_uuid != ar.ar_uuid {
                Ok(RecordError::write(RecordErrorCode::StateConflict, 0).status())
            } else if dev.params.delegated(h.api, h.slot, h.subslot, h.index)
                && plugged(dev.real, SubslotAddr::new(h.api, h.slot, h.subslot))
            {
                Err(d.to_vec())
            } else {
                Ok(write_one(ar.records, &mut dev, h, d))
            };
            (*h, r)
        })
        .collect();
    if parts.iter().any(|(_, r)| r.is_err()) {
        return Outcome::Pending(Pending::Write { outer, parts });
    }
    let parts: Vec<(IodHeader, PnioStatus)> = parts
        .into_iter()
        .map(|(h, r)| (h, r.unwrap_or(PnioStatus::OK)))
        .collect();
    let (s, b) = write_response(&outer, &parts);
    Outcome::Done(s, b)
}

/// Whether (API, slot, subslot) is plugged.
fn plugged(real: &[PluggedSubmodule], at: SubslotAddr) -> bool {
    real.iter().any(|r| r.addr() == at)
}

/// Whether `index` is one the device serves itself and so cannot be written: the
/// identification, ModuleDiff and diagnosis records.
fn served(index: u16) -> bool {
    matches!(
        index,
        0x8000 | 0x8001 | 0xc000 | 0xc001 | 0xe000..=0xe002 | 0xf000
    ) || matches!(
        index,
        INDEX_PD_PORT_DATA_REAL
            | INDEX_PD_PORT_STATISTIC
            | INDEX_PD_INTERFACE_DATA_REAL
            | INDEX_PD_REAL_DATA
            | INDEX_PD_EXPECTED_DATA
            | INDEX_AR_DATA
            | INDEX_API_DATA
            | INDEX_LOG_BOOK_DATA
    ) || diagnosis_index(index).is_some()
        || index == INDEX_IM0_FILTER_DATA
}

fn write_one(
    records: &mut WrittenRecords,
    dev: &mut DeviceWrite<'_>,
    h: &IodHeader,
    data: &[u8],
) -> PnioStatus {
    let fail = |code| RecordError::write(code, 0).status();
    if !plugged(dev.real, SubslotAddr::new(h.api, h.slot, h.subslot)) {
        return fail(RecordErrorCode::InvalidSlotSubslot);
    }
    if served(h.index) {
        return fail(RecordErrorCode::AccessDenied);
    }
    if (INDEX_IM0..=INDEX_IM4).contains(&h.index) {
        return match dev.im.write(h.index - INDEX_IM0, data) {
            Ok(()) => {
                *dev.im_writes = dev.im_writes.saturating_add(1);
                PnioStatus::OK
            }
            Err(e) => e.status(),
        };
    }
    if let Err(code) = dev
        .params
        .check_write(h.api, h.slot, h.subslot, h.index, data.len())
    {
        return fail(code);
    }
    if h.index == INDEX_PE_SERVICE {
        // The station's own PE entity: the answer waits as the record for the next read.
        records.insert(
            (h.api, h.slot, h.subslot, h.index),
            super::pe::answer_bytes(data),
        );
        return PnioStatus::OK;
    }
    let writable = match h.index {
        0x0000..=0x7fff => true,
        0x8000..=0x80ff => h.subslot >= 0x8000,
        _ => false,
    };
    if !writable {
        return fail(RecordErrorCode::InvalidIndex);
    }
    // The port's parameters the device acts on are taken only as blocks it can read: a
    // malformed one would be kept and never checked.
    let malformed = match h.index {
        INDEX_PD_PORT_DATA_CHECK => PdPortDataCheck::parse(data).is_err(),
        INDEX_PD_PORT_DATA_ADJUST => PdPortDataAdjust::parse(data).is_err(),
        _ => false,
    };
    if malformed {
        return fail(RecordErrorCode::InvalidParameter);
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

/// The AR a read may see: the one it names (Read) or targets (ReadImplicit).
pub(super) struct ArView<'a> {
    /// ARUUID.
    pub(super) ar_uuid: Uuid,
    /// What was written in it.
    pub(super) records: &'a WrittenRecords,
    /// Its expected submodules.
    pub(super) submodules: &'a [ArSubmodule],
    /// The submodules the application is not ready for.
    pub(super) app_ready_pending: &'a [SubslotAddr],
}

/// What of the device a read may see.
pub(super) struct DeviceRead<'a> {
    /// What is plugged.
    pub(super) real: &'a [PluggedSubmodule],
    /// I&M0.
    pub(super) im0: &'a Im0,
    /// I&M1–I&M4.
    pub(super) im: &'a ImRecords,
    /// The pending diagnosis.
    pub(super) diagnosis: &'a DiagnosisStore,
    /// Which user records are accepted, and which the application answers.
    pub(super) params: &'a ParameterRecords,
    /// The interface and port, for the physical device's records.
    pub(super) physical: PhysicalView<'a>,
    /// The ARs as ARData reports them: the IO AR, the device access AR.
    pub(super) ars: Vec<ArDataEntry>,
    /// The log book.
    pub(super) log: &'a LogBook,
    /// The device's clock now.
    pub(super) now_ns: u64,
}

/// Handles a Read request's blocks in the device access AR (`ar_uuid`, which the request
/// names): what a Read Implicit outside any AR may read.
pub(super) fn read_by_access(dev: &DeviceRead<'_>, blocks: &[u8]) -> Outcome {
    let Ok(h) = IodHeader::parse(blocks) else {
        return Outcome::Done(pnio(ERROR_CODE_READ, CMRPC, CMRPC_ARGS_LENGTH), Vec::new());
    };
    if h.kind != IodKind::ReadReq {
        return Outcome::Done(
            pnio(ERROR_CODE_READ, CMRPC, CMRPC_UNKNOWN_BLOCKS),
            Vec::new(),
        );
    }
    let (s, b) = read_response(&h, read_one(None, dev, &h));
    Outcome::Done(s, b)
}

/// Handles a Write request's blocks in the device access AR `ar_uuid`: I&M1 to I&M4 of the
/// plugged submodules, nothing else (the parameters are the IO AR's).
pub(super) fn write_by_access(
    ar_uuid: Uuid,
    dev: DeviceWrite<'_>,
    blocks: &[u8],
) -> (PnioStatus, Vec<u8>) {
    let Ok((outer, data, rest)) = IodHeader::split(blocks) else {
        return (pnio(ERROR_CODE_WRITE, CMRPC, CMRPC_ARGS_LENGTH), Vec::new());
    };
    if outer.kind != IodKind::WriteReq || !rest.is_empty() {
        return (
            pnio(ERROR_CODE_WRITE, CMRPC, CMRPC_UNKNOWN_BLOCKS),
            Vec::new(),
        );
    }
    let writes = if outer.is_write_multiple() {
        match split_write_multiple(data) {
            Ok(w) => w,
            Err(_) => {
                let s = RecordError::write(RecordErrorCode::InvalidParameter, 0).status();
                return write_response(&outer, &[(outer, s)]);
            }
        }
    } else {
        vec![(outer, data)]
    };
    let fail = |code| RecordError::write(code, 0).status();
    let parts: Vec<(IodHeader, PnioStatus)> = writes
        .iter()
        .map(|(h, d)| {
            let status = if h.ar_uuid != ar_uuid {
                fail(RecordErrorCode::StateConflict)
            } else if !plugged(dev.real, SubslotAddr::new(h.api, h.slot, h.subslot)) {
                fail(RecordErrorCode::InvalidSlotSubslot)
            } else if (INDEX_IM0 + 1..=INDEX_IM4).contains(&h.index) {
                match dev.im.write(h.index - INDEX_IM0, d) {
                    Ok(()) => {
                        *dev.im_writes = dev.im_writes.saturating_add(1);
                        PnioStatus::OK
                    }
                    Err(e) => e.status(),
                }
            } else {
                fail(RecordErrorCode::AccessDenied)
            };
            (*h, status)
        })
        .collect();
    write_response(&outer, &parts)
}

/// Handles a Read (or ReadImplicit) request's blocks: answered at once, or waiting for the
/// application. `ar` is the current AR; a Read (not implicit) must name it.
pub(super) fn read(
    implicit: bool,
    ar: Option<ArView<'_>>,
    dev: &DeviceRead<'_>,
    blocks: &[u8],
) -> Outcome {
    let Ok(h) = IodHeader::parse(blocks) else {
        return Outcome::Done(pnio(ERROR_CODE_READ, CMRPC, CMRPC_ARGS_LENGTH), Vec::new());
    };
    if h.kind != IodKind::ReadReq {
        return Outcome::Done(
            pnio(ERROR_CODE_READ, CMRPC, CMRPC_UNKNOWN_BLOCKS),
            Vec::new(),
        );
    }
    let ar = if implicit {
        // ReadImplicit runs outside any AR; the AR's records (written or its own) are read
        // through it when the TargetARUUID names it.
        Ok(ar.filter(|a| a.ar_uuid == h.target_ar_uuid))
    } else {
        ar.filter(|a| a.ar_uuid == h.ar_uuid).map(Some).ok_or(pnio(
            ERROR_CODE_READ,
            CMRPC,
            CMRPC_AR_UUID_UNKNOWN,
        ))
    };
    let application = dev.params.delegated(h.api, h.slot, h.subslot, h.index)
        && plugged(dev.real, SubslotAddr::new(h.api, h.slot, h.subslot));
    if application && ar.is_ok() {
        let ar_uuid = if implicit {
            h.target_ar_uuid
        } else {
            h.ar_uuid
        };
        return Outcome::Pending(Pending::Read { header: h, ar_uuid });
    }
    let result = ar.and_then(|a| read_one(a.as_ref(), dev, &h));
    let (s, b) = read_response(&h, result);
    Outcome::Done(s, b)
}

/// The expected submodules of `ar` that `keep` selects.
fn expected_of<'a>(
    ar: Option<&'a ArView<'_>>,
    keep: impl Fn(SubslotAddr) -> bool + 'a,
) -> impl Iterator<Item = &'a ArSubmodule> + 'a {
    ar.into_iter()
        .flat_map(|a| a.submodules.iter())
        .filter(move |s| keep(s.expected.addr()))
}

fn read_one(
    ar: Option<&ArView<'_>>,
    dev: &DeviceRead<'_>,
    h: &IodHeader,
) -> Result<Vec<u8>, PnioStatus> {
    let fail = |code| RecordError::read(code, 0).status();
    let at = SubslotAddr::new(h.api, h.slot, h.subslot);
    let in_ar = |pick: &dyn Fn(SubslotAddr) -> bool| expected_of(ar, pick).next().is_some();
    // The levels: the subslot and slot must exist (plugged or expected), the others not.
    let subslot_known = plugged(dev.real, at) || in_ar(&|a| a == at);
    let same_slot = |a: SubslotAddr| (a.api, a.slot) == (at.api, at.slot);
    let slot_known = dev.real.iter().any(|r| same_slot(r.addr())) || in_ar(&same_slot);
    let emitted = |r: crate::wire::EmitResult<Vec<u8>>| {
        r.map_err(|_| fail(RecordErrorCode::ReadConstrainConflict))
    };
    if let Some((scope, selection)) = diagnosis_index(h.index) {
        let mut real: Vec<SubslotAddr> = dev.real.iter().map(PluggedSubmodule::addr).collect();
        real.sort();
        let subslots: Vec<SubslotAddr> = match scope {
            DiagnosisScope::Subslot if !subslot_known => {
                return Err(fail(RecordErrorCode::InvalidSlotSubslot));
            }
            DiagnosisScope::Slot if !slot_known => {
                return Err(fail(RecordErrorCode::InvalidSlotSubslot));
            }
            DiagnosisScope::Subslot => vec![at],
            DiagnosisScope::Slot => real.into_iter().filter(|a| same_slot(*a)).collect(),
            // Without an AR there are none of its submodules to report on.
            DiagnosisScope::Ar => expected_of(ar, |_| true)
                .filter(|s| s.proper)
                .map(|s| s.expected.addr())
                .collect(),
            DiagnosisScope::Api => real.into_iter().filter(|a| a.api == at.api).collect(),
            DiagnosisScope::Device => real,
        };
        return emitted(dev.diagnosis.record(selection, subslots));
    }
    let needs_ar = || ar.ok_or_else(|| fail(RecordErrorCode::StateConflict));
    match h.index {
        0x8000 | 0x8001 if !subslot_known => Err(fail(RecordErrorCode::InvalidSlotSubslot)),
        0xc000 | 0xc001 if !slot_known => Err(fail(RecordErrorCode::InvalidSlotSubslot)),
        0x8000 | 0xc000 | 0xe000 => {
            needs_ar()?;
            let pick = |a: SubslotAddr| match h.index {
                0x8000 => a == at,
                0xc000 => same_slot(a),
                _ => true,
            };
            let expected: Vec<_> = expected_of(ar, pick).map(|s| &s.expected).collect();
            // Nothing of it in the AR: nothing to report.
            if expected.is_empty() {
                return Ok(Vec::new());
            }
            emitted(expected_data(expected).to_vec())
        }
        0x8001 | 0xc001 | 0xe001 | 0xf000 => {
            let real: Vec<&PluggedSubmodule> = match h.index {
                0x8001 => dev.real.iter().filter(|r| r.addr() == at).collect(),
                0xc001 => dev.real.iter().filter(|r| same_slot(r.addr())).collect(),
                0xe001 => {
                    let a = needs_ar()?;
                    dev.real
                        .iter()
                        .filter(|r| a.submodules.iter().any(|s| s.expected.addr() == r.addr()))
                        .collect()
                }
                _ => dev.real.iter().filter(|r| r.api == at.api).collect(),
            };
            if real.is_empty() {
                return Ok(Vec::new());
            }
            emitted(real_data(real).to_vec())
        }
        INDEX_MODULE_DIFF => {
            let a = needs_ar()?;
            let expected: Vec<_> = a.submodules.iter().map(|s| s.expected).collect();
            match module_diff(&expected, dev.real, dev.diagnosis, a.app_ready_pending) {
                Some(d) => emitted(d.to_vec()),
                None => Ok(Vec::new()),
            }
        }
        INDEX_IM0_FILTER_DATA => emitted(filter_data(dev.real).to_vec()),
        // The device's own records, whatever address the request names.
        INDEX_PD_REAL_DATA => emitted(
            dev.physical
                .real_data(dev.real.iter().map(|r| (r.api, r.slot, r.subslot))),
        ),
        INDEX_PD_EXPECTED_DATA => emitted(expected_pd_data(ar, dev.real)),
        INDEX_AR_DATA => emitted(
            ArData {
                ars: dev.ars.clone(),
            }
            .to_vec(),
        ),
        INDEX_API_DATA => {
            let mut apis: Vec<u32> = dev.real.iter().map(|r| r.api).collect();
            apis.sort_unstable();
            apis.dedup();
            emitted(ApiData { apis }.to_vec())
        }
        INDEX_LOG_BOOK_DATA => emitted(dev.log.record(dev.now_ns).to_vec()),
        // The interface's data, at the interface submodule or its slot's subslot 0.
        INDEX_PD_INTERFACE_DATA_REAL => {
            let interface = dev.real.iter().any(|r| {
                (r.api, r.slot) == (at.api, at.slot)
                    && physical::is_interface(r.subslot)
                    && (r.subslot == at.subslot || at.subslot == 0)
            });
            if !interface {
                return Err(fail(RecordErrorCode::InvalidSlotSubslot));
            }
            emitted(dev.physical.interface_data_real().to_vec())
        }
        INDEX_PD_PORT_DATA_REAL if plugged(dev.real, at) && physical::is_port(at.subslot) => {
            emitted(dev.physical.port_data_real(at.slot, at.subslot).to_vec())
        }
        INDEX_PD_PORT_STATISTIC
            if plugged(dev.real, at)
                && (physical::is_port(at.subslot) || physical::is_interface(at.subslot)) =>
        {
            emitted(dev.physical.statistic().to_vec())
        }
        INDEX_PD_PORT_DATA_REAL | INDEX_PD_PORT_STATISTIC => {
            Err(fail(RecordErrorCode::InvalidSlotSubslot))
        }
        _ if !plugged(dev.real, at) => Err(fail(RecordErrorCode::InvalidSlotSubslot)),
        // No PE request before: nothing to answer.
        INDEX_PE_SERVICE => ar
            .and_then(|a| a.records.get(&(h.api, h.slot, h.subslot, h.index)))
            .cloned()
            .ok_or_else(|| fail(RecordErrorCode::StateConflict)),
        INDEX_IM0..=INDEX_IM4 => dev
            .im
            .read(dev.im0, h.index - INDEX_IM0)
            .ok_or_else(|| fail(RecordErrorCode::InvalidIndex)),
        _ => ar
            .and_then(|a| a.records.get(&(h.api, h.slot, h.subslot, h.index)))
            .cloned()
            .or_else(|| dev.params.initial(h.api, h.slot, h.subslot, h.index))
            .ok_or_else(|| fail(RecordErrorCode::InvalidIndex)),
    }
}

/// PDExpectedData: for each interface and port of `real`, a MultipleBlockHeader with what
/// the AR wrote of its PD parameters (PDInterfaceAdjust; PDPortDataCheck, PDPortDataAdjust),
/// none for a submodule it wrote none of; empty without an AR.
fn expected_pd_data(ar: Option<&ArView<'_>>, real: &[PluggedSubmodule]) -> EmitResult<Vec<u8>> {
    let mut out = Vec::new();
    let Some(ar) = ar else {
        return Ok(out);
    };
    for r in real
        .iter()
        .filter(|r| physical::is_interface(r.subslot) || physical::is_port(r.subslot))
    {
        let blocks: Vec<u8> = [
            INDEX_PD_INTERFACE_ADJUST,
            INDEX_PD_PORT_DATA_CHECK,
            INDEX_PD_PORT_DATA_ADJUST,
        ]
        .iter()
        .filter_map(|i| ar.records.get(&(r.api, r.slot, r.subslot, *i)))
        // A record that is not whole 4-byte blocks cannot stand in a MultipleBlockHeader.
        .filter(|b| b.len().is_multiple_of(4))
        .flatten()
        .copied()
        .collect();
        if blocks.is_empty() {
            continue;
        }
        out.extend(
            MultipleBlockHeader {
                api: r.api,
                slot: r.slot,
                subslot: r.subslot,
                blocks,
            }
            .to_vec()?,
        );
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn served_indices_are_read_only() {
        for i in [
            0x800a, 0x800c, 0x8010, 0xc00b, 0xe00a, 0xf00c, 0xf80c, 0x8000, 0x8001, 0xe002, 0xf000,
            0xf840, 0xf841, 0xf842, 0xf820, 0xf821, 0xf830, 0x8080, 0x802a, 0x8072,
        ] {
            assert!(served(i), "{i:#06x}");
        }
        for i in [0x8071, 0xaff0, 0xaff1, 0x000a, 0x802b, 0x802f] {
            assert!(!served(i), "{i:#06x}");
        }
    }
}
