// SPDX-License-Identifier: MIT OR Apache-2.0
//! Where each synchronous client's outputs lie when it signals OPDONE, so that the server
//! copies them straight from the client's sample, without an iceoryx2 send and receive.
//!
//! The client keeps one output sample loaned across cycles. At OPDONE it names the sample
//! in its slot's word ([`Posts::post`](crate::posts::Posts::post): the cycle and the
//! payload's offset in its output segment) and moves the block's OPDONE word. The server
//! turns the offset into an address of its own mapping of the client's segment
//! ([`crate::segment::Segment`]), learnt once from a sample the client sent through
//! iceoryx2 while it named it here too; it says so in the slot
//! ([`Posts::set_learnt`](crate::posts::Posts::set_learnt)), and from then on the client
//! only names its samples.
//!
//! A sample is taken whole: before the client writes its kept sample again (in its next
//! cycle window, after the server's next STARTOP, by which time the server has long copied
//! it) it withdraws the word ([`Posts::withdraw`](crate::posts::Posts::withdraw)), and the
//! server, after copying, checks that the word is still there
//! ([`Posts::still_posted`](crate::posts::Posts::still_posted)): a copy that overlapped a
//! write shows as a withdrawn word (in the way of a sequence lock), and the server does not
//! use it.

use core::sync::atomic::{AtomicU64, Ordering, fence};

use crate::MAX_CLIENTS;
use crate::line::Line;
use crate::segment::SamplePlace;

/// One client's words, on a cache line of their own.
#[repr(C)]
#[derive(Debug, Default)]
pub struct SlotPost {
    /// The sample with this cycle's outputs ([`SamplePlace`]), 0 for none.
    posted: AtomicU64,
    /// The token of the registration whose output segment the server has learnt, 0 before.
    learnt: AtomicU64,
    /// Samples the client sent through iceoryx2 (wrapping), counted after each send: the
    /// server looks at a learnt client's port only when this moved, so that a busy OPDONE
    /// does not pay for a receive (and its port's mutex) when nothing was sent.
    sent: AtomicU64,
}

/// The clients' posted output samples (`#[repr(C)]`, in the handshake block).
#[repr(C)]
#[derive(Debug)]
pub struct Posts {
    slots: [Line<SlotPost>; MAX_CLIENTS],
}

impl Default for Posts {
    fn default() -> Self {
        Posts {
            slots: core::array::from_fn(|_| Line::default()),
        }
    }
}

impl Posts {
    fn slot(&self, slot: u32) -> Option<&SlotPost> {
        self.slots.get(slot as usize).map(|l| &l.0)
    }

    // ----- a client's side -----

    /// Names the sample at `place` as the client's outputs of its cycle, every byte of which
    /// (header and payload) it has written.
    pub fn post(&self, slot: u32, place: SamplePlace) {
        if let Some(s) = self.slot(slot) {
            // Release: the server that sees the word sees what was written before it.
            s.posted.store(place.word(), Ordering::Release);
        }
    }

    /// Withdraws the client's sample, before it writes it again.
    pub fn withdraw(&self, slot: u32) {
        if let Some(s) = self.slot(slot) {
            s.posted.store(0, Ordering::Relaxed);
            // The writes that follow come after the withdrawal for a server that sees them
            // (it reads the word again after an acquire fence).
            fence(Ordering::Release);
        }
    }

    /// Counts a sample the client just sent through iceoryx2.
    pub fn count_sent(&self, slot: u32) {
        if let Some(s) = self.slot(slot) {
            // Release: a server that sees the count finds the sample in the port.
            s.sent.fetch_add(1, Ordering::Release);
        }
    }

    /// The token of the registration whose output segment the server has learnt (0: none).
    pub fn learnt(&self, slot: u32) -> u64 {
        self.slot(slot)
            .map_or(0, |s| s.learnt.load(Ordering::Acquire))
    }

    // ----- the server's side -----

    /// The sample the client of `slot` names, if any.
    pub fn posted(&self, slot: u32) -> Option<SamplePlace> {
        SamplePlace::from_word(self.slot(slot)?.posted.load(Ordering::Acquire))
    }

