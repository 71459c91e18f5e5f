// SPDX-License-Identifier: MIT OR Apache-2.0
//! The controller's end of an AR's cyclic exchange ([`crate::cyclic`]): built from the
//! device's plan when the Connect response arrives. The controller consumes the input CR
//! and produces the output CR.

use super::plan::DevicePlan;
pub use crate::cyclic::{CrMap, CyclicAr, DataMap, IocsMap};
use crate::iocr_layout::CrLayout;
use crate::wire::MacAddress;

/// The map of one CR of a planned device, in the controller's submodule table.
fn cr_map(frame_id: u16, layout: &CrLayout, first_submodule: usize) -> CrMap {
    CrMap {
        frame_id,
        data_length: layout.data_length as usize,
        objects: layout
            .objects
            .iter()
            .map(|o| DataMap {
                submodule: first_submodule + o.submodule,
                data: o.data_offset as usize,
                len: o.length as usize,
                iops: o.iops_offset as usize,
            })
            .collect(),
        iocs: layout
            .iocs
            .iter()
            .map(|c| IocsMap {
                submodule: first_submodule + c.submodule,
                offset: c.offset as usize,
            })
            .collect(),
    }
}

impl CyclicAr {
    /// The exchange of `plan`'s device at `peer`, with the FrameIDs the Connect settled.
    pub fn new(
        plan: &DevicePlan,
        epoch: u32,
        own: MacAddress,
        peer: MacAddress,
        frame_ids: (u16, u16),
    ) -> CyclicAr {
        CyclicAr::from_maps(
            plan.device,
            epoch,
            (own, peer),
            cr_map(frame_ids.0, &plan.layout.input, plan.first_submodule),
            cr_map(frame_ids.1, &plan.layout.output, plan.first_submodule),
            plan.timing,
            plan.first_submodule..plan.first_submodule + plan.submodules.len(),
        )
    }
}
