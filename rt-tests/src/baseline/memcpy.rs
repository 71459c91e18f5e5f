// SPDX-License-Identifier: MIT OR Apache-2.0
//! The copy limit: one `copy_from_slice` of N bytes between two page-aligned, pre-faulted
//! buffers, timed copy by copy. The buffers stay hot in the caches, so this is the best a
//! copy of the image can do on this machine, which is what a ratio should be taken to.

use hdrhistogram::Histogram;
use procimg_rt_tests::report::{HIGHEST_NS, new_histogram};
use procimg_runtime::sys::clock::now_ns;
use std::hint::black_box;

const PAGE: usize = 4096;

/// Largest size accepted: a bigger copy says nothing about a process image.
pub const MAX_BYTES: usize = 1 << 30;

/// Why a size was refused.
#[derive(Debug, thiserror::Error)]
pub enum SizeError {
    /// Not a number with an optional suffix.
    #[error("{0:?} is not a size: write bytes, optionally with KiB or MiB (e.g. 64, 4KiB, 1MiB)")]
    Syntax(String),
    /// Zero or too large.
    #[error("{0:?}: a size must be 1 byte to 1 GiB")]
    Range(String),
}

/// Parses `64`, `64B`, `4K`, `4KiB`, `1M`, `1MiB`.
pub fn parse_size(s: &str) -> Result<usize, SizeError> {
    let t = s.trim();
    let (num, unit) = t.split_at(t.find(|c: char| !c.is_ascii_digit()).unwrap_or(t.len()));
    let factor = match unit.trim() {
        "" | "B" => 1,
        "K" | "KiB" | "k" => 1 << 10,
        "M" | "MiB" => 1 << 20,
        _ => return Err(SizeError::Syntax(s.to_string())),
    };
    let n: usize = num.parse().map_err(|_| SizeError::Syntax(s.to_string()))?;
    match n.checked_mul(factor) {
        Some(bytes) if (1..=MAX_BYTES).contains(&bytes) => Ok(bytes),
        _ => Err(SizeError::Range(s.to_string())),
    }
}

/// Copies of `bytes` to time: `loops`, but no more than about 1 GiB copied in all, so that
/// a 1 MiB run takes a second and not minutes; at least 100 so the percentiles mean something.
pub fn repetitions(bytes: usize, loops: u64) -> u64 {
    let budget = ((1u64 << 30) / bytes as u64).max(100);
    loops.min(budget)
}

/// A page-aligned slice of `bytes` inside an over-allocated Vec (no unsafe allocation API
/// needed), written once so every page is faulted in before the clock runs.
struct Aligned {
    storage: Vec<u8>,
    start: usize,
    bytes: usize,
}

impl Aligned {
    fn new(bytes: usize, fill: u8) -> Aligned {
        let storage = vec![fill; bytes + PAGE];
        let start = storage.as_ptr().align_offset(PAGE);
        let mut a = Aligned {
            storage,
            start,
            bytes,
        };
        // vec! of a non-zero byte writes every page; write again in case the allocator handed
        // out zero pages for a zero fill.
        for b in a.slice_mut().iter_mut().step_by(PAGE) {
            *b = black_box(fill);
        }
        a
    }

    fn slice(&self) -> &[u8] {
        &self.storage[self.start..self.start + self.bytes]
    }

    fn slice_mut(&mut self) -> &mut [u8] {
        &mut self.storage[self.start..self.start + self.bytes]
    }
}

/// Times `reps` copies of `bytes`, after a tenth as many untimed ones.
pub fn measure(bytes: usize, reps: u64) -> Histogram<u64> {
    let src = Aligned::new(bytes, 0xa5);
    let mut dst = Aligned::new(bytes, 0x5a);
    let mut h = new_histogram();
    for i in 0..reps + reps / 10 {
        let start = now_ns();
        dst.slice_mut().copy_from_slice(black_box(src.slice()));
        black_box(dst.slice_mut().as_mut_ptr());
        let end = now_ns();
        if i >= reps / 10 {
            h.saturating_record(end.saturating_sub(start).clamp(1, HIGHEST_NS));
        }
    }
    h
}

/// What reading the clock twice costs (p50, ns): it is inside every timed copy, and
/// dominates the small ones.
pub fn clock_overhead_ns() -> u64 {
    let mut h = new_histogram();
    for _ in 0..10_000 {
        let a = now_ns();
        let b = now_ns();
        h.saturating_record(b.saturating_sub(a).max(1));
    }
    h.value_at_quantile(0.5)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_take_suffixes() {
        assert_eq!(parse_size("64").unwrap(), 64);
        assert_eq!(parse_size("64B").unwrap(), 64);
        assert_eq!(parse_size("4KiB").unwrap(), 4096);
        assert_eq!(parse_size("64K").unwrap(), 65536);
        assert_eq!(parse_size("1MiB").unwrap(), 1 << 20);
        assert!(parse_size("0").is_err());
        assert!(parse_size("2GiB").is_err());
        assert!(parse_size("lots").is_err());
        assert!(parse_size("99999999999999999999").is_err());
    }

    #[test]
    fn big_copies_are_repeated_less() {
        assert_eq!(repetitions(64, 100_000), 100_000);
        assert_eq!(repetitions(1 << 20, 100_000), 1024);
        assert_eq!(repetitions(1 << 30, 100_000), 100);
        assert_eq!(repetitions(1 << 20, 300), 300);
    }

    #[test]
    fn a_copy_is_timed_reps_times() {
        let h = measure(4096, 200);
        assert_eq!(h.len(), 200);
    }
}
