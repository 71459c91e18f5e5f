// SPDX-License-Identifier: MIT OR Apache-2.0
//! The device's identification and maintenance data: I&M0 from its description, I&M1–I&M4
//! as controllers and engineering tools write them, and I&M0FilterData (record 0xF840).
//!
//! The device has one set of I&M data, as it has one I&M0: every plugged submodule answers
//! the I&M records with it, and I&M0FilterData names the submodule that carries it (the
//! first plugged one, in API, slot and subslot order: the access point) as the one with I&M
//! data of its own, standing for its module and for the device. I&M1–I&M4 live in the
//! engine, not in an AR: they outlast ARs, and a runtime keeps them across restarts through
//! [`Station::im_records`](super::Station::im_records) and [`Station::set_im_records`](super::Station::set_im_records) (the engine itself has no storage).

use super::PluggedSubmodule;
use super::diagnosis::SubslotAddr;
use crate::wire::record::{
    IdentApi, Im0, Im0FilterData, Im1, Im2, Im3, Im4, RecordError, RecordErrorCode,
};

/// I&M1–I&M4 of the device.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct ImRecords {
    /// I&M1: function and location tags (index 0xAFF1).
    pub im1: Im1,
    /// I&M2: installation date (index 0xAFF2).
    pub im2: Im2,
    /// I&M3: descriptor (index 0xAFF3).
    pub im3: Im3,
    /// I&M4: signature (index 0xAFF4).
    pub im4: Im4,
}

impl ImRecords {
    /// The block of I&M`n` (0 to 4) as record data; `None` for other `n`.
    pub(super) fn read(&self, im0: &Im0, n: u16) -> Option<Vec<u8>> {
        Some(match n {
            0 => im0.to_bytes().to_vec(),
            1 => self.im1.to_bytes().to_vec(),
            2 => self.im2.to_bytes().to_vec(),
            3 => self.im3.to_bytes().to_vec(),
            4 => self.im4.to_bytes().to_vec(),
            _ => return None,
        })
    }

    /// Takes a write of I&M`n` (1 to 4): the whole block, nothing more. I&M0 is read-only;
    /// data of another length is a write length error, a block of another type an invalid
    /// parameter.
    pub(super) fn write(&mut self, n: u16, data: &[u8]) -> Result<(), RecordError> {
        let fail = |code| Err(RecordError::write(code, 0));
        let len = match n {
            1 => self.im1.buffer_len(),
            2 => self.im2.buffer_len(),
            3 => self.im3.buffer_len(),
            4 => self.im4.buffer_len(),
            0 => return fail(RecordErrorCode::AccessDenied),
            _ => return fail(RecordErrorCode::InvalidIndex),
        };
        if data.len() != len {
            return fail(RecordErrorCode::WriteLengthError);
        }
        let parsed = match n {
            1 => Im1::parse(data).map(|v| self.im1 = v),
            2 => Im2::parse(data).map(|v| self.im2 = v),
            3 => Im3::parse(data).map(|v| self.im3 = v),
            _ => Im4::parse(data).map(|v| self.im4 = v),
        };
        parsed.or(fail(RecordErrorCode::InvalidParameter))
    }
}

/// The submodule that carries the device's I&M data: the first plugged one in API, slot and
/// subslot order.
pub(super) fn im_owner(real: &[PluggedSubmodule]) -> Option<&PluggedSubmodule> {
    real.iter().min_by_key(|r| r.addr())
}

/// The I&M0FilterData record: the owner in all three lists (empty without submodules).
pub(super) fn filter_data(real: &[PluggedSubmodule]) -> Im0FilterData {
    let owner: Vec<IdentApi> = im_owner(real)
        .map(|r| IdentApi::group([(r.api, r.slot, r.module_ident, r.subslot, r.submodule_ident)]))
        .unwrap_or_default();
    Im0FilterData {
        submodules: owner.clone(),
        modules: owner.clone(),
        device: owner,
    }
}

impl PluggedSubmodule {
    /// Where it is.
    pub const fn addr(&self) -> SubslotAddr {
        SubslotAddr::new(self.api, self.slot, self.subslot)
    }
}
