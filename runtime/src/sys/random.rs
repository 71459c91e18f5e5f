// SPDX-License-Identifier: MIT OR Apache-2.0
//! Random bytes from the kernel, for values nobody may guess or repeat: client tokens, AR and
//! activity UUIDs.

/// Fills `b` from `getrandom(2)`; `false` if the kernel gave fewer bytes.
pub fn fill(b: &mut [u8]) -> bool {
    // SAFETY: `b` is a valid, writable buffer of the given length.
    let n = unsafe { libc::getrandom(b.as_mut_ptr().cast(), b.len(), 0) };
    usize::try_from(n).is_ok_and(|n| n == b.len())
}

/// A random (version 4, RFC 4122 variant) UUID as 16 big-endian bytes.
pub fn uuid_v4() -> [u8; 16] {
    let mut b = [0u8; 16];
    if !fill(&mut b) {
        // Never nil and never the same twice in one process, even without the kernel's help.
        static FALLBACK: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(1);
        let n = FALLBACK.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        b[..8].copy_from_slice(&n.to_be_bytes());
        b[8..].copy_from_slice(&(std::process::id() as u64).to_be_bytes());
    }
    b[6] = (b[6] & 0x0f) | 0x40;
    b[8] = (b[8] & 0x3f) | 0x80;
    b
}
