// SPDX-License-Identifier: MIT OR Apache-2.0
//! Which input image each synchronous client (and each busy-polling one) reads, so that the
//! server never writes it: the newest image's place in one word of the handshake block, and
//! one hold mark per client slot, in the way of hazard pointers.
//!
//! A busy client finds the cycle's image without an iceoryx2 receive: it reads
//! [`Pins`](crate::pins::Pins)'s newest word (the cycle and the offset of the image's
//! sample in the input segment), marks that offset as held in its slot, and reads the
//! newest word again. When it is unchanged, the mark is in time: the server, which reuses a
//! sample only after it published a newer image and only after it looked at every mark
//! ([`Pins::held`](crate::pins::Pins::held)), sees it. When the word moved meanwhile, the
//! client marks the newer image instead. It clears its mark when it is done with the image
//! ([`Pins::unpin`](crate::pins::Pins::unpin)), and the server clears a dead client's
//! ([`Pins::forget_slot`](crate::pins::Pins::forget_slot)).
//!
//! Why one of the two sides sees the other: every access here is `SeqCst`, so all of them
//! fall into one order. If the client's second read saw image k, it came before the
//! server's publication of k + 1; the client's mark came before that read, and the server's
//! look at the marks comes after its publication of k + 1. So the mark comes before the
//! look.
//!
//! The server keeps a sample some client holds out of use (it keeps the loan aside and
//! loans another) until the mark is gone; the marks are about samples, not images, so a
//! sample that comes round again under a newer image is held just the same.
//!
//! The payload is all a mark keeps: iceoryx2 rewrites a sample's user header when it loans
//! the sample, before the server can see the mark and set the loan aside. A reader copies
//! the header while the image is still the newest and checks that with
//! [`Pins::still_newest`](crate::pins::Pins::still_newest) afterwards, or takes the image's
//! cycle and mode from the record on the newest word's line
//! ([`Pins::record_of`](crate::pins::Pins::record_of), `crate::cycle_record`).

use core::sync::atomic::{AtomicU64, Ordering, fence};

use crate::MAX_CLIENTS;
use crate::cycle_record::{CycleRecord, Recorded};
use crate::line::Line;
use crate::segment::SamplePlace;

/// A hold mark: the offset held, plus one, so that 0 means nothing held.
fn mark(offset: u32) -> u64 {
    u64::from(offset) + 1
}

/// The newest image's word, with its cycle record on the same line.
#[repr(C)]
#[derive(Debug, Default)]
struct Newest {
    /// The newest image's place ([`SamplePlace`]), 0 before the first.
    word: AtomicU64,
    /// The cycle info and mode of the image named (or about to be).
    record: CycleRecord,
}

// The record shares the word's cache line.
const _: () = assert!(core::mem::size_of::<Newest>() <= 64);

/// The newest image's word and the clients' hold marks (`#[repr(C)]`, in the handshake
/// block). Each mark is on a cache line of its own: a busy client writes its own twice per
/// cycle and shares it with nobody but the server.
#[repr(C)]
#[derive(Debug)]
pub struct Pins {
    /// The newest image's word and record.
    newest: Line<Newest>,
    /// Bit `slot`: that client may hold marks (it asked for the busy path), so that the
    /// server looks at the marks of those only.
    busy: Line<AtomicU64>,
    /// Per slot: the offset of the sample held, plus one; 0 for none.
    holds: [Line<AtomicU64>; MAX_CLIENTS],
}

impl Default for Pins {
    fn default() -> Self {
        Pins {
            newest: Line::default(),
            busy: Line::default(),
            holds: core::array::from_fn(|_| Line::default()),
        }
    }
}

fn bit(slot: u32) -> u64 {
    1u64 << (slot as usize % MAX_CLIENTS)
}

impl Pins {
    // ----- the server's side -----

    /// Records the cycle info and mode of the image about to be named, on the newest word's
    /// cache line (`crate::cycle_record`): before [`Pins::publish`] of that image.
    pub fn record(&self, r: &Recorded) {
        self.newest.0.record.write(r);
    }

    /// Says that `newest` is the newest image (after it was published).
    pub fn publish(&self, newest: SamplePlace) {
        self.newest.0.word.store(newest.word(), Ordering::SeqCst);
        // Before anything written later (iceoryx2 rewrites the user header of a sample it
        // loans, also a held one): a reader that sees such a write sees the word moved
        // ([`Pins::still_newest`]).
        fence(Ordering::Release);
    }

