// SPDX-License-Identifier: MIT OR Apache-2.0
//! Waiting for a file descriptor with nanosecond timeouts (shared with the clients).

pub use procimg_shm_layout::os::wait_readable;
use std::os::fd::RawFd;

/// Waits until `first` or `second` is readable or `timeout_ns` passed. Returns which are.
pub fn wait_readable_either(first: RawFd, second: RawFd, timeout_ns: u64) -> (bool, bool) {
    let mut fds = [first, second].map(|fd| libc::pollfd {
        fd,
        events: libc::POLLIN,
        revents: 0,
    });
    let ts = libc::timespec {
        tv_sec: (timeout_ns / 1_000_000_000) as libc::time_t,
        tv_nsec: (timeout_ns % 1_000_000_000) as libc::c_long,
    };
    // SAFETY: `fds` is an array of two valid pollfds, `ts` a valid timespec, and a null sigmask
    // keeps the current signal mask.
    let rc = unsafe { libc::ppoll(fds.as_mut_ptr(), 2, &ts, core::ptr::null()) };
    if rc <= 0 {
        return (false, false);
    }
    let readable = |p: &libc::pollfd| p.revents & (libc::POLLIN | libc::POLLERR) != 0;
    (readable(&fds[0]), readable(&fds[1]))
}
