// SPDX-License-Identifier: MIT OR Apache-2.0
//! Which user records (indices 0x0000–0x7FFF) the device takes: its configured parameter
//! records, with their lengths and initial data, or any; and which it hands to its
//! application instead (see [`super::delegated_records`]).

use super::diagnosis::SubslotAddr;
use super::{Application, Device};
use crate::wire::record::pe::INDEX_PE_SERVICE;
use crate::wire::record::{INDEX_IM0, INDEX_IM4, RecordErrorCode};
use std::collections::{BTreeMap, BTreeSet};

/// A user record the device accepts itself.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ParameterRecord {
    /// Where.
    pub at: SubslotAddr,
    /// Record index (0x0000–0x7FFF).
    pub index: u16,
    /// Its length: a write of another length is refused (write length error).
    pub length: u16,
    /// What a read returns before the controller wrote it.
    pub initial: Vec<u8>,
}

/// Accepted user records by (where, index): their length and initial data.
type Accepted = BTreeMap<(SubslotAddr, u16), (u16, Vec<u8>)>;

/// Which user records the device accepts, and which go to the application.
#[derive(Clone, Debug, Default)]
pub(super) struct ParameterRecords {
    /// `None`: every user record of a plugged submodule is accepted and kept.
    accepted: Option<Accepted>,
    /// Submodules whose user records the application answers.
    delegated: BTreeSet<SubslotAddr>,
    /// Submodules whose I&M0–I&M4 (0xAFF0–0xAFF4) the application answers.
    delegated_im: BTreeSet<SubslotAddr>,
    /// Submodules whose PROFIenergy record (0x80A0) the application answers.
    delegated_pe: BTreeSet<SubslotAddr>,
}

impl ParameterRecords {
    /// Whether the application answers record `index` of (`api`, `slot`, `subslot`).
    pub(super) fn delegated(&self, api: u32, slot: u16, subslot: u16, index: u16) -> bool {
        let at = SubslotAddr::new(api, slot, subslot);
        match index {
            0x0000..=0x7fff => self.delegated.contains(&at),
            INDEX_IM0..=INDEX_IM4 => self.delegated_im.contains(&at),
            INDEX_PE_SERVICE => self.delegated_pe.contains(&at),
            _ => false,
        }
    }

    /// Whether the device takes a write of `len` bytes to user record `index` (other
    /// indices pass).
    pub(super) fn check_write(
        &self,
        api: u32,
        slot: u16,
        subslot: u16,
        index: u16,
        len: usize,
    ) -> Result<(), RecordErrorCode> {
        let Some(accepted) = self.accepted.as_ref().filter(|_| index <= 0x7fff) else {
            return Ok(());
        };
        match accepted.get(&(SubslotAddr::new(api, slot, subslot), index)) {
            None => Err(RecordErrorCode::InvalidIndex),
            Some((length, _)) if usize::from(*length) != len => {
                Err(RecordErrorCode::WriteLengthError)
            }
            Some(_) => Ok(()),
        }
    }

    /// What a read of user record `index` returns before it is written.
    pub(super) fn initial(&self, api: u32, slot: u16, subslot: u16, index: u16) -> Option<Vec<u8>> {
        let (length, initial) = self
            .accepted
            .as_ref()?
            .get(&(SubslotAddr::new(api, slot, subslot), index))?;
        let mut data = initial.clone();
        data.resize(usize::from(*length), 0);
        Some(data)
    }
}

impl<A: Application> Device<A> {
    /// Accept only `records` as user records (indices 0x0000–0x7FFF) of the submodules
    /// they name, with their lengths; a read of one not yet written gives its initial data.
    /// Without this call every user record of a plugged submodule is accepted and kept.
    pub fn set_parameter_records(&mut self, records: &[ParameterRecord]) {
        self.records.params.accepted = Some(
            records
                .iter()
                .map(|r| ((r.at, r.index), (r.length, r.initial.clone())))
                .collect(),
        );
    }

    /// Hands the user records (0x0000–0x7FFF) of submodule `at` to the application
    /// (`true`) as [`DeviceAction::Record`](super::DeviceAction::Record) jobs, or has the device answer them again.
    pub fn delegate_records(&mut self, at: SubslotAddr, to_application: bool) {
        if to_application {
            self.records.params.delegated.insert(at);
        } else {
            self.records.params.delegated.remove(&at);
        }
    }

    /// Hands the PROFIenergy record (0x80A0) of submodule `at` to the application (`true`),
    /// as IO-Base's device interface does with `PNIO_CEP_PE_MODE_ENABLE`, or has the device
    /// give the standard's answer again ([`super::pe`]).
    pub fn delegate_pe_records(&mut self, at: SubslotAddr, to_application: bool) {
        if to_application {
            self.records.params.delegated_pe.insert(at);
        } else {
            self.records.params.delegated_pe.remove(&at);
        }
    }

    /// Hands the I&M records (I&M0–I&M4, 0xAFF0–0xAFF4) of submodule `at` to the
    /// application (`true`), as IO-Base's device interface does for a submodule it plugged
    /// as an I&M carrier, or has the device answer them again. I&M0FilterData (0xF840)
    /// stays the device's.
    pub fn delegate_im_records(&mut self, at: SubslotAddr, to_application: bool) {
        if to_application {
            self.records.params.delegated_im.insert(at);
        } else {
            self.records.params.delegated_im.remove(&at);
        }
    }
}