    /// Whether any client holds the sample at `offset` (to be asked after the image that
    /// replaced it was published, before the sample is written again).
    pub fn held(&self, offset: u32) -> bool {
        let want = mark(offset);
        let mut busy = self.busy.0.load(Ordering::SeqCst);
        while busy != 0 {
            let slot = busy.trailing_zeros() as usize;
            busy &= busy - 1;
            if self.holds[slot].0.load(Ordering::SeqCst) == want {
                return true;
            }
        }
        false
    }

    /// Forgets the client of `slot` (it left, or died holding an image).
    pub fn forget_slot(&self, slot: u32) {
        self.busy.0.fetch_and(!bit(slot), Ordering::SeqCst);
        if let Some(hold) = self.holds.get(slot as usize) {
            hold.0.store(0, Ordering::SeqCst);
        }
    }

    /// The slots of the clients that read images by their mark (bit per slot), from their
    /// first [`Pins::pin_newest`] until the server forgets the slot.
    pub fn joined(&self) -> u64 {
        self.busy.0.load(Ordering::Acquire)
    }

    // ----- a client's side -----

    /// Makes the client of `slot` one that may hold images ([`Pins::pin_newest`] does it
    /// when needed).
    pub fn join(&self, slot: u32) {
        self.busy.0.fetch_or(bit(slot), Ordering::SeqCst);
    }

    /// Holds the newest image for the client of `slot` and returns where it is; `None`
    /// before the first image, or for a slot out of range. The image stays as it is until
    /// [`Pins::unpin`] (or the next `pin_newest`, which lets go of it).
    pub fn pin_newest(&self, slot: u32) -> Option<SamplePlace> {
        let hold = &self.holds.get(slot as usize)?.0;
        // Joined first (once: the server clears the bit only when it forgets the slot), so
        // that the server looks at the mark.
        if self.busy.0.load(Ordering::SeqCst) & bit(slot) == 0 {
            self.join(slot);
        }
        let mut seen = self.newest.0.word.load(Ordering::SeqCst);
        loop {
            let newest = SamplePlace::from_word(seen)?;
            hold.store(mark(newest.offset), Ordering::SeqCst);
            let now = self.newest.0.word.load(Ordering::SeqCst);
            if now == seen {
                return Some(newest);
            }
            // A newer image came between the read and the mark: hold that one.
            seen = now;
        }
    }

    /// Lets go of what the client of `slot` holds.
    pub fn unpin(&self, slot: u32) {
        if let Some(hold) = self.holds.get(slot as usize) {
            hold.0.store(0, Ordering::SeqCst);
        }
    }

    /// Whether `place` is still the newest image, after the caller read from it: `false`
    /// when a newer one was named meanwhile, and what was read of the sample's header may
    /// have been rewritten (see [`Pins::publish`]).
    pub fn still_newest(&self, place: SamplePlace) -> bool {
        fence(Ordering::Acquire);
        self.newest.0.word.load(Ordering::Relaxed) == place.word()
    }

    /// The newest image, without holding it (to see whether a new one came).
    pub fn newest(&self) -> Option<SamplePlace> {
        SamplePlace::from_word(self.newest.0.word.load(Ordering::SeqCst))
    }

    /// The cycle info and mode recorded for the image `place` names, if the record is whole
    /// and that image's ([`Pins::record`]).
    pub fn record_of(&self, place: SamplePlace) -> Option<Recorded> {
        self.newest.0.record.read(place.cycle)
    }

