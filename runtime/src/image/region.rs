// SPDX-License-Identifier: MIT OR Apache-2.0
//! One region of the input-image payload (the input data, or the mirror of the outputs)
//! written in place in the shared-memory sample that will be published, submodule by
//! submodule. When the region moves to a new sample, what is not written there afresh is
//! carried over from where it was: once per byte, in runs of neighbouring submodules.
//!
//! The region's place is a raw pointer to the start of a sample's payload (a loaned
//! iceoryx2 sample, or after its publication the published one, which the publisher's
//! history of one keeps in place until the next is sent) or the image's own payload, which
//! every method takes as a parameter. [`Region::bind`] carries the contract.
//!
//! A sample comes back from its readers as it was published: iceoryx2's readers map it
//! read-only and iceoryx2 does not clear it. (A process that writes the segment's file
//! outside iceoryx2, with the owner's or the access group's rights, could change a sample,
//! which would then be published again until the submodule changes; such a process can as
//! well change the image that is published now.) So the carry-over skips what a sample holds
//! already: the region remembers, for each sample it was published in, the edition it holds
//! (editions end at each publication), and for each submodule the edition its bytes last
//! changed in. A submodule unchanged since the sample's edition is there already. With no
//! device and no client writing, a cycle then copies nothing; otherwise it copies what
//! changed since the sample last held the image.

use core::ptr::NonNull;

/// Where a region's bytes are.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Place {
    /// In the image's own payload.
    Own,
    /// In a loaned shared-memory sample (the pointer is the start of its payload): being
    /// written.
    Sample(NonNull<u8>),
    /// In a published sample: read-only, clients read it.
    Published(NonNull<u8>),
}

/// Samples a region remembers the edition of: more than the input image publisher has
/// (`shm::ports::INPUT_IMAGES`). A sample beyond them is carried over whole.
pub(super) const REMEMBERED_SAMPLES: usize = 128;

/// A region of the payload and where its bytes are.
pub(super) struct Region {
    at: Place,
    /// Where the bytes were before the last [`Region::bind`], until carried over.
    previous: Place,
    /// Per submodule: written in place since the last bind (or carried over already).
    fresh: Vec<bool>,
    /// Per submodule: its bytes, as a range of payload offsets.
    spans: Vec<(usize, usize)>,
    /// The whole region, as a range of payload offsets.
    extent: (usize, usize),
    /// The edition being written. It ends when the region's sample is published; editions
    /// count from 1.
    edition: u64,
    /// Per submodule: the edition its bytes last changed in (0: not since the start).
    changed_in: Vec<u64>,
    /// Each sample the region was bound to, with the edition it holds whole (0: none yet,
    /// or it is being written). Its capacity, [`REMEMBERED_SAMPLES`], is never exceeded.
    samples: Vec<(NonNull<u8>, u64)>,
    /// The edition the sample the region is bound to held when it was bound (0: none).
    at_holds: u64,
    /// Bytes carried over since the region was made.
    carried: u64,
}

impl Region {
    /// A region in the own payload; submodule `s` occupies `spans[s]`, all of it `extent`.
    pub(super) fn new(spans: Vec<(usize, usize)>, extent: (usize, usize)) -> Region {
        Region {
            at: Place::Own,
            previous: Place::Own,
            fresh: vec![false; spans.len()],
            changed_in: vec![0; spans.len()],
            spans,
            extent,
            edition: 1,
            samples: Vec::with_capacity(REMEMBERED_SAMPLES),
            at_holds: 0,
            carried: 0,
        }
    }

    /// Bytes carried over (copied from the last image) since the region was made.
    pub(super) fn carried(&self) -> u64 {
        self.carried
    }

    /// Whether the sample the region is bound to holds submodule `s` as it is already.
    fn holds(&self, s: usize) -> bool {
        self.at_holds != 0 && self.changed_in[s] <= self.at_holds
    }

