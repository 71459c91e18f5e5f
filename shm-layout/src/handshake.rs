// SPDX-License-Identifier: MIT OR Apache-2.0
//! The handshake block: the futex words of STARTOP and OPDONE, in three pages of shared
//! memory that procimgd creates per server generation and every client maps read-write.
//!
//! The image and the outputs live in iceoryx2 samples; the block says *when*, and on the
//! busy path also *where*: the newest image's place ([`crate::pins`]) and each busy
//! client's output sample's ([`crate::posts`]), so that no sample need go through
//! iceoryx2's queues. It replaces iceoryx2's event sockets on the hot path: one
//! `FUTEX_WAKE` wakes every client sleeping for STARTOP at once, a client's OPDONE costs an
//! atomic add and, only when the server sleeps, one `FUTEX_WAKE`, and the server sleeps for
//! OPDONE with `FUTEX_WAIT_BITSET` until its absolute deadline on `CLOCK_MONOTONIC`.
//!
//! Every word is a hint, never the truth: the truth is the samples. A word that moves wakes
//! a waiter, who then looks at the samples; a word a broken client overwrote costs at most
//! a wake-up or a sleep until the deadline, never a wrong image. A process that dies while
//! waiting holds nothing: its bits in the sleeper masks are cleared by the server when it
//! reaps the slot
//! ([`HandshakeBlock::forget_slot`](crate::handshake::HandshakeBlock::forget_slot)).
//!
//! Ordering: a waiter publishes that it sleeps (`fetch_or` of its bit, or `server_sleeps`)
//! and then reads the word again; a waker moves the word and then reads whether anybody
//! sleeps. Both sides use `SeqCst`, so one of them sees the other: either the waiter sees
//! the new value and does not sleep, or the waker sees the sleeper and wakes it. The futex
//! call itself compares the word once more in the kernel.

use core::sync::atomic::{AtomicU32, AtomicU64, Ordering};

use crate::MAX_CLIENTS;
use crate::pins::Pins;
use crate::posts::Posts;

/// "PIMGHSK4": marks an initialised block (3: with the busy path's [`Pins`] and [`Posts`];
/// 4: with the count of samples a client sent, which a server of 4 relies on).
pub const HANDSHAKE_MAGIC: u64 = 0x344b_5348_474d_4950;

/// Size of the block's mapping: three pages.
pub const HANDSHAKE_BLOCK_SIZE: usize = 12288;

pub use crate::line::Line;

/// The block's contents (`#[repr(C)]`, at the start of the page).
///
/// cbindgen:ignore
#[repr(C)]
#[derive(Debug, Default)]
pub struct HandshakeBlock {
    /// [`HANDSHAKE_MAGIC`] once the server has initialised the block.
    pub magic: Line<AtomicU64>,
    /// The server generation the block belongs to.
    pub generation: Line<AtomicU64>,
    /// Moved by the server with every STARTOP and every other cycle event: clients sleep on
    /// it (futex word).
    pub events: Line<AtomicU32>,
    /// Moved by the server with every event other than STARTOP (MODE, OPFAULT, NEWCYCLE,
    /// shutdown), after it signalled the event on iceoryx2's cycle event service: a client
    /// drains that service only when this moved.
    pub other_events: Line<AtomicU32>,
    /// Bit `slot`: that client sleeps on `events` (a STARTOP then needs a `FUTEX_WAKE`).
    pub sleepers: Line<AtomicU64>,
    /// Bit `slot`: that client waits on the descriptor of iceoryx2's cycle event listener
    /// ([`crate::events`]): STARTOP is then signalled there too.
    pub fd_waiters: Line<AtomicU64>,
    /// Moved by a client after it sent its OPDONE sample: the server sleeps on it (futex
    /// word).
    pub opdone: Line<AtomicU32>,
    /// Non-zero while the server sleeps on `opdone` (an OPDONE then needs a `FUTEX_WAKE`);
    /// zero while it busy-polls, so a client's OPDONE makes no system call.
    pub server_sleeps: Line<AtomicU32>,
    /// The newest input image and the images busy clients hold (see [`crate::pins`]).
    pub pins: Pins,
    /// The output samples busy clients name at OPDONE (see [`crate::posts`]).
    pub posts: Posts,
}

