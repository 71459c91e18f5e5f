// SPDX-License-Identifier: MIT OR Apache-2.0
//! Input samples a busy client holds by its mark (`procimg_shm_layout::pins`), kept out of
//! use by the cycle thread.
//!
//! A busy client reads the newest image without an iceoryx2 receive, so iceoryx2 does not
//! know it holds the sample: once a newer image is published, the sample goes back to the
//! publisher's free samples and may be loaned again. When the cycle thread loans a sample a
//! client marks as held, it keeps the loan aside, unwritten, and loans another; it drops
//! the loan (the sample goes back to the free ones) once no client holds it. A client holds
//! one image at a time, so at most one sample per client is ever aside: the input publisher
//! may loan that many more.

use super::Ipc;
use core::mem::MaybeUninit;
use iceoryx2::sample_mut_uninit::SampleMutUninit;
use procimg_shm_layout::pins::Pins;
use procimg_shm_layout::{ImageHeader, MAX_CLIENTS};

/// A loaned input sample.
pub type InputSample = SampleMutUninit<Ipc, [MaybeUninit<u8>], ImageHeader>;

/// An input sample as the cycle thread loaned it, with where its payload lies noted once:
/// iceoryx2's thread-safe services look a slice sample's length up behind two mutexes each
/// time its payload is asked for, and the loans are used between STARTOP and the clients'
/// answers.
pub struct Loan {
    /// The sample.
    pub sample: InputSample,
    /// The first address of its payload.
    pub at: usize,
    /// Its payload's length.
    pub len: usize,
}

impl Loan {
    /// Notes where `sample`'s payload lies.
    pub fn new(mut sample: InputSample) -> Loan {
        let payload = sample.payload_mut();
        let (at, len) = (payload.as_mut_ptr() as usize, payload.len());
        Loan { sample, at, len }
    }
}

/// Loans the input publisher may have at once: two of the sample being written, the one
/// loaned ahead for the next image (`CyclePorts::ahead`) and the one named and not yet sent
/// (`CyclePorts::unsent`); and one kept aside per client.
pub const INPUT_LOANS: usize = 2 + MAX_CLIENTS;

/// The samples kept aside, and where the input segment starts (offsets are counted from
/// there, the same in every process that maps it).
pub struct Aside {
    /// The input segment's first address; 0 while unknown (no offsets, nothing kept aside:
    /// busy clients then take the images through iceoryx2).
    segment: usize,
    samples: Box<[Option<Loan>]>,
    /// How many of `samples` are `Some`.
    kept: usize,
}

impl Default for Aside {
    fn default() -> Self {
        Aside {
            segment: 0,
            samples: (0..MAX_CLIENTS).map(|_| None).collect(),
            kept: 0,
        }
    }
}

impl Aside {
    /// Offsets count from `segment`, the first address of the input samples' segment.
    pub fn set_segment(&mut self, segment: usize) {
        self.segment = segment;
    }

    /// The offset of the payload at `at` in the input segment, `None` if unknown or out of
    /// range.
    pub fn offset(&self, at: usize) -> Option<u32> {
        if self.segment == 0 {
            return None;
        }
        u32::try_from(at.checked_sub(self.segment)?).ok()
    }

    /// Drops the samples kept aside that no client holds any more (they go back to the
    /// free ones). Nothing to do, and nothing looked at, when none is kept.
    pub fn release(&mut self, pins: &Pins) {
        if self.kept == 0 {
            return;
        }
        let segment = self.segment;
        for entry in self.samples.iter_mut() {
            let Some(loan) = entry else { continue };
            let held = u32::try_from(loan.at.wrapping_sub(segment)).is_ok_and(|off| pins.held(off));
            if !held {
                *entry = None;
                self.kept -= 1;
            }
        }
    }

    /// Keeps `loan` aside. Without room (cannot happen while each client holds at most
    /// one sample) it goes back to the free ones unwritten, and `false` says so.
    pub fn keep(&mut self, loan: Loan) -> bool {
        match self.samples.iter_mut().find(|e| e.is_none()) {
            Some(entry) => {
                *entry = Some(loan);
                self.kept += 1;
                true
            }
            None => false,
        }
    }

    /// Samples kept aside now.
    pub fn kept(&self) -> usize {
        self.kept
    }
}
