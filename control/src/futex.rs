// SPDX-License-Identifier: MIT OR Apache-2.0
//! Linux futexes on shared memory: the [`Futex`] the handshake block runs on.
//!
//! The words live in a `MAP_SHARED` mapping of a file, so the calls are the shared (not
//! `FUTEX_PRIVATE_FLAG`) variants: the kernel keys them by the page, which every process that
//! maps the file sees alike.

use core::sync::atomic::AtomicU32;
use procimg_shm_layout::handshake::Futex;

/// The kernel's futexes, on `CLOCK_MONOTONIC`.
#[derive(Debug, Clone, Copy, Default)]
pub struct LinuxFutex;

impl Futex for LinuxFutex {
    fn wait_until(&self, word: &AtomicU32, expected: u32, deadline_ns: u64) {
        let ts = libc::timespec {
            tv_sec: (deadline_ns / 1_000_000_000) as libc::time_t,
            tv_nsec: (deadline_ns % 1_000_000_000) as libc::c_long,
        };
        // SAFETY: `word` is a valid, aligned 32-bit word for the whole call; FUTEX_WAIT_BITSET
        // only reads it, takes `ts` as an absolute CLOCK_MONOTONIC time (no
        // FUTEX_CLOCK_REALTIME) and ignores the second address. Errors (EAGAIN: the word
        // moved; ETIMEDOUT; EINTR) all mean "look again", which the caller does.
        unsafe {
            libc::syscall(
                libc::SYS_futex,
                word.as_ptr(),
                libc::FUTEX_WAIT_BITSET,
                expected,
                &ts as *const libc::timespec,
                core::ptr::null::<u32>(),
                libc::FUTEX_BITSET_MATCH_ANY,
            )
        };
    }

    fn wake(&self, word: &AtomicU32, count: u32) {
        // SAFETY: `word` is a valid, aligned 32-bit word; FUTEX_WAKE neither reads nor writes
        // it and takes no further pointers.
        unsafe {
            libc::syscall(
                libc::SYS_futex,
                word.as_ptr(),
                libc::FUTEX_WAKE,
                count.min(i32::MAX as u32),
                core::ptr::null::<libc::timespec>(),
                core::ptr::null::<u32>(),
                0u32,
            )
        };
    }

    fn now_ns(&self) -> u64 {
        procimg_shm_layout::os::monotonic_ns()
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use procimg_shm_layout::handshake::{HandshakeBlock, Woken};
    use std::sync::Arc;

    #[test]
    fn a_sleeping_waiter_is_woken_by_the_other_thread() {
        let block = Arc::new(HandshakeBlock::default());
        let seen = block.opdone_seen();
        let client = {
            let block = block.clone();
            std::thread::spawn(move || {
                // Until the server sleeps (or has seen the word move): then signal.
                while block
                    .server_sleeps
                    .0
                    .load(core::sync::atomic::Ordering::SeqCst)
                    == 0
                    && block.opdone_seen() == seen
                {
                    std::thread::yield_now();
                }
                block.signal_opdone(&LinuxFutex);
            })
        };
        // A deadline far away: the wake-up, not the time, must end the wait.
        let far = LinuxFutex.now_ns() + 3_600_000_000_000;
        assert_eq!(block.wait_opdone(&LinuxFutex, seen, far, 0), Woken::Moved);
        client.join().unwrap();
    }

    #[test]
    fn a_timed_wait_returns_at_its_deadline() {
        let block = HandshakeBlock::default();
        let deadline = LinuxFutex.now_ns() + 1_000_000;
        assert_eq!(
            block.wait_event(&LinuxFutex, 0, block.events_seen(), deadline),
            Woken::TimedOut
        );
        assert!(LinuxFutex.now_ns() >= deadline);
    }
}
