// SPDX-License-Identifier: MIT OR Apache-2.0
//! The cyclic side of an AR: the provider of the input CR (device → controller) and the
//! consumer of the output CR (controller → device) with its data hold watchdog.
//!
//! Timing follows the IOCRBlockReq: a frame every SendClockFactor × ReductionRatio × 31.25 µs,
//! CycleCounter in 31.25 µs units taken from the frame's scheduled time, so it steps by
//! SendClockFactor × ReductionRatio per frame. A consumer takes a frame only from the
//! controller's MAC, with the CR's FrameID, TransferStatus 0, DataValid set and a CycleCounter
//! newer than the last one; only such frames reload its watchdog (as p-net does).

use super::ethernet_frame;
use crate::wire::MacAddress;
use crate::wire::connect::IocrBlockReq;
use crate::wire::rt::{self, cycle_counter_is_newer};

/// The CycleCounter unit.
const CYCLE_UNIT_NS: u64 = 31_250;

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
            period_ns: iocr.period_ns().max(CYCLE_UNIT_NS),
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
        // Truncation intended: the CycleCounter is the time in 31.25 µs units modulo 2^16.
        Some((due / CYCLE_UNIT_NS) as u16)
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

/// The consumer of the output CR.
pub(super) struct Consumer {
    /// FrameID of the CR.
    pub(super) frame_id: u16,
    /// C_SDU bytes.
    pub(super) data_length: usize,
    /// The controller's MAC: frames from elsewhere are not ours.
    src: MacAddress,
    period_ns: u64,
    data_hold_factor: u64,
    last_cycle_counter: Option<u16>,
    last_valid_ns: Option<u64>,
    /// DataStatus of the last accepted frame.
    pub(super) data_status: u8,
    /// Frames accepted.
    pub(super) frames: u64,
}

impl Consumer {
    /// The consumer of `iocr` with `frame_id`, taking frames from `src` (the controller).
    pub(super) fn new(iocr: &IocrBlockReq, frame_id: u16, src: MacAddress) -> Consumer {
        Consumer {
            frame_id,
            data_length: usize::from(iocr.data_length),
            src,
            period_ns: iocr.period_ns().max(CYCLE_UNIT_NS),
            data_hold_factor: u64::from(iocr.data_hold_factor.max(1)),
            last_cycle_counter: None,
            last_valid_ns: None,
            data_status: 0,
            frames: 0,
        }
    }

    /// Takes a cyclic frame (`pdu` from the FrameID on) from `src`: the C_SDU if the frame is
    /// ours, fresh and valid; `None` (frame ignored) otherwise.
    pub(super) fn accept<'a>(
        &mut self,
        src: MacAddress,
        pdu: &'a [u8],
        now_ns: u64,
    ) -> Option<&'a [u8]> {
        if src != self.src {
            return None;
        }
        let packet = rt::Packet::new_checked(pdu, self.data_length).ok()?;
        let repr = rt::Repr::parse(&packet).ok()?;
        if repr.frame_id != self.frame_id || !repr.data_usable() {
            return None;
        }
        if self
            .last_cycle_counter
            .is_some_and(|last| !cycle_counter_is_newer(repr.cycle_counter, last))
        {
            return None;
        }
        self.last_cycle_counter = Some(repr.cycle_counter);
        self.last_valid_ns = Some(now_ns);
        self.data_status = repr.data_status;
        self.frames += 1;
        pdu.get(2..2 + self.data_length)
    }

    /// Starts the watchdog at `now_ns` if no frame started it yet (data exchange began).
    pub(super) fn arm(&mut self, now_ns: u64) {
        self.last_valid_ns.get_or_insert(now_ns);
    }

    /// When the data hold time runs out: DataHoldFactor periods after the last valid frame.
    pub(super) fn deadline(&self) -> Option<u64> {
        let hold = self.data_hold_factor.saturating_mul(self.period_ns);
        self.last_valid_ns.map(|t| t.saturating_add(hold))
    }
}
