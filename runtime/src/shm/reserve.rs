// SPDX-License-Identifier: MIT OR Apache-2.0
//! The input image's samples, faulted in (and so locked) as they come into use, a few ahead
//! of the cycle.
//!
//! The input publisher has a sample for every reader that may hold one (two per possible
//! subscriber, as iceoryx2 counts them: 164 at 64 clients, 59 MiB at a 360 KiB image), so
//! that readers holding old images never stop the publication. Few are ever used at once:
//! the newest image, the one being built, and one per reader that lags behind. iceoryx2
//! loans the free sample at the lowest address (its free list is a stack that starts at the
//! segment's first sample, and a sample that comes back goes on top:
//! `tests/input_samples.rs` checks it), so the samples in use stay at the segment's start
//! and reach further only as readers hold more of them at once.
//!
//! So the segment is faulted in from its start up to the highest sample loaned so far plus
//! [`AHEAD`] samples (fewer for large images: [`ahead_samples`]). The cycle thread notes
//! each loan ([`InputReserve::note_loan`], two atomic operations) and, when a loan reaches
//! into the last half of the samples faulted in ahead, asks the control thread, which
//! faults in more ([`InputReserve::extend`]), off the cycle and a chunk at a time
//! (`sys::populate`). A loan beyond what is faulted in still works: it costs that cycle the
//! page faults, and is counted ([`InputReserve::unready_loans`]).

use crate::sys::populate::{self, Mapping};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};

/// Samples faulted in beyond the highest one loaned so far, at most: fewer where they would
/// take more than [`AHEAD_BYTES`], never fewer than [`MIN_AHEAD`].
pub const AHEAD: usize = 6;
/// See [`AHEAD`]: the memory locked ahead is bounded where the samples are large (6 samples
/// of a 360 KiB image each way were 4.4 MiB; the control thread extends the reserve when a
/// loan reaches into its last half, which for one sample of that image takes some 150 µs).
pub const AHEAD_BYTES: usize = 1024 * 1024;
/// See [`AHEAD`]: a reader that comes to hold an image loans one more sample; with two
/// ahead, one more can come before the control thread has extended the reserve.
pub const MIN_AHEAD: usize = 2;

/// Samples faulted in ahead for samples of `span` bytes.
pub fn ahead_samples(span: usize) -> usize {
    (AHEAD_BYTES / span.max(1)).clamp(MIN_AHEAD, AHEAD)
}

/// Room a sample takes in the segment beyond its payload (iceoryx2's header, the user
/// header, alignment): an upper bound, so that the samples ahead are never short.
const SAMPLE_OVERHEAD: usize = 4096;

/// What of the input publisher's data segment is faulted in, and what of it is in use.
#[derive(Debug, Default)]
pub struct InputReserve {
    /// The segment's first address and its end; 0 and 0 until [`InputReserve::set_up`].
    start: AtomicUsize,
    end: AtomicUsize,
    /// Bytes faulted in ahead of the highest sample loaned.
    ahead: AtomicUsize,
    /// The end of the highest sample loaned so far (written by the cycle thread).
    used: AtomicUsize,
    /// The end of what is faulted in (written by the control thread, and at the set-up).
    ready: AtomicUsize,
    /// The cycle thread asked for more and the control thread has not yet answered.
    asked: AtomicBool,
    /// Loans of a sample not wholly faulted in.
    unready_loans: AtomicU64,
}

impl InputReserve {
    /// Before the first cycle (cycle thread): `first` is the payload of a sample of `len`
    /// bytes just loaned from the segment `segment`. Faults in the segment from its start
    /// to [`ahead_samples`] past that one. Returns the bytes faulted in.
    pub fn set_up(&self, segment: &Mapping, first: usize, len: usize) -> usize {
        let end = segment.start + segment.len;
        // A new server generation's segment: nothing of it is faulted in yet.
        self.ready.store(segment.start, Ordering::Release);
        self.start.store(segment.start, Ordering::Relaxed);
        self.end.store(end, Ordering::Relaxed);
        let span = len + SAMPLE_OVERHEAD;
        self.ahead
            .store(ahead_samples(span) * span, Ordering::Relaxed);
        self.used.store((first + len).min(end), Ordering::Relaxed);
        self.extend()
    }

    /// Notes a loan of the sample at `at`, of `len` bytes (cycle thread): no system call,
    /// no lock, no allocation. A sample outside the segment (not set up, or a test's own
    /// memory) is not noted.
    pub fn note_loan(&self, at: usize, len: usize) {
        let start = self.start.load(Ordering::Relaxed);
        let end = at.saturating_add(len);
        if at < start || end > self.end.load(Ordering::Relaxed) {
            return;
        }
        if end > self.ready.load(Ordering::Acquire) {
            self.unready_loans.fetch_add(1, Ordering::Relaxed);
        }
        if end > self.used.load(Ordering::Relaxed) {
            self.used.store(end, Ordering::Release);
        }
    }

    /// Whether the control thread should fault in more now (cycle thread, once per cycle):
    /// `true` once when the highest loan reaches into the last half of what is ahead of it,
    /// and again only after [`InputReserve::extend`] ran.
    pub fn needs_extending(&self) -> bool {
        let used = self.used.load(Ordering::Relaxed);
        let ready = self.ready.load(Ordering::Acquire);
        let half = self.ahead.load(Ordering::Relaxed) / 2;
        let end = self.end.load(Ordering::Relaxed);
        if ready >= end || used.saturating_add(half) <= ready {
            return false;
        }
        !self.asked.swap(true, Ordering::AcqRel)
    }

    /// Faults in the segment up to [`ahead_samples`] past the highest loaned (control
    /// thread; at the set-up, the cycle thread). Returns the bytes faulted in now.
    pub fn extend(&self) -> usize {
        let (start, end) = (
            self.start.load(Ordering::Relaxed),
            self.end.load(Ordering::Relaxed),
        );
        let ready = self.ready.load(Ordering::Acquire).max(start);
        let want = self
            .used
            .load(Ordering::Acquire)
            .saturating_add(self.ahead.load(Ordering::Relaxed))
            .next_multiple_of(populate::PAGE)
            .min(end);
        let mut done = 0;
        if want > ready {
            done = populate::populate(&Mapping {
                start: ready,
                len: want - ready,
                readable: true,
                writable: true,
                path: String::new(),
            });
            self.ready.store(ready + done, Ordering::Release);
        }
        self.asked.store(false, Ordering::Release);
        done
    }

    /// The segment's bytes faulted in.
    pub fn ready_bytes(&self) -> usize {
        self.ready
            .load(Ordering::Acquire)
            .saturating_sub(self.start.load(Ordering::Relaxed))
    }

    /// Loans of a sample not wholly faulted in so far: each cost a cycle its page faults.
    pub fn unready_loans(&self) -> u64 {
        self.unready_loans.load(Ordering::Relaxed)
    }
}