    /// Whether the client still names `place`, after the server read the sample: `false`
    /// when it withdrew it meanwhile, and the copy may mix two cycles' bytes.
    pub fn still_posted(&self, slot: u32, place: SamplePlace) -> bool {
        fence(Ordering::Acquire);
        self.slot(slot)
            .is_some_and(|s| s.posted.load(Ordering::Relaxed) == place.word())
    }

    /// How many samples the client of `slot` has sent through iceoryx2 (wrapping).
    pub fn sent(&self, slot: u32) -> u64 {
        self.slot(slot)
            .map_or(0, |s| s.sent.load(Ordering::Acquire))
    }

    /// Says that the server learnt the output segment of the registration `token` in `slot`.
    pub fn set_learnt(&self, slot: u32, token: u64) {
        if let Some(s) = self.slot(slot) {
            s.learnt.store(token, Ordering::Release);
        }
    }

    /// Forgets the client of `slot` (it left, registered anew or died).
    pub fn forget_slot(&self, slot: u32) {
        if let Some(s) = self.slot(slot) {
            s.learnt.store(0, Ordering::Release);
            s.posted.store(0, Ordering::Release);
            s.sent.store(0, Ordering::Release);
        }
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use core::sync::atomic::AtomicBool;
    use std::sync::Arc;

    #[test]
    fn a_post_is_seen_until_withdrawn_and_a_forgotten_slot_names_nothing() {
        let posts = Posts::default();
        let place = SamplePlace {
            cycle: 9,
            offset: 4160,
        };
        assert_eq!(posts.posted(2), None);
        posts.post(2, place);
        assert_eq!(posts.posted(2), Some(place));
        assert!(posts.still_posted(2, place));
        posts.withdraw(2);
        assert!(!posts.still_posted(2, place));
        posts.set_learnt(2, 77);
        assert_eq!(posts.learnt(2), 77);
        posts.count_sent(2);
        posts.count_sent(2);
        assert_eq!((posts.sent(2), posts.sent(3)), (2, 0));
        posts.post(2, place);
        posts.forget_slot(2);
        assert_eq!(
            (posts.posted(2), posts.learnt(2), posts.sent(2)),
            (None, 0, 0)
        );
        assert_eq!(posts.posted(MAX_CLIENTS as u32), None);
        posts.post(MAX_CLIENTS as u32, place);
        posts.count_sent(MAX_CLIENTS as u32);
        assert_eq!(posts.sent(MAX_CLIENTS as u32), 0);
    }

    /// A client that writes its sample over and over (as one writing outside its window
    /// would), withdrawing it before each write: every copy the server keeps (the word still
    /// there after it) holds one cycle's bytes only.
    #[test]
    fn a_copy_that_overlaps_a_write_is_never_kept() {
        const CELLS: usize = 32;
        let posts = Arc::new(Posts::default());
        let cells: Arc<[AtomicU64; CELLS]> = Arc::new(core::array::from_fn(|_| AtomicU64::new(0)));
        let done = Arc::new(AtomicBool::new(false));
        let writer = {
            let (posts, cells, done) = (posts.clone(), cells.clone(), done.clone());
            std::thread::spawn(move || {
                let mut cycle = 0u32;
                while !done.load(Ordering::Relaxed) {
                    cycle = cycle.wrapping_add(1).max(1);
                    posts.withdraw(0);
                    for c in cells.iter() {
                        c.store(u64::from(cycle), Ordering::Relaxed);
                    }
                    posts.post(0, SamplePlace { cycle, offset: 64 });
                }
            })
        };
        let (mut kept, mut refused) = (0u64, 0u64);
        while kept < 20_000 {
            let Some(place) = posts.posted(0) else {
                continue;
            };
            let mut copy = [0u64; CELLS];
            for (d, c) in copy.iter_mut().zip(cells.iter()) {
                *d = c.load(Ordering::Relaxed);
            }
            if !posts.still_posted(0, place) {
                refused += 1;
                continue;
            }
            assert!(
                copy.iter().all(|&v| v == u64::from(place.cycle)),
                "a kept copy mixes cycles: {copy:?} for {place:?}"
            );
            kept += 1;
        }
        done.store(true, Ordering::Relaxed);
        writer.join().expect("the writer");
        // Refusals depend on the scheduler; only that the copies kept are whole is asserted.
        let _ = refused;
    }
}
