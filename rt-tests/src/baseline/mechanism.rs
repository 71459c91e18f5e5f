// SPDX-License-Identifier: MIT OR Apache-2.0
//! The four ways the two processes hand a sequence number to each other: spinning on a
//! cache line, sleeping on a futex, blocking on an eventfd, blocking on a unix datagram
//! socket. Each is made before `fork` so that both processes share it.

use super::shared::{SharedMap, SharedMapError, ZeroShareable};
use std::fs::File;
use std::io::{Read, Write};
use std::os::fd::{FromRawFd, OwnedFd};
use std::os::unix::net::UnixDatagram;
use std::sync::atomic::{AtomicU32, AtomicU64, Ordering};

/// Which way a number goes: A (the measuring process) to B, or back.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dir {
    /// A → B.
    ToB,
    /// B → A.
    ToA,
}

/// Why a mechanism could not be made or used.
#[derive(Debug, thiserror::Error)]
pub enum MechanismError {
    /// The shared page for spin or futex.
    #[error(transparent)]
    Shared(#[from] SharedMapError),
    /// eventfd, socketpair, read, write or futex failed.
    #[error("{what} failed ({source}); this is unexpected on Linux, please report it")]
    Os {
        /// The call.
        what: &'static str,
        /// The OS error.
        source: std::io::Error,
    },
    /// The other side sent something out of turn.
    #[error("expected sequence number {expected}, received {received}: the ping-pong lost step")]
    OutOfStep {
        /// What the protocol expected.
        expected: u64,
        /// What came.
        received: u64,
    },
}

fn os(what: &'static str) -> impl FnOnce(std::io::Error) -> MechanismError {
    move |source| MechanismError::Os { what, source }
}

/// A way to hand a number to the other process and to wait for one.
pub trait Channel {
    /// Makes `n` visible to the other side (and wakes it if it sleeps).
    fn send(&self, dir: Dir, n: u64) -> Result<(), MechanismError>;
    /// Returns once the other side has sent `n` this way.
    fn wait(&self, dir: Dir, n: u64) -> Result<(), MechanismError>;
}

/// One value on a cache line of its own, so the two directions never share a line (a
/// shared line would measure false sharing, not the handshake).
#[repr(C, align(64))]
struct Line<A> {
    value: A,
}

/// The two lines of the spin and futex handshakes.
#[repr(C)]
struct Lines<A> {
    to_b: Line<A>,
    to_a: Line<A>,
}

impl<A> Lines<A> {
    fn get(&self, dir: Dir) -> &A {
        match dir {
            Dir::ToB => &self.to_b.value,
            Dir::ToA => &self.to_a.value,
        }
    }
}

// SAFETY: atomics are valid at zero and hold no pointers.
unsafe impl ZeroShareable for Lines<AtomicU64> {}
// SAFETY: as above.
unsafe impl ZeroShareable for Lines<AtomicU32> {}

/// Busy-polling: each side spins reading the other's cache line.
pub struct Spin(SharedMap<Lines<AtomicU64>>);

impl Spin {
    /// Maps the two lines.
    pub fn new() -> Result<Spin, MechanismError> {
        Ok(Spin(SharedMap::new()?))
    }
}

impl Channel for Spin {
    fn send(&self, dir: Dir, n: u64) -> Result<(), MechanismError> {
        self.0.get(dir).store(n, Ordering::Release);
        Ok(())
    }

    fn wait(&self, dir: Dir, n: u64) -> Result<(), MechanismError> {
        let line = self.0.get(dir);
        while line.load(Ordering::Acquire) != n {
            std::hint::spin_loop();
        }
        Ok(())
    }
}

/// Sleeping on a futex word per direction; non-private, because the two sides are
/// different processes (a private futex is keyed by address space).
pub struct Futex(SharedMap<Lines<AtomicU32>>);

impl Futex {
    /// Maps the two words.
    pub fn new() -> Result<Futex, MechanismError> {
        Ok(Futex(SharedMap::new()?))
    }
}

/// The futex words hold the low 32 bits of the sequence number: consecutive numbers differ.
fn low32(n: u64) -> u32 {
    n as u32
}

impl Channel for Futex {
    fn send(&self, dir: Dir, n: u64) -> Result<(), MechanismError> {
        let word = self.0.get(dir);
        word.store(low32(n), Ordering::Release);
        // SAFETY: the word is a live, aligned u32 in the shared mapping; FUTEX_WAKE only
        // reads the address to find waiters.
        let rc = unsafe { libc::syscall(libc::SYS_futex, word.as_ptr(), libc::FUTEX_WAKE, 1) };
        if rc < 0 {
            return Err(os("FUTEX_WAKE")(std::io::Error::last_os_error()));
        }
        Ok(())
    }

