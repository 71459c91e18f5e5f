// SPDX-License-Identifier: MIT OR Apache-2.0
//! What is expected and what is plugged, as the identification records (0x8000/0x8001,
//! 0xC000/0xC001, 0xE000/0xE001, 0xF000) and the ModuleDiffBlock (Connect response,
//! ApplicationReady, record 0xE002) give it.
//!
//! The identification blocks are written in BlockVersion 1.1 (with the API level), as
//! current devices do; the expected configuration is the AR's, in the Connect's order, the
//! real one sorted by API, slot and subslot.

use super::connect::{self, Expected};
use super::diagnosis::{DiagnosisStore, SubslotAddr};
use super::{Application, Device, PluggedSubmodule};
use crate::wire::connect::ModuleDiffBlock;
use crate::wire::record::{IdentApi, IdentificationData, IdentificationKind, RecordVersion};

/// SubmoduleState ARInfo (bits 7–10) 1: the application is not ready for the submodule.
const ARINFO_APPLICATION_READY_PENDING: u16 = 1 << 7;

/// ExpectedIdentificationData of `expected`.
pub(super) fn expected_data<'a>(
    expected: impl IntoIterator<Item = &'a Expected>,
) -> IdentificationData {
    IdentificationData {
        kind: IdentificationKind::Expected,
        version: RecordVersion::V1_1,
        apis: IdentApi::group(
            expected
                .into_iter()
                .map(|e| (e.api, e.slot, e.module_ident, e.subslot, e.submodule_ident)),
        ),
    }
}

/// RealIdentificationData of `real`, sorted by API, slot and subslot.
pub(super) fn real_data<'a>(
    real: impl IntoIterator<Item = &'a PluggedSubmodule>,
) -> IdentificationData {
    let mut real: Vec<&PluggedSubmodule> = real.into_iter().collect();
    real.sort_by_key(|r| r.addr());
    IdentificationData {
        kind: IdentificationKind::Real,
        version: RecordVersion::V1_1,
        apis: IdentApi::group(
            real.iter()
                .map(|r| (r.api, r.slot, r.module_ident, r.subslot, r.submodule_ident)),
        ),
    }
}

/// The ModuleDiffBlock of `expected` against `real` with the diagnosis as it is now and the
/// submodules the application is not ready for (`pending`: ARInfo "application ready
/// pending"); `None` when everything is as expected, free of diagnosis and ready.
pub(super) fn module_diff(
    expected: &[Expected],
    real: &[PluggedSubmodule],
    diagnosis: &DiagnosisStore,
    pending: &[SubslotAddr],
) -> Option<ModuleDiffBlock> {
    let state = |api, slot, subslot| {
        let at = SubslotAddr::new(api, slot, subslot);
        let ar_info = if pending.contains(&at) {
            ARINFO_APPLICATION_READY_PENDING
        } else {
            0
        };
        diagnosis.submodule_state(at) | ar_info
    };
    connect::module_diff(expected, real, state).1
}

impl<A: Application> Device<A> {
    /// The ModuleDiffBlock of the current AR as things are now.
    pub(super) fn ar_module_diff(&self) -> Option<ModuleDiffBlock> {
        let ar = self.ar.current.as_ref()?;
        module_diff(
            &ar.expected(),
            self.plugging.plugged(),
            &self.diagnosis,
            &ar.app_ready_pending,
        )
    }
}
