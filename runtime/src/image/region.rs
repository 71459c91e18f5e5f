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
}

impl Region {
    /// A region in the own payload; submodule `s` occupies `spans[s]`, all of it `extent`.
    pub(super) fn new(spans: Vec<(usize, usize)>, extent: (usize, usize)) -> Region {
        Region {
            at: Place::Own,
            previous: Place::Own,
            fresh: vec![false; spans.len()],
            spans,
            extent,
        }
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
    /// one, which is sent before the next is loaned, is.
    pub(super) unsafe fn bind(&mut self, to: Option<NonNull<u8>>, own: &mut [u8]) {
        self.carry_over(own);
        self.at = to.map_or(Place::Own, Place::Sample);
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
        let mut s = 0;
        while s < n {
            if self.fresh[s] {
                s += 1;
                continue;
            }
            let (start, mut end) = self.spans[s];
            s += 1;
            while s < n && !self.fresh[s] && self.spans[s].0 == end {
                end = self.spans[s].1;
                s += 1;
            }
            self.copy(from, to, start, end, own);
        }
    }

    /// Copies payload bytes `start..end` of the region from `from` to `to`.
    fn copy(&self, from: Place, to: Place, start: usize, end: usize, own: &mut [u8]) {
        let end = end.min(self.extent.1);
        if start >= end || start < self.extent.0 || matches!(to, Place::Published(_)) {
            return;
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
            if self.previous != self.at {
                let (start, end) = self.spans[s];
                self.copy(self.previous, self.at, start, end, own);
            }
            self.fresh[s] = true;
        }
        let (start, end) = self.spans[s];
        let base = match self.at {
            Place::Own => own.as_mut_ptr(),
            Place::Sample(p) | Place::Published(p) => p.as_ptr(),
        };
        // SAFETY: the own payload, or a loaned sample written by nobody else (`bind`);
        // `start..end` lies inside it and the region is borrowed mutably.
        unsafe { core::slice::from_raw_parts_mut(base.add(start), end - start) }
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

    /// The sample the region is in was published: from now on it is read-only.
    pub(super) fn published(&mut self) {
        if let Place::Sample(p) = self.at {
            self.at = Place::Published(p);
            if self.previous == Place::Sample(p) {
                self.previous = self.at;
            }
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
        }
    }
}
