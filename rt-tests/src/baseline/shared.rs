// SPDX-License-Identifier: MIT OR Apache-2.0
//! A value in a shared anonymous mapping: after `fork` both processes see the same memory,
//! which is what a cross-process handshake works on (as iceoryx2's shared memory does).

use std::ptr::NonNull;

/// Why the shared mapping could not be made.
#[derive(Debug, thiserror::Error)]
pub enum SharedMapError {
    /// mmap refused.
    #[error(
        "cannot map {bytes} bytes of shared memory ({source}); check the memory limits of \
         this process (ulimit -v) and that the machine is not out of memory"
    )]
    Mmap {
        /// Size asked for.
        bytes: usize,
        /// The OS error.
        source: std::io::Error,
    },
}

/// Types that are valid when all their bytes are zero and that may be shared between
/// processes: atomics and arrays of them, nothing that points anywhere.
///
/// # Safety
///
/// Implementors must be valid at all-zero bytes and hold no pointers or file descriptors.
pub unsafe trait ZeroShareable: Sync {}

/// A `T` in a `MAP_SHARED | MAP_ANONYMOUS` mapping of its own, zeroed by the kernel.
pub struct SharedMap<T: ZeroShareable> {
    ptr: NonNull<T>,
    bytes: usize,
}

impl<T: ZeroShareable> SharedMap<T> {
    /// Maps a zeroed `T`. Call before `fork`: the child inherits the mapping.
    pub fn new() -> Result<SharedMap<T>, SharedMapError> {
        // Whole pages: the mapping is page-aligned, so any alignment up to a page holds.
        let bytes = size_of::<T>().max(1).next_multiple_of(4096);
        debug_assert!(align_of::<T>() <= 4096);
        // SAFETY: a new anonymous mapping with no address hint aliases nothing; the result is
        // checked against MAP_FAILED before use.
        let ptr = unsafe {
            libc::mmap(
                std::ptr::null_mut(),
                bytes,
                libc::PROT_READ | libc::PROT_WRITE,
                libc::MAP_SHARED | libc::MAP_ANONYMOUS,
                -1,
                0,
            )
        };
        if ptr == libc::MAP_FAILED {
            return Err(SharedMapError::Mmap {
                bytes,
                source: std::io::Error::last_os_error(),
            });
        }
        let ptr = NonNull::new(ptr.cast::<T>()).ok_or_else(|| SharedMapError::Mmap {
            bytes,
            source: std::io::Error::other("mmap returned a null pointer"),
        })?;
        Ok(SharedMap { ptr, bytes })
    }
}

impl<T: ZeroShareable> std::ops::Deref for SharedMap<T> {
    type Target = T;

    fn deref(&self) -> &T {
        // SAFETY: the mapping is page-aligned, at least size_of::<T>() long, zero-filled by the
        // kernel (a valid T by ZeroShareable) and lives until drop; T is Sync, and only shared
        // references are handed out, so concurrent access from the other process goes through
        // T's atomics.
        unsafe { self.ptr.as_ref() }
    }
}

impl<T: ZeroShareable> Drop for SharedMap<T> {
    fn drop(&mut self) {
        // SAFETY: ptr/bytes are exactly what mmap returned and were asked for; no reference
        // into the mapping outlives self (they borrow from it).
        unsafe {
            libc::munmap(self.ptr.as_ptr().cast(), self.bytes);
        }
    }
}
