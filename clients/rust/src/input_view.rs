// SPDX-License-Identifier: MIT OR Apache-2.0
//! The input image a client reads: a sample received through iceoryx2, or, on the busy path,
//! the newest image found through the handshake block and held by the client's mark
//! (`procimg_shm_layout::pins`), without a receive.

use crate::connection::Ipc;
use iceoryx2::sample::Sample;
use procimg_shm_layout::ImageHeader;
use procimg_shm_layout::maps::mapping_of;
use procimg_shm_layout::pins::Newest;

/// A received input sample.
pub type InputSample = Sample<Ipc, [u8], ImageHeader>;

/// Where the input segment lies in this process, learnt from one received sample: the
/// busy path turns the offsets procimgd names into places, and checks each against the
/// segment's bounds (the block's words are hints: a wrong one may name a wrong image, never
/// an address outside the segment).
#[derive(Debug, Clone, Copy)]
pub struct Segment {
    /// Where offset 0 lies.
    base: usize,
    /// The segment's first address and its end.
    start: usize,
    end: usize,
    /// The header's place relative to the payload's (the same for every sample).
    header_delta: isize,
    /// The payload's length.
    len: usize,
}

impl Segment {
    /// Learns the segment from `sample`, the image `newest` names (its cycle must be the
    /// sample's: else `None`, and the next image is tried).
    pub fn learn(sample: &InputSample, newest: Newest) -> Option<Segment> {
        if sample.user_header().cycle.cycle_number as u32 != newest.cycle {
            return None;
        }
        let payload = sample.payload().as_ptr() as usize;
        let header = sample.user_header() as *const ImageHeader as usize;
        let mapping = mapping_of(payload)?;
        Some(Segment {
            base: payload.checked_sub(newest.offset as usize)?,
            start: mapping.start,
            end: mapping.start + mapping.len,
            header_delta: header as isize - payload as isize,
            len: sample.payload().len(),
        })
    }

    /// The image `newest` names, if it lies in the segment.
    fn place(&self, newest: Newest) -> Option<Pinned> {
        let payload = self.base.checked_add(newest.offset as usize)?;
        let header = payload.checked_add_signed(self.header_delta)?;
        let first = payload.min(header);
        let last = (payload + self.len).max(header + size_of::<ImageHeader>());
        let aligned = header.is_multiple_of(align_of::<ImageHeader>());
        (first >= self.start && last <= self.end && aligned).then_some(Pinned {
            header: header as *const ImageHeader,
            payload: payload as *const u8,
            len: self.len,
        })
    }
}

/// An image held by the client's mark.
#[derive(Debug)]
pub struct Pinned {
    header: *const ImageHeader,
    payload: *const u8,
    len: usize,
}

// SAFETY: the pointers name shared memory the client's subscriber maps for as long as the
// connection lives; the view is only read.
unsafe impl Send for Pinned {}
// SAFETY: as above.
unsafe impl Sync for Pinned {}

/// The image a client reads.
#[derive(Debug)]
pub enum InputView {
    /// Received through iceoryx2, held by the sample.
    Received(InputSample),
    /// Found through the handshake block, held by the client's mark: valid until the client
    /// marks another image or lets go of it, which only it does (`&mut` of the client).
    Pinned(Pinned),
}

impl InputView {
    /// The image `newest` names in `segment`, held by a mark the caller made.
    pub fn pinned(segment: &Segment, newest: Newest) -> Option<InputView> {
        segment.place(newest).map(InputView::Pinned)
    }

    /// The image's payload.
    pub fn payload(&self) -> &[u8] {
        match self {
            InputView::Received(s) => s.payload(),
            // SAFETY: `Segment::place` checked that the payload lies in the input segment,
            // which the connection maps read-only for as long as it lives (the view goes
            // before the connection); the client's mark keeps procimgd from writing the
            // sample while the view exists (`procimg_shm_layout::pins`).
            InputView::Pinned(p) => unsafe { core::slice::from_raw_parts(p.payload, p.len) },
        }
    }

    /// The image's header.
    pub fn user_header(&self) -> &ImageHeader {
        match self {
            InputView::Received(s) => s.user_header(),
            // SAFETY: as for the payload; the header was checked to lie in the segment,
            // aligned.
            InputView::Pinned(p) => unsafe { &*p.header },
        }
    }
}