const _: () = assert!(core::mem::size_of::<HandshakeBlock>() <= HANDSHAKE_BLOCK_SIZE);
const _: () = assert!(MAX_CLIENTS <= 64, "the sleeper masks hold one bit per slot");

/// How a wait ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Woken {
    /// The word moved (or a wake-up came).
    Moved,
    /// The time was up first.
    TimedOut,
}

/// The futex calls the block needs: provided by `procimg_control::futex` on Linux (beside the
/// doorbell, its other user), by a model in tests.
pub trait Futex {
    /// Sleeps while `word` holds `expected`, at most until `deadline_ns` on `CLOCK_MONOTONIC`
    /// (absolute). May return early (a wake-up, a signal).
    fn wait_until(&self, word: &AtomicU32, expected: u32, deadline_ns: u64);
    /// Wakes up to `count` sleepers on `word`.
    fn wake(&self, word: &AtomicU32, count: u32);
    /// Now on `CLOCK_MONOTONIC`, in ns.
    fn now_ns(&self) -> u64;
}

/// Turns of a spin between two looks at the clock. A look costs some 30 ns through a
/// virtual machine's vDSO, and a turn a few: a busy client that looked every turn spent
/// three fifths of its time in `clock_gettime` (`perf record`), and saw the word move up to
/// a look late. A deadline is still met to well under a µs.
const SPINS_PER_CLOCK: u32 = 32;

/// Spins until `moved()`, or `until_ns` on the clock (then `false`), looking at the clock at
/// once and then every [`SPINS_PER_CLOCK`] turns.
fn spin(futex: &impl Futex, until_ns: u64, mut moved: impl FnMut() -> bool) -> bool {
    let mut turn = 0u32;
    loop {
        if moved() {
            return true;
        }
        if turn.is_multiple_of(SPINS_PER_CLOCK) && futex.now_ns() >= until_ns {
            return false;
        }
        turn = turn.wrapping_add(1);
        core::hint::spin_loop();
    }
}

fn woken(moved: bool) -> Woken {
    if moved { Woken::Moved } else { Woken::TimedOut }
}

fn bit(slot: u32) -> u64 {
    1u64 << (slot as usize % MAX_CLIENTS)
}

impl HandshakeBlock {
    /// Marks the block as the one of `generation` (the server, once, after creating it).
    pub fn initialise(&self, generation: u64) {
        self.generation.0.store(generation, Ordering::Relaxed);
        self.magic.0.store(HANDSHAKE_MAGIC, Ordering::Release);
    }

    /// Whether the block is initialised for `generation`.
    pub fn belongs_to(&self, generation: u64) -> bool {
        self.magic.0.load(Ordering::Acquire) == HANDSHAKE_MAGIC
            && self.generation.0.load(Ordering::Relaxed) == generation
    }

    // ----- the server's side -----

    /// Signals STARTOP (`other == false`) or another cycle event: moves the event word and
    /// wakes every sleeping client with one system call (none when nobody sleeps).
    pub fn announce(&self, futex: &impl Futex, other: bool) {
        if other {
            self.other_events.0.fetch_add(1, Ordering::SeqCst);
        }
        self.events.0.fetch_add(1, Ordering::SeqCst);
        if self.sleepers.0.load(Ordering::SeqCst) != 0 {
            futex.wake(&self.events.0, u32::MAX >> 1);
        }
    }

    /// Whether some client waits on iceoryx2's event descriptor (STARTOP must go there too).
    pub fn has_fd_waiters(&self) -> bool {
        self.fd_waiters.0.load(Ordering::Relaxed) != 0
    }

    /// The OPDONE word now: read before looking at the samples, then hand it to
    /// [`HandshakeBlock::wait_opdone`], so that an OPDONE in between is not slept through.
    pub fn opdone_seen(&self) -> u32 {
        self.opdone.0.load(Ordering::Acquire)
    }

