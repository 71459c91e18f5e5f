// SPDX-License-Identifier: MIT OR Apache-2.0
//! The provider of the input CR (device → controller) of an AR the engine runs itself (when
//! it has not handed it over). The output CR's consumer is the workspace's one
//! [`crate::cyclic::Consumer`], which the AR holds.
//!
//! Timing follows the IOCRBlockReq: a frame every SendClockFactor × ReductionRatio × 31.25 µs,
//! CycleCounter taken from the frame's scheduled time ([`cycle_counter_at`]), so it steps by
//! SendClockFactor × ReductionRatio per frame.

use super::ethernet_frame;
use crate::wire::MacAddress;
use crate::wire::connect::IocrBlockReq;
use crate::wire::rt::{self, TIME_UNIT_NS, cycle_counter_at};

/// The provider of the input CR.
pub(super) struct Provider {
    /// FrameID of the CR.
    pub(super) frame_id: u16,
    /// C_SDU bytes.
    pub(super) data_length: usize,
    period_ns: u64,
    tci: u16,
    dst: MacAddress,
    next_due: Option<u64>,
}

impl Provider {
    /// The provider of `iocr` with `frame_id`, sending to `dst` (the controller).
    pub(super) fn new(iocr: &IocrBlockReq, frame_id: u16, dst: MacAddress) -> Provider {
        Provider {
            frame_id,
            data_length: usize::from(iocr.data_length),
            period_ns: iocr.period_ns().max(TIME_UNIT_NS),
            tci: iocr.tag_header,
            dst,
            next_due: None,
        }
    }

    /// Starts sending (the first frame is due at once); no-op when running.
    pub(super) fn start(&mut self, now_ns: u64) {
        self.next_due.get_or_insert(now_ns);
    }

    /// When the next frame is due, if running.
    pub(super) fn next_due(&self) -> Option<u64> {
        self.next_due
    }

    /// If a frame is due at `now_ns`: its CycleCounter; the next one is scheduled a period
    /// later on the same grid (cycles missed by a late call are skipped, not sent in a burst).
    pub(super) fn take_due(&mut self, now_ns: u64) -> Option<u16> {
        let due = self.next_due?;
        if due > now_ns {
            return None;
        }
        let missed = (now_ns - due) / self.period_ns;
        self.next_due = Some(due.saturating_add(self.period_ns.saturating_mul(missed + 1)));
        Some(cycle_counter_at(due))
    }

    /// The frame carrying `c_sdu` (exactly `data_length` bytes): tagged with the CR's
    /// IOCRTagHeader, from `src` to the controller. `None` if the RT header could not be
    /// written (the buffer is sized for it, so it always can).
    pub(super) fn frame(
        &self,
        src: MacAddress,
        cycle_counter: u16,
        data_status: u8,
        c_sdu: &[u8],
    ) -> Option<Vec<u8>> {
        let repr = rt::Repr {
            frame_id: self.frame_id,
            data_length: self.data_length,
            cycle_counter,
            data_status,
            transfer_status: 0,
        };
        let mut pdu = vec![0u8; repr.buffer_len()];
        let mut packet = rt::Packet::new_unchecked(&mut pdu[..], self.data_length);
        let data = packet.data_mut();
        let n = data.len().min(c_sdu.len());
        data[..n].copy_from_slice(&c_sdu[..n]);
        repr.emit(&mut packet).ok()?;
        Some(ethernet_frame(self.dst, src, Some(self.tci), &pdu))
    }
}
