// SPDX-License-Identifier: MIT OR Apache-2.0
//! A counting global allocator for the client processes: it counts the allocations a thread
//! makes while it has counting switched on ([`counting`]), and passes everything to the
//! system allocator. The client switches it on around its measured cycles only (after the
//! warm-up), so the count is the steady-state allocations of a cycle: the goal is 0.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicU64, Ordering};

static ALLOCATIONS: AtomicU64 = AtomicU64::new(0);

thread_local! {
    // A const-initialised Cell without a destructor: reading it never allocates, so the
    // allocator may read it.
    static COUNTING: Cell<bool> = const { Cell::new(false) };
}

/// Runs `f` with this thread's allocations counted when `on`.
pub fn counting<R>(on: bool, f: impl FnOnce() -> R) -> R {
    COUNTING.with(|c| c.set(on));
    let r = f();
    COUNTING.with(|c| c.set(false));
    r
}

/// Allocations (including reallocations) counted so far.
pub fn allocations() -> u64 {
    ALLOCATIONS.load(Ordering::Relaxed)
}

fn note() {
    // `try_with`: allocations while the thread is torn down are not counted, and do not panic.
    if COUNTING.try_with(Cell::get).unwrap_or(false) {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
    }
}

/// The allocator: the system's, counted. Installed in procimg-handshake's `main.rs`.
pub struct Counting;

// SAFETY: every call is passed unchanged to `System`, which upholds GlobalAlloc's contract;
// the counting touches only an atomic and a thread-local flag, neither of which allocates.
#[allow(unsafe_code)]
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        note();
        // SAFETY: the caller's layout, as GlobalAlloc::alloc requires it, passed on.
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        note();
        // SAFETY: as in `alloc`.
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` came from `System` (every allocation here does) with this layout.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        note();
        // SAFETY: `ptr` came from `System` with `layout`; the caller guarantees `new_size`.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_switched_on_sections_count() {
        // This test binary is procimg-handshake's, with the counting allocator installed.
        let before = allocations();
        let v = counting(true, || vec![1u8; 16]);
        let during = allocations();
        assert!(during > before, "{before} -> {during}");
        // Outside the section nothing counts (no other test switches counting on).
        let w: Vec<u8> = Vec::with_capacity(16);
        assert_eq!(allocations(), during);
        assert_eq!(v.len() + w.capacity().min(16), 32);
        assert!(!COUNTING.with(Cell::get));
    }
}