    /// Waits until a client signals OPDONE after `seen` was read, or `deadline_ns`: spinning
    /// on the word without a system call until `spin_until_ns`, then sleeping in the kernel
    /// (a `spin_until_ns` at or past the deadline never sleeps: busy-polling).
    pub fn wait_opdone(
        &self,
        futex: &impl Futex,
        seen: u32,
        deadline_ns: u64,
        spin_until_ns: u64,
    ) -> Woken {
        let moved = || self.opdone.0.load(Ordering::Acquire) != seen;
        if spin(futex, spin_until_ns.min(deadline_ns), moved) {
            return Woken::Moved;
        }
        if futex.now_ns() < deadline_ns {
            self.sleep_for_opdone(futex, seen, deadline_ns);
        }
        woken(moved())
    }

    fn sleep_for_opdone(&self, futex: &impl Futex, seen: u32, deadline_ns: u64) {
        self.server_sleeps.0.store(1, Ordering::SeqCst);
        if self.opdone.0.load(Ordering::SeqCst) == seen {
            futex.wait_until(&self.opdone.0, seen, deadline_ns);
        }
        self.server_sleeps.0.store(0, Ordering::Relaxed);
    }

    /// Forgets what client `slot` left in the block (it left or died): it no longer sleeps
    /// nor waits on a descriptor, so STARTOP stops waking for it.
    pub fn forget_slot(&self, slot: u32) {
        self.sleepers.0.fetch_and(!bit(slot), Ordering::SeqCst);
        self.fd_waiters.0.fetch_and(!bit(slot), Ordering::SeqCst);
        self.pins.forget_slot(slot);
        self.posts.forget_slot(slot);
    }

    // ----- a client's side -----

    /// The event word now: read before looking for a new image, then hand it to
    /// [`HandshakeBlock::wait_event`].
    pub fn events_seen(&self) -> u32 {
        self.events.0.load(Ordering::Acquire)
    }

    /// The other-events word now: when it moved since the client last looked, there is
    /// something on iceoryx2's cycle event service.
    pub fn other_events_seen(&self) -> u32 {
        self.other_events.0.load(Ordering::Acquire)
    }

    /// Client `slot` sleeps until the server signals an event after `seen` was read, or
    /// `deadline_ns`.
    pub fn wait_event(&self, futex: &impl Futex, slot: u32, seen: u32, deadline_ns: u64) -> Woken {
        self.sleepers.0.fetch_or(bit(slot), Ordering::SeqCst);
        if self.events.0.load(Ordering::SeqCst) == seen {
            futex.wait_until(&self.events.0, seen, deadline_ns);
        }
        self.sleepers.0.fetch_and(!bit(slot), Ordering::SeqCst);
        woken(self.events.0.load(Ordering::Acquire) != seen)
    }

    /// Spins until the server signals an event after `seen` was read, or `deadline_ns`,
    /// without a system call.
    pub fn spin_event(&self, futex: &impl Futex, seen: u32, deadline_ns: u64) -> Woken {
        woken(spin(futex, deadline_ns, || {
            self.events.0.load(Ordering::Acquire) != seen
        }))
    }

    /// Spins until a new image is named ([`Pins::newest_word`] moved from `newest`) or the
    /// server signals an event after `seen` was read, or `deadline_ns`, without a system
    /// call: the busy path, which learns of a new image as soon as procimgd names it, before
    /// iceoryx2 has delivered it and STARTOP is announced.
    pub fn spin_startop(
        &self,
        futex: &impl Futex,
        seen: u32,
        newest: u64,
        deadline_ns: u64,
    ) -> Woken {
        woken(spin(futex, deadline_ns, || {
            self.events.0.load(Ordering::Acquire) != seen || self.pins.newest_word() != newest
        }))
    }

    /// A sleeping client's wait for STARTOP that wakes ahead: sleeps on the event word until
    /// `poll.0`, then polls as [`HandshakeBlock::spin_startop`] until `poll.1`, ending early
    /// when the server signals or names an image after `seen` and `newest` were read;
    /// without `poll` (or when it ends at or before the wait's start) it only sleeps, until
    /// `deadline_ns`. A client that polls when STARTOP comes costs the server no
    /// `FUTEX_WAKE` and finds it on a running CPU; a STARTOP after `poll.1` ends the wait
    /// as [`Woken::TimedOut`], and the caller sleeps again.
    pub fn wait_startop_ahead(
        &self,
        futex: &impl Futex,
        slot: u32,
        (seen, newest): (u32, u64),
        poll: Option<(u64, u64)>,
        deadline_ns: u64,
    ) -> Woken {
        let Some((from, until)) = poll.filter(|&(from, _)| from < deadline_ns) else {
            return self.wait_event(futex, slot, seen, deadline_ns);
        };
        if from > futex.now_ns() && self.wait_event(futex, slot, seen, from) == Woken::Moved {
            return Woken::Moved;
        }
        self.spin_startop(futex, seen, newest, until.min(deadline_ns))
    }

