// SPDX-License-Identifier: MIT OR Apache-2.0
//! An AR's cyclic exchange as the cycle thread runs it: where every submodule's data and
//! status sit in the two frames, which FrameIDs and MAC address belong to it, and how often
//! frames go and must come. Built on the acyclic side (which may allocate) when the Connect
//! response arrives and handed to the cycle thread whole.

use super::plan::{CrTiming, DevicePlan};
use crate::iocr_layout::CrLayout;
use crate::wire::MacAddress;
use crate::wire::ethernet::{self, ETHERTYPE_PROFINET, VlanTag};

/// One IO data object of a frame, mapped to the submodule table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DataMap {
    /// Index in the submodule table.
    pub submodule: usize,
    /// Offset of the data in the C_SDU.
    pub data: usize,
    /// Data bytes.
    pub len: usize,
    /// Offset of the IOPS in the C_SDU.
    pub iops: usize,
}

/// One consumer status of a frame, mapped to the submodule table.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct IocsMap {
    /// Index in the submodule table.
    pub submodule: usize,
    /// Offset of the IOCS in the C_SDU.
    pub offset: usize,
}

/// One direction of the exchange.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CrMap {
    /// FrameID.
    pub frame_id: u16,
    /// C_SDU bytes.
    pub data_length: usize,
    /// IO data objects.
    pub objects: Vec<DataMap>,
    /// Consumer statuses.
    pub iocs: Vec<IocsMap>,
}

impl CrMap {
    fn new(frame_id: u16, layout: &CrLayout, first_submodule: usize) -> CrMap {
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
}

/// An AR's cyclic exchange.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CyclicAr {
    /// Device index.
    pub device: usize,
    /// Which connect of the device this is: reports about an older one are ignored.
    pub epoch: u32,
    /// The device's MAC address (source of the input frames, destination of the outputs).
    pub peer: MacAddress,
    /// Input CR (device → controller).
    pub input: CrMap,
    /// Output CR (controller → device).
    pub output: CrMap,
    /// Timing of both CRs.
    pub timing: CrTiming,
    /// The submodule table range of the device.
    pub submodules: core::ops::Range<usize>,
    /// The output frame, header written once; the cycle fills its C_SDU and status.
    pub frame: Vec<u8>,
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
        let input = CrMap::new(frame_ids.0, &plan.layout.input, plan.first_submodule);
        let output = CrMap::new(frame_ids.1, &plan.layout.output, plan.first_submodule);
        let eth = ethernet::Repr {
            dst: peer,
            src: own,
            vlan: Some(VlanTag::RT),
            ethertype: ETHERTYPE_PROFINET,
        };
        // Header, FrameID, C_SDU, CycleCounter, DataStatus, TransferStatus.
        let mut pdu = output.frame_id.to_be_bytes().to_vec();
        pdu.resize(2 + output.data_length + 4, 0);
        let frame = eth.frame(&pdu, 0);
        CyclicAr {
            device: plan.device,
            epoch,
            peer,
            input,
            output,
            timing: plan.timing,
            submodules: plan.first_submodule..plan.first_submodule + plan.submodules.len(),
            frame,
        }
    }

    /// Offset of the FrameID in [`frame`](Self::frame).
    pub fn payload_offset(&self) -> usize {
        self.frame.len() - 2 - self.output.data_length - 4
    }
}
