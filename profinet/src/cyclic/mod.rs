// SPDX-License-Identifier: MIT OR Apache-2.0
//! An AR's cyclic exchange as a cycle thread runs it, for either end of the AR: where every
//! submodule's data and status sit in the frame consumed and the frame produced, which
//! FrameIDs and MAC address belong to it, and how often frames go and must come. Built on
//! the acyclic side (which may allocate) — by the controller when the Connect response
//! arrives, by the device when its parameterization ends — and handed to the cycle thread
//! whole.
//!
//! The submodule indexes are those of the caller's submodule table (procimgd's image): the
//! controller's devices one after another, or the device's own submodules.
//!
//! Both ends of every exchange run the same two halves: the [`Consumer`] judges each
//! received frame and keeps the watchdog, and the producer half
//! ([`CyclicAr::due`], [`CyclicAr::fill`], [`CyclicAr::seal`]) writes the frame of each
//! cycle it is due in.

pub mod consumer;
mod producer;
pub mod trial;

pub use consumer::{Consumer, FIRST_FRAME_GRACE_NS, Verdict, VerdictCounts, VerdictKind};
pub use producer::ProducedData;

use crate::wire::MacAddress;
use crate::wire::ethernet::{self, ETHERTYPE_PROFINET, VlanTag};
use crate::wire::rt::TIME_UNIT_NS;

/// The send clock and reduction ratio of an AR's CRs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CrTiming {
    /// SendClockFactor (× 31.25 µs).
    pub send_clock_factor: u16,
    /// ReductionRatio: one frame every this many send clocks.
    pub reduction_ratio: u16,
    /// Frames go out every this many cycles of the cycle thread.
    pub every_cycles: u32,
    /// DataHoldFactor = WatchdogFactor.
    pub data_hold_factor: u16,
}

impl CrTiming {
    /// The time between two frames of the CR, in ns.
    pub const fn period_ns(&self) -> u64 {
        self.send_clock_factor as u64 * self.reduction_ratio as u64 * TIME_UNIT_NS
    }

    /// How long the consumer waits for a frame before it gives up: DataHoldFactor periods.
    pub const fn watchdog_ns(&self) -> u64 {
        self.period_ns() * self.data_hold_factor as u64
    }

    /// CycleCounter increment per frame (the counter counts 31.25 µs units).
    pub const fn counter_step(&self) -> u16 {
        // Not a length: the CycleCounter runs modulo 2^16, so the step is taken modulo 2^16.
        (self.send_clock_factor as u32 * self.reduction_ratio as u32) as u16
    }
}

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

/// Where the C_SDU starts in a produced frame: behind the Ethernet header with its RT VLAN
/// tag and the FrameID.
pub const PRODUCED_C_SDU_OFFSET: usize = ethernet::TAGGED_HEADER_LEN + 2;

/// Bytes of a produced frame whose C_SDU is `data_length` bytes: header, FrameID, C_SDU,
/// CycleCounter, DataStatus, TransferStatus.
pub const fn produced_frame_len(data_length: usize) -> usize {
    PRODUCED_C_SDU_OFFSET + data_length + 4
}

/// An AR's cyclic exchange.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CyclicAr {
    /// The peer's index: the device's in the controller's table; 0 on a device.
    pub device: usize,
    /// Which connect of the device this is: reports about an older one are ignored.
    pub epoch: u32,
    /// The peer's MAC address (source of the frames consumed, destination of those
    /// produced).
    pub peer: MacAddress,
    /// The CR consumed: the input CR on a controller, the output CR on a device.
    pub input: CrMap,
    /// The CR produced: the output CR on a controller, the input CR on a device.
    pub output: CrMap,
    /// Timing of both CRs.
    pub timing: CrTiming,
    /// The submodule table range of the device.
    pub submodules: core::ops::Range<usize>,
    /// The output frame, header written once; the cycle fills its C_SDU and status.
    pub frame: Vec<u8>,
}

impl CyclicAr {
    /// An exchange with peer `peer` (index `device` in the caller's terms), consuming
    /// `input` and producing `output` from `own`. The produced frame's header is written
    /// here, tagged with the RT priority (VLAN 0, priority 6).
    pub fn from_maps(
        device: usize,
        epoch: u32,
        (own, peer): (MacAddress, MacAddress),
        input: CrMap,
        output: CrMap,
        timing: CrTiming,
        submodules: core::ops::Range<usize>,
    ) -> CyclicAr {
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
        debug_assert_eq!(frame.len(), produced_frame_len(output.data_length));
        CyclicAr {
            device,
            epoch,
            peer,
            input,
            output,
            timing,
            submodules,
            frame,
        }
    }

    /// Offset of the FrameID in [`frame`](Self::frame).
    #[inline]
    pub fn payload_offset(&self) -> usize {
        self.frame.len() - 2 - self.output.data_length - 4
    }
}