    /// Signals OPDONE, after the output sample was sent: moves the word, and wakes the server
    /// only if it sleeps.
    pub fn signal_opdone(&self, futex: &impl Futex) {
        self.opdone.0.fetch_add(1, Ordering::SeqCst);
        if self.server_sleeps.0.load(Ordering::SeqCst) != 0 {
            futex.wake(&self.opdone.0, 1);
        }
    }

    /// Client `slot` waits (also) on iceoryx2's event descriptor from now on, or no longer.
    pub fn set_fd_waiter(&self, slot: u32, on: bool) {
        if on {
            self.fd_waiters.0.fetch_or(bit(slot), Ordering::SeqCst);
        } else {
            self.fd_waiters.0.fetch_and(!bit(slot), Ordering::SeqCst);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::cell::Cell;

    /// Counts the system calls the protocol would make; a wait only moves the clock.
    #[derive(Default)]
    struct Model {
        waits: Cell<u32>,
        wakes: Cell<u32>,
        now: Cell<u64>,
    }

    impl Futex for Model {
        fn wait_until(&self, word: &AtomicU32, expected: u32, deadline_ns: u64) {
            self.waits.set(self.waits.get() + 1);
            if word.load(Ordering::SeqCst) == expected {
                self.now.set(deadline_ns);
            }
        }
        fn wake(&self, _: &AtomicU32, _: u32) {
            self.wakes.set(self.wakes.get() + 1);
        }
        fn now_ns(&self) -> u64 {
            let t = self.now.get();
            self.now.set(t + 1);
            t
        }
    }

    #[test]
    fn startop_wakes_only_when_a_client_sleeps() {
        let (b, f) = (HandshakeBlock::default(), Model::default());
        b.announce(&f, false);
        assert_eq!(f.wakes.get(), 0);
        b.sleepers.0.fetch_or(bit(3), Ordering::SeqCst);
        b.announce(&f, false);
        assert_eq!(f.wakes.get(), 1);
        assert_eq!(b.events_seen(), 2);
        assert_eq!(b.other_events_seen(), 0);
        b.announce(&f, true);
        assert_eq!(b.other_events_seen(), 1);
    }

    #[test]
    fn opdone_wakes_only_a_sleeping_server() {
        let (b, f) = (HandshakeBlock::default(), Model::default());
        b.signal_opdone(&f);
        assert_eq!(f.wakes.get(), 0, "a polling server needs no wake-up");
        b.server_sleeps.0.store(1, Ordering::SeqCst);
        b.signal_opdone(&f);
        assert_eq!(f.wakes.get(), 1);
    }

    #[test]
    fn a_word_that_moved_is_not_slept_on() {
        let (b, f) = (HandshakeBlock::default(), Model::default());
        let seen = b.opdone_seen();
        b.signal_opdone(&f);
        assert_eq!(b.wait_opdone(&f, seen, 1000, 0), Woken::Moved);
        assert_eq!(f.waits.get(), 0);
        assert_eq!(b.server_sleeps.0.load(Ordering::SeqCst), 0);
        let seen = b.events_seen();
        b.announce(&f, false);
        assert_eq!(b.wait_event(&f, 5, seen, 1000), Woken::Moved);
        assert_eq!(f.waits.get(), 0);
        assert_eq!(b.sleepers.0.load(Ordering::SeqCst), 0);
    }

    #[test]
    fn a_spin_looks_at_the_clock_once_in_so_many_turns() {
        let f = Model::default();
        let mut turns = 0;
        let moved = spin(&f, 1000, || {
            turns += 1;
            turns > 100
        });
        // Looks at turns 0, 32, 64 and 96.
        assert_eq!((moved, f.now.get()), (true, 4));
        // A deadline already past ends the spin at the first look.
        let mut turns = 0;
        let moved = spin(&f, 0, || {
            turns += 1;
            false
        });
        assert_eq!((moved, turns), (false, 1));
    }

    #[test]
    fn waits_end_at_the_deadline() {
        let (b, f) = (HandshakeBlock::default(), Model::default());
        assert_eq!(b.wait_opdone(&f, b.opdone_seen(), 500, 0), Woken::TimedOut);
        assert_eq!(f.waits.get(), 1, "no spin: one sleep");
        // Spinning until the deadline: busy-polling, never a system call.
        assert_eq!(
            b.wait_opdone(&f, b.opdone_seen(), 900, 900),
            Woken::TimedOut
        );
        assert_eq!(f.waits.get(), 1);
        // A spin first, then a sleep for the rest.
        assert_eq!(
            b.wait_opdone(&f, b.opdone_seen(), 2000, 1000),
            Woken::TimedOut
        );
        assert_eq!(f.waits.get(), 2);
        assert_eq!(b.server_sleeps.0.load(Ordering::SeqCst), 0);
        assert_eq!(b.wait_event(&f, 1, b.events_seen(), 3000), Woken::TimedOut);
        assert_eq!(b.spin_event(&f, b.events_seen(), 3500), Woken::TimedOut);
        assert_eq!(b.sleepers.0.load(Ordering::SeqCst), 0);
    }

    #[test]
    fn waking_ahead_sleeps_until_the_window_then_polls_without_a_system_call() {
        let (b, f) = (HandshakeBlock::default(), Model::default());
        let seen = (b.events_seen(), b.pins.newest_word());
        // Nothing comes: one sleep until the window, then polling until its end.
        let woken = b.wait_startop_ahead(&f, 2, seen, Some((100, 200)), 1000);
        assert_eq!(woken, Woken::TimedOut);
        assert_eq!(f.waits.get(), 1);
        assert!(f.now.get() >= 200 && f.now.get() < 1000, "{}", f.now.get());
        assert_eq!(
            b.sleepers.0.load(Ordering::SeqCst),
            0,
            "not asleep while polling"
        );
        // Inside the window already: no sleep at all.
        f.now.set(150);
        b.wait_startop_ahead(&f, 2, seen, Some((100, 200)), 1000);
        assert_eq!(f.waits.get(), 1);
        // A STARTOP announced while the client polls costs the server no wake-up.
        b.announce(&f, false);
        assert_eq!(f.wakes.get(), 0);
        assert_eq!(
            b.wait_startop_ahead(&f, 2, seen, Some((100, 200)), 1000),
            Woken::Moved
        );
    }

    #[test]
    fn without_a_window_or_past_the_deadline_waking_ahead_only_sleeps() {
        let (b, f) = (HandshakeBlock::default(), Model::default());
        let seen = (b.events_seen(), b.pins.newest_word());
        assert_eq!(
            b.wait_startop_ahead(&f, 2, seen, None, 500),
            Woken::TimedOut
        );
        assert_eq!((f.waits.get(), f.now.get()), (1, 500));
        assert_eq!(
            b.wait_startop_ahead(&f, 2, seen, Some((900, 950)), 800),
            Woken::TimedOut
        );
        assert_eq!((f.waits.get(), f.now.get()), (2, 800));
    }

    #[test]
    fn a_forgotten_slot_stops_costing_wake_ups() {
        let (b, f) = (HandshakeBlock::default(), Model::default());
        // A client killed inside its wait leaves its bits set.
        b.sleepers.0.fetch_or(bit(7), Ordering::SeqCst);
        b.set_fd_waiter(7, true);
        assert!(b.has_fd_waiters());
        b.forget_slot(7);
        b.announce(&f, false);
        assert_eq!(f.wakes.get(), 0);
        assert!(!b.has_fd_waiters());
    }

    #[test]
    fn the_block_belongs_to_one_generation() {
        let b = HandshakeBlock::default();
        assert!(!b.belongs_to(0));
        b.initialise(0x42);
        assert!(b.belongs_to(0x42));
        assert!(!b.belongs_to(0x43));
    }
}
