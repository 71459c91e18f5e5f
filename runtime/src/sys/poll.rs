// SPDX-License-Identifier: MIT OR Apache-2.0
//! Waiting for a file descriptor with nanosecond timeouts.
//!
//! iceoryx2's own `Listener::timed_wait` rounds short timeouts up to several milliseconds
//! (it uses `SO_RCVTIMEO`), far too coarse for an OPDONE deadline; `ppoll` on the listener's
//! socket sleeps on a high-resolution timer instead.

use std::os::fd::RawFd;

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
    let rc = unsafe { libc::ppoll(&mut pfd, 1, &ts, std::ptr::null()) };
    rc > 0 && pfd.revents & libc::POLLIN != 0
}