    /// The newest image's word as it is now: a busy client spins until it moves
    /// ([`crate::handshake::HandshakeBlock::spin_startop`]).
    pub fn newest_word(&self) -> u64 {
        self.newest.0.word.load(Ordering::Acquire)
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use core::sync::atomic::AtomicBool;
    use std::sync::Arc;
    use std::vec::Vec;

    #[test]
    fn a_pin_holds_the_newest_image_until_unpinned() {
        let pins = Pins::default();
        assert_eq!(pins.pin_newest(3), None, "nothing published yet");
        pins.join(3);
        let first = SamplePlace {
            cycle: 7,
            offset: 4096,
        };
        pins.publish(first);
        assert_eq!(pins.pin_newest(3), Some(first));
        assert!(pins.held(4096));
        assert!(!pins.held(8192));
        pins.publish(SamplePlace {
            cycle: 8,
            offset: 8192,
        });
        assert!(pins.held(4096), "still read after a newer image came");
        pins.unpin(3);
        assert!(!pins.held(4096));
        assert_eq!(pins.pin_newest(3).map(|n| n.cycle), Some(8));
        pins.forget_slot(3);
        assert!(!pins.held(8192), "a forgotten client holds nothing");
        assert_eq!(pins.pin_newest(MAX_CLIENTS as u32), None);
    }

    #[test]
    fn the_newest_words_record_is_read_for_the_image_it_names_only() {
        let pins = Pins::default();
        let place = SamplePlace {
            cycle: 7,
            offset: 4096,
        };
        assert_eq!(pins.record_of(place), None, "nothing recorded yet");
        let r = Recorded {
            cycle: crate::CycleInfo {
                cycle_number: 7,
                cycle_start_ns: 100,
                clock_ns: 130,
                since_cycle_start_ns: 30,
                cycle_count: 224,
                reserved: 0,
            },
            mode: 2,
            mode_changes: 3,
        };
        pins.record(&r);
        pins.publish(place);
        assert_eq!(pins.record_of(place), Some(r));
        let next = SamplePlace {
            cycle: 8,
            offset: 8192,
        };
        assert_eq!(pins.record_of(next), None, "another image's word");
    }

    /// Samples as cells written with relaxed stores (no data race for the model): a server
    /// thread publishes an image per round into a free sample it may write, readers pin the
    /// newest and check that it does not change while they hold it.
    #[test]
    fn no_reader_ever_sees_its_image_change_while_it_holds_it() {
        const SAMPLES: usize = 8;
        const CELLS: usize = 16;
        const ROUNDS: u32 = 100_000;
        const READERS: u32 = 2;
        let pins = Arc::new(Pins::default());
        let samples: Arc<Vec<[AtomicU64; CELLS]>> = Arc::new(
            (0..SAMPLES)
                .map(|_| core::array::from_fn(|_| AtomicU64::new(0)))
                .collect(),
        );
        let offset = |i: usize| (i as u32 + 1) * 4096;
        let done = Arc::new(AtomicBool::new(false));
        let readers: Vec<_> = (0..READERS)
            .map(|slot| {
                let (pins, samples, done) = (pins.clone(), samples.clone(), done.clone());
                std::thread::spawn(move || {
                    pins.join(slot);
                    let (mut reads, mut torn) = (0u64, 0u64);
                    while !done.load(Ordering::Relaxed) {
                        let Some(n) = pins.pin_newest(slot) else {
                            continue;
                        };
                        let cells = &samples[(n.offset / 4096 - 1) as usize];
                        // Read the image a few times over, as a program reads its inputs.
                        for _ in 0..4 {
                            for c in cells {
                                if c.load(Ordering::Relaxed) != u64::from(n.cycle) {
                                    torn += 1;
                                }
                            }
                            std::hint::spin_loop();
                        }
                        reads += 1;
                        pins.unpin(slot);
                    }
                    (reads, torn)
                })
            })
            .collect();

        // The server: the newest image stays unwritten (it is the history); a sample is
        // loaned from the free ones, and one some reader holds is kept aside until free.
        let mut free: Vec<usize> = (0..SAMPLES).collect();
        let mut aside: Vec<usize> = Vec::new();
        let mut newest: Option<usize> = None;
        let mut skipped = 0u32;
        for round in 1..=ROUNDS {
            // Samples kept aside go back once nobody holds them.
            aside.retain(|&i| {
                let held = pins.held(offset(i));
                if !held {
                    free.push(i);
                }
                held
            });
            let loaned = loop {
                match free.pop() {
                    Some(i) if pins.held(offset(i)) => aside.push(i),
                    other => break other,
                }
            };
            let Some(i) = loaned else {
                // Every sample is held: no image this round (never a held one written).
                skipped += 1;
                continue;
            };
            for c in &samples[i] {
                c.store(u64::from(round), Ordering::Relaxed);
            }
            pins.publish(SamplePlace {
                cycle: round,
                offset: offset(i),
            });
            if let Some(old) = newest.replace(i) {
                free.push(old);
            }
        }
        done.store(true, Ordering::Relaxed);
        let mut total = 0;
        for r in readers {
            let (reads, torn) = r.join().expect("a reader");
            assert_eq!(torn, 0, "a held image changed under its reader");
            total += reads;
        }
        assert!(total > 0, "the readers read nothing");
        assert!(skipped < ROUNDS, "every round was skipped");
    }
}
