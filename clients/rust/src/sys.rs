// SPDX-License-Identifier: MIT OR Apache-2.0
//! Waiting on the event socket with a precise timeout (iceoryx2's own timed wait is coarse).

use std::os::fd::RawFd;
use std::time::Duration;

/// Waits until `fd` is readable or `timeout` passed; returns whether it is readable.
pub fn wait_readable(fd: RawFd, timeout: Duration) -> bool {
    let mut pfd = libc::pollfd {
        fd,
        events: libc::POLLIN,
        revents: 0,
    };
    let ts = libc::timespec {
        tv_sec: timeout.as_secs() as libc::time_t,
        tv_nsec: timeout.subsec_nanos() as libc::c_long,
    };
    // SAFETY: one valid pollfd, a valid timespec, and a null signal mask (keep the current).
    let rc = unsafe { libc::ppoll(&mut pfd, 1, &ts, std::ptr::null()) };
    rc > 0 && pfd.revents & libc::POLLIN != 0
}
