// SPDX-License-Identifier: MIT OR Apache-2.0
//! The clock and the wait that server and clients share: `CLOCK_MONOTONIC` (the clock of
//! `CycleInfo`) and a precise wait on an event socket.
//!
//! iceoryx2's own `Listener::timed_wait` rounds short timeouts up to several milliseconds (it
//! uses `SO_RCVTIMEO`); `ppoll` on the listener's socket sleeps on a high-resolution timer.

extern crate std;

use std::os::fd::RawFd;

/// Now on `CLOCK_MONOTONIC`, in ns.
pub fn monotonic_ns() -> u64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec; CLOCK_MONOTONIC always exists on Linux.
    unsafe { libc::clock_gettime(libc::CLOCK_MONOTONIC, &mut ts) };
    ts.tv_sec as u64 * 1_000_000_000 + ts.tv_nsec as u64
}

/// Waits until `fd` is readable or `timeout_ns` passed. Returns whether it is readable.
pub fn wait_readable(fd: RawFd, timeout_ns: u64) -> bool {
    let mut pfd = libc::pollfd {
        fd,
        events: libc::POLLIN,
        revents: 0,
    };
    let ts = libc::timespec {
        tv_sec: (timeout_ns / 1_000_000_000) as libc::time_t,
        tv_nsec: (timeout_ns % 1_000_000_000) as libc::c_long,
    };
    // SAFETY: `pfd` is one valid pollfd, `ts` a valid timespec, and a null sigmask keeps the
    // current signal mask.
    let rc = unsafe { libc::ppoll(&mut pfd, 1, &ts, core::ptr::null()) };
    rc > 0 && pfd.revents & libc::POLLIN != 0
}
