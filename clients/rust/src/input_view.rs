// SPDX-License-Identifier: MIT OR Apache-2.0
//! The input image a client reads: a sample received through iceoryx2, or, on the busy path,
//! the newest image found through the handshake block and held by the client's mark
//! (`procimg_shm_layout::pins`), without a receive.

use crate::connection::Ipc;
use iceoryx2::sample::Sample;
use procimg_shm_layout::maps::mapping_of;
use procimg_shm_layout::pins::Pins;
use procimg_shm_layout::segment::{SamplePlace, Segment};
use procimg_shm_layout::{ImageHeader, MAX_CLIENTS};

/// A received input sample.
pub type InputSample = Sample<Ipc, [u8], ImageHeader>;

/// What a busy client knows of where its input segment lies in its address space.
#[derive(Clone, Copy, Debug, Default)]
pub enum SegmentKnowledge {
    /// Not yet learnt: the next received image that the handshake block names is tried.
    #[default]
    Unknown,
    /// Learnt: images are found through the handshake block from now on.
    Known(Segment),
    /// Cannot be learnt in this connection (no `/proc/self/maps`, or a sample outside the
    /// mapping it names): images keep coming through iceoryx2, and nothing is tried again
    /// until the next connection, so no image pays for another look.
    Unknowable,
}

/// Learns where the input segment lies in this process from `sample`, the image `newest`
/// names. Its cycle must be the sample's, else the knowledge stays `Unknown` and the next
/// image is tried.
pub fn learn_segment(sample: &InputSample, newest: SamplePlace) -> SegmentKnowledge {
    if sample.user_header().cycle.cycle_number as u32 != newest.cycle {
        return SegmentKnowledge::Unknown;
    }
    let payload = sample.payload().as_ptr() as usize;
    let header = sample.user_header() as *const ImageHeader as usize;
    mapping_of(payload)
        .and_then(|mapping| {
            Segment::learn(
                payload,
                header,
                sample.payload().len(),
                newest.offset,
                (mapping.start, mapping.start + mapping.len),
            )
        })
        .map_or(SegmentKnowledge::Unknowable, SegmentKnowledge::Known)
}

/// An image held by the client's mark: its header copied (as [`copy_header`] does), or only
/// its cycle and mode taken from the newest word's record over an earlier image's header
/// ([`InputView::follow_record`]); its payload in place.
#[derive(Debug)]
pub struct Pinned {
    header: ImageHeader,
    payload: *const u8,
    len: usize,
    /// Whether `header` was copied from this image: otherwise its OPFAULT record and mode
    /// history are an earlier image's.
    whole: bool,
}

// SAFETY: the pointer names shared memory the client's subscriber maps for as long as the
// connection lives; the view is only read.
unsafe impl Send for Pinned {}
// SAFETY: as above.
unsafe impl Sync for Pinned {}

/// The image a client reads.
// One view per client: the header copied inline, not boxed, as boxing would allocate for
// every image on the busy path.
#[allow(clippy::large_enum_variant)]
#[derive(Debug)]
pub enum InputView {
    /// Received through iceoryx2, held by the sample.
    Received(InputSample),
    /// Found through the handshake block, held by the client's mark: valid until the client
    /// marks another image or lets go of it, which only it does (`&mut` of the client).
    Pinned(Pinned),
}

impl InputView {
    /// The image `newest` names in `segment`, held by a mark the caller made, for the client
    /// of `slot`.
    ///
    /// The header is copied now, while the image is still the newest: iceoryx2 rewrites a
    /// sample's user header whenever the sample is loaned, also one a mark holds (procimgd
    /// then keeps it aside with its payload unwritten, but the header is rewritten by then).
    /// A sample is loaned again only after a newer image was named, so a copy made before
    /// the newest word moved is whole; one made after is not used (`None`: the next image
    /// is taken instead). What is copied is [`copy_header`]'s.
    pub fn pinned(
        segment: &Segment,
        newest: SamplePlace,
        pins: &Pins,
        slot: u32,
    ) -> Option<InputView> {
        let p = segment.place::<ImageHeader>(newest.offset)?;
        // SAFETY: `Segment::place` checked that the header lies in the input segment,
        // aligned; the segment stays mapped while the connection lives. Read as a copy, its
        // wholeness checked below.
        let header = unsafe { copy_header(p.header as *const ImageHeader, slot) };
        let whole = pins.still_newest(newest) && header.cycle.cycle_number as u32 == newest.cycle;
        whole.then_some(InputView::Pinned(Pinned {
            header,
            payload: p.payload as *const u8,
            len: p.len,
            whole: true,
        }))
    }