    fn wait(&self, dir: Dir, n: u64) -> Result<(), MechanismError> {
        let word = self.0.get(dir);
        loop {
            let seen = word.load(Ordering::Acquire);
            if seen == low32(n) {
                return Ok(());
            }
            // SAFETY: the word is a live, aligned u32 in the shared mapping; a null timeout
            // waits without limit (a dead partner is caught by the parent's watchdog).
            let rc = unsafe {
                libc::syscall(
                    libc::SYS_futex,
                    word.as_ptr(),
                    libc::FUTEX_WAIT,
                    seen,
                    std::ptr::null::<libc::timespec>(),
                )
            };
            if rc < 0 {
                let e = std::io::Error::last_os_error();
                // EAGAIN: the word changed before we slept; EINTR: a signal. Look again.
                if !matches!(e.raw_os_error(), Some(libc::EAGAIN) | Some(libc::EINTR)) {
                    return Err(os("FUTEX_WAIT")(e));
                }
            }
        }
    }
}

/// Blocking reads and writes on one eventfd per direction.
pub struct EventFd {
    to_b: File,
    to_a: File,
}

fn eventfd() -> Result<File, MechanismError> {
    // SAFETY: eventfd takes an initial value and flags and returns a new descriptor or -1.
    let fd = unsafe { libc::eventfd(0, libc::EFD_CLOEXEC) };
    if fd < 0 {
        return Err(os("eventfd")(std::io::Error::last_os_error()));
    }
    // SAFETY: fd is a freshly created descriptor that nothing else owns.
    Ok(File::from(unsafe { OwnedFd::from_raw_fd(fd) }))
}

impl EventFd {
    /// Makes the two eventfds.
    pub fn new() -> Result<EventFd, MechanismError> {
        Ok(EventFd {
            to_b: eventfd()?,
            to_a: eventfd()?,
        })
    }

    fn file(&self, dir: Dir) -> &File {
        match dir {
            Dir::ToB => &self.to_b,
            Dir::ToA => &self.to_a,
        }
    }
}

impl Channel for EventFd {
    fn send(&self, dir: Dir, _n: u64) -> Result<(), MechanismError> {
        // An eventfd carries a counter, not the number: the strict alternation of the
        // ping-pong keeps the two sides in step.
        self.file(dir)
            .write_all(&1u64.to_ne_bytes())
            .map_err(os("eventfd write"))
    }

    fn wait(&self, dir: Dir, n: u64) -> Result<(), MechanismError> {
        let mut buf = [0u8; 8];
        self.file(dir)
            .read_exact(&mut buf)
            .map_err(os("eventfd read"))?;
        let received = u64::from_ne_bytes(buf);
        if received != 1 {
            return Err(MechanismError::OutOfStep {
                expected: n,
                received,
            });
        }
        Ok(())
    }
}

/// A unix datagram socket pair: iceoryx2's default event mechanism.
pub struct Socket {
    a: UnixDatagram,
    b: UnixDatagram,
}

impl Socket {
    /// Makes the pair.
    pub fn new() -> Result<Socket, MechanismError> {
        let (a, b) = UnixDatagram::pair().map_err(os("socketpair"))?;
        Ok(Socket { a, b })
    }
}

impl Channel for Socket {
    fn send(&self, dir: Dir, n: u64) -> Result<(), MechanismError> {
        let from = if dir == Dir::ToB { &self.a } else { &self.b };
        from.send(&n.to_ne_bytes())
            .map(|_| ())
            .map_err(os("socket send"))
    }

    fn wait(&self, dir: Dir, n: u64) -> Result<(), MechanismError> {
        let at = if dir == Dir::ToB { &self.b } else { &self.a };
        let mut buf = [0u8; 8];
        let len = at.recv(&mut buf).map_err(os("socket recv"))?;
        let received = u64::from_ne_bytes(buf);
        if len != 8 || received != n {
            return Err(MechanismError::OutOfStep {
                expected: n,
                received,
            });
        }
        Ok(())
    }
}
