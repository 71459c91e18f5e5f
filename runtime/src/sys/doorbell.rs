// SPDX-License-Identifier: MIT OR Apache-2.0
//! A doorbell between threads: an eventfd the cycle thread rings when it leaves a report for
//! the acyclic thread, which waits on it beside its UDP socket. Ringing is one non-blocking
//! write(2): no allocation, no lock.

use std::os::fd::{AsRawFd as _, FromRawFd as _, OwnedFd, RawFd};

/// The eventfd.
#[derive(Debug)]
pub struct Doorbell {
    fd: OwnedFd,
}

impl Doorbell {
    /// A new doorbell, not rung.
    pub fn new() -> std::io::Result<Doorbell> {
        // SAFETY: eventfd(2) takes an initial value and flags; it returns a new descriptor or -1.
        let fd = unsafe { libc::eventfd(0, libc::EFD_NONBLOCK | libc::EFD_CLOEXEC) };
        if fd < 0 {
            return Err(std::io::Error::last_os_error());
        }
        // SAFETY: `fd` was just returned by eventfd(2) and is owned by nobody else.
        let fd = unsafe { OwnedFd::from_raw_fd(fd) };
        Ok(Doorbell { fd })
    }

    /// Rings it (a full counter, which takes years of rings, stays rung).
    pub fn ring(&self) {
        let one = 1u64.to_ne_bytes();
        // SAFETY: writes 8 bytes from a live local buffer to a descriptor this struct owns.
        let _ = unsafe { libc::write(self.fd.as_raw_fd(), one.as_ptr().cast(), one.len()) };
    }

    /// Takes the rings so far; whether there were any.
    pub fn take(&self) -> bool {
        let mut count = [0u8; 8];
        // SAFETY: reads at most 8 bytes into a live local buffer from a descriptor this struct
        // owns; non-blocking, so an unrung bell returns EAGAIN at once.
        let n = unsafe { libc::read(self.fd.as_raw_fd(), count.as_mut_ptr().cast(), count.len()) };
        n == 8
    }

    /// The descriptor, readable while rung.
    pub fn fd(&self) -> RawFd {
        self.fd.as_raw_fd()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ring_is_taken_once() {
        let bell = Doorbell::new().unwrap();
        assert!(!bell.take());
        bell.ring();
        bell.ring();
        assert!(crate::sys::poll::wait_readable(bell.fd(), 0));
        assert!(bell.take());
        assert!(!bell.take());
        assert!(!crate::sys::poll::wait_readable(bell.fd(), 0));
    }
}