    /// Moves this view, an image held by the client's mark, to the image `newest` names,
    /// which the mark now holds, taking its cycle and mode from the newest word's record
    /// (`procimg_shm_layout::cycle_record`): the header's other fields stay as copied from an
    /// earlier image of this connection, whose constants they are, apart from the OPFAULT
    /// record and the mode history ([`InputView::whole`] says so). `false`, and the view
    /// unchanged, when the record was being rewritten or this view was received.
    pub fn follow_record(&mut self, segment: &Segment, newest: SamplePlace, pins: &Pins) -> bool {
        let InputView::Pinned(p) = self else {
            return false;
        };
        let (Some(r), Some(place)) = (
            pins.record_of(newest),
            segment.place::<ImageHeader>(newest.offset),
        ) else {
            return false;
        };
        p.header.cycle = r.cycle;
        p.header.mode = r.mode;
        p.header.mode_changes = r.mode_changes;
        p.payload = place.payload as *const u8;
        p.len = place.len;
        p.whole = false;
        true
    }

    /// Whether the header is this image's in every field (a received image's, or one copied
    /// from the held sample), not only in its cycle and mode.
    pub fn whole(&self) -> bool {
        match self {
            InputView::Received(_) => true,
            InputView::Pinned(p) => p.whole,
        }
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
            InputView::Pinned(p) => &p.header,
        }
    }
}

/// A copy of the header at `src` as the client of `slot` reads it: every field but the other
/// clients' OPFAULT cycles, which stay 0. Those are 512 of the header's 632 bytes (8 of its
/// 10 cache lines), which the server has just written: on the busy path every line copied is
/// a line brought over from the server's CPU between STARTOP and the client's answer.
///
/// # Safety
///
/// `src` must point to a readable, aligned `ImageHeader`. It may be written meanwhile (each
/// field is read once, volatile); the caller checks afterwards whether the copy is whole.
pub unsafe fn copy_header(src: *const ImageHeader, slot: u32) -> ImageHeader {
    use core::ptr::{addr_of, read_volatile};
    // SAFETY: every field lies inside `*src`, which the caller vouches for.
    unsafe {
        let mut h = ImageHeader {
            magic: read_volatile(addr_of!((*src).magic)),
            layout_version: read_volatile(addr_of!((*src).layout_version)),
            header_size: read_volatile(addr_of!((*src).header_size)),
            layout_hash: read_volatile(addr_of!((*src).layout_hash)),
            generation: read_volatile(addr_of!((*src).generation)),
            cycle: read_volatile(addr_of!((*src).cycle)),
            mode: read_volatile(addr_of!((*src).mode)),
            submodule_count: read_volatile(addr_of!((*src).submodule_count)),
            payload_size: read_volatile(addr_of!((*src).payload_size)),
            mode_changes: read_volatile(addr_of!((*src).mode_changes)),
            cycle_ns: read_volatile(addr_of!((*src).cycle_ns)),
            opdone_deadline_ns: read_volatile(addr_of!((*src).opdone_deadline_ns)),
            opfault_cycle: [0; MAX_CLIENTS],
            mode_history: read_volatile(addr_of!((*src).mode_history)),
        };
        let own = slot as usize % MAX_CLIENTS;
        h.opfault_cycle[own] = read_volatile(addr_of!((*src).opfault_cycle[own]));
        h
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use procimg_shm_layout::CycleInfo;

    #[test]
    fn a_held_images_header_is_copied_whole_but_for_the_other_clients_opfault_cycles() {
        let mut h = ImageHeader {
            magic: 1,
            layout_version: 2,
            header_size: 3,
            layout_hash: 4,
            generation: 5,
            cycle: CycleInfo {
                cycle_number: 6,
                cycle_start_ns: 7,
                clock_ns: 8,
                since_cycle_start_ns: 9,
                cycle_count: 10,
                reserved: 11,
            },
            mode: 12,
            submodule_count: 13,
            payload_size: 14,
            mode_changes: 15,
            cycle_ns: 16,
            opdone_deadline_ns: 17,
            ..ImageHeader::default()
        };
        for (i, c) in h.opfault_cycle.iter_mut().enumerate() {
            *c = 100 + i as u64;
        }
        for (i, m) in h.mode_history.iter_mut().enumerate() {
            *m = 200 + i as u32;
        }
        for slot in [0u32, 7, MAX_CLIENTS as u32 - 1] {
            // SAFETY: `h` is a live, aligned header.
            #[allow(unsafe_code)]
            let copy = unsafe { copy_header(&h, slot) };
            let mut expected = h;
            expected.opfault_cycle = [0; MAX_CLIENTS];
            expected.opfault_cycle[slot as usize] = 100 + u64::from(slot);
            assert_eq!(copy, expected, "slot {slot}");
        }
    }
}