    /// Takes the edition `sample` holds and marks it as being written (it will hold none
    /// until it is published). 0 if the region never completed it.
    fn take_edition(&mut self, sample: NonNull<u8>) -> u64 {
        if let Some(entry) = self.samples.iter_mut().find(|(p, _)| *p == sample) {
            return core::mem::take(&mut entry.1);
        }
        if self.samples.len() < self.samples.capacity() {
            self.samples.push((sample, 0));
        }
        0
    }

    /// Where the region's bytes are now.
    pub(super) fn place(&self) -> Place {
        self.at
    }

    /// The whole region, as a range of payload offsets.
    pub(super) fn extent(&self) -> (usize, usize) {
        self.extent
    }

    /// Where the payload the region is in starts.
    pub(super) fn base(&self, own: &[u8]) -> *const u8 {
        Region::base_of(self.at, own)
    }

    fn base_of(place: Place, own: &[u8]) -> *const u8 {
        match place {
            Place::Own => own.as_ptr(),
            Place::Sample(p) | Place::Published(p) => p.as_ptr(),
        }
    }

    /// Moves the region to `to` (`None`: the own payload). Bytes written from now on are
    /// fresh; [`Region::carry_over`] brings the others from where they were.
    ///
    /// # Safety
    ///
    /// `to` must be valid for reads and writes of the whole payload and written by nobody
    /// else until [`Region::published`]; then readable and unchanged until the region is
    /// bound elsewhere and carried over. A loaned sample of a publisher with a history of
    /// one, which is sent before the next is loaned, is. A sample the region was bound to
    /// before must hold what it held when it was last [published](Region::published):
    /// nobody else writes it meanwhile, as iceoryx2's readers cannot (they map it read-only).
    pub(super) unsafe fn bind(&mut self, to: Option<NonNull<u8>>, own: &mut [u8]) {
        self.carry_over(own);
        self.at = to.map_or(Place::Own, Place::Sample);
        self.at_holds = match to {
            Some(sample) => self.take_edition(sample),
            None => 0,
        };
        self.fresh.iter_mut().for_each(|f| *f = false);
    }

    /// Copies every submodule not written since the last bind from where the region was.
    pub(super) fn carry_over(&mut self, own: &mut [u8]) {
        let (from, to) = (self.previous, self.at);
        self.previous = self.at;
        if from == to {
            return;
        }
        let n = self.spans.len();
        let wanted = |r: &Region, s: usize| !r.fresh[s] && !r.holds(s);
        let mut s = 0;
        while s < n {
            if !wanted(self, s) {
                s += 1;
                continue;
            }
            let (start, mut end) = self.spans[s];
            s += 1;
            while s < n && wanted(self, s) && self.spans[s].0 == end {
                end = self.spans[s].1;
                s += 1;
            }
            self.carried += self.copy(from, to, start, end, own) as u64;
        }
    }

    /// Copies payload bytes `start..end` of the region from `from` to `to`; how many.
    fn copy(&self, from: Place, to: Place, start: usize, end: usize, own: &mut [u8]) -> usize {
        let end = end.min(self.extent.1);
        if start >= end || start < self.extent.0 || matches!(to, Place::Published(_)) {
            return 0;
        }
        let src = Region::base_of(from, own);
        let dst = match to {
            Place::Own => own.as_mut_ptr(),
            Place::Sample(p) | Place::Published(p) => p.as_ptr(),
        };
        // SAFETY: both places hold the whole payload (the own one by construction, a sample
        // as `bind` requires) and `start..end` lies inside the region; the destination is
        // not published; `copy` allows the two to overlap (they may be one sample).
        unsafe { core::ptr::copy(src.add(start), dst.add(start), end - start) };
        end - start
    }

    /// The bytes of submodule `s` as they are: from where the region was if `s` has not been
    /// carried over yet.
    pub(super) fn get<'a>(&'a self, s: usize, own: &'a [u8]) -> &'a [u8] {
        let (start, end) = self.spans[s];
        let place = if self.previous != self.at && !self.fresh[s] {
            self.previous
        } else {
            self.at
        };
        let base = Region::base_of(place, own);
        // SAFETY: the own payload, or a sample valid for reads of the whole payload (`bind`);
        // `start..end` lies inside it.
        unsafe { core::slice::from_raw_parts(base.add(start), end - start) }
    }

