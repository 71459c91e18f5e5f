// SPDX-License-Identifier: MIT OR Apache-2.0
//! Samples named by their place in an iceoryx2 data segment, for the busy path: one side
//! names a sample by its payload's offset from the start of the segment it lies in
//! ([`SamplePlace`](crate::segment::SamplePlace), one word of the handshake block), the
//! other turns that offset into an address of its own mapping of the segment
//! ([`Segment`](crate::segment::Segment)).
//!
//! The two sides map the segment at different addresses, so the other side learns once
//! where offset 0 lies in its mapping: from a sample it has in hand (received through
//! iceoryx2) whose place was named too. Every place is then checked against the bounds of
//! that mapping: a word of the block is a hint, and a wrong one may name a wrong sample,
//! never an address outside the segment.

/// A sample named in the handshake block: the cycle it was written for and where its payload
/// lies in its segment.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SamplePlace {
    /// The cycle number, modulo 2³².
    pub cycle: u32,
    /// Bytes from the start of the segment to the sample's payload.
    pub offset: u32,
}

impl SamplePlace {
    /// The word: the offset in the high half, the cycle in the low half, so that a reader
    /// gets both with one load. Never 0 for a sample (its payload comes after iceoryx2's
    /// chunk header, so its offset is more than 0); 0 names none.
    pub(crate) fn word(self) -> u64 {
        (u64::from(self.offset) << 32) | u64::from(self.cycle)
    }

    pub(crate) fn from_word(w: u64) -> Option<SamplePlace> {
        (w != 0).then_some(SamplePlace {
            cycle: w as u32,
            offset: (w >> 32) as u32,
        })
    }
}

/// Where a segment's samples lie in this process.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Segment {
    /// Where offset 0 lies.
    base: usize,
    /// The mapping's first address and its end.
    start: usize,
    end: usize,
    /// A sample's user header's place relative to its payload's (the same for every sample
    /// of a service).
    header_delta: isize,
    /// The payload's length.
    len: usize,
}

/// A sample of a [`Segment`]: where its user header and its payload lie, both checked to be
/// inside the mapping.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Placed {
    /// The user header's address (aligned for the header type asked for).
    pub header: usize,
    /// The payload's address.
    pub payload: usize,
    /// The payload's length.
    pub len: usize,
}

impl Segment {
    /// Learns the segment from a sample in hand: its payload (`payload`, `len` bytes) and
    /// user header (`header`) at these addresses, named at `offset`, in the mapping
    /// `start..end`. `None` when the sample does not lie in the mapping or the offset cannot
    /// be its own.
    pub fn learn(
        payload: usize,
        header: usize,
        len: usize,
        offset: u32,
        (start, end): (usize, usize),
    ) -> Option<Segment> {
        let base = payload.checked_sub(offset as usize)?;
        let inside = start <= payload.min(header) && payload.checked_add(len)? <= end;
        (inside && base >= start).then_some(Segment {
            base,
            start,
            end,
            header_delta: (header as isize).wrapping_sub(payload as isize),
            len,
        })
    }

    /// The sample at `offset`, if its header (of type `H`) and payload lie in the mapping.
    pub fn place<H>(&self, offset: u32) -> Option<Placed> {
        let payload = self.base.checked_add(offset as usize)?;
        let header = payload.checked_add_signed(self.header_delta)?;
        let first = payload.min(header);
        let last = payload
            .checked_add(self.len)?
            .max(header.checked_add(size_of::<H>())?);
        let aligned = header.is_multiple_of(align_of::<H>());
        (first >= self.start && last <= self.end && aligned).then_some(Placed {
            header,
            payload,
            len: self.len,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_place_round_trips_through_its_word_and_zero_names_none() {
        let p = SamplePlace {
            cycle: u32::MAX,
            offset: 4160,
        };
        assert_eq!(SamplePlace::from_word(p.word()), Some(p));
        assert_eq!(SamplePlace::from_word(0), None);
    }

    #[test]
    fn places_are_found_from_one_sample_and_kept_inside_the_mapping() {
        // A mapping at 0x10000 of 64 KiB; samples of 1000 bytes with a 64-byte header
        // 128 bytes before the payload; the one in hand at offset 4224.
        let (start, end) = (0x10000, 0x20000);
        let seg =
            Segment::learn(start + 4224, start + 4096, 1000, 4224, (start, end)).expect("learnt");
        let other = seg.place::<[u64; 8]>(8320).expect("another sample");
        assert_eq!(other.payload, start + 8320);
        assert_eq!(other.header, start + 8192);
        assert_eq!(
            seg.place::<[u64; 8]>(64),
            None,
            "its header before the mapping"
        );
        assert_eq!(
            seg.place::<[u64; 8]>(65000),
            None,
            "its payload past the end"
        );
        assert_eq!(
            seg.place::<[u64; 8]>(8321),
            None,
            "a header out of alignment"
        );
        assert_eq!(seg.place::<[u64; 8]>(u32::MAX), None);
        assert_eq!(
            Segment::learn(start + 4224, start + 4096, 1000, 8192, (start, end)),
            None,
            "an offset that puts offset 0 before the mapping"
        );
        assert_eq!(
            Segment::learn(end - 10, end - 138, 1000, 4224, (start, end)),
            None,
            "a sample not in the mapping"
        );
    }
}
