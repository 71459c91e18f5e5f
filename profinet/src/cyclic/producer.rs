// SPDX-License-Identifier: MIT OR Apache-2.0
//! The producer half of an exchange: the frame of the CR an end produces, written in place
//! in the buffer [`CyclicAr`] built once, in the cycles it is due in. Every cycle-driven
//! producer in the workspace writes it this way: the cycle thread's from the image, the demo
//! PLC's from its program, the test world's with constant data.

use super::{CrMap, CyclicAr};

// The cycle thread calls these once per AR and cycle from another crate: `#[inline]` lets
// them inline there, as the code they replaced did.

/// What a producer puts in its frame, per submodule of the caller's table.
pub trait ProducedData {
    /// The data of `submodule`; left as it is in the frame unless exactly as long as the
    /// frame's object.
    fn data(&self, submodule: usize) -> &[u8];
    /// The provider status (IOPS) of `submodule`'s data.
    fn iops(&self, submodule: usize) -> u8;
    /// The consumer status (IOCS) this end returns for `submodule`'s data from the peer.
    fn iocs(&self, submodule: usize) -> u8;
}

impl CyclicAr {
    /// Whether the produced CR has a frame due in cycle `cycle` of the cycle thread: one
    /// every `every_cycles` (the reduction ratio in cycles), from cycle 0 on.
    #[inline]
    pub const fn due(&self, cycle: u64) -> bool {
        let every = self.timing.every_cycles as u64;
        every <= 1 || cycle.is_multiple_of(every)
    }

    /// The produced frame's C_SDU, to be written in place, and its map.
    #[inline]
    pub fn c_sdu_mut(&mut self) -> (&CrMap, &mut [u8]) {
        let at = self.payload_offset() + 2;
        let CyclicAr { output, frame, .. } = self;
        let end = (at + output.data_length).min(frame.len());
        (output, frame.get_mut(at.min(end)..end).unwrap_or_default())
    }

    /// Writes every data object, IOPS and IOCS of the produced CR from `from`.
    #[inline]
    pub fn fill(&mut self, from: &impl ProducedData) {
        let (output, c_sdu) = self.c_sdu_mut();
        for o in &output.objects {
            let data = from.data(o.submodule);
            if let Some(dst) = c_sdu.get_mut(o.data..o.data + o.len)
                && dst.len() == data.len()
            {
                dst.copy_from_slice(data);
            }
        }
        self.fill_status(from);
    }

    /// Writes every IOPS and IOCS of the produced CR from `from`, and no data.
    #[inline]
    pub fn fill_status(&mut self, from: &impl ProducedData) {
        let (output, c_sdu) = self.c_sdu_mut();
        for o in &output.objects {
            if let Some(b) = c_sdu.get_mut(o.iops) {
                *b = from.iops(o.submodule);
            }
        }
        for c in &output.iocs {
            if let Some(b) = c_sdu.get_mut(c.offset) {
                *b = from.iocs(c.submodule);
            }
        }
    }

    /// Whether the produced CR's data objects (those with data) lie in the C_SDU one after
    /// another in the order listed, none over another: what
    /// [`write_around_data`](Self::write_around_data) needs.
    pub fn data_in_frame_order(&self) -> bool {
        let mut end = 0;
        self.output.objects.iter().filter(|o| o.len > 0).all(|o| {
            let in_order = o.data >= end && o.data + o.len <= self.output.data_length;
            end = o.data + o.len;
            in_order
        })
    }

    /// Copies every byte of the produced frame but its data objects' into `frame`, a buffer
    /// of the frame's length that holds the data already where the frame carries them: the
    /// header, FrameID, status bytes and APDU status [`fill_status`](Self::fill_status) and
    /// [`seal`](Self::seal) wrote. Only for a CR whose data lie in frame order
    /// ([`data_in_frame_order`](Self::data_in_frame_order)); `false`, and nothing written,
    /// for a buffer of another length.
    #[inline]
    pub fn write_around_data(&self, frame: &mut [u8]) -> bool {
        if frame.len() != self.frame.len() {
            return false;
        }
        let at = self.payload_offset() + 2;
        let mut copy = |range: core::ops::Range<usize>| {
            if let (Some(dst), Some(src)) = (frame.get_mut(range.clone()), self.frame.get(range)) {
                dst.copy_from_slice(src);
            }
        };
        let mut done = 0;
        for o in self.output.objects.iter().filter(|o| o.len > 0) {
            copy(done..at + o.data);
            done = at + o.data + o.len;
        }
        copy(done..self.frame.len());
        true
    }

    /// Writes the APDU status (CycleCounter, DataStatus, TransferStatus 0) behind the
    /// C_SDU and returns the frame, ready to send.
    #[inline]
    pub fn seal(&mut self, cycle_counter: u16, data_status: u8) -> &[u8] {
        let trailer = self.payload_offset() + 2 + self.output.data_length;
        if let Some(t) = self.frame.get_mut(trailer..trailer + 4) {
            let [hi, lo] = cycle_counter.to_be_bytes();
            t.copy_from_slice(&[hi, lo, data_status, 0]);
        }
        &self.frame
    }
}

#[cfg(test)]
#[path = "producer_tests.rs"]
mod tests;