    /// The bytes of submodule `s`, writable in place: carried over first if they were not,
    /// so that a partial write keeps the rest. A published sample is not written: the
    /// region is taken into the own payload first.
    pub(super) fn get_mut<'a>(&'a mut self, s: usize, own: &'a mut [u8]) -> &'a mut [u8] {
        if matches!(self.at, Place::Published(_)) {
            self.keep(own);
        }
        if !self.fresh[s] {
            if self.previous != self.at && !self.holds(s) {
                let (start, end) = self.spans[s];
                self.carried += self.copy(self.previous, self.at, start, end, own) as u64;
            }
            self.fresh[s] = true;
        }
        // Handed out writable: counted as changed, whatever the caller does with it.
        self.changed_in[s] = self.edition;
        let (start, end) = self.spans[s];
        let base = match self.at {
            Place::Own => own.as_mut_ptr(),
            Place::Sample(p) | Place::Published(p) => p.as_ptr(),
        };
        // SAFETY: the own payload, or a loaned sample written by nobody else (`bind`);
        // `start..end` lies inside it and the region is borrowed mutably.
        unsafe { core::slice::from_raw_parts_mut(base.add(start), end - start) }
    }

    /// The payload bytes `start..end` of the region, writable in place, with no submodule
    /// counted as written: for the bytes between submodules' (an output frame's header and
    /// status around its outputs). Carried over first, so that the submodules' bytes in the
    /// range are current; a published sample is not written (as in [`Region::get_mut`]).
    /// `None` for a range outside the region.
    pub(super) fn range_mut<'a>(
        &'a mut self,
        start: usize,
        end: usize,
        own: &'a mut [u8],
    ) -> Option<&'a mut [u8]> {
        if start > end || start < self.extent.0 || end > self.extent.1 {
            return None;
        }
        if matches!(self.at, Place::Published(_)) {
            self.keep(own);
        }
        self.carry_over(own);
        let base = match self.at {
            Place::Own => own.as_mut_ptr(),
            Place::Sample(p) | Place::Published(p) => p.as_ptr(),
        };
        // SAFETY: the own payload, or a loaned sample written by nobody else (`bind`);
        // `start..end` lies inside the region, so inside the payload, and the region is
        // borrowed mutably.
        Some(unsafe { core::slice::from_raw_parts_mut(base.add(start), end - start) })
    }

    /// Sets all bytes of submodule `s` to `data`, without carrying the old ones over.
    /// `false` (and nothing written) if `data` has another length.
    pub(super) fn set(&mut self, s: usize, data: &[u8], own: &mut [u8]) -> bool {
        let (start, end) = self.spans[s];
        if end - start != data.len() {
            return false;
        }
        self.fresh[s] = true;
        self.get_mut(s, own).copy_from_slice(data);
        true
    }

    /// The sample the region is in was published: from now on it is read-only, and it holds
    /// this edition whole. Whatever changes from now on belongs to the next one.
    pub(super) fn published(&mut self) {
        if let Place::Sample(p) = self.at {
            self.at = Place::Published(p);
            if self.previous == Place::Sample(p) {
                self.previous = self.at;
            }
            let edition = self.edition;
            if let Some(entry) = self.samples.iter_mut().find(|(q, _)| *q == p) {
                entry.1 = edition;
            }
            self.at_holds = 0;
            self.edition += 1;
        }
    }

    /// Takes the region into the own payload (its sample could not be published, or is
    /// published and is to be written).
    pub(super) fn keep(&mut self, own: &mut [u8]) {
        self.carry_over(own);
        if self.at != Place::Own {
            let (start, end) = self.extent;
            self.copy(self.at, Place::Own, start, end, own);
            self.at = Place::Own;
            self.previous = Place::Own;
            self.at_holds = 0;
        }
    }
}
